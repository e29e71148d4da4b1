"""Atomic file output: a reader never sees a half-written file.

Written files get the permissions any other tool would give them: a new file
``0o666`` and a new directory ``0o777``, less the process umask (``0o644`` and
``0o755`` under the usual umask ``0o022``); a file written over an existing one
keeps that file's permissions. (The temporary files and directories of
:mod:`tempfile` are private, ``0o600`` and ``0o700``: the final mode is set
before the rename.)

Where output may go is checked first (:mod:`orthoglide_pin._paths`): special
files (FIFO, devices, sockets) are refused, temporary files are removed on
every exit path and the stale ones of killed runs at the next write, and
errors name the path the caller gave. Whole directories are written by
:mod:`orthoglide_pin._outdir`.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import stat
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from orthoglide_pin._paths import (
    as_output_error,
    output_file,
    remove_stale_temps,
    special_kind,
    temp_prefix,
)
from orthoglide_pin.exceptions import Described, InvalidParameterError, cut_text

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


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename.

    The temporary file lives in the target directory (same file system), is
    flushed and fsynced, then renamed over ``path``. On any failure the
    temporary file is removed and ``path`` is left as it was. The file gets
    the mode of the file it replaces, or ``0o666`` less the umask if new.

    Raises:
        OutputPathError: ``path`` is a directory or a special file (FIFO,
            device such as ``/dev/null``, socket), or cannot be written; the
            message names ``path`` as given.
    """
    given = path
    path = output_file(path)  # refuses special files; follows a link to a file
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temps(path.parent)
        mode = _final_file_mode(path)
        fd, tmp = tempfile.mkstemp(prefix=temp_prefix(path.name), suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise as_output_error(exc, given) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fchmod(fh.fileno(), mode)
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise as_output_error(exc, given) from None
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write UTF-8 ``text`` to ``path`` atomically (see :func:`atomic_write_bytes`)."""
    atomic_write_bytes(path, text.encode("utf-8"))


def strict_json(value: Any) -> Any:
    """``value`` ready for strict JSON: numpy to Python, NaN and infinities to ``None``.

    ``null`` in a file of the package therefore always means "no value" (an
    invalid design's metrics, a margin where the motor has no torque).
    """
    if isinstance(value, dict):
        return {str(k): strict_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict_json(v) for v in value]
    if isinstance(value, np.ndarray):
        return strict_json(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def json_text(value: Any, *, indent: int | None = None, sort_keys: bool = False) -> str:
    """Strict JSON text of ``value`` (see :func:`strict_json`): never ``NaN`` or ``Infinity``."""
    return json.dumps(strict_json(value), indent=indent, sort_keys=sort_keys, allow_nan=False)


# ----------------------------------------------------------------- safe input
#: Largest configuration or drive file read [bytes] (such files hold a few kB).
MAX_INPUT_BYTES = 1_000_000
#: Largest single read [bytes].
READ_CHUNK = 1 << 20
#: Deepest nesting of lists and mappings accepted in such a file.
MAX_YAML_DEPTH = 16


#: libyaml's safe loader where PyYAML was built with it (about 50 times faster).
_LOADER: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
#: A number with an exponent, as YAML 1.2 (and JSON) write it: ``1e-3``, ``2E+5``, ``.5e1``.
#: PyYAML follows YAML 1.1, which wants a dot and a signed exponent (``1.0e-3``)
#: and reads ``1e-3`` as a string.
FLOAT_WITH_EXPONENT = re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)[eE][-+]?[0-9]+$")


class _NumberLoader(_LOADER):  # type: ignore[misc]
    """The safe loader, reading every YAML 1.2 number as a number (``1e-3`` too)."""


_NumberLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float", FLOAT_WITH_EXPONENT, list("-+.0123456789")
)


def _check_events(text: str) -> str | None:
    """Why ``text`` is unsafe (an alias, too deep), from the parser's events, or ``None``.

    Runs on the event stream, before any node is built: an alias bomb is refused
    at its first alias, a deep nest at its 17th level.
    """
    depth = 0
    for event in yaml.parse(text, Loader=_LOADER):
        if isinstance(event, yaml.AliasEvent):
            line = event.start_mark.line + 1 if event.start_mark is not None else "?"
            return f"alias *{event.anchor} at line {line}: aliases are not accepted"
        if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
            depth += 1
            if depth > MAX_YAML_DEPTH:
                return f"at most {MAX_YAML_DEPTH} nested levels"
        elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
            depth -= 1
    return None


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


def _yaml_problem(exc: yaml.YAMLError) -> str:
    """What the YAML parser found wrong and where, without the snippet of the document it quotes.

    At most :data:`~orthoglide_pin.exceptions.MAX_VALUE_CHARS` characters of
    the parser's own words (which may quote a tag or a character) are kept.
    """
    if isinstance(exc, yaml.MarkedYAMLError):
        words = " ".join(str(part) for part in (exc.context, exc.problem) if part)
        mark = exc.problem_mark or exc.context_mark
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
    elif isinstance(exc, yaml.reader.ReaderError):
        words, where = str(exc.reason), f" at offset {exc.position}"
    else:
        words, where = type(exc).__name__, ""
    return cut_text(words) + where


def parse_yaml_mapping(text: str, what: str, *, source: str | None = None) -> dict[str, Any]:
    """Parse one YAML document that must be a mapping with string keys.

    Anchors may be defined but aliases (``*name``, ``<<: *name``) are refused,
    so a document cannot expand beyond its own size; nesting is bounded by
    :data:`MAX_YAML_DEPTH`. An empty document is an empty mapping.

    Numbers follow one rule in every file of the package (design and
    configuration files, drive files, and their meshes, inertias and motor
    curves): a number may be written as YAML 1.2 and JSON write it, so
    ``1e-3``, ``1E-3`` and ``1.0e-3`` all read as 0.001 (PyYAML alone, following
    YAML 1.1, would read the first two as strings). A quoted value
    (``"1e-3"``) stays a string.

    Args:
        text: The document.
        what: What it is, for the error message (``"config"``, ``"motor file"``).
        source: The file it came from, shown in the errors instead of the text.

    Raises:
        InvalidParameterError: Invalid or unsafe YAML, a non-mapping, a key that
            is not a string; the message is one line.
    """
    shown: object = text[:40] if source is None else Path(source)
    if source is None:
        check_text(text, what)
    if len(text) > MAX_INPUT_BYTES:
        raise InvalidParameterError(
            what, f"{len(text)} characters", f"at most {MAX_INPUT_BYTES} characters of YAML"
        )
    try:
        unsafe = _check_events(text)
        data = None if unsafe else yaml.load(text, Loader=_NumberLoader)  # a safe loader
    except yaml.YAMLError as exc:
        why = _yaml_problem(exc)
        raise InvalidParameterError(what, shown, f"valid YAML ({why})") from None
    if unsafe:
        raise InvalidParameterError(what, shown, f"safe YAML ({unsafe})")
    if data is None:
        return {}
    if not isinstance(data, dict):
        kind = "list" if isinstance(data, list) else "single value"
        raise InvalidParameterError(what, shown, f"a mapping of names to values (it is a {kind})")
    _check_tree(what, data)
    return data


def _stat(name: str, what: str, shown: Path) -> os.stat_result:
    """The status of the file ``name`` (links followed), or an error naming it."""
    try:
        return os.stat(name)
    except (OSError, ValueError) as exc:
        why = getattr(exc, "strerror", None) or str(exc)
        raise InvalidParameterError(what, shown, f"a readable file ({why})") from None


def _regular_input(mode: int, what: str, shown: Path) -> None:
    """Refuse an input that is not a regular file (a directory, a FIFO, a device)."""
    if stat.S_ISDIR(mode):
        raise InvalidParameterError(what, shown, "a readable file (it is a directory)")
    kind = special_kind(mode)
    if kind is not None or not stat.S_ISREG(mode):
        raise InvalidParameterError(
            what, shown, f"a regular file (it is a {kind or 'special file'})"
        )


def _check_size(status: os.stat_result, what: str, shown: Path, limit: int) -> None:
    """Refuse a regular file whose size is known to exceed ``limit``, before reading it."""
    _regular_input(status.st_mode, what, shown)
    if status.st_size > limit:
        raise InvalidParameterError(
            what, shown, f"a file of at most {limit} bytes (it has {status.st_size})"
        )


def read_input_bytes(
    path: str | os.PathLike[str], what: str, limit: int = MAX_INPUT_BYTES
) -> bytes:
    """The bytes of a small input file, read safely.

    Only a regular file is read (a symbolic link to one too). Its size is
    checked before any read; a file that reports no size (those of ``/proc``
    and ``/sys`` show as empty regular files) is read up to ``limit + 1``
    bytes, then refused if there is more. An empty path, a directory and a
    special file (a FIFO, which would wait for a writer or read as an empty
    file; a device such as ``/dev/zero``; a socket) are refused before any
    read, as they are as outputs. No error quotes the content.

    Args:
        path: The file, as the user gave it (named in every error).
        what: What it is, for the error message (``"config"``, ``"motor file"``).
        limit: Largest accepted size [bytes].

    Raises:
        InvalidParameterError: Not a readable regular file, or larger than ``limit``.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidParameterError("path", path, "a file path (str or os.PathLike)")
    name = os.fspath(path)
    if not isinstance(name, str):
        raise InvalidParameterError("path", path, "a file path (str or os.PathLike of str)")
    shown = Path(name)  # a long path is cut in the middle (see short_repr)
    if not name:
        raise InvalidParameterError(what, name, "a file (an empty path names no file)")
    # Checked before opening, since opening a device may act on it; opened
    # without blocking and checked again, for a file replaced by a FIFO meanwhile.
    _check_size(_stat(name, what, shown), what, shown, limit)
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError) as exc:
        why = getattr(exc, "strerror", None) or str(exc)
        raise InvalidParameterError(what, shown, f"a readable file ({why})") from None
    try:
        _check_size(os.fstat(fd), what, shown, limit)
        chunks: list[bytes] = []
        size = 0
        while size <= limit:
            chunk = os.read(fd, min(limit + 1 - size, READ_CHUNK))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise InvalidParameterError(
            what, shown, f"a readable file ({exc.strerror or exc})"
        ) from None
    finally:
        os.close(fd)
    if size > limit:
        raise InvalidParameterError(
            what,
            shown,
            f"a file of at most {limit} bytes (it has more, though it reports no size)",
        )
    return b"".join(chunks)


def not_text(data: bytes) -> str | None:
    """Why ``data`` is not a text file (a NUL byte, a byte that is not UTF-8), or ``None``.

    The reason names the byte offset, never the content. A UTF-8 byte-order
    mark is allowed.
    """
    nul = data.find(b"\0")
    if nul >= 0:
        return f"a NUL byte at offset {nul}"
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        return f"a byte that is not UTF-8 at offset {exc.start}"
    return None


def decode_text(data: bytes, what: str, shown: object) -> str:
    """``data`` as text, checked by :func:`not_text` before anything parses it.

    Args:
        data: The file's bytes.
        what: What it is, for the error message.
        shown: What names it in the message (its path).

    Raises:
        InvalidParameterError: ``not a text file``, naming the byte offset.
    """
    why = not_text(data)
    if why is not None:
        raise InvalidParameterError(
            what, shown, f"a UTF-8 text file (it is not a text file: {why})"
        )
    return data.decode("utf-8-sig")


def check_text(text: str, what: str) -> str:
    """Refuse text given as a string that no text file could hold (a NUL character).

    The API's counterpart of :func:`decode_text`: a lone surrogate (which no
    UTF-8 file holds) is refused too. The message names the offset [characters].

    Raises:
        InvalidParameterError: ``not a text``, naming the offset.
    """
    nul = text.find("\0")
    why = f"a NUL character at offset {nul}" if nul >= 0 else None
    if why is None:
        try:
            text.encode("utf-8")
        except UnicodeEncodeError as exc:
            why = f"a character that is not UTF-8 at offset {exc.start}"
    if why is not None:
        raise InvalidParameterError(
            what, Described(f"<text of {len(text)} characters>"), f"a text file's text ({why})"
        )
    return text


def read_yaml_mapping(path: str | os.PathLike[str], what: str) -> dict[str, Any]:
    """Read a small YAML file safely: :func:`read_input_text`, then :func:`parse_yaml_mapping`.

    Args:
        path: The file, as the user gave it (named in every error).
        what: What it is, for the error message (``"config"``, ``"motor file"``).

    Returns:
        The mapping (string keys).

    Raises:
        InvalidParameterError: Not a readable regular file, too large, not
            UTF-8, or bad YAML.
    """
    return parse_yaml_mapping(read_input_text(path, what), what, source=os.fspath(path))


def read_input_text(path: str | os.PathLike[str], what: str, limit: int = MAX_INPUT_BYTES) -> str:
    """The text of a small input file (configuration, drive, loop data), read safely.

    The bytes are read by :func:`read_input_bytes` (at most ``limit``, the
    size checked first); they must be text (:func:`not_text`: UTF-8 without a
    NUL byte, a byte-order mark allowed), checked before anything parses them.

    Args:
        path: The file, as the user gave it (named in every error).
        what: What it is, for the error message.
        limit: Largest accepted size [bytes].

    Raises:
        InvalidParameterError: Not a readable regular file, too large, or not a
            text file (a NUL byte, a byte that is not UTF-8: named by its offset).
    """
    return decode_text(read_input_bytes(path, what, limit), what, Path(os.fspath(path)))
