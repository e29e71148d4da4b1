"""The words of a block that set modes and offsets, in LinuxCNC's order.

Feed, tool change, plane, units, tool length (``G43 H``, ``G43.1``,
``G49``), work offset (``G54`` to ``G59.3``), path control (``G61``,
``G64``), distance modes (``G90``/``G91``, ``G90.1``/``G91.1``), retract mode
(``G98``/``G99``), then ``G10 L2``/``L20``, ``G28``/``G30`` (their moves: to
the waypoint, even where it is the current point, as LinuxCNC does, then to
the reference point), ``G28.1``/``G30.1`` and ``G92`` to ``G92.3``. Lengths
are kept in metres, so a change of units changes nothing already set.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import MAX_LENGTH
from orthoglide_pin.program.block import Block
from orthoglide_pin.program.modes import (
    CYCLES,
    DEFAULT_TOLERANCE,
    INCH,
    MAX_FEED,
    MIN_FEED,
    MM,
    PLANE_AXES,
    PLANES,
    SYSTEM_CODES,
    State,
)

FloatArray = NDArray[np.float64]


class RefusedError(Exception):
    """A refusal of the line being executed (its reason)."""


class _Mover(Protocol):
    def straight(self, line: int, kind: str, end: FloatArray) -> None: ...

    def target(self, b: Block) -> FloatArray: ...


def apply_settings(b: Block, s: State, mover: _Mover) -> None:
    """Set the modes and offsets of block ``b`` on ``s``, making G28/G30's moves.

    Raises:
        RefusedError: A word cannot be applied (a tool missing from the table ...).
    """
    unit = (INCH if 200 in b.gs else MM) if b.gs & {200, 210} else s.unit
    if "F" in b.values:
        f = b.values["F"]
        if not MIN_FEED <= f * unit / 60.0 <= MAX_FEED:
            raise RefusedError(
                f"feed F{f:g}: it must be > 0, from {MIN_FEED * 60.0 / unit:g} to "
                f"{MAX_FEED * 60.0 / unit:g} {'mm' if unit == MM else 'in'}/min "
                f"({MIN_FEED:g} to {MAX_FEED:g} m/s)"
            )
    if "T" in b.values:
        t = b.values["T"]
        if t != int(t) or t < 0:
            raise RefusedError(f"tool T{t:g}: a whole number >= 0")
        s.selected = int(t)
    if "M6" in b.values and s.selected is not None:
        s.tool = s.selected
    for code, plane in PLANES.items():
        if code in b.gs:
            s.plane = plane
    if b.gs & {171, 181, 191}:
        s.plane = 0
    if 200 in b.gs or 210 in b.gs:
        s.unit = INCH if 200 in b.gs else MM
    if "F" in b.values:
        s.feed = b.values["F"] * s.unit / 60.0
    _tool_length(b, s)
    for k, code in enumerate(SYSTEM_CODES):
        if code in b.gs:
            s.system = k
    if 610 in b.gs or 611 in b.gs:
        s.tolerance = None
    if 640 in b.gs:
        p = b.values.get("G64 P")
        if p is not None and not 0.0 <= p * s.unit <= MAX_LENGTH:
            raise RefusedError(f"G64 P{p:g}: the tolerance must be in [0, {MAX_LENGTH:g}] m")
        s.tolerance = DEFAULT_TOLERANCE if p is None else p * s.unit
    if b.gs & {610, 611, 640} and not s.mode_line:
        s.mode_line = b.line
    if 900 in b.gs or 910 in b.gs:
        s.absolute = 900 in b.gs
    if 901 in b.gs or 911 in b.gs:
        s.arc_absolute = 901 in b.gs
    if 980 in b.gs or 990 in b.gs:
        s.retract_r = 990 in b.gs
    if b.g53 and not s.absolute:
        raise RefusedError("G53 under incremental distance mode (G91)")
    _offsets(b, s, mover)
    if b.mode is not None:
        s.motion = None if b.mode == 800 else b.mode
    if b.motion in CYCLES:
        normal = PLANE_AXES.get(s.plane, (0, 1, 2))[2]  # the drilling axis: its depth
        given = {"Z": b.axes.get(normal)} | {k: b.values.get(f"cycle {k}") for k in "RPQ"}
        for letter, value in given.items():
            if value is not None:
                s.cycle[letter] = value


def _tool_length(b: Block, s: State) -> None:
    if 430 in b.gs:
        h = b.values.get("H", float(s.tool))
        if h != int(h) or h < 0:
            raise RefusedError(f"G43 H{h:g}: a tool number >= 0")
        if int(h) == 0:
            s.tool_length = 0.0
        elif int(h) not in s.tools:
            raise RefusedError(f"G43 H{int(h)}: tool {int(h)} is not in the tool table")
        else:
            s.tool_length = s.tools[int(h)]
    elif 431 in b.gs:
        s.tool_length = b.axes.get(2, 0.0) * s.unit
    elif 490 in b.gs:
        s.tool_length = 0.0


def _offsets(b: Block, s: State, mover: _Mover) -> None:
    if 100 in b.gs:
        level, p = b.values.get("G10 L"), b.values.get("G10 P", 0.0)
        if level not in (2.0, 20.0):
            shown = "without L" if level is None else f"L{level:g}"
            raise RefusedError(f"G10 {shown}: only G10 L2 and G10 L20 (work offsets) are read")
        if p != int(p) or not 0 <= p <= 9:
            raise RefusedError(f"G10 L{level:g} P{p:g}: P0 (the active offset) to P9 (G59.3)")
        k = s.system if p == 0 else int(p) - 1
        if "G10 R" in b.values:
            if level != 2.0:
                raise RefusedError("G10 L20 R: a rotation is set by G10 L2 R")
            s.rotation[k] = b.values["G10 R"]
        if level == 20.0 and s.rotated() is not None:
            raise RefusedError("G10 L20 under a rotated work offset (G10 L2 R) is not planned")
        for axis, value in b.axes.items():
            if level == 2.0:
                s.work[k, axis] = value * s.unit
            else:
                rest = s.g92[axis] + (s.tool_length if axis == 2 else 0.0)
                s.work[k, axis] = s.pos[axis] - rest - value * s.unit
    for code, attr in ((280, "g28"), (300, "g30")):
        if code in b.gs:
            home = getattr(s, attr)
            mover.straight(b.line, "rapid", mover.target(b))  # the waypoint, even without axes
            end = s.pos.copy()
            for axis in b.axes or (0, 1, 2):
                end[axis] = home[axis]
            mover.straight(b.line, "rapid", end)
    if 281 in b.gs:
        s.g28 = s.pos.copy()
    if 301 in b.gs:
        s.g30 = s.pos.copy()
    if 920 in b.gs:
        if not b.axes:
            raise RefusedError("G92 without an axis word")
        if s.rotated() is not None:
            raise RefusedError("G92 under a rotated work offset (G10 L2 R) is not planned")
        for axis, value in b.axes.items():
            rest = s.work[s.system, axis] + (s.tool_length if axis == 2 else 0.0)
            s.g92[axis] = s.pos[axis] - rest - value * s.unit
        s.g92_saved = s.g92.copy()
    if 921 in b.gs:
        s.g92 = np.zeros(3)
        s.g92_saved = np.zeros(3)
    if 922 in b.gs:
        s.g92 = np.zeros(3)
    if 923 in b.gs:
        s.g92 = s.g92_saved.copy()
