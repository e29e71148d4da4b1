"""Local tightening: the limits lowered only around where a plan exceeds them.

A plan holds the path acceleration constant between planning-grid points, so
between them (on the verification grid ten times finer,
:mod:`~orthoglide_pin.planning.verify`) a limit's use may exceed 1. The
section is then planned again with that limit tightened, but only on the
planning-grid points next to the fine samples where it is exceeded and
:data:`NEIGHBOURS` points on either side (more in later rounds): each factor
of :class:`~orthoglide_pin.planning.limits.Scales` becomes one per grid point,
divided there by the largest use found nearby (and :data:`MARGIN`). The rest
of the section keeps its untightened optimum, where a factor for the whole
section would slow it all for one short overshoot.

Local tightening may not settle (an overshoot moved from one interval to the
next, round after round). After its rounds, the planner falls back on a
slower plan that is safe: :func:`whole_section` lowers each exceeded limit on
the whole section by the overshoot and :data:`FALLBACK_MARGIN`, and the
:class:`Fallback` says where and what it cost.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.limits import Scales
from orthoglide_pin.planning.verify_compiled import intervals

FloatArray = NDArray[np.float64]

#: Planning-grid points tightened on either side of an exceeding interval (first round).
NEIGHBOURS: Final[int] = 1
#: Extra tightening beyond the measured overshoot [-].
MARGIN: Final[float] = 2e-4
#: Extra lowering of a whole section's limit when local tightening has not settled [-].
FALLBACK_MARGIN: Final[float] = 2e-3


@dataclass(frozen=True)
class Fallback:
    """A section planned slower because local tightening did not settle.

    Attributes:
        line: The program line where the limit was still exceeded.
        limit: The limit exceeded.
        use: Its worst use then [-].
        factor: The factor applied to it on the whole section [-].
        cost: The time the section lost to it [s].
    """

    line: int
    limit: str
    use: float
    factor: float
    cost: float

    def as_dict(self) -> dict[str, float | int | str]:
        """The fallback as JSON values (SI units)."""
        return {
            "line": self.line,
            "limit": self.limit,
            "use": self.use,
            "factor": self.factor,
            "cost": self.cost,
        }


def whole_section(scales: Scales, over: dict[str, float], applied: dict[str, float]) -> None:
    """Lower, in place, each exceeded limit on the whole section (see the module).

    Args:
        scales: The section's factors (updated).
        over: The worst use of each exceeded limit [-].
        applied: The whole-section factor applied so far to each limit (updated).
    """
    for name, use in over.items():
        factor = 1.0 / (use * (1.0 + FALLBACK_MARGIN))
        scales.factors[name] = np.asarray(scales.get(name) * factor)
        applied[name] = applied.get(name, 1.0) * factor


def interval_uses(grid: FloatArray, fine: FloatArray, use: FloatArray) -> FloatArray:
    """The largest use on each planning-grid interval, (n - 1,).

    Args:
        grid: The planning grid's arc lengths [m], (n,).
        fine: The verification grid's arc lengths [m], (m,), within ``grid``'s span.
        use: A limit's use at the fine samples [-], (m,).
    """
    n = grid.size
    raw = intervals(grid, fine)  # the last grid point at or before each sample
    idx = np.clip(raw, 0, n - 2)
    out = np.zeros(n - 1)
    np.maximum.at(out, idx, use)
    # a fine sample on a grid point belongs to both intervals (a point of grid[1:-1])
    inner = (raw >= 1) & ((raw <= n - 2) | (grid[n - 2] == fine))
    on = np.flatnonzero(inner & (grid[np.clip(raw, 0, n - 1)] == fine))
    np.maximum.at(out, np.clip(idx[on] - 1, 0, None), use[on])
    return out


def point_ratios(grid: FloatArray, fine: FloatArray, use: FloatArray, width: int) -> FloatArray:
    """The largest use within ``width`` intervals of each planning-grid point, (n,)."""
    per = interval_uses(grid, fine, use)
    n = grid.size
    out = np.zeros(n)
    for shift in range(-width, width):  # intervals i + shift touch point i for shift in [-w, w)
        lo, hi = max(0, -shift), min(n, n - 1 - shift)
        if hi > lo:
            out[lo:hi] = np.maximum(out[lo:hi], per[lo + shift : hi + shift])
    return out


def tighten(
    scales: Scales,
    uses: dict[str, FloatArray],
    grid: FloatArray,
    fine: FloatArray,
    tol: float,
    rounds: int,
) -> dict[str, float]:
    """Tighten, in place, each limit whose use exceeds ``1 + tol``, around where it does.

    Args:
        scales: The section's factors (updated).
        uses: Each limit's use at the fine samples [-], each (m,).
        grid: The planning grid's arc lengths [m], (n,).
        fine: The verification grid's arc lengths [m], (m,).
        tol: The use tolerated above 1 [-].
        rounds: Plans of the section made so far: the neighbourhood widens with them.

    Returns:
        The worst use of each limit that was exceeded (empty when none was).
    """
    over: dict[str, float] = {}
    width = 1 + NEIGHBOURS + max(rounds - 1, 0)  # intervals i - w .. i + w - 1 touch point i
    for name, use in uses.items():
        worst = float(use.max())
        if worst <= 1.0 + tol:
            continue
        over[name] = worst
        ratio = point_ratios(grid, fine, use, width)
        factor = np.where(ratio > 1.0, 1.0 / (ratio * (1.0 + MARGIN)), 1.0)
        scales.factors[name] = np.asarray(scales.get(name) * np.ones(grid.size)) * factor
    return over


def on_fine_grid(scales: Scales, grid: FloatArray, fine: FloatArray) -> Scales:
    """The factors at the fine samples: the lower of the two planning-grid points around each."""
    out: dict[str, float | FloatArray] = {}
    for name, f in scales.factors.items():
        if isinstance(f, float):
            out[name] = f
            continue
        i = np.clip(np.searchsorted(grid, fine, side="right") - 1, 0, grid.size - 2)
        out[name] = np.minimum(f[i], f[i + 1])
    return Scales(out)


def smallest(scales: Scales) -> dict[str, float]:
    """Each limit's smallest factor over the section."""
    return {name: float(np.min(f)) for name, f in scales.factors.items()}
