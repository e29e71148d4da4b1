"""LinuxCNC's canonical machining calls, as ``rs274 -g`` prints them, read into moves.

The standalone interpreter prints one canonical call a line, e.g.::

        9 N12    STRAIGHT_FEED(10.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)

(a call counter, the block's ``N`` word or ``N.....``, the call and its arguments,
at 4 decimals in the program's units). Its coordinates are those of the current
work coordinate system; the machine's are reached as LinuxCNC's own canon layer
(``emccanon.cc``, ``rotate_and_offset_pos``) does it: add the ``G92`` offset,
rotate by the XY rotation of ``G10 L2 R``, add the ``G54``-``G59.3`` offset and the
tool length offset. The offsets are converted from the program's units when they
are set, and every length is turned into metres.

``ARC_FEED(first_end, second_end, first_centre, second_centre, rotation,
axis_end, ...)`` names its coordinates in the order of the active plane: (X, Y)
about Z for ``G17``, (Z, X) about Y for ``G18``, (Y, Z) about X for ``G19``; the
rotation is LinuxCNC's signed turn count (positive counter-clockwise about the
plane's normal).

The path control is read too, as the built-in reader reads it:
``SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)`` (``G61``) and
``(CANON_EXACT_STOP)`` (``G61.1``) stop at the end of every move;
``(CANON_CONTINUOUS, P)`` (``G64``) blends within ``P`` in the program's units.
LinuxCNC prints ``P = 0`` for a ``G64`` without ``P`` and for ``G64 P0`` alike
(both mean "no tolerance" there): the planner then blends within
:data:`~orthoglide_pin.program.modes.DEFAULT_TOLERANCE`, as after a ``G64``
without ``P`` read by the built-in reader. The tolerance in force at each move
and the first line that sets the path control are kept in the
:class:`CanonState` (``tolerances``, ``mode_line``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Final

import numpy as np

from orthoglide_pin._validation import MAX_LENGTH
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.program.modes import DEFAULT_TOLERANCE
from orthoglide_pin.program.moves import FloatArray, Move

#: Metres per program unit, by ``USE_LENGTH_UNITS`` argument.
UNITS: Final = {"CANON_UNITS_MM": 1e-3, "CANON_UNITS_INCHES": 0.0254, "CANON_UNITS_CM": 1e-2}
#: Per plane: indices (first, second, axis) of the ARC_FEED coordinates in (X, Y, Z).
PLANES: Final = {
    "CANON_PLANE_XY": (0, 1, 2),
    "CANON_PLANE_XZ": (2, 0, 1),
    "CANON_PLANE_YZ": (1, 2, 0),
}
#: Canonical motions that cannot be planned as a tool path, with the reason.
REFUSED: Final = {
    "STRAIGHT_PROBE": "probing (G38) depends on where the probe trips",
    "RIGID_TAP": "rigid tapping (G33.1) follows the spindle",
    "NURBS_G5_FEED": "NURBS feeds (G5.2) are not planned",
    "NURBS_G6_FEED": "NURBS feeds (G6.2) are not planned",
    "START_SPEED_FEED_SYNCH": "spindle-synchronised motion (G33, G76) is not planned",
    "START_SPEED_FEED_SYNC": "spindle-synchronised motion (G33, G76) is not planned",
}
#: One printed call: counter, N word (digits or ``.....``), name, arguments.
_CALL = re.compile(r"^\s*\d+\s+N(\d+|\.{5})\s*([A-Z_][A-Za-z0-9_.]*)\((.*)\)\s*$")
_LINE = re.compile(r"^\s*\d+\s+N(\d+)")
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf)", re.IGNORECASE)


def _numbers(args: str, count: int, line: int, name: str) -> list[float]:
    """The first ``count`` numbers of a call's arguments (all finite)."""
    values = [float(v) for v in _NUMBER.findall(args)][:count]
    if len(values) < count or not all(math.isfinite(v) for v in values):
        raise ProgramError(
            line, f"LinuxCNC's interpreter printed an unreadable {name}({args[:60]})"
        )
    return values


@dataclass
class CanonState:
    """What LinuxCNC's canon layer remembers between calls (lengths in metres).

    Attributes:
        unit: Metres per program unit.
        g5x: Active work offset (``G54``-``G59.3``) [m], shape (3,).
        g92: ``G92`` offset [m], shape (3,).
        rotation: XY rotation of the work coordinate system [deg].
        tool: Tool length offset [m], shape (3,).
        plane: Active plane, a key of :data:`PLANES`.
        feed: Feed rate [m/s].
        feed_mode: 0 units per minute (inverse time too: the interpreter then
            sets each move's rate), 1 units per revolution.
        line: Line of the last numbered call.
        position: Machine position [m], shape (3,): ``rs274`` starts at the
            machine origin (its work coordinates are then minus the offsets).
        tolerance: Blending tolerance in force [m] (``G64``), ``None`` under
            exact stop (``G61``, ``G61.1``, and before any path control).
        mode_line: The first line that sets the path control, 0 before any does.
        tolerances: The tolerance in force at each move read, in order.
    """

    unit: float = 1e-3
    g5x: FloatArray = field(default_factory=lambda: np.zeros(3))
    g92: FloatArray = field(default_factory=lambda: np.zeros(3))
    rotation: float = 0.0
    tool: FloatArray = field(default_factory=lambda: np.zeros(3))
    plane: str = "CANON_PLANE_XY"
    feed: float = 0.0
    feed_mode: int = 0
    line: int = 1
    position: FloatArray = field(default_factory=lambda: np.zeros(3))
    tolerance: float | None = None
    mode_line: int = 0
    tolerances: list[float | None] = field(default_factory=list)

    def rotate(self, v: FloatArray) -> FloatArray:
        """Rotate a vector about Z by the XY rotation."""
        if self.rotation == 0.0:
            return v
        t = math.radians(self.rotation)
        c, s = math.cos(t), math.sin(t)
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])

    def machine(self, point: Iterable[float]) -> FloatArray:
        """Machine coordinates [m] of a point given in program units and work coordinates."""
        p = np.asarray(list(point), dtype=float) * self.unit
        return self.rotate(p + self.g92) + self.g5x + self.tool


def _arc(state: CanonState, v: list[float], line: int) -> Move:
    """An ``ARC_FEED`` call read into an arc move (plane, centre, turns)."""
    if state.plane not in PLANES:
        raise ProgramError(line, f"an arc in {state.plane[13:]}: only XY, XZ and YZ planes")
    first, second, axis = PLANES[state.plane]
    end_p, centre_p = np.zeros(3), np.zeros(3)
    end_p[first], end_p[second], end_p[axis] = v[0], v[1], v[5]
    centre_p[first], centre_p[second], centre_p[axis] = v[2], v[3], v[5]
    normal = np.zeros(3)
    normal[axis] = 1.0
    normal = state.rotate(normal)
    start = state.position
    end, centre = state.machine(end_p), state.machine(centre_p)
    centre = centre - float(np.dot(centre - start, normal)) * normal
    state.position = end
    return Move(
        line, "arc", start, end, feed=_feed(state, line), center=centre, normal=normal,
        turns=int(v[4]),
    )  # fmt: skip


def _feed(state: CanonState, line: int) -> float:
    """The feed of a cutting move [m/s]; feed per revolution and no feed are refused."""
    if state.feed_mode == 1:
        raise ProgramError(line, "feed per revolution (G95) is not planned: use G94")
    if state.feed <= 0.0:
        raise ProgramError(line, "a cutting move with no feed rate (F word)")
    return state.feed


def _offset(state: CanonState, v: list[float]) -> FloatArray:
    """An offset's X, Y, Z [m], converted from the program's units now."""
    return np.array(v[:3]) * state.unit


def _path_control(state: CanonState, args: str, line: int) -> None:
    """``SET_MOTION_CONTROL_MODE``: exact stop, or blending within a tolerance (see the module)."""
    mode = args.split(",")[0].strip()
    if mode in ("CANON_EXACT_PATH", "CANON_EXACT_STOP"):
        state.tolerance = None
    elif mode == "CANON_CONTINUOUS":
        tol = _numbers(args, 1, line, "SET_MOTION_CONTROL_MODE")[0] * state.unit
        if not 0.0 <= tol <= MAX_LENGTH:
            raise ProgramError(line, f"G64 P: the tolerance must be in [0, {MAX_LENGTH:g}] m")
        state.tolerance = tol if tol > 0.0 else DEFAULT_TOLERANCE
    else:
        raise ProgramError(line, f"unknown path control {args[:40]}")
    if not state.mode_line:
        state.mode_line = line


def read_canon(output: str, state: CanonState | None = None) -> list[Move]:
    """Read the canonical calls printed by ``rs274 -g`` into moves.

    The ``N`` word printed on each call is taken as its line number (the bridge
    numbers every line of the program; calls of an unnumbered line, e.g. of a
    subroutine file, keep the last number).

    Args:
        output: Standard output of ``rs274 -g``.
        state: Canon state to start from (a fresh one by default: millimetres,
            no offsets, XY plane, exact stop); it is updated as the calls are
            read (its ``tolerances`` and ``mode_line`` among them).

    Returns:
        The moves, in machine coordinates of the program's axes [m].

    Raises:
        ProgramError: A motion that cannot be planned (probing, tapping, NURBS,
            feed per revolution, an arc outside XY/XZ/YZ), or an unreadable call.
    """
    s = state if state is not None else CanonState()
    moves: list[Move] = []
    for text in output.splitlines():
        numbered = _LINE.match(text)
        if numbered is not None:
            s.line = int(numbered.group(1))
        match = _CALL.match(text)
        if match is None:
            if "NURBS" in text:  # printed as "saicanon NURBS_G6_FEED_(...)"
                raise ProgramError(s.line, "NURBS feeds (G6.2) are not planned")
            continue
        _, name, args = match.groups()
        line, count = s.line, len(moves)
        if name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            end = s.machine(_numbers(args, 3, line, name))
            rapid = name == "STRAIGHT_TRAVERSE"
            feed = None if rapid else _feed(s, line)
            moves.append(Move(line, "rapid" if rapid else "line", s.position, end, feed=feed))
            s.position = end
        elif name == "ARC_FEED":
            moves.append(_arc(s, _numbers(args, 6, line, name), line))
        elif name == "DWELL":
            here = s.position
            seconds = _numbers(args, 1, line, name)[0]
            moves.append(Move(line, "dwell", here, here.copy(), dwell=seconds))
        elif name == "SET_FEED_RATE":
            s.feed = _numbers(args, 1, line, name)[0] * s.unit / 60.0
        elif name == "SET_FEED_MODE":
            s.feed_mode = int(_numbers(args, 2, line, name)[1])
        elif name == "USE_LENGTH_UNITS":
            if args not in UNITS:
                raise ProgramError(line, f"unknown length units {args[:40]}")
            s.unit = UNITS[args]
        elif name == "SET_G5X_OFFSET":
            s.g5x = _offset(s, _numbers(args, 4, line, name)[1:])
        elif name == "SET_G92_OFFSET":
            s.g92 = _offset(s, _numbers(args, 3, line, name))
        elif name == "SET_XY_ROTATION":
            s.rotation = _numbers(args, 1, line, name)[0]
        elif name == "USE_TOOL_LENGTH_OFFSET":
            s.tool = _offset(s, _numbers(args, 3, line, name))
        elif name == "SELECT_PLANE":
            s.plane = args
        elif name == "SET_MOTION_CONTROL_MODE":
            _path_control(s, args, line)
        elif name in REFUSED or name.startswith("NURBS"):
            reason = REFUSED.get(name, "NURBS feeds are not planned")
            raise ProgramError(line, f"{reason} ({name})")
        if len(moves) > count:
            s.tolerances.append(s.tolerance)
    return moves
