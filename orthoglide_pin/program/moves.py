"""The canonical moves of a part program: what the tool is asked to do, in SI units.

A :class:`Move` is one canonical motion of a program after the language has been
read (units, modes, work offsets, G92, tool length, canned cycles, subroutines):
a rapid, a straight feed, an arc or helix (LinuxCNC's ``ARC_FEED``: centre kept
as programmed, signed turns), or a dwell. Both readers of the package, the
built-in one and LinuxCNC's ``rs274`` interpreter bridge, produce these, so the
two can be compared move by move.

Points are in **machine coordinates of the program's axes** [m]: the
coordinates ``G53`` would name (after units, work offsets, ``G92`` and the tool
length), with the ISO 841 axes of the program (+Z moves the tool away from the
part). The machine's world frame is reached through the design's axis mapping
(:mod:`orthoglide_pin.program.axes`), not here: this layer knows nothing of the
machine.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: The kinds of move.
KINDS: Final = ("rapid", "line", "arc", "dwell")


@dataclass(frozen=True)
class Move:
    """One canonical move of a program.

    Attributes:
        line: Line of the program the move comes from (1 for the first).
        kind: One of :data:`KINDS`.
        start: Start point [m], shape (3,), machine coordinates, program axes.
        end: End point [m], shape (3,), same frame.
        feed: Programmed path speed [m/s]; ``None`` for a rapid or a dwell.
        center: Arc only: the centre [m], shape (3,), in the plane through the
            start point (its normal component is the start's).
        normal: Arc only: the unit normal of the arc's plane, shape (3,) (+Z for
            G17, +Y for G18, +X for G19); the arc turns counter-clockwise about
            it when ``turns`` > 0.
        turns: Arc only: signed turn count as LinuxCNC counts it: +1 for a G3
            of less than one turn, -1 for a G2, +-(P) with a ``P`` word; 0 for
            other moves.
        dwell: Dwell only: its duration [s].
    """

    line: int
    kind: str
    start: FloatArray
    end: FloatArray
    feed: float | None = None
    center: FloatArray | None = None
    normal: FloatArray | None = None
    turns: int = 0
    dwell: float = 0.0
