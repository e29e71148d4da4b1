"""A part program read by the :mod:`orthoglide_pin.program` layer, into blocks in the world frame.

:func:`read_program` reads a program with the built-in reader
(:func:`orthoglide_pin.program.reader.read_moves`: the words and modes a 3-axis
CAM post writes, work offsets, ``G92``, tool lengths, canned cycles, arcs as
LinuxCNC cuts them), refuses it with every refusal listed in one line, and
maps its moves from the program's axes to the machine's world frame
(:class:`~orthoglide_pin.program.axes.ProgramAxes`: on every design program Z
points up, along -e3, so ``G1 Z-10`` moves the tool down, towards the table).

Each move becomes a :class:`Block`: its end points and arc centre in the world
frame, its arc's plane and signed sweep about the world axis of the plane's
normal (LinuxCNC's angle: turns, full circles), and the path control in force
(``G61`` exact stop; ``G64 P`` blending within ``P``). The blocks before the
first ``G61`` or ``G64`` line (:attr:`Program.mode_line`) are read under exact
stop and marked so: the planner gives them the controller's default mode
(:mod:`~orthoglide_pin.planning.controller`).
:mod:`orthoglide_pin.planning.path` turns the blocks into geometry.

With ``interpreter="linuxcnc"`` (or ``"auto"``, where the built-in reader
refuses the program for LinuxCNC's language) the moves are those of
LinuxCNC's ``rs274`` interpreter, read with the same setup, and planned the same way.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import check_text, read_input_text
from orthoglide_pin._validation import MAX_LENGTH, bounded_vector, instance_of
from orthoglide_pin._validation import text as text_argument
from orthoglide_pin.exceptions import InvalidParameterError, ProgramError
from orthoglide_pin.program.arcs import arc_geometry, plane_axes
from orthoglide_pin.program.axes import ProgramAxes, design_axes
from orthoglide_pin.program.modes import (
    DEFAULT_TOLERANCE,
    INCH,
    MAX_DWELL,
    MAX_FEED,
    MAX_PROGRAM_BYTES,
    MIN_FEED,
    MM,
)
from orthoglide_pin.program.moves import Move
from orthoglide_pin.program.offsets import Setup, make_setup
from orthoglide_pin.program.reader import MAX_LINES, Ignored, check_refusals, read_moves
from orthoglide_pin.program.rs274 import read_rs274_program
from orthoglide_pin.program.words import NGC_LANGUAGE

FloatArray = NDArray[np.float64]

__all__ = [
    "DEFAULT_TOLERANCE",
    "INCH",
    "INTERPRETERS",
    "MAX_DWELL",
    "MAX_FEED",
    "MAX_LINES",
    "MAX_PROGRAM_BYTES",
    "MIN_FEED",
    "MM",
    "PLANES",
    "Block",
    "Program",
    "read_program",
    "read_program_file",
]

#: Largest tilt of an arc's normal from a machine axis [-] (a rotated G18/G19 arc is refused).
PLANE_TOL: Final[float] = 1e-9
#: The readers of a program (see :func:`read_program`).
INTERPRETERS: Final = ("builtin", "linuxcnc", "auto")
#: The world plane of each normal axis: its two in-plane axes and the normal.
PLANES: Final = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}


@dataclass(frozen=True)
class Block:
    """One move or dwell of a program, in the world frame (SI units).

    Attributes:
        line: Line of the program (1 for the first).
        kind: ``"rapid"``, ``"line"``, ``"arc"`` or ``"dwell"``.
        start: Start point [m], shape (3,).
        end: End point [m], shape (3,).
        feed: Programmed path speed [m/s] (``None`` for a rapid or a dwell).
        center: Arc centre [m], in the plane of the start point (arcs only).
        plane: Indices of the plane's two world axes and of its normal axis,
            e.g. ``(0, 1, 2)``.
        sweep: Signed angle swept about the normal axis's +e direction [rad]
            (arcs only; positive counter-clockwise about it).
        dwell: Dwell time [s] (dwells only).
        exact_stop: The tool stops at the end of the block (G61).
        tolerance: Blending tolerance at the end of the block [m] (G64).
    """

    line: int
    kind: str
    start: FloatArray
    end: FloatArray
    feed: float | None = None
    center: FloatArray | None = None
    plane: tuple[int, int, int] = (0, 1, 2)
    sweep: float = 0.0
    dwell: float = 0.0
    exact_stop: bool = True
    tolerance: float = 0.0


@dataclass(frozen=True)
class Program:
    """A program read into blocks.

    Attributes:
        blocks: The moves and dwells, in order, in the world frame.
        start: The tool's start point [m], shape (3,), world frame.
        lines: Number of lines read.
        moves: The canonical moves the blocks come from (program axes,
            machine coordinates).
        ignored: The words read without effect on the path.
        axes: The program axes on the machine.
        mode_line: The first line that says ``G61`` or ``G64``, 0 when none
            does (the blocks before it run in the controller's default mode,
            :mod:`~orthoglide_pin.planning.controller`).
    """

    blocks: tuple[Block, ...]
    start: FloatArray
    lines: int
    moves: tuple[Move, ...] = ()
    ignored: tuple[Ignored, ...] = ()
    axes: ProgramAxes = field(default_factory=ProgramAxes)
    mode_line: int = 0


def _block(move: Move, tolerance: float | None, r: FloatArray) -> Block:
    """The block of a move, ``r`` the program -> world rotation."""
    start, end = r @ move.start, r @ move.end
    exact = tolerance is None
    tol = 0.0 if tolerance is None else tolerance
    if move.kind == "dwell":
        return Block(move.line, "dwell", start, end, dwell=move.dwell)
    if move.kind != "arc":
        return Block(move.line, move.kind, start, end, move.feed, exact_stop=exact, tolerance=tol)
    assert move.center is not None and move.normal is not None
    sweep = arc_geometry(move)[0]
    normal = r @ move.normal
    plane = plane_axes(normal)
    if abs(abs(normal[plane[2]]) - 1.0) > PLANE_TOL:
        raise ProgramError(
            move.line,
            "an arc whose plane is not a plane of the machine's axes (a G18 or G19 arc "
            "under a rotated work offset, G10 L2 R) is not planned",
        )
    sign = 1.0 if normal[plane[2]] > 0.0 else -1.0
    centre = r @ move.center
    return Block(
        move.line, "arc", start, end, move.feed, centre, plane, sign * sweep,
        exact_stop=exact, tolerance=tol,
    )  # fmt: skip


def read_program(
    text: str,
    *,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    start: ArrayLike = (0.0, 0.0, 0.0),
    setup: Setup | None = None,
    axes: ProgramAxes | None = None,
    interpreter: str = "builtin",
) -> Program:
    """Read a program (see the module) into blocks in the world frame.

    Args:
        text: The program.
        origin: The part zero in the world frame [m], shape (3,): ``G54``'s
            offset (ignored when ``setup`` is given).
        start: The tool's start point in the world frame [m], shape (3,)
            (ignored when ``setup`` is given).
        setup: Work offsets, reference points, tools, start point and block
            delete, in machine coordinates of the program's axes
            (:func:`~orthoglide_pin.program.offsets.make_setup`).
        axes: The program axes on the machine (default: the design's,
            :func:`~orthoglide_pin.program.axes.design_axes`).
        interpreter: ``"builtin"`` (the built-in reader), ``"linuxcnc"``
            (LinuxCNC's ``rs274``, ``orthoglide_pin.program.rs274.read_rs274_program``:
            the NGC language and cutter compensation; its path control read
            from its calls, :mod:`~orthoglide_pin.program.canon`; no ``ignored``
            list; the tool starts at the machine origin)
            or ``"auto"`` (the built-in reader, or ``rs274`` where the built-in
            reader refuses the program for LinuxCNC's language or ``G41``/``G42``).

    Returns:
        The program's blocks, in the world frame [m].

    Raises:
        ProgramError: Every refusal of the program, in one line naming the first
            (through ``rs274``: its message and line).
        MissingExecutableError: ``rs274`` is needed and not installed (one line
            naming the Debian package ``linuxcnc-uspace``).
        InvalidParameterError: A bad origin, start, setup, axes or interpreter.
    """
    axes = design_axes() if axes is None else instance_of("axes", axes, ProgramAxes, "ProgramAxes")
    if setup is None:
        zero = axes.to_program(bounded_vector("origin", origin, 3, MAX_LENGTH, "[m]"))
        first = axes.to_program(bounded_vector("start", start, 3, MAX_LENGTH, "[m]"))
        setup = make_setup(origin=zero, start=first)
    text = check_text(text_argument("text", text, "the text of a program (str)"), "text")
    if not isinstance(interpreter, str) or interpreter not in INTERPRETERS:
        raise InvalidParameterError("interpreter", interpreter, " or ".join(INTERPRETERS))
    read = None
    if interpreter != "linuxcnc":
        read = read_moves(text, setup)
        if interpreter == "builtin" or not any(needs_linuxcnc(x.reason) for x in read.refusals):
            read = check_refusals(read)
        else:
            read = None  # LinuxCNC's language: read through rs274
    if read is None:
        read = read_rs274_program(text, setup)
    r = axes.matrix
    blocks = tuple(_block(m, t, r) for m, t in zip(read.moves, read.tolerances, strict=True))
    start = axes.to_world(read.start)
    return Program(blocks, start, read.lines, read.moves, read.ignored, axes, read.mode_line)


def needs_linuxcnc(reason: str) -> bool:
    """Whether a refusal of the built-in reader is for LinuxCNC's language (or G41/G42)."""
    return NGC_LANGUAGE in reason or "read the program through LinuxCNC" in reason


def read_program_file(
    path: str | os.PathLike[str],
    *,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    start: ArrayLike = (0.0, 0.0, 0.0),
    setup: Setup | None = None,
    axes: ProgramAxes | None = None,
    interpreter: str = "builtin",
) -> Program:
    """Read a program file as ``orthoglide plan`` does, then :func:`read_program`.

    The file is read safely (:func:`~orthoglide_pin._io.read_input_text`): a
    regular file (a link to one is followed; a FIFO, a device or a directory
    is refused before any read), its size checked against
    :data:`MAX_PROGRAM_BYTES` before it is read, and text (UTF-8 without a NUL
    byte) before it is parsed. No error quotes more than 80 characters of it.

    Args:
        path: The file, named in the errors as given.
        origin: The part zero in the world frame [m], shape (3,).
        start: The tool's start point in the world frame [m], shape (3,).
        setup: Work offsets, tools, start and block delete (see :func:`read_program`).
        axes: The program axes on the machine (default: the design's).
        interpreter: ``"builtin"``, ``"linuxcnc"`` or ``"auto"`` (see :func:`read_program`).

    Raises:
        InvalidParameterError: Not a readable regular text file of at most
            :data:`MAX_PROGRAM_BYTES`.
        ProgramError: Every refusal of the program, in one line naming the first.
    """
    text = read_input_text(path, "program", MAX_PROGRAM_BYTES)
    return read_program(
        text, origin=origin, start=start, setup=setup, axes=axes, interpreter=interpreter
    )
