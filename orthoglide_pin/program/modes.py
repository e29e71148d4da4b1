"""The modal state of a program being read, and the words it accepts.

G codes are keyed by ten times their number (``G59.3`` is 593). The tables say
what each accepted word does; :data:`REFUSED_G` names the G codes a 3-axis
milling program may write that this reader refuses, with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import MAX_SPEED

FloatArray = NDArray[np.float64]

#: Millimetres and inches in metres.
MM: Final[float] = 1e-3
INCH: Final[float] = 25.4e-3
#: Blending tolerance of ``G64`` without ``P`` [m].
DEFAULT_TOLERANCE: Final[float] = 0.01e-3
#: Range of a feed [m/s]: 0.06 mm/min to 60,000,000 mm/min (the speeds' cap of the package).
MIN_FEED: Final[float] = 1e-6
MAX_FEED: Final[float] = MAX_SPEED
#: Longest dwell (``G4 P``) [s].
MAX_DWELL: Final[float] = 3600.0
#: Largest program file read [bytes] (its size is checked before it is read).
MAX_PROGRAM_BYTES: Final[int] = 64_000_000

MOTION: Final = frozenset({0, 10, 20, 30})
CYCLES: Final = frozenset({730, 810, 820, 830, 840, 850, 860, 890})
PLANES: Final = {170: 17, 180: 18, 190: 19}
#: The plane's normal axis, and its two in-plane axes (first, second).
PLANE_AXES: Final = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}
SYSTEM_CODES: Final = (540, 550, 560, 570, 580, 590, 591, 592, 593)
#: G codes read and listed as ignored: they do not change the path.
IGNORED_G: Final = frozenset({400, 940, 960, 970, 171, 181, 191})
#: M codes read and listed as ignored.
IGNORED_M: Final = frozenset(
    {0, 1, 3, 4, 5, 7, 8, 9, 19, 48, 49, 50, 51, 52, 53, 60, 62, 63, 64, 65, 66, 67, 68}
    | {70, 71, 72, 73}
    | set(range(100, 200))
)
#: The words an M code of :data:`IGNORED_M` carries (M100-M199: P and Q).
M_ARGUMENTS: Final = {19: "RQP", 50: "P", 51: "P", 52: "P", 53: "P"} | {
    m: "PQLE" for m in (62, 63, 64, 65, 66, 67, 68)
}
END_M: Final = frozenset({2, 30})
NGC_M: Final = frozenset({98, 99})
#: Refused G codes: why.
REFUSED_G: Final = {
    410: "cutter radius compensation G41 needs the tool's radius: read the program through "
    "LinuxCNC's interpreter with a tool table",
    420: "cutter radius compensation G42 needs the tool's radius: read the program through "
    "LinuxCNC's interpreter with a tool table",
    411: "dynamic cutter radius compensation G41.1 needs LinuxCNC's interpreter",
    421: "dynamic cutter radius compensation G42.1 needs LinuxCNC's interpreter",
    870: "back boring G87 (spindle orientation) is not planned",
    880: "boring G88 (manual retract) is not planned",
    930: "inverse-time feed G93 is not planned (G94, units per minute)",
    950: "feed per revolution G95 is not planned (G94, units per minute)",
    330: "spindle-synchronised motion G33 is not planned",
    331: "rigid tapping G33.1 is not planned",
    760: "threading cycle G76 is not planned (a lathe cycle)",
    50: "splines G5 are not planned",
    51: "splines G5.1 are not planned",
    52: "NURBS G5.2 are not planned",
    432: "additional tool length offset G43.2 is not planned",
    520: "local offset G52 is not planned (use G10 L2 or G92)",
}


@dataclass
class State:
    """The modes and offsets while reading (lengths [m], machine coordinates).

    Attributes:
        pos: The spindle nose's position, machine coordinates.
        work: The nine work offsets.
        system: Index of the active work offset (0 is ``G54``).
        g92: The ``G92`` offset in force; ``g92_saved`` the one ``G92.3`` restores.
        tool_length: The tool length offset in force (``G43``), along program Z.
        tool: The tool in the spindle; ``selected``: the last ``T``.
        cycle: The sticky words of canned cycles (Z, R, P, Q, program units);
            ``cycle_level``: the initial level of the cycles in progress.
        mode_line: The first line that sets the path control (``G61``,
            ``G61.1`` or ``G64``), 0 before any does.
        rotation: Each work offset's rotation about Z [deg] (``G10 L2 R``).
    """

    pos: FloatArray
    work: FloatArray
    g28: FloatArray
    g30: FloatArray
    tools: dict[int, float]
    unit: float = MM
    absolute: bool = True
    arc_absolute: bool = False
    plane: int = 17
    motion: int | None = None
    feed: float | None = None
    tolerance: float | None = None
    mode_line: int = 0
    system: int = 0
    g92: FloatArray = field(default_factory=lambda: np.zeros(3))
    g92_saved: FloatArray = field(default_factory=lambda: np.zeros(3))
    tool_length: float = 0.0
    tool: int = 0
    selected: int | None = None
    retract_r: bool = False
    cycle: dict[str, float] = field(default_factory=dict)
    cycle_level: float | None = None
    rotation: FloatArray = field(default_factory=lambda: np.zeros(9))

    def rotated(self) -> tuple[FloatArray, FloatArray] | None:
        """``(R, base)`` of a rotated work offset (``G10 L2 R``), else ``None``.

        A point ``q`` of the program (work coordinates [m]) is then at
        ``R @ (q + g92) + base`` in machine coordinates, ``R`` the rotation
        about Z and ``base`` the work offset and tool length (as LinuxCNC).
        """
        angle = float(self.rotation[self.system])
        if angle == 0.0:
            return None
        t = np.radians(angle)
        c, s = float(np.cos(t)), float(np.sin(t))
        base = np.array(self.work[self.system], dtype=np.float64)
        base[2] += self.tool_length
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), base

    @property
    def inch(self) -> bool:
        """Whether the program is in inches (``G20``)."""
        return self.unit == INCH

    def offset(self) -> FloatArray:
        """Machine coordinates of the program's zero: work offset, G92, tool length."""
        out = np.array(self.work[self.system] + self.g92, dtype=np.float64)
        out[2] += self.tool_length
        return out

    def program_point(self) -> FloatArray:
        """The current point in the program's coordinates [program units]."""
        return np.asarray((self.pos - self.offset()) / self.unit, dtype=np.float64)
