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
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import yaml

from orthoglide_pin.exceptions import InvalidParameterError

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


# ----------------------------------------------------------------- safe input
#: Largest configuration or drive file read [bytes] (such files hold a few kB).
MAX_INPUT_BYTES = 1_000_000
#: Deepest nesting of lists and mappings accepted in such a file.
MAX_YAML_DEPTH = 16


class _NoAliasLoader(yaml.SafeLoader):
    """PyYAML's safe loader with aliases refused: no exponential expansion."""

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()  # type: ignore[no-untyped-call]
            raise yaml.composer.ComposerError(
                None, None, f"alias *{event.anchor} (aliases are not accepted)", event.start_mark
            )
        return super().compose_node(parent, index)


def _check_tree(what: str, node: Any, depth: int = 0) -> None:
    """Refuse non-string keys and nesting beyond :data:`MAX_YAML_DEPTH`."""
    if depth > MAX_YAML_DEPTH:
        raise InvalidParameterError(what, "...", f"at most {MAX_YAML_DEPTH} nested levels")
    if isinstance(node, dict):
        for key, item in node.items():
            if not isinstance(key, str):
                raise InvalidParameterError(f"{what} key", key, "a string (a parameter name)")
            _check_tree(what, item, depth + 1)
    elif isinstance(node, list):
        for item in node:
            _check_tree(what, item, depth + 1)


def parse_yaml_mapping(text: str, what: str, *, source: str | None = None) -> dict[str, Any]:
    """Parse one YAML document that must be a mapping with string keys.

    Anchors may be defined but aliases (``*name``, ``<<: *name``) are refused,
    so a document cannot expand beyond its own size; nesting is bounded by
    :data:`MAX_YAML_DEPTH`. An empty document is an empty mapping.

    Args:
        text: The document.
        what: What it is, for the error message (``"config"``, ``"motor file"``).
        source: The file it came from, shown in the errors instead of the text.

    Raises:
        InvalidParameterError: Invalid or unsafe YAML, a non-mapping, a key that
            is not a string; the message is one line.
    """
    shown = text[:40] if source is None else source
    if len(text) > MAX_INPUT_BYTES:
        raise InvalidParameterError(
            what, f"{len(text)} characters", f"at most {MAX_INPUT_BYTES} characters of YAML"
        )
    try:
        data = yaml.load(text, Loader=_NoAliasLoader)  # a SafeLoader without aliases
    except yaml.YAMLError as exc:
        why = " ".join(str(exc).split())
        raise InvalidParameterError(what, shown, f"valid YAML without aliases ({why})") from None
    except RecursionError:
        raise InvalidParameterError(
            what, shown, f"YAML nested at most {MAX_YAML_DEPTH} levels"
        ) from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise InvalidParameterError(what, data, "a mapping of names to values")
    _check_tree(what, data)
    return data


def read_yaml_mapping(path: str | os.PathLike[str], what: str) -> dict[str, Any]:
    """Read a small YAML file safely: see :func:`parse_yaml_mapping`.

    At most ``MAX_INPUT_BYTES + 1`` bytes are read, whatever the file is (a
    device such as ``/dev/zero``, a pipe); a directory is refused before any
    read, and a FIFO without a writer is not waited for. The text must be
    UTF-8 (a byte-order mark is allowed).

    Args:
        path: The file, as the user gave it (named in every error).
        what: What it is, for the error message (``"config"``, ``"motor file"``).

    Returns:
        The mapping (string keys).

    Raises:
        InvalidParameterError: Unreadable, too large, not UTF-8, or bad YAML.
    """
    name = os.fspath(path)
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError) as exc:
        why = getattr(exc, "strerror", None) or str(exc)
        raise InvalidParameterError(what, name, f"a readable YAML file ({why})") from None
    try:
        mode = os.fstat(fd).st_mode
        if stat.S_ISDIR(mode):
            raise InvalidParameterError(what, name, "a readable YAML file (it is a directory)")
        if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
            os.set_blocking(fd, True)  # a pipe being written: wait for its data
        chunks: list[bytes] = []
        size = 0
        while size <= MAX_INPUT_BYTES:
            chunk = os.read(fd, MAX_INPUT_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise InvalidParameterError(
            what, name, f"a readable YAML file ({exc.strerror or exc})"
        ) from None
    finally:
        os.close(fd)
    if size > MAX_INPUT_BYTES:
        raise InvalidParameterError(
            what, name, f"a YAML file of at most {MAX_INPUT_BYTES} bytes (it is larger)"
        )
    data = b"".join(chunks)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InvalidParameterError(
            what, name, f"a UTF-8 text file (byte {data[exc.start]:#04x} at offset {exc.start})"
        ) from None
    return parse_yaml_mapping(text, what, source=name)
