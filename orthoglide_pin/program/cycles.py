"""Canned drilling cycles (G73, G81 to G86, G89) expanded as LinuxCNC 2.9 expands them.

In the XY plane (``G17``), with ``R`` the retract plane, ``Z`` the bottom of
the hole and ``L`` repeats (the reader turns a ``G18`` or ``G19`` cycle into
this frame: the plane's two axes, then the drilling axis, Y or X); the initial
level is the height where the cycle mode began (kept by the next cycle blocks,
until a move of another kind). At the start, if the initial level is below R,
the tool rises to R where it is. The clearance height is the initial level
(``G98``; R if that is higher) or R (``G99``). Then for each repeat: on the
first, from above R, a rapid in XY at the current height and down to R; else a
rapid in XY at the clearance height and down to R if that is higher; then the
cycle's own moves. With ``G91`` the X and Y words are increments added at each
repeat, ``R`` is measured from the initial level and ``Z`` from R. The cycles'
own moves (feed to the bottom ``z``, R plane ``r``, clearance ``c``):

* ``G81``: feed to z, rapid to c; ``G82``: with a dwell ``P`` [s] at z;
* ``G73``: feed down ``Q`` at a time, each peck followed by a rapid back up
  ``rapid_delta`` (0.010 inch, 0.254 mm), then to z, rapid to c; ``G83``: the
  same, but each peck rapids out to r and back down to ``rapid_delta`` above
  the last depth;
* ``G84``: feed to z, dwell (``P``, 0 by default), feed to c (the spindle's
  reversal is not modelled); ``G85``: feed to z, feed to r, rapid to c;
  ``G86``: feed to z, dwell, rapid to c; ``G89``: feed to z, dwell, feed to c.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Peck clearance of G73 and G83 [inch] (LinuxCNC's ``G83_RAPID_DELTA``).
RAPID_DELTA_INCH: Final[float] = 0.010
#: Most moves a cycle block may expand to.
MAX_MOVES: Final[int] = 1_000_000


@dataclass(frozen=True)
class Step:
    """One move of an expanded cycle (machine coordinates [m]).

    Attributes:
        kind: ``"rapid"``, ``"line"`` or ``"dwell"``.
        end: End point, shape (3,).
        dwell: Dwell time [s] (dwells only).
    """

    kind: str
    end: FloatArray
    dwell: float = 0.0


def expand_cycle(
    code: int,
    pos: FloatArray,
    holes: list[tuple[float, float]],
    r: float,
    bottom: float,
    *,
    initial: float,
    retract_r: bool,
    peck: float,
    dwell: float,
    rapid_delta: float,
) -> list[Step]:
    """The moves of one cycle block (see the module).

    Args:
        code: The cycle's G code times ten (730, 810 ... 890).
        pos: The tool's position at the start [m], shape (3,).
        holes: X, Y [m] of each repeat, in order.
        r: The retract plane's Z [m].
        bottom: The hole's bottom Z [m] (below ``r``).
        initial: The initial level's Z [m].
        retract_r: ``G99`` (retract to R) rather than ``G98``.
        peck: ``Q`` [m] (G73, G83), > 0.
        dwell: ``P`` [s] (G82, G84, G86, G89).
        rapid_delta: The pecks' clearance [m].

    Raises:
        ValueError: The expansion would exceed :data:`MAX_MOVES` moves.
    """
    steps: list[Step] = []
    x, y, current = float(pos[0]), float(pos[1]), float(pos[2])

    def go(kind: str, z: float) -> None:
        steps.append(Step(kind, np.array([x, y, z])))

    old = initial
    if old < r:
        go("rapid", r)
        old = current = r
    clear = r if retract_r else old
    if peck > 0.0 and code in (730, 830):
        per_hole = 3 * int((r - bottom) / peck + 2)
        if per_hole * len(holes) > MAX_MOVES:
            raise ValueError(f"more than {MAX_MOVES} moves")
    for n, (x, y) in enumerate(holes):
        if n == 0 and current > r:
            go("rapid", current)
            go("rapid", r)
        else:
            go("rapid", clear)
            if clear > r:
                go("rapid", r)
        if code in (730, 830):
            depth = r - peck
            while depth > bottom:
                go("line", depth)
                if code == 830:
                    go("rapid", r)
                go("rapid", depth + rapid_delta)
                depth -= peck
        go("line", bottom)
        if code in (820, 840, 860, 890):
            steps.append(Step("dwell", np.array([x, y, bottom]), dwell))
        if code == 850:
            go("line", r)
        go("line" if code in (840, 890) else "rapid", clear)
    return steps
