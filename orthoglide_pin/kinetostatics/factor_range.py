"""The transmission factors over a machine's cube, and whether its criterion holds there.

:func:`factor_range` evaluates the three velocity transmission factors on a
regular grid of the machine's prescribed cube (corners and faces included) and
gives the smallest and the largest, where they are, and the verdict of the
machine's criterion with the package's one tolerance rule
(:func:`~orthoglide_pin.machine.criterion.within`): the quick look that
``orthoglide summary`` and ``orthoglide report`` show, so that a design file
whose cube breaks its criterion shows at once. The design method's grid check
(:func:`~orthoglide_pin.kinetostatics.design.design_from_workspace`) reads the
same extremes (:func:`grid_extremes`). On a design method's cube the extremes
lie at the corners Q1 and Q2 (the paper's claim, which the design checks), and
on the prototype's both at Q2, [0.4989, 2.0090]: corners that every grid holds.
:func:`~orthoglide_pin.kinetostatics.certify.certify` proves the verdict over
the continuum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import instance_of, positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.workspace import cube_grid, transmission_factor_map
from orthoglide_pin.machine.criterion import CRITERION_TOL, check_bounds, within
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Default points per edge of the grid (41^3 = 68,921 points, a few ms).
DEFAULT_GRID: Final[int] = 41
#: Largest grid, points per edge (201^3 = 8.1 M points, 0.2 GB of factors).
MAX_GRID: Final[int] = 201


@dataclass(frozen=True)
class FactorRange:
    """The factors over a cube's grid, judged by a criterion.

    Attributes:
        psi_min: Lower bound of the criterion.
        psi_max: Upper bound of the criterion.
        tolerance: Tolerance of the rule (the bounds widened by it).
        grid_points: Points per edge of the grid.
        lowest: Smallest factor on the grid (NaN if no point is reachable).
        lowest_at: Where [m], shape (3,).
        highest: Largest factor on the grid (``inf`` if a point is singular or
            out of reach).
        highest_at: Where [m], shape (3,) (such a point, if any).
        holds: Whether every point of the grid meets the criterion.
    """

    psi_min: float
    psi_max: float
    tolerance: float
    grid_points: int
    lowest: float
    lowest_at: FloatArray
    highest: float
    highest_at: FloatArray
    holds: bool

    @property
    def verdict(self) -> str:
        """``"holds"`` or ``"DOES NOT HOLD"``."""
        return "holds" if self.holds else "DOES NOT HOLD"

    def describe(self) -> str:
        """The range on its grid: ``[0.498888, 2.008957] on a 41^3 grid of the cube``."""
        shown = ", ".join(_number(v) for v in (self.lowest, self.highest))
        return f"[{shown}] on a {self.grid_points}^3 grid of the cube"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (strict: a non-finite extreme is ``None``)."""

        def plain(value: float) -> float | None:
            return value if math.isfinite(value) else None

        return {
            "psi_min": self.psi_min,
            "psi_max": self.psi_max,
            "tolerance": self.tolerance,
            "grid_points": self.grid_points,
            "lowest": plain(self.lowest),
            "lowest_at": self.lowest_at.tolist(),
            "highest": plain(self.highest),
            "highest_at": self.highest_at.tolist(),
            "holds": self.holds,
        }


def _number(value: float) -> str:
    return f"{value:.6f}" if math.isfinite(value) else ("none" if math.isnan(value) else "inf")


def grid_extremes(
    leg_length: float, corner: ArrayLike, side: float, grid_points: int
) -> tuple[float, FloatArray, float, FloatArray]:
    """The smallest and largest factor on a ``grid_points^3`` grid of a cube, and where.

    A point out of reach or singular counts as an infinite largest factor (it
    meets no criterion) and is left out of the smallest.

    Args:
        leg_length: Leg length ``L`` [m].
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        grid_points: Points per edge, corners included.

    Returns:
        ``(lowest, lowest_at, highest, highest_at)``: factors and points [m],
        shape (3,) each (``lowest`` is ``inf`` if no point is reachable).
    """
    grid = cube_grid(np.asarray(corner, dtype=np.float64), side, grid_points)
    factors = transmission_factor_map(grid, leg_length).reshape(-1, 3)
    bad = ~np.isfinite(factors).all(axis=1)
    lowest = np.where(bad, np.inf, factors[:, 0])
    highest = np.where(bad, np.inf, factors[:, 2])
    i_min, i_max = int(np.argmin(lowest)), int(np.argmax(highest))
    return float(lowest[i_min]), grid.point(i_min), float(highest[i_max]), grid.point(i_max)


def factor_range(
    params: OrthoglideParams,
    *,
    grid_points: int = DEFAULT_GRID,
    psi_min: float | None = None,
    psi_max: float | None = None,
    tol: float = CRITERION_TOL,
) -> FactorRange:
    """The factors over the machine's cube, on a grid, and its criterion's verdict there.

    Args:
        params: The machine: its leg length, its cube and, by default, its
            criterion (``psi_min``, ``psi_max``).
        grid_points: Points per edge of the grid, in ``[2, MAX_GRID]``.
        psi_min: Another lower bound (default: ``params.psi_min``).
        psi_max: Another upper bound (default: ``params.psi_max``).
        tol: Tolerance of the rule, positive and finite.

    Returns:
        The range and the verdict.

    Raises:
        InvalidParameterError: Bad parameters, grid, bounds or tolerance.
    """
    instance_of("params", params, OrthoglideParams, "OrthoglideParams")
    n = grid_points
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 2 <= n <= MAX_GRID:
        raise InvalidParameterError("grid_points", n, f"an integer in [2, {MAX_GRID}]")
    lo, hi = check_bounds(
        params.psi_min if psi_min is None else psi_min,
        params.psi_max if psi_max is None else psi_max,
    )
    tol = positive_number("tol", tol, "a positive tolerance")
    cube = params.workspace
    low, low_at, high, high_at = grid_extremes(params.leg_length, cube.q1, cube.side, int(n))
    return FactorRange(
        psi_min=lo,
        psi_max=hi,
        tolerance=tol,
        grid_points=int(n),
        lowest=low if math.isfinite(low) else math.nan,
        lowest_at=low_at,
        highest=high,
        highest_at=high_at,
        holds=bool(within(low, high, lo, hi, tol)),
    )


__all__ = ["DEFAULT_GRID", "MAX_GRID", "FactorRange", "factor_range", "grid_extremes"]
