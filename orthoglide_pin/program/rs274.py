"""Part programs read through LinuxCNC's own interpreter, the standalone ``rs274``.

The NGC language (parameters, expressions, O-word subroutines and control flow,
canned cycles, cutter compensation) is LinuxCNC's, and its interpreter is a
maintained component: Debian's ``linuxcnc-uspace`` package installs it as
``rs274``. :func:`read_rs274` runs it on a copy of the program in a fresh
temporary directory (the user's files are only read), with every line numbered
(``N`` words, so that each canonical call names its line), a work-offset file
and a tool table written from the arguments, a time limit, a bound on its output,
and its life tied to this process. Its canonical calls are read into
:class:`~orthoglide_pin.program.moves.Move` records by
:mod:`orthoglide_pin.program.canon`; its refusals become a
:class:`~orthoglide_pin.exceptions.ProgramError` naming the line.

Without a ``-i`` INI file ``rs274``'s machine units are inches: the offset file
(parameters 5221-5383) and the tool table are written in inches. Both are
always given (``-v``, ``-t``), since its defaults are files of a LinuxCNC
configuration. ``HOME`` and ``TMPDIR`` point to the temporary directory: the
``rs274`` of Debian 12 writes its tool table's shared memory file to
``$HOME/.tool.mmap``, the live tool table of a LinuxCNC running there.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Final

import numpy as np

from orthoglide_pin._io import read_input_text
from orthoglide_pin._validation import (
    finite_vector,
    flag,
    instance_of,
    path_argument,
    positive_number,
)
from orthoglide_pin._validation import text as text_argument
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    MissingExecutableError,
    ProgramError,
)
from orthoglide_pin.program.canon import CanonState, read_canon
from orthoglide_pin.program.modes import MAX_PROGRAM_BYTES
from orthoglide_pin.program.moves import FloatArray, Move
from orthoglide_pin.program.offsets import Setup
from orthoglide_pin.program.reader import ReadProgram

#: Name of LinuxCNC's standalone interpreter.
RS274: Final = "rs274"
#: Debian package that installs it.
PACKAGE: Final = "linuxcnc-uspace"
#: Default time limit of one run [s].
TIMEOUT: Final[float] = 60.0
#: Largest output of one run [bytes]; beyond it the run is stopped (a loop).
MAX_OUTPUT: Final[int] = 256 * 1024 * 1024
#: Longest line LinuxCNC's interpreter reads [characters].
MAX_LINE: Final[int] = 253
#: Metres per inch (``rs274``'s machine unit without an INI file).
INCH: Final[float] = 0.0254
#: First parameter of each work coordinate system's X offset (Y, Z follow).
WORK_OFFSETS: Final = {
    name: 5221 + 20 * i
    for i, name in enumerate(("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"))
} | {"G28": 5161, "G30": 5181}  # and the reference points of G28 and G30
#: The message of a program with neither ``M2``/``M30`` nor ``%`` at its end:
#: LinuxCNC runs such a program to its last line, so it is not a refusal.
NO_END: Final = "File ended with no percent sign or program end"
_LEAD = re.compile(r"^(\s*/?\s*)(?:[nN]\s*\d+\s*)?")
_NUMBERED = re.compile(r"^\s*/?\s*[nN](\d+)")
_PR_SET_PDEATHSIG: Final = 1


def find_rs274(executable: str | os.PathLike[str] | None = None) -> str:
    """Path of the ``rs274`` executable.

    Args:
        executable: A path or name to use instead of ``rs274`` on ``PATH``.

    Raises:
        MissingExecutableError: It is not found: the message names the package.
    """
    if executable is not None:
        path_argument("executable", executable)
    found = shutil.which(os.fspath(executable) if executable is not None else RS274)
    if found is None:
        raise MissingExecutableError(
            os.fspath(executable or RS274), f"{PACKAGE} (Debian)", "LinuxCNC's interpreter"
        )
    return found


def numbered(text: str) -> str:
    """The program with each line's ``N`` word set to its line number (1 for the first).

    Lines starting with ``%`` are kept as they are; a block delete ``/`` stays
    first; an ``N`` word already there is replaced. A line that LinuxCNC reads
    (at most :data:`MAX_LINE` characters) but would not read with its number
    is kept as it is: its moves are then counted to the last numbered line.
    """
    out = []
    for i, line in enumerate(text.split("\n"), start=1):
        if line.lstrip().startswith("%"):
            out.append(line)
        else:
            lead = _LEAD.match(line)
            start = lead.group(1) if lead else ""
            new = f"{start}N{i} {line[lead.end() if lead else 0 :]}"
            fits, fits_numbered = (len(t.rstrip("\r")) <= MAX_LINE for t in (line, new))
            out.append(line if fits and not fits_numbered else new)
    return "\n".join(out)


def _inches(value: float) -> str:
    """A length [m] written in inches for ``rs274``'s files."""
    return repr(value / INCH)


def _write_setup(
    folder: Path, work_offsets: dict[str, FloatArray], tools: dict[int, tuple[float, float]]
) -> tuple[Path, Path]:
    """Write the parameter (offsets) file and the tool table; return their paths."""
    var, table = folder / "offsets.var", folder / "tools.tbl"
    values = {5220: "1"}  # G54 active; LinuxCNC reads the parameters in increasing order
    for name, xyz in work_offsets.items():
        first = WORK_OFFSETS[name]
        values |= {first + k: _inches(float(v)) for k, v in enumerate(xyz)}
    rows = [f"{number} {value}" for number, value in sorted(values.items())]
    var.write_text("\n".join(rows) + "\n", encoding="ascii")
    lines = []
    for number, (length, diameter) in sorted(tools.items()):
        lines.append(f"T{number} P{number} Z{_inches(length)} D{_inches(diameter)}")
    table.write_text("\n".join(lines) + "\n", encoding="ascii")
    return var, table


#: Largest work offset or tool length accepted [m].
MAX_LENGTH: Final[float] = 1000.0
_OFFSETS_ALLOWED = "a mapping G54 to G59.3, G28 or G30 -> (X, Y, Z) [m]"
_TOOLS_ALLOWED = "a mapping tool number 1-99999 -> (length [m], diameter >= 0 [m])"


def _offsets(value: object) -> dict[str, FloatArray]:
    """Checked work offsets: name (upper case) -> (X, Y, Z) [m]."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidParameterError("work_offsets", value, _OFFSETS_ALLOWED)
    out = {}
    for name, xyz in value.items():
        if not isinstance(name, str) or name.upper() not in WORK_OFFSETS:
            raise InvalidParameterError("work_offsets", {name: xyz}, _OFFSETS_ALLOWED)
        point = finite_vector(f"work_offsets[{name}]", xyz, 3, "[m]")
        if np.max(np.abs(point)) > MAX_LENGTH:
            raise InvalidParameterError(f"work_offsets[{name}]", xyz, "within 1000 m")
        out[name.upper()] = point
    return out


def _tools(value: object) -> dict[int, tuple[float, float]]:
    """Checked tool table: number -> (length [m], diameter [m])."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidParameterError("tools", value, _TOOLS_ALLOWED)
    out = {}
    for number, spec in value.items():
        ok = isinstance(number, (int, np.integer)) and not isinstance(number, bool)
        if not ok or not 0 < int(number) < 100000:
            raise InvalidParameterError("tools", {number: spec}, _TOOLS_ALLOWED)
        size = np.size(spec) if isinstance(spec, (Sequence, np.ndarray)) else 0
        if size not in (1, 2):
            raise InvalidParameterError("tools", {number: spec}, _TOOLS_ALLOWED)
        values = finite_vector(f"tools[{number}]", spec, size, "[m]")
        length, diameter = float(values[0]), float(values[1]) if size == 2 else 0.0
        if abs(length) > MAX_LENGTH or not 0.0 <= diameter <= MAX_LENGTH:
            raise InvalidParameterError("tools", {number: spec}, _TOOLS_ALLOWED)
        out[int(number)] = (length, diameter)
    return out


def _limit_child() -> None:  # pragma: no cover - runs in the child
    """In ``rs274``: die with this process, and stop at :data:`MAX_OUTPUT` bytes."""
    import resource  # POSIX only, as rs274

    resource.setrlimit(resource.RLIMIT_FSIZE, (MAX_OUTPUT, MAX_OUTPUT))
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)


def _refusal(stderr: str, fallback: int) -> ProgramError | None:
    """The program error in ``rs274``'s standard error, or ``None`` for no refusal.

    ``rs274`` ends its standard error with the error's message and the text of
    the line at fault (``report_error`` of its driver), whose ``N`` word is the
    line number; what comes before (``executing``, ``(print, ...)`` comments)
    is not the error.
    """
    lines = stderr.split("\n")
    if lines and lines[-1] == "":
        lines.pop()  # the newline that ends the last line
    if len(lines) < 2 or lines[-2].strip() in ("", "executing"):
        return ProgramError(fallback, "LinuxCNC's interpreter stopped without a message")
    message, text = lines[-2].strip(), lines[-1]
    if message == NO_END:
        return None
    numbered_line = _NUMBERED.match(text)
    line = int(numbered_line.group(1)) if numbered_line else fallback
    return ProgramError(line, f"LinuxCNC's interpreter refuses it: {message[:200]}")


def run_rs274(
    text: str,
    *,
    work_offsets: Mapping[str, Sequence[float]] | None = None,
    tools: Mapping[int, Sequence[float]] | None = None,
    block_delete: bool = False,
    timeout: float = TIMEOUT,
    executable: str | os.PathLike[str] | None = None,
) -> tuple[str, str, int]:
    """Run ``rs274 -g`` on a program's text (its lines numbered); return its output.

    Args:
        text: The program.
        work_offsets: ``G54``-``G59.3`` offsets, e.g. ``{"G54": (0.1, 0.0, -0.05)}`` [m].
        tools: Tool table: number -> (length [m], diameter [m]) (``G43 H``, ``G41/G42``).
        block_delete: Skip the lines that start with ``/``.
        timeout: Time limit [s].
        executable: ``rs274`` to run instead of the one on ``PATH``.

    Returns:
        Standard output, standard error and exit status of ``rs274``.

    Raises:
        MissingExecutableError: ``rs274`` is not installed.
        ProgramError: The run exceeded the time limit or :data:`MAX_OUTPUT`.
        InvalidParameterError: A bad argument (named).
    """
    text = text_argument("text", text, "the text of a program (str)")
    offsets, table_rows = _offsets(work_offsets), _tools(tools)
    delete = flag("block_delete", block_delete)
    limit = positive_number("timeout", timeout, "a positive number of seconds")
    rs274 = find_rs274(executable)
    with tempfile.TemporaryDirectory(prefix="orthoglide-rs274-") as tmp:
        folder = Path(tmp)
        program = folder / "program.ngc"
        program.write_text(numbered(text), encoding="utf-8", errors="surrogateescape")
        var, table = _write_setup(folder, offsets, table_rows)
        out, err = folder / "canon.txt", folder / "errors.txt"
        args = [rs274, "-g", "-v", str(var), "-t", str(table)]
        args += ["-b"] if delete else []
        env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": tmp, "TMPDIR": tmp}
        env |= {"LC_ALL": "C", "LANG": "C"}
        with out.open("wb") as fout, err.open("wb") as ferr:
            try:
                done = subprocess.run(
                    [*args, str(program)],
                    stdin=subprocess.DEVNULL,
                    stdout=fout,
                    stderr=ferr,
                    cwd=tmp,
                    env=env,
                    timeout=limit,
                    preexec_fn=_limit_child,
                    check=False,
                )
            except subprocess.TimeoutExpired:
                raise ProgramError(
                    1, f"LinuxCNC's interpreter ran longer than {limit:g} s (a loop?)"
                ) from None
        if done.returncode == -signal.SIGXFSZ:
            raise ProgramError(
                1, f"LinuxCNC's interpreter printed more than {MAX_OUTPUT} bytes (a loop?)"
            )
        stdout = out.read_text(encoding="utf-8", errors="replace")
        stderr = err.read_text(encoding="utf-8", errors="replace")
    return stdout, stderr, done.returncode


def read_rs274_text(
    text: str,
    *,
    work_offsets: Mapping[str, Sequence[float]] | None = None,
    tools: Mapping[int, Sequence[float]] | None = None,
    block_delete: bool = False,
    timeout: float = TIMEOUT,
    executable: str | os.PathLike[str] | None = None,
    state: CanonState | None = None,
) -> list[Move]:
    """Read a program's text through LinuxCNC's interpreter (see :func:`read_rs274`).

    ``state``: the canon state to read into (its path control at each move,
    ``tolerances``, and ``mode_line``: :func:`~orthoglide_pin.program.canon.read_canon`),
    or ``None`` for a fresh one.
    """
    if state is not None:
        state = instance_of("state", state, CanonState, "a CanonState (program.canon) or None")
    stdout, stderr, status = run_rs274(
        text,
        work_offsets=work_offsets,
        tools=tools,
        block_delete=block_delete,
        timeout=timeout,
        executable=executable,
    )
    moves = read_canon(stdout, state)
    if status != 0:
        last = moves[-1].line if moves else 1
        error = _refusal(stderr, last)
        if error is not None:
            raise error
    return moves


def read_rs274_setup(
    text: str,
    setup: Setup,
    *,
    timeout: float = TIMEOUT,
    executable: str | os.PathLike[str] | None = None,
    state: CanonState | None = None,
) -> list[Move]:
    """Read a program's text through ``rs274`` with the built-in reader's :class:`Setup`.

    The work offsets, the G28/G30 points, the tool table (lengths and
    diameters; tool 0 is the empty spindle) and block delete are LinuxCNC's;
    the tool starts at the machine origin, where ``rs274`` starts. ``state``:
    as :func:`read_rs274_text`.

    Raises:
        InvalidParameterError: A start point other than the machine origin.
        MissingExecutableError, ProgramError: As :func:`read_rs274_text`.
    """
    if np.any(setup.start != 0.0):
        raise InvalidParameterError(
            "start", tuple(setup.start), "the machine origin through LinuxCNC's interpreter"
        )
    names = sorted(WORK_OFFSETS, key=WORK_OFFSETS.__getitem__)[2:]  # G54 ... G59.3
    offsets = {name: setup.work_offsets[k] for k, name in enumerate(names)}
    offsets |= {"G28": setup.g28, "G30": setup.g30}
    tools = {n: (length, setup.diameters.get(n, 0.0)) for n, length in setup.tools.items() if n}
    tools |= {n: (0.0, d) for n, d in setup.diameters.items() if n and n not in tools}
    return read_rs274_text(
        text,
        work_offsets=offsets,
        tools=tools,
        block_delete=setup.block_delete,
        timeout=timeout,
        executable=executable,
        state=state,
    )


def read_rs274_program(
    text: str,
    setup: Setup,
    *,
    timeout: float = TIMEOUT,
    executable: str | os.PathLike[str] | None = None,
) -> ReadProgram:
    """:func:`read_rs274_setup` as the built-in reader's :class:`ReadProgram`.

    Its moves, the path control at each (``tolerances``, ``mode_line``, read
    from ``rs274``'s calls by :func:`~orthoglide_pin.program.canon.read_canon`),
    no word ignored and no refusal (``rs274`` raises its own), the lines of the
    text, and the start: the first move's, or the setup's.

    Raises:
        InvalidParameterError, MissingExecutableError, ProgramError: As
            :func:`read_rs274_setup`.
    """
    state = CanonState()
    moves = tuple(
        read_rs274_setup(text, setup, timeout=timeout, executable=executable, state=state)
    )
    start = moves[0].start if moves else setup.start
    lines = len(text.splitlines())
    return ReadProgram(moves, tuple(state.tolerances), (), (), lines, start, state.mode_line)


def read_rs274(
    path: str | os.PathLike[str],
    *,
    work_offsets: Mapping[str, Sequence[float]] | None = None,
    tools: Mapping[int, Sequence[float]] | None = None,
    block_delete: bool = False,
    timeout: float = TIMEOUT,
    executable: str | os.PathLike[str] | None = None,
) -> list[Move]:
    """Read a part program through LinuxCNC's ``rs274`` into canonical moves.

    The program starts where ``rs274`` assumes the tool is: at the machine
    origin (its first move goes from there). A program with no ``M2``/``M30`` or ``%``
    at its end is read to its last line, as LinuxCNC runs it. Subroutines in
    files of their own (``o<name> call`` of ``name.ngc``) are not found.

    Args:
        path: The program file (only read).
        work_offsets: ``G54``-``G59.3`` offsets, e.g. ``{"G54": (0.1, 0.0, -0.05)}`` [m]
            (all zero by default).
        tools: Tool table: number -> (length [m], diameter [m]), for ``G43 H``
            and cutter compensation (empty by default).
        block_delete: Skip the lines that start with ``/`` (LinuxCNC's switch).
        timeout: Time limit of the run [s].
        executable: ``rs274`` to run instead of the one on ``PATH``.

    Returns:
        The moves, in machine coordinates of the program's axes [m] (as ``G53``
        names them: after units, work offsets, ``G92`` and tool length).

    Raises:
        MissingExecutableError: ``rs274`` is not installed (one line naming the
            Debian package ``linuxcnc-uspace``).
        ProgramError: The interpreter refuses the program (its message and line),
            or a move cannot be planned (probing, threading, NURBS, G95).
        InvalidParameterError: The file is not a readable regular UTF-8 file of
            at most 64 MB, or a bad argument.
    """
    return read_rs274_text(
        read_input_text(path, "program", MAX_PROGRAM_BYTES),
        work_offsets=work_offsets,
        tools=tools,
        block_delete=block_delete,
        timeout=timeout,
        executable=executable,
    )
