"""Design from a prescribed cubic workspace (paper, section 3.4; Chablat & Wenger 2003).

Inputs: the cube side ``Lw`` and bounds ``psi_min < 1 < psi_max`` on the
velocity transmission factors. Along the main diagonal ``P = (t, t, t)``, with
``s = sqrt(L^2 - 2 t^2)`` and ``r = t / s``, ``J`` is symmetric with factors
``1 / (1 + 2 r)`` (along (1, 1, 1)) and ``1 / (1 - r)`` (twice). Q2 (``t > 0``,
away from the sliders) and Q1 (``t < 0``) are the points where the first bound
is reached:

* ``r_2 = min((1 / psi_min - 1) / 2, 1 - 1 / psi_max)``,
* ``r_1 = max((1 / psi_max - 1) / 2, 1 - 1 / psi_min)``,

and ``t = L r / sqrt(1 + 2 r^2)``: both scale with ``L``, so the cube of side
``Lw = t_Q2 - t_Q1`` with Q1 and Q2 as opposite corners fixes the leg length.
The slider limits are the range of the slider values over the whole cube
(:func:`~orthoglide_pin.kinematics.closed_form.slider_range_over_cube`). The claim that the
bounds then hold in the whole cube is checked on a dense grid for every design,
and reported (:attr:`WorkspaceDesign.bounds_hold`), never assumed; and it is
proven over the continuum by :meth:`WorkspaceDesign.certify`
(:mod:`~orthoglide_pin.kinetostatics.certify`). Q1 and Q2 reach the bounds
exactly, so both use the package's one tolerance rule
(:mod:`~orthoglide_pin.machine.criterion`): the factors within the bounds to
1e-4. The designed machine carries its bounds as its criterion
(:meth:`WorkspaceDesign.to_params`), so ``orthoglide certify --config`` on its
file proves what ``orthoglide design`` proved.

For the paper's 200 mm cube and [0.5, 2] the method gives legs of 310.58 mm;
the paper's prototype has 310 mm (:func:`~orthoglide_pin.machine.params.prototype`),
whose factors over that cube are [0.4989, 2.0090] (:func:`prototype_note`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import slider_range_over_cube
from orthoglide_pin.kinematics.singularity import MAX_CONDITION
from orthoglide_pin.kinetostatics.certify import CERTIFY_TOL, Certification, certify_cube
from orthoglide_pin.kinetostatics.factor_range import grid_extremes
from orthoglide_pin.kinetostatics.transmission import transmission_factors
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.criterion import CRITERION_TOL, PAPER_BOUNDS, check_bounds, within
from orthoglide_pin.machine.params import (
    PROTOTYPE_CUBE_CORNER,
    PROTOTYPE_LEG_LENGTH,
    PROTOTYPE_WORKSPACE_SIDE,
    OrthoglideParams,
)
from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

FloatArray = NDArray[np.float64]

#: Points per edge of the verification grid (corners and Q1, Q2 included).
VERIFY_POINTS: Final[int] = 101
#: Largest verification grid, points per edge (201^3 = 8.1 M points, 0.2 GB of
#: factors): checked before anything is allocated.
MAX_VERIFY_POINTS: Final[int] = 201


@dataclass(frozen=True)
class WorkspaceDesign:
    """A machine designed for a prescribed cube, with its verification.

    Attributes:
        cube_side: Side ``Lw`` of the prescribed cube [m].
        psi_min: Lower bound on the transmission factors.
        psi_max: Upper bound on the transmission factors.
        leg_length: Leg length ``L`` [m].
        slider_limits: ``(lower, upper)`` slider values over the cube [m].
        stroke: ``upper - lower`` [m].
        ratio: ``Lw / stroke``.
        q1: Reference point Q1 on the slider side [m], shape (3,).
        q2: Reference point Q2 [m], shape (3,).
        cube_corner: Lowest corner of the cube (= Q1) [m], shape (3,).
        factors_q1: Transmission factors at Q1, ascending, shape (3,).
        factors_q2: Transmission factors at Q2, ascending, shape (3,).
        grid_points: Points per edge of the verification grid.
        psi_min_found: Smallest factor found on the grid.
        psi_min_at: Where [m], shape (3,).
        psi_max_found: Largest factor found on the grid (``inf`` if some grid
            point is unreachable or singular).
        psi_max_at: Where [m], shape (3,).
        bounds_hold: Whether the factors of the whole grid meet the bounds, to
            the package's tolerance (``psi_min - 1e-4 <= factors <= psi_max +
            1e-4``, :func:`~orthoglide_pin.machine.criterion.within`).
    """

    cube_side: float
    psi_min: float
    psi_max: float
    leg_length: float
    slider_limits: tuple[float, float]
    stroke: float
    ratio: float
    q1: FloatArray
    q2: FloatArray
    cube_corner: FloatArray
    factors_q1: FloatArray
    factors_q2: FloatArray
    grid_points: int
    psi_min_found: float
    psi_min_at: FloatArray
    psi_max_found: float
    psi_max_at: FloatArray
    bounds_hold: bool

    def to_params(self, base: OrthoglideParams | None = None) -> OrthoglideParams:
        """Parameters of the designed machine, ready for the description.

        ``base`` (default: the prototype's sizes and masses) with this leg
        length, this cube as the prescribed workspace (corner Q1, side) and
        these bounds as its criterion (``psi_min``, ``psi_max``); the slider
        limits are derived from the cube (equal to :attr:`slider_limits`), so
        that a file written from these parameters keeps deriving them.

        Raises:
            InvalidParameterError: If ``base`` cannot take them (the
                parameters require a leg longer than the largest slider
                excursion from home).
        """
        from orthoglide_pin.machine.params import prototype

        if base is None:
            base = prototype()
        base = instance_of("base", base, OrthoglideParams, "OrthoglideParams or None")
        return base.replace(
            leg_length=self.leg_length,
            workspace_corner=tuple(self.cube_corner.tolist()),
            workspace_side=self.cube_side,
            psi_min=self.psi_min,
            psi_max=self.psi_max,
            slider_lower=None,
            slider_upper=None,
        )

    def certify(self, tol: float = CERTIFY_TOL, **options: Any) -> Certification:
        """Prove the bounds over the whole cube (the continuum), to within ``tol``.

        The design method puts Q1 and Q2 exactly on the bounds, where a proof
        can have no margin; the cube is certified with the package's one rule
        (:func:`~orthoglide_pin.kinetostatics.certify.certify_cube`): every
        factor within ``[psi_min - tol, psi_max + tol]``, as ``orthoglide
        certify`` does for the machine of :meth:`to_params`. The
        certification's ``factor_bounds`` are the certified enclosure and its
        ``margin`` (``>= 0`` when certified) is measured to those widened bounds.

        Args:
            tol: Tolerance [-], positive: the widening of the bounds and the
                tolerance of the enclosure.
            **options: ``refine``, ``max_depth``, ``max_boxes`` of
                :func:`~orthoglide_pin.kinetostatics.certify.certify_cube`.
        """
        return certify_cube(
            self.leg_length,
            self.cube_corner,
            self.cube_side,
            self.psi_min,
            self.psi_max,
            tol=tol,
            **options,
        )

    def urdf(self, base: OrthoglideParams | None = None) -> str:
        """The URDF of the designed machine (see :meth:`to_params`)."""
        from orthoglide_pin.machine.description import render_urdf

        return render_urdf(self.to_params(base))

    def model(self, base: OrthoglideParams | None = None) -> ClosedLoopModel:
        """Render the URDF and load the closed-loop model of the designed machine."""
        from orthoglide_pin.machine.closed_loop import ClosedLoopModel

        return ClosedLoopModel(self.to_params(base))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (SI units; arrays as lists)."""
        out: dict[str, Any] = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            out[name] = value.tolist() if isinstance(value, np.ndarray) else value
        out["slider_limits"] = list(self.slider_limits)
        return out


def _number(name: str, value: float, allowed: str) -> float:
    """``value`` as a finite float, or :class:`InvalidParameterError`."""
    try:
        out = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, allowed)
    return out


def diagonal_ratios(psi_min: float, psi_max: float) -> tuple[float, float]:
    """``r = t / sqrt(L^2 - 2 t^2)`` at Q1 and Q2 for the given bounds (see the module)."""
    r1 = max((1.0 / psi_max - 1.0) / 2.0, 1.0 - 1.0 / psi_min)
    r2 = min((1.0 / psi_min - 1.0) / 2.0, 1.0 - 1.0 / psi_max)
    return r1, r2


def diagonal_factors(t: float, leg_length: float) -> tuple[float, float]:
    """The factors at ``(t, t, t)``: ``1 / (1 + 2 r)`` (along (1, 1, 1)) and ``1 / (1 - r)``."""
    r = t / math.sqrt(leg_length**2 - 2.0 * t * t)
    return 1.0 / (1.0 + 2.0 * r), 1.0 / (1.0 - r)


def design_from_workspace(
    side: float, psi_min: float, psi_max: float, *, grid_points: int = VERIFY_POINTS
) -> WorkspaceDesign:
    """Design the machine whose prescribed cube of side ``side`` keeps the bounds.

    Args:
        side: Cube side ``Lw`` [m], positive.
        psi_min: Lower bound on the transmission factors, in ``(0, 1)``.
        psi_max: Upper bound, greater than 1.
        grid_points: Points per edge of the verification grid, in
            ``[2, MAX_VERIFY_POINTS]``.

    Returns:
        The design and its verification on the grid.

    Raises:
        InvalidParameterError: A non-positive side, ``psi_min`` not in
            ``(0, 1)``, ``psi_max <= 1``, or ``psi_max / psi_min`` beyond
            ``MAX_CONDITION`` (a cube reaching near-singular points), or a
            derived leg length outside its plausible range
            (:data:`~orthoglide_pin.machine.ranges.PLAUSIBLE_RANGES`).
    """
    allowed = "a positive cube side [m]"
    lw = _number("side", side, allowed)
    if not lw > 0:
        raise InvalidParameterError("side", lw, allowed)
    lo, hi = check_bounds(psi_min, psi_max)
    if hi / lo > MAX_CONDITION:  # the indices refuse such points: so does the design
        raise InvalidParameterError(
            "psi_max / psi_min",
            hi / lo,
            f"at most {MAX_CONDITION:g}, the condition limit of the indices "
            "(orthoglide_pin.kinematics.singularity.MAX_CONDITION)",
        )
    if (
        isinstance(grid_points, bool)
        or not isinstance(grid_points, int)
        or not 2 <= grid_points <= MAX_VERIFY_POINTS
    ):
        raise InvalidParameterError(
            "grid_points", grid_points, f"an integer in [2, {MAX_VERIFY_POINTS}]"
        )
    r1, r2 = diagonal_ratios(lo, hi)
    f1, f2 = r1 / math.sqrt(1.0 + 2.0 * r1 * r1), r2 / math.sqrt(1.0 + 2.0 * r2 * r2)
    L = lw / (f2 - f1)
    low, high, _ = PLAUSIBLE_RANGES["leg_length"]
    if not low <= L <= high:  # also refuses an overflow to inf
        raise InvalidParameterError(
            "side",
            side,
            f"a cube whose design has a plausible leg length (here {L:.3g} m, outside "
            f"[{low:g}, {high:g}] m; the leg is {1.0 / (f2 - f1):.3g} times the side)",
        )
    t1, t2 = L * f1, L * f2
    corner = np.full(3, t1)
    limits = slider_range_over_cube(L, corner, lw)
    stroke = limits[1] - limits[0]
    # out of reach or singular: an infinite factor, a violation
    found_min, min_at, found_max, max_at = grid_extremes(L, corner, lw, grid_points)
    holds = bool(within(found_min, found_max, lo, hi, CRITERION_TOL))
    return WorkspaceDesign(
        cube_side=lw,
        psi_min=lo,
        psi_max=hi,
        leg_length=L,
        slider_limits=limits,
        stroke=stroke,
        ratio=lw / stroke,
        q1=corner,
        q2=np.full(3, t2),
        cube_corner=corner.copy(),
        factors_q1=transmission_factors(corner, L, check=False),
        factors_q2=transmission_factors(np.full(3, t2), L, check=False),
        grid_points=grid_points,
        psi_min_found=found_min,
        psi_min_at=min_at,
        psi_max_found=found_max,
        psi_max_at=max_at,
        bounds_hold=holds,
    )


def prototype_cube(params: OrthoglideParams) -> tuple[FloatArray, float]:
    """The prescribed cube of a machine as ``(corner, side)``: ``params.workspace``.

    The machine's own cube (``workspace_corner``, ``workspace_side``); for
    :func:`~orthoglide_pin.machine.params.prototype`, the paper's 200 mm cube
    with its lowest corner at ``-0.31 / sqrt(18)`` on each axis, kept when the
    leg length changes. Prefer :attr:`OrthoglideParams.workspace`.

    Returns:
        ``(corner, side)``: shape (3,) [m], and [m].
    """
    cube = as_params(params).workspace
    return cube.q1, cube.side


def prototype_note(params: OrthoglideParams) -> str | None:
    """Why the prototype's cube misses its criterion, or ``None`` for another machine.

    For a machine with the prototype's 310 mm legs, 200 mm cube and the paper's
    criterion [0.5, 2]: the paper rounded the leg that the design method gives
    for them (310.58 mm, computed here), so the factors over the cube reach
    [0.4989, 2.0090] instead (at Q2).

    Raises:
        InvalidParameterError: ``params`` is not an :class:`OrthoglideParams`.
    """
    instance_of("params", params, OrthoglideParams, "OrthoglideParams")
    cube = params.workspace
    if (
        params.leg_length != PROTOTYPE_LEG_LENGTH
        or cube.side != PROTOTYPE_WORKSPACE_SIDE
        or cube.corner != (PROTOTYPE_CUBE_CORNER,) * 3
        or (params.psi_min, params.psi_max) != PAPER_BOUNDS
    ):
        return None
    exact = design_from_workspace(cube.side, *PAPER_BOUNDS, grid_points=2).leg_length
    return (
        f"the prototype's {1e3 * params.leg_length:g} mm legs are the paper's rounding of the "
        f"{1e3 * exact:.2f} mm that the design method gives for this cube and "
        f"[{PAPER_BOUNDS[0]:g}, {PAPER_BOUNDS[1]:g}], so its factors slightly leave these bounds"
    )
