"""The caches of rendered URDFs: in memory and on disk, bounded, least recently used out first.

Rendering a URDF runs xacro, so :func:`~orthoglide_pin.machine.description.render_urdf`
keeps what it rendered, keyed by
:func:`~orthoglide_pin.machine.description.cache_key` (a hash of everything
the text depends on):

* **in memory**, at most :data:`MEMORY_ENTRIES` texts per process;
* **on disk**, in :func:`cache_dir`, one file ``orthoglide-<key>.urdf`` per
  machine, at most :data:`MAX_ENTRIES` files and :data:`MAX_BYTES` bytes in
  all (a URDF is about 24 kB, so the entry cap comes first: about 12 MB).

Both are least-recently-used caches: a hit makes an entry the newest (on
disk, its modification time is set to now), and each new entry evicts the
oldest ones beyond the caps. So a sweep of any number of designs, on any
number of worker processes sharing the directory, leaves at most the caps,
and the machines in use stay cached.

The disk cache is safe under concurrent processes: entries are written
atomically (:func:`~orthoglide_pin._io.atomic_write_text`); evictions take
turns on a lock file, :data:`LOCK_NAME` (``flock``; without it, as on a
read-only cache, two evictors still never fail on each other's removals);
an entry touched after the evictor listed the directory is spared; a reader
that loses a race with an eviction renders again. While processes write, the
directory may hold one entry more per writer for an instant; once they are
done it holds at most the caps. It never removes what the package did not write: only
regular files of the current user named ``orthoglide-<32 hex digits>.urdf``
whose beginning is a URDF of the Orthoglide are eviction candidates; any
other file in the directory (which ``$ORTHOGLIDE_PIN_CACHE`` may point
anywhere) is left alone and does not count. A read-only cache is not an
error: the text is still returned.
"""

from __future__ import annotations

import contextlib
import os
import re
import stat
import threading
from collections import OrderedDict
from collections.abc import Iterator
from pathlib import Path
from typing import Final

from orthoglide_pin._io import atomic_write_text

#: Environment variable that overrides the on-disk URDF cache directory.
CACHE_ENV: Final = "ORTHOGLIDE_PIN_CACHE"
#: Most URDF files kept on disk.
MAX_ENTRIES: Final[int] = 512
#: Most bytes of URDF files kept on disk [bytes] (32 MiB).
MAX_BYTES: Final[int] = 32 * 1024 * 1024
#: Most URDF texts kept in memory by one process.
MEMORY_ENTRIES: Final[int] = 32
#: Bytes read from the start of a file to recognise a cached URDF.
HEAD_BYTES: Final[int] = 16384
#: Lock file of the evictions, in the cache directory (never removed).
LOCK_NAME: Final = ".orthoglide-cache.lock"

_ENTRY = re.compile(r"^orthoglide-[0-9a-f]{32}\.urdf$")
_SIGNATURE = b'<robot name="orthoglide"'
_MEMORY: OrderedDict[str, str] = OrderedDict()
_MEMORY_LOCK = threading.Lock()


def cache_dir() -> Path:
    """Directory of the on-disk URDF cache.

    ``$ORTHOGLIDE_PIN_CACHE`` if set, else ``$XDG_CACHE_HOME/orthoglide-pin``,
    else ``~/.cache/orthoglide-pin``.
    """
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "orthoglide-pin"


def entry_path(key: str) -> Path:
    """The cache file of ``key`` (it may not exist)."""
    return cache_dir() / f"orthoglide-{key}.urdf"


def remembered(key: str) -> str | None:
    """The text of ``key`` in this process's memory cache (now its newest), or ``None``."""
    with _MEMORY_LOCK:
        text = _MEMORY.get(key)
        if text is not None:
            _MEMORY.move_to_end(key)
        return text


def remember(key: str, text: str) -> None:
    """Keep ``text`` in memory as the newest entry, forgetting the oldest beyond the cap."""
    with _MEMORY_LOCK:
        _MEMORY[key] = text
        _MEMORY.move_to_end(key)
        while len(_MEMORY) > MEMORY_ENTRIES:
            _MEMORY.popitem(last=False)


def forget_all() -> None:
    """Empty this process's memory cache (the disk cache is kept)."""
    with _MEMORY_LOCK:
        _MEMORY.clear()


def memory_keys() -> list[str]:
    """Keys in the memory cache, oldest first."""
    with _MEMORY_LOCK:
        return list(_MEMORY)


def touch(path: Path) -> None:
    """Make the cache file ``path`` the most recently used (a read-only cache is fine)."""
    with contextlib.suppress(OSError):
        os.utime(path)


def read(key: str) -> str | None:
    """The cached text of ``key`` on disk, touched; ``None`` when it is not there."""
    path = entry_path(key)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    touch(path)
    return text


def store(key: str, text: str) -> Path:
    """Write ``text`` as the entry of ``key``, atomically, then evict beyond the caps.

    Returns:
        The path of the entry.

    Raises:
        OutputPathError: The cache cannot be written.
    """
    path = entry_path(key)
    atomic_write_text(path, text)
    evict(path.parent, keep=path.name)
    return path


def _is_ours(path: str) -> bool:
    """Whether the file begins as a URDF of the Orthoglide that the package rendered."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(HEAD_BYTES)
    except OSError:
        return False
    return head.startswith(b"<?xml") and _SIGNATURE in head


def _candidates(directory: Path) -> list[tuple[int, str, int]]:
    """The cache files in ``directory`` named as entries: ``(mtime [ns], path, size)``."""
    out: list[tuple[int, str, int]] = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return out
    uid = os.getuid()
    for entry in entries:
        if not _ENTRY.match(entry.name):
            continue
        try:
            info = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        if stat.S_ISREG(info.st_mode) and info.st_uid == uid:
            out.append((info.st_mtime_ns, entry.path, info.st_size))
    return out


@contextlib.contextmanager
def _turn(directory: Path) -> Iterator[None]:
    """Hold the directory's eviction lock, when it can be had (else go on without)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on POSIX
        yield
        return
    try:
        fd = os.open(directory / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:
        yield
        return
    try:
        with contextlib.suppress(OSError):
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def evict(
    directory: Path | None = None,
    *,
    keep: str | None = None,
    max_entries: int | None = None,
    max_bytes: int | None = None,
) -> list[Path]:
    """Remove the least recently used cache entries beyond the caps (see the module).

    Args:
        directory: The cache directory; :func:`cache_dir` when ``None``.
        keep: Name of an entry never removed (the one just written).
        max_entries: Cap on the entries; :data:`MAX_ENTRIES` when ``None``.
        max_bytes: Cap on their bytes; :data:`MAX_BYTES` when ``None``.

    Returns:
        The entries removed, oldest first.
    """
    directory = cache_dir() if directory is None else directory
    most = MAX_ENTRIES if max_entries is None else max_entries
    most_bytes = MAX_BYTES if max_bytes is None else max_bytes
    with _turn(directory):
        return _evict(directory, keep, most, most_bytes)


def _evict(directory: Path, keep: str | None, most: int, most_bytes: int) -> list[Path]:
    found = _candidates(directory)
    count, size = len(found), sum(s for _, _, s in found)
    removed: list[Path] = []
    for mtime, path, nbytes in sorted(found):
        if count <= most and size <= most_bytes:
            break
        name = os.path.basename(path)
        if name == keep:
            continue
        if not _is_ours(path):  # named like an entry, but not one: not ours to count
            count, size = count - 1, size - nbytes
            continue
        try:
            if os.lstat(path).st_mtime_ns != mtime:
                continue  # used since it was listed: it is no longer the oldest
            os.unlink(path)
        except FileNotFoundError:
            pass  # another process evicted it first
        except OSError:
            continue  # a read-only cache keeps what it has
        else:
            removed.append(Path(path))
        count, size = count - 1, size - nbytes
    return removed


__all__ = [
    "CACHE_ENV",
    "LOCK_NAME",
    "MAX_BYTES",
    "MAX_ENTRIES",
    "MEMORY_ENTRIES",
    "cache_dir",
    "entry_path",
    "evict",
    "forget_all",
    "read",
    "remember",
    "remembered",
    "store",
]
