"""Atomic file output: a reader never sees a half-written file.

Written files get the permissions any other tool would give them: a new file
``0o666`` and a new directory ``0o777``, less the process umask (``0o644`` and
``0o755`` under the usual umask ``0o022``); a file written over an existing one
keeps that file's permissions. (The temporary files and directories of
:mod:`tempfile` are private, ``0o600`` and ``0o700``: the final mode is set
before the rename.)
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

#: Modes of a new file and of a new directory before the umask.
FILE_MODE = 0o666
DIRECTORY_MODE = 0o777


def current_umask() -> int:
    """The process umask (read from ``/proc`` where it can, so it is never changed)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # no /proc: read it by setting it, then put it back
    os.umask(mask)
    return mask


def _final_file_mode(path: Path) -> int:
    """The mode a file written to ``path`` gets: the existing file's, else from the umask."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        return FILE_MODE & ~current_umask()


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename.

    The temporary file lives in the target directory (same file system), is
    flushed and fsynced, then renamed over ``path``. On any failure the
    temporary file is removed and ``path`` is left as it was. The file gets
    the mode of the file it replaces, or ``0o666`` less the umask if new.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = _final_file_mode(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fchmod(fh.fileno(), mode)
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write_text(path: Path, text: str) -> None:
    """Write UTF-8 ``text`` to ``path`` atomically (see :func:`atomic_write_bytes`)."""
    atomic_write_bytes(path, text.encode("utf-8"))


@contextlib.contextmanager
def atomic_directory(path: Path) -> Iterator[Path]:
    """Fill a temporary sibling directory of ``path``, then rename it to ``path``.

    Yields the temporary directory. On success its files are fsynced and it
    replaces ``path`` (an existing directory is swapped out only then, and
    removed); on any failure it is removed and ``path`` is left as it was. The
    directory gets the mode ``0o777`` less the umask.

    Raises:
        NotADirectoryError: ``path`` exists and is not a directory.
    """
    target = Path(path)
    if target.exists() and not target.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, "not a directory", str(target))
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent))
    try:
        tmp.chmod(DIRECTORY_MODE & ~current_umask())  # mkdtemp's 0o700 is private
        yield tmp
        for item in tmp.rglob("*"):
            if item.is_file():
                with open(item, "rb") as fh:
                    os.fsync(fh.fileno())
        if target.exists():
            old = Path(
                tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent)
            )
            os.replace(target, old / target.name)
            try:
                os.replace(tmp, target)
            except BaseException:
                os.replace(old / target.name, target)  # put the previous one back
                raise
            finally:
                shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
