"""Output directories: written whole and atomically, never at the cost of the user's files.

:func:`atomic_directory` fills a temporary sibling directory and puts it in
place at the end; :func:`claim_directory` prepares a directory that a long
run fills file by file (a sweep). Both follow the rules of
:mod:`orthoglide_pin._paths`: a directory is written only if it is new, empty,
marked as the package's own (:data:`~orthoglide_pin._paths.MARKER_NAME`) or
forced, and even then no file that the package does not write is removed or
replaced. The files themselves are written by :mod:`orthoglide_pin._io`.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable, Collection, Iterable, Iterator
from pathlib import Path

from orthoglide_pin._io import DIRECTORY_MODE, atomic_write_text, current_umask
from orthoglide_pin._paths import (
    MARKER_NAME,
    as_output_error,
    check_replaceable,
    marker_text,
    may_swap,
    output_directory,
    remove_stale_temps,
    temp_prefix,
    tree_lines,
)


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike[str], *, force: bool = False) -> Iterator[Path]:
    """Fill a temporary sibling directory of ``path``, then put it in place.

    Yields the temporary directory (its files only are installed, with a
    marker, :data:`~orthoglide_pin._paths.MARKER_NAME`, that lists them). On
    any failure, Ctrl-C or SIGTERM included, it is removed and ``path`` is
    left as it was. At the end:

    * a new ``path`` is the temporary directory, renamed (mode ``0o777`` less
      the umask);
    * an existing directory of the package's own that holds nothing but files
      it wrote (listed by its marker) of the same names is replaced whole,
      atomically (not the working directory or a parent of it);
    * any other allowed directory (empty, marked but holding other files, or
      forced) receives the new files one by one, each replaced atomically,
      and every other file in it is kept. (So does an existing directory
      whose parent refuses the temporary sibling: the temporary directory is
      then made inside it.)
    * either way, an entry in the way is refused before anything is replaced
      or removed (:func:`~orthoglide_pin._paths.check_replaceable`): a
      directory or a special file of one of the new names, even forced, and
      unless forced a file of one of the names that the marker does not list.

    Args:
        path: The directory.
        force: Also write into an existing non-empty directory that the package
            did not write (its other files are kept).

    Raises:
        OutputPathError: ``path`` is empty, is not a directory, is a non-empty
            directory without the marker (checked before anything is written,
            and again at the end), holds an entry in the way (see above), or
            cannot be written.
    """
    given = os.fspath(path)
    output_directory(given, force=force)
    target = Path(os.path.abspath(given))
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temps(target.parent)
        tmp = _temporary(target)
    except OSError as exc:
        raise as_output_error(exc, given) from None
    try:
        tmp.chmod(DIRECTORY_MODE & ~current_umask())  # mkdtemp's 0o700 is private
        yield tmp
        names = sorted(p.name for p in tmp.iterdir() if p.name != MARKER_NAME)
        nested = [line for name in names for line in tree_lines(tmp, name)]
        (tmp / MARKER_NAME).write_text(marker_text(names, nested), encoding="utf-8")
        for item in tmp.rglob("*"):
            if item.is_file():
                with open(item, "rb") as fh:
                    os.fsync(fh.fileno())
        try:
            _install(tmp, target, given, names, force)
        except OSError as exc:
            raise as_output_error(exc, given) from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def claim_directory(
    path: str | os.PathLike[str],
    names: Iterable[str],
    *,
    force: bool = False,
    earlier: Callable[[Path], bool] | None = None,
    folders: Collection[str] = (),
) -> Path:
    """Make ``path`` a directory of the package's own, before files are written into it.

    Allowed as for :func:`atomic_directory` (new, empty, marked, or forced),
    or when ``earlier`` recognises in it an earlier run of the package (its
    own record, read and checked, so that the run can carry on). The
    directory is created and its marker lists ``names`` (with the names it
    listed before). Unless forced or recognised, a file of one of ``names``
    that the marker does not list is refused, and so is, even then, a
    directory or a special file where a file of ``names`` goes
    (:func:`~orthoglide_pin._paths.check_replaceable`; ``folders`` are the
    names that are directories).

    Args:
        path: The directory.
        names: The files and directories the package will write in it.
        force: Also claim a non-empty directory the package did not write
            (its other files are kept).
        earlier: Whether a directory holds an earlier run of the package.
        folders: The names of ``names`` that are directories.

    Returns:
        ``Path(path)``.

    Raises:
        OutputPathError: See :func:`~orthoglide_pin._paths.output_directory`
            and :func:`~orthoglide_pin._paths.check_replaceable`.
    """
    target = Path(os.fspath(path))
    names = list(names)
    ours = earlier is not None and target.is_dir() and earlier(target)
    output_directory(path, force=force or ours)
    if target.is_dir():
        files = [n for n in names if n not in folders]
        check_replaceable(path, [*files, MARKER_NAME], force=force or ours)
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise as_output_error(exc, path) from None
    listed = set(names)
    with contextlib.suppress(OSError, IndexError):
        listed |= set((target / MARKER_NAME).read_text(encoding="utf-8").splitlines()[1:])
    atomic_write_text(target / MARKER_NAME, marker_text(n for n in listed if n))
    return target


def _temporary(target: Path) -> Path:
    """A new temporary directory next to ``target``.

    Inside ``target`` instead when the parent refuses it (``--out .`` in a
    directory whose parent the user cannot write): the files are then
    written into ``target`` one by one.
    """
    prefix = temp_prefix(target.name)
    try:
        return Path(tempfile.mkdtemp(prefix=prefix, suffix=".tmp", dir=target.parent))
    except PermissionError:
        if not target.is_dir():
            raise
        remove_stale_temps(target)
        return Path(tempfile.mkdtemp(prefix=prefix, suffix=".tmp", dir=target))


def _install(tmp: Path, target: Path, given: str, names: list[str], force: bool) -> None:
    """Put the filled temporary directory ``tmp`` in place of ``target`` (see above)."""
    if not os.path.lexists(target):
        os.replace(tmp, target)
        return
    # it may have changed during the work
    output_directory(given, force=force, ignore={tmp.name})
    if tmp.parent != target and may_swap(target, names):
        old = Path(
            tempfile.mkdtemp(prefix=temp_prefix(target.name), suffix=".old", dir=target.parent)
        )
        os.replace(target, old / target.name)
        try:
            os.replace(tmp, target)
        except BaseException:
            os.replace(old / target.name, target)  # put the previous one back
            raise
        finally:
            shutil.rmtree(old, ignore_errors=True)
        return
    # all checked first: nothing is half installed, nothing the package did not write replaced
    check_replaceable(given, [*names, MARKER_NAME], force=force)
    new = set(names)
    listed, nested = set(names), [line for name in names for line in tree_lines(tmp, name)]
    with contextlib.suppress(OSError):
        previous = (target / MARKER_NAME).read_text(encoding="utf-8").splitlines()[1:]
        for line in previous:  # the earlier entries kept, and what is below them
            if not line or line.split("/")[0] in new or not os.path.lexists(target / line):
                continue
            if "/" in line:
                nested.append(line)
            else:
                listed.add(line)
    (tmp / MARKER_NAME).write_text(marker_text(listed, nested), encoding="utf-8")
    for name in [*names, MARKER_NAME]:  # the marker last: it lists complete files
        os.replace(tmp / name, target / name)
    shutil.rmtree(tmp, ignore_errors=True)
