"""Where output may go: special files, owned directories and stale temporary files.

The atomic writers of :mod:`orthoglide_pin._io` call these checks so that the
package never destroys what it did not write:

* **Special files are refused.** Writing onto a FIFO, a character or block
  device (``/dev/full``, ``/dev/null`` too) or a socket raises
  :class:`~orthoglide_pin.exceptions.OutputPathError`: an atomic write
  replaces the path by a rename, which would put a regular file in place of
  the device. To discard an output, do not ask for it (or print to stdout
  where the command allows it and redirect that). A symbolic link to a
  regular file is written through: the file it points to is replaced.
* **Directories carry a marker.** A directory written whole by the package
  holds :data:`MARKER_NAME`, which lists the files it wrote (and, for a
  directory it wrote inside, ``NAME/`` and everything below it). An existing
  directory without it that is not empty (the working directory included) is
  refused unless forced; even forced, only the files of the package's names
  are replaced and every other file is kept. A directory or a special file
  where the package writes a file is never replaced, nor, unless forced, a
  file that the marker does not list (:func:`check_replaceable`). A directory
  is replaced whole only when everything in it is listed (:func:`may_swap`).
* **Temporary files are named after their owner.** They are hidden siblings
  of the target, ``.<name>.orthoglide-tmp-<pid>-<random>.tmp`` (``.old`` for
  a directory being replaced), removed on every exit path of the writer; the
  ones of a killed run (their process is gone, or they are older than
  :data:`STALE_AGE`) are removed by the next write into the same directory.
  Nothing else is ever removed.
* **Errors name the path as the caller gave it**, never a temporary file.
"""

from __future__ import annotations

import os
import re
import shutil
import stat
import time
from collections.abc import Collection, Iterable
from pathlib import Path
from typing import Final

from orthoglide_pin.exceptions import OutputPathError, short_repr

#: Tag in the names of temporary files and directories.
TEMP_TAG: Final = "orthoglide-tmp"
#: A temporary file or directory older than this is stale whatever its owner [s].
STALE_AGE: Final = 24 * 3600.0
#: Marker file of a directory written by the package (first line: :data:`MARKER_HEADER`,
#: then the names of the files written, one a line, then ``NAME/`` and ``NAME/PATH``
#: below each directory written; readers of the names alone skip lines with a ``/``).
MARKER_NAME: Final = ".orthoglide-output"
MARKER_HEADER: Final = (
    "# Written by orthoglide-pin. The next run may replace the files listed below; "
    "any other file is kept."
)

_TEMP_NAME = re.compile(rf"^\..+\.{TEMP_TAG}-(?P<pid>\d+)-[^/]+\.(tmp|old)$")
_KINDS: Final = (
    (stat.S_ISFIFO, "named pipe (FIFO)"),
    (stat.S_ISCHR, "character device"),
    (stat.S_ISBLK, "block device"),
    (stat.S_ISSOCK, "socket"),
)
#: Directories already cleaned of stale temporary files by this process.
_CLEANED: set[str] = set()


def temp_prefix(name: str) -> str:
    """Prefix of a temporary sibling of ``name`` written by this process."""
    return f".{name}.{TEMP_TAG}-{os.getpid()}-"


def _owner_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return pid > 0  # another user's process holds it, or a malformed name
    return True


def remove_stale_temps(directory: str | os.PathLike[str], *, again: bool = False) -> list[Path]:
    """Remove the temporary files and directories that killed runs left in ``directory``.

    Only entries named like the package's temporary files (see the module),
    owned by this user, whose process is gone or that are older than
    :data:`STALE_AGE`, are removed. A directory is scanned once per process
    unless ``again``.

    Returns:
        The paths removed.
    """
    key = os.path.abspath(directory)
    if key in _CLEANED and not again:
        return []
    _CLEANED.add(key)
    removed: list[Path] = []
    try:
        entries = list(os.scandir(key))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        match = _TEMP_NAME.match(entry.name)
        if match is None:
            continue
        try:
            info = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        if info.st_uid != os.getuid():
            continue
        if _owner_alive(int(match["pid"])) and now - info.st_mtime < STALE_AGE:
            continue
        if stat.S_ISDIR(info.st_mode):
            shutil.rmtree(entry.path, ignore_errors=True)
        elif stat.S_ISREG(info.st_mode):
            try:
                os.unlink(entry.path)
            except OSError:
                continue
        else:
            continue
        removed.append(Path(entry.path))
    return removed


def special_kind(mode: int) -> str | None:
    """The kind of special file of an ``st_mode`` ("named pipe (FIFO)", ...), or ``None``."""
    for test, name in _KINDS:
        if test(mode):
            return name
    return None


def output_file(path: str | os.PathLike[str]) -> Path:
    """The file an atomic write of ``path`` replaces, after refusing what it must not.

    Args:
        path: The output path as the caller gave it.

    Returns:
        ``path``, or the file it points to when it is a symbolic link.

    Raises:
        OutputPathError: An empty path, a directory, or a special file (FIFO,
            device, socket).
    """
    text = os.fspath(path)
    if text == "":
        raise OutputPathError(text, "an empty path: give a file name")
    try:
        info = os.stat(text)
    except FileNotFoundError:
        return Path(text)
    except OSError as exc:
        raise as_output_error(exc, text) from None
    if stat.S_ISDIR(info.st_mode):
        raise OutputPathError(text, "it is a directory: give a file name")
    kind = special_kind(info.st_mode)
    if kind is not None:
        raise OutputPathError(
            text,
            f"it is a {kind}, not a regular file; the package writes regular files "
            "only (replacing it would destroy the special file): give a file name",
        )
    return Path(os.path.realpath(text)) if os.path.islink(text) else Path(text)


def given_path(path: str | os.PathLike[str], what: str = "a file name") -> Path:
    """``Path(path)``, refusing an empty path, which ``Path`` would turn into ``.``.

    Args:
        path: The output path as the caller gave it.
        what: What to give instead, for the message.

    Raises:
        OutputPathError: On an empty path.
    """
    if isinstance(path, (str, os.PathLike)) and os.fspath(path) == "":
        raise OutputPathError("", f"an empty path: give {what}")
    return Path(path)


def as_output_error(exc: OSError, path: str | os.PathLike[str]) -> OutputPathError:
    """``exc`` as an :class:`OutputPathError` that names ``path`` (not a temporary file)."""
    if isinstance(exc, OutputPathError):
        return exc
    reason = exc.strerror or str(exc) or type(exc).__name__
    return OutputPathError(os.fspath(path), reason[:1].lower() + reason[1:])


def _marker_lines(directory: Path) -> list[str] | None:
    """The lines of a directory's marker after its header, or ``None`` without a marker."""
    marker = directory / MARKER_NAME
    if not marker.is_file() or marker.is_symlink():
        return None
    try:
        lines = marker.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return None
    if not lines or lines[0] != MARKER_HEADER:
        return None
    return lines[1:]


def _listed(directory: Path) -> set[str] | None:
    """The names a directory's marker lists, or ``None`` without a marker."""
    lines = _marker_lines(directory)
    if lines is None:
        return None
    return {line for line in lines if line and "/" not in line and line not in (".", "..")}


def _written(directory: Path) -> set[str]:
    """Every path its marker lists: names, and ``NAME/``, ``NAME/...`` inside directories."""
    return {line for line in _marker_lines(directory) or () if line and not line.startswith("/")}


def tree_lines(root: Path, name: str) -> list[str]:
    """The marker lines of the entry ``name`` of ``root``, which the package wrote.

    A file is its name; a directory is ``NAME/`` and, below it, each file as
    ``NAME/PATH`` and each directory as ``NAME/PATH/`` (the name itself is
    listed apart). Names with a line break cannot be listed: left out, they
    are never taken for the package's.
    """
    top = root / name
    if not top.is_dir() or top.is_symlink():
        return []
    out = [f"{name}/"]
    for below in sorted(top.rglob("*")):
        rel = below.relative_to(root).as_posix()
        if "\n" in rel or "\r" in rel:
            continue
        out.append(rel + "/" if below.is_dir() and not below.is_symlink() else rel)
    return out


def marker_text(names: Iterable[str], nested: Iterable[str] = ()) -> str:
    """Content of the marker of a directory holding ``names`` (and ``nested`` lines below them)."""
    top = sorted(set(names) - {MARKER_NAME})
    return "\n".join([MARKER_HEADER, *top, *sorted(set(nested) - set(top))]) + "\n"


def output_directory(
    path: str | os.PathLike[str], *, force: bool = False, ignore: Collection[str] = ()
) -> Path:
    """Check, before any work, that the directory ``path`` may receive the package's files.

    Allowed: a new path; an empty directory; a directory with the package's
    marker; any directory when ``force`` (whose other files are kept).

    Args:
        path: The directory as the caller gave it.
        force: Write into an existing directory that the package did not write.
        ignore: Names that do not count as content (the writer's own temporary).

    Returns:
        ``Path(path)``.

    Raises:
        OutputPathError: An empty path, a path that is not a directory, or a
            non-empty directory without the marker (unless ``force``).
    """
    text = os.fspath(path)
    if text == "":
        raise OutputPathError(text, 'an empty path: give a directory ("." is the current one)')
    target = Path(text)
    if os.path.islink(text) and not target.exists():
        raise OutputPathError(text, "a broken symbolic link")
    if not target.exists():
        return target
    if not target.is_dir():
        raise OutputPathError(text, "it exists and is not a directory")
    if force or _listed(target) is not None:
        return target
    try:
        empty = not any(entry.name not in ignore for entry in os.scandir(text))
    except OSError as exc:
        raise as_output_error(exc, text) from None
    if empty:
        return target
    raise OutputPathError(
        text,
        f"the directory exists, is not empty and was not written by orthoglide-pin "
        f"(no {MARKER_NAME} file in it); nothing was written: choose a new directory, "
        "or force it (--force), which writes the package's files into it and keeps "
        "every other file",
    )


def _kind(mode: int) -> str | None:
    """What an entry of ``st_mode`` is when the package never writes it, or ``None``."""
    if stat.S_ISDIR(mode):
        return "directory"
    return special_kind(mode)  # a regular file or a symbolic link (its own target kept)


def check_replaceable(
    path: str | os.PathLike[str], names: Collection[str], *, force: bool = False
) -> None:
    """Refuse to write ``names`` into the existing directory ``path`` where that would lose data.

    Every entry of ``names`` already in the directory must be a regular file
    (or a symbolic link, replaced itself, its target kept), and, unless
    ``force``, one the package wrote: listed by the directory's marker. A
    directory or a special file in the way is refused even when forced.
    Nothing is changed.

    Args:
        path: The directory as the caller gave it.
        names: Names of the files the package will put in it.
        force: Accept regular files of those names that the package did not write.

    Raises:
        OutputPathError: Naming the first entry in the way and what it is.
    """
    text = os.fspath(path)
    target = Path(text)
    listed = _listed(target) or set()
    for name in sorted(names):
        try:
            mode = (target / name).lstat().st_mode
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise as_output_error(exc, text) from None
        kind = _kind(mode)
        if kind is not None:
            raise OutputPathError(
                text,
                f"it holds a {kind} named {short_repr(name)} where the package writes a file; "
                "nothing was written or removed: move it, or choose another directory",
            )
        if not force and name != MARKER_NAME and name not in listed:
            raise OutputPathError(
                text,
                f"it holds a file named {short_repr(name)} that orthoglide-pin did not write (not "
                f"listed in its {MARKER_NAME}); nothing was written or removed: move it, "
                "or force it (--force), which replaces it",
            )


def _all_written(path: str, rel: str, written: set[str]) -> bool:
    """Whether the directory ``path`` (``rel`` in the marker) holds only what the marker lists."""
    try:
        entries = list(os.scandir(path))
    except OSError:
        return False
    for entry in entries:
        mode = entry.stat(follow_symlinks=False).st_mode
        below = f"{rel}/{entry.name}"
        if stat.S_ISDIR(mode):
            if below + "/" not in written or not _all_written(entry.path, below, written):
                return False
        elif special_kind(mode) is not None or below not in written:
            return False
    return True


def may_swap(target: Path, names: Collection[str]) -> bool:
    """Whether the existing directory ``target`` may be replaced whole by one holding ``names``.

    Only when it is a real directory (not a link) with the package's marker,
    not the working directory or one of its parents, and holds nothing but
    its marker and entries that ``names`` will replace and that the package
    wrote, directories and their content included (each listed by the
    marker, a directory as a directory): nothing is lost, not even an earlier
    output of the package under another name (a sweep's results when a
    report is written into its directory).
    """
    if target.is_symlink() or not target.is_dir() or _listed(target) is None:
        return False
    real = target.resolve()
    cwd = Path.cwd().resolve()
    if real == cwd or real in cwd.parents:
        return False
    written = _written(target)
    try:
        for entry in os.scandir(target):
            if entry.name == MARKER_NAME:
                continue
            if entry.name not in names or entry.name not in written:
                return False
            mode = entry.stat(follow_symlinks=False).st_mode
            if stat.S_ISDIR(mode):
                if f"{entry.name}/" not in written:
                    return False  # a directory where the package wrote a file
                if not _all_written(entry.path, entry.name, written):
                    return False
            elif special_kind(mode) is not None:
                return False
    except OSError:
        return False
    return True
