"""Metrics of one design of a sweep (:mod:`orthoglide_pin.sweep.spec`).

For a design (a dictionary of :meth:`~orthoglide_pin.sweep.spec.SweepSpec.designs`)
:func:`evaluate_design` builds the machine and its cube, then measures, all in
SI units:

* **cube and slider stroke**: ``cube_side`` [m] and ``cube_corner_*`` [m]
  (fixed cube, or the design method's cube Q1-Q2 in redesign mode), which
  becomes the machine's prescribed workspace; the slider limits
  ``slider_lower``, ``slider_upper`` [m] derived from it (the range of the
  slider values over the whole cube,
  :func:`~orthoglide_pin.kinematics.closed_form.slider_range_over_cube`), the
  ``stroke`` [m] and the compactness ``ratio = Lw / stroke``;
* **the largest certified cube of the bounds**: ``design_cube_side`` [m], the
  side of the largest cube, centred on the design method's cube for this leg
  and the bounds (Q1 and Q2 as opposite corners, side ``L (f2 - f1)``,
  :mod:`orthoglide_pin.kinetostatics.design`), where every point of the
  continuum is proven to have its factors within the bounds
  (:func:`~orthoglide_pin.kinetostatics.largest_cube.largest_certified_side`:
  bisection on the side to ``SIDE_RESOLUTION`` = 0.1 mm, interval arithmetic;
  about 0.1 s per design; the bounds to the package's tolerance, as
  ``orthoglide certify``). Where the design method's claim holds, it is the
  method's side to within 0.1 mm (the bounds are reached exactly at Q1 and Q2);
* **transmission factors over the cube**, on a ``grid^3`` grid (corners
  included): the bounds reached, ``psi_min_reached`` (smallest factor) and
  ``psi_max_reached`` (largest, ``inf`` if a grid point is singular);
  ``bounds_hold`` (both within ``[psi_min, psi_max]``, to the package's
  tolerance of 1e-4: :func:`~orthoglide_pin.machine.criterion.within`, as
  ``orthoglide certify`` and ``summary`` judge); ``in_bounds_fraction``, the
  share of grid points whose three factors are within the bounds; and the
  homogeneity, the condition number ``sigma_max / sigma_min`` (1 at home):
  ``condition_min``, ``condition_max``, ``condition_mean``, ``condition_std``;
* ``moving_mass`` [kg]: every moving body of the inertial model
  (:attr:`~orthoglide_pin.dynamics.inertia.InertiaTable.total_moving_mass`);
* **requirements**: ``max_slider_force`` [N] and ``max_motor_torque`` [N.m],
  the worst over the three sliders and over a coarser ``requirement_grid^3``
  grid of the cube of the exact worst case over every direction of a tool
  motion with ``|v| <= speed`` and ``|a| <= acceleration``, gravity
  ``(0, 0, +9.81)`` m/s^2 (:func:`~orthoglide_pin.dynamics.requirements.worst_case_over_cube`,
  the torque through the sweep's drive train; a conservative bound);
* **footprint**: the axis-aligned bounding box of the three rails and carriages
  over the whole stroke (:func:`footprint`): its sizes ``footprint_x``,
  ``footprint_y``, ``footprint_z`` [m], the floor area ``footprint_area =
  footprint_x * footprint_y`` [m^2] (e3 vertical, as on the prototype) and
  ``footprint_volume`` [m^3];
* **stiffness** of the tool tip (:mod:`orthoglide_pin.elasticity.stiffness`,
  actuators and links, the design's moduli, sections and actuator stiffness),
  on the ``requirement_grid^3`` grid of the cube: ``min_stiffness`` [N/m], the
  smallest eigenvalue of ``K`` over the grid (the softest direction at the
  worst point), ``centre_stiffness`` [N/m], the same at the cube's centre, and
  ``max_deflection`` [m], the deflection under
  :data:`~orthoglide_pin.elasticity.maps.DEFAULT_CUTTING_FORCE` (100 N)
  in the softest direction at the worst point (NaN when a grid point is
  singular or out of reach). Long bars are soft (a bar's
  bending compliance grows as ``L^3``); short legs work nearer their
  singularities: the leg-length trade-off;
* **a part program** (when the sweep has one, :mod:`~orthoglide_pin.sweep.program`):
  ``cycle_time`` [s] and ``binding_limit``, the program planned with the
  design's ``speed`` and ``acceleration`` as slider limits.
* ``lowest_frequency`` [Hz]: the lowest natural frequency over the same grid,
  from the platform model of :mod:`orthoglide_pin.elasticity.modes` with the
  sweep's drive train reflected onto the carriages (NaN when a grid point is
  singular or out of reach). That model has the first bending mode of each
  leg's bars bending together in their plane (which comes first with legs of
  0.7 m and more), not the bars' other bending nor the small links';
  ``orthoglide modes --model full`` has them all.

A design that cannot be built (a leg too short for its cube, bounds that do
not contain 1, a bad parameter) gives a row with ``status = "invalid"``, the
error message in ``error`` and NaN metrics; it never stops the sweep.
"""

from __future__ import annotations

import contextlib
import functools
import math
from collections.abc import Iterator, Mapping, Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import mapping
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.elasticity.maps import DEFAULT_CUTTING_FORCE, stiffness_map
from orthoglide_pin.elasticity.stiffness import cartesian_stiffness
from orthoglide_pin.exceptions import InvalidParameterError, OrthoglideError
from orthoglide_pin.kinetostatics.design import design_from_workspace, diagonal_ratios
from orthoglide_pin.kinetostatics.largest_cube import largest_certified_side
from orthoglide_pin.kinetostatics.workspace import cube_grid, transmission_factor_map
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.criterion import within
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.sweep.spec import design_key

FloatArray = NDArray[np.float64]

_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))
#: Keys every design must have (:meth:`~orthoglide_pin.sweep.spec.SweepSpec.designs`).
DESIGN_KEYS: Final = (
    "mode",
    "values",
    "params",
    "psi_min",
    "psi_max",
    "speed",
    "acceleration",
    "grid",
    "requirement_grid",
    "drive",
)


def footprint(params: OrthoglideParams) -> tuple[FloatArray, FloatArray]:
    """Bounding box of the rails and carriages over the whole stroke [m].

    Leg ``i``'s rail frame sits at ``home - (L + platform_offset +
    carriage_offset) e_i`` with axes ``(e_i, e_(i+1), e_(i+2))``, ``home =
    -tool_offset`` the platform centre at home (the description's geometry).
    In that frame the carriage box (``carriage_size``) slides from
    ``slider_lower`` to ``slider_upper`` along x, and the rail, of square
    section ``rail_size``, lies under it (``-z``) along the same span.

    Returns:
        ``(lower, upper)`` corners of the box in the world frame, shape (3,) each.
    """
    params = as_params(params)
    sx, sy, sz = params.carriage_size
    r = params.rail_size
    local_lo = np.array([params.slider_lower - sx / 2, -max(sy, r) / 2, -(sz / 2 + r)])
    local_hi = np.array([params.slider_upper + sx / 2, max(sy, r) / 2, sz / 2])
    home = -np.asarray(params.tool_offset, dtype=float)
    reach = params.leg_length + params.platform_offset + params.carriage_offset
    lower, upper = np.full(3, np.inf), np.full(3, -np.inf)
    for i, j, k in _CYCLIC:
        origin = home.copy()
        origin[i] -= reach
        for world, local in ((i, 0), (j, 1), (k, 2)):
            lower[world] = min(lower[world], origin[world] + local_lo[local])
            upper[world] = max(upper[world], origin[world] + local_hi[local])
    return lower, upper


def _finite(name: str, value: Any, allowed: str) -> float:
    """``value`` as a float allowed for ``name``, or :class:`InvalidParameterError`."""
    try:
        out = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and _check(name, out)):
        raise InvalidParameterError(name, value, allowed)
    return out


def _check(name: str, value: float) -> bool:
    if name == "psi_min":
        return 0.0 < value < 1.0
    if name == "psi_max":
        return value > 1.0
    return value > 0.0


def _cube(design: Mapping[str, Any], f1: float, f2: float) -> tuple[float, float, FloatArray]:
    """Leg length [m], cube side [m] and corner [m] of a design."""
    leg = design.get("leg_length")
    if design["mode"] == "fixed-cube":
        L = _finite("leg_length", leg, "a positive leg length [m]")
        side = _finite("cube_side", design["cube_side"], "a positive cube side [m]")
        corner = np.asarray(design["cube_corner"], dtype=float)
    elif leg is not None:
        L = _finite("leg_length", leg, "a positive leg length [m]")
        side, corner = L * (f2 - f1), np.full(3, L * f1)
    else:
        side = _finite("cube_side", design["cube_side"], "a positive cube side [m]")
        made = design_from_workspace(side, design["psi_min"], design["psi_max"], grid_points=2)
        L, corner = made.leg_length, made.cube_corner
    return L, side, corner


def _factor_metrics(
    L: float, corner: FloatArray, side: float, n: int, lo: float, hi: float
) -> dict[str, Any]:
    """Bounds reached, share within the bounds and condition numbers on the cube's grid."""
    factors = transmission_factor_map(cube_grid(corner, side, n), L).reshape(-1, 3)
    good = np.isfinite(factors).all(axis=1) & (factors[:, 0] > 0.0)
    inside = good & within(factors[:, 0], factors[:, 2], lo, hi)
    ok = factors[good]
    cond = ok[:, 2] / ok[:, 0]
    every = bool(good.all())
    reached_min = float(ok[:, 0].min()) if ok.size else math.nan
    reached_max = float(ok[:, 2].max()) if every else math.inf
    return {
        "psi_min_reached": reached_min,
        "psi_max_reached": reached_max,
        "bounds_hold": bool(inside.all()),
        "in_bounds_fraction": float(inside.mean()),
        "condition_min": float(cond.min()) if cond.size else math.nan,
        "condition_max": float(cond.max()) if every else math.inf,
        "condition_mean": float(cond.mean()) if cond.size else math.nan,
        "condition_std": float(cond.std()) if cond.size else math.nan,
    }


def _requirements(params: OrthoglideParams, design: Mapping[str, Any]) -> dict[str, float]:
    """Worst slider force [N] and motor torque [N.m] over the cube (coarse grid)."""
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.dynamics.requirements import worst_case_over_cube
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    worst = worst_case_over_cube(  # the machine's own cube: the report's numbers
        dyn,
        resolution=int(design["requirement_grid"]),
        v_max=design["speed"],
        a_max=design["acceleration"],
        drive=Drive(DriveTrain(**design["drive"])),
    )
    return {
        "max_slider_force": float(np.max(worst.max_force)),
        "max_motor_torque": float(np.max(worst.max_torque)),
    }


def _stiffness(params: OrthoglideParams, design: Mapping[str, Any]) -> dict[str, float]:
    """Softest-direction stiffness [N/m] over the cube and at its centre, worst deflection [m]."""
    cube = params.workspace
    grid = cube_grid(cube.q1, cube.side, int(design["requirement_grid"]))
    try:
        smap = stiffness_map(grid, params)
        centre = cartesian_stiffness(cube.center, params).min_stiffness()
    except OrthoglideError:  # a singular or unreachable point: no finite stiffness there
        return dict.fromkeys(("min_stiffness", "centre_stiffness", "max_deflection"), math.nan)
    return {
        "min_stiffness": float(smap.min_stiffness.min()),
        "centre_stiffness": float(centre),
        "max_deflection": float(DEFAULT_CUTTING_FORCE / smap.min_stiffness.min()),
    }


def _lowest_frequency(params: OrthoglideParams, design: Mapping[str, Any]) -> float:
    """Lowest natural frequency [Hz] over the cube (platform model, the sweep's drive)."""
    from orthoglide_pin.elasticity.modes import natural_frequencies

    cube = params.workspace
    grid = cube_grid(cube.q1, cube.side, int(design["requirement_grid"]))
    try:
        modes = natural_frequencies(params, grid.points(), DriveTrain(**design["drive"]), count=1)
    except OrthoglideError:  # a singular or unreachable point: no frequency there
        return math.nan
    return float(modes.lowest.min())


def _evaluate(design: Mapping[str, Any], row: dict[str, Any]) -> dict[str, Any]:
    """The metrics of a design; its derived parameters go into ``row`` at once."""
    lo = _finite("psi_min", design["psi_min"], "a lower bound in (0, 1)")
    hi = _finite("psi_max", design["psi_max"], "an upper bound > 1")
    r1, r2 = diagonal_ratios(lo, hi)
    f1, f2 = r1 / math.sqrt(1.0 + 2.0 * r1 * r1), r2 / math.sqrt(1.0 + 2.0 * r2 * r2)
    L, side, corner = _cube(design, f1, f2)
    row.update(_corner_columns(corner), leg_length=L, cube_side=side)
    params = OrthoglideParams.from_dict(
        {
            **design["params"],
            "leg_length": L,
            "workspace_corner": corner.tolist(),
            "workspace_side": side,
            "psi_min": lo,  # the criterion the design is judged by
            "psi_max": hi,
            "slider_lower": None,  # derived from the cube
            "slider_upper": None,
        }
    )
    lower, upper = params.slider_lower, params.slider_upper
    stroke = upper - lower
    out: dict[str, Any] = dict(
        slider_lower=lower,
        slider_upper=upper,
        stroke=stroke,
        ratio=side / stroke,
        design_cube_side=largest_certified_side(
            L, np.full(3, L * (f1 + f2) / 2), lo, hi, guess=L * (f2 - f1)
        ),
    )
    out.update(_factor_metrics(L, corner, side, int(design["grid"]), lo, hi))
    out["moving_mass"] = inertia_table(params).total_moving_mass
    out.update(_requirements(params, design))
    out.update(_stiffness(params, design))
    out["lowest_frequency"] = _lowest_frequency(params, design)
    if design.get("program") is not None:
        from orthoglide_pin.sweep.program import program_metrics

        out.update(program_metrics(params, design))
    box_lo, box_hi = footprint(params)
    size = box_hi - box_lo
    out.update({f"footprint_{a}": float(s) for a, s in zip("xyz", size, strict=True)})
    out["footprint_area"] = float(size[0] * size[1])
    out["footprint_volume"] = float(np.prod(size))
    return out


def _corner_columns(corner: Sequence[float] | FloatArray | None) -> dict[str, float]:
    values = [math.nan] * 3 if corner is None else [float(c) for c in corner]
    return {f"cube_corner_{a}": v for a, v in zip("xyz", values, strict=True)}


def evaluate_design(design: Mapping[str, Any]) -> dict[str, Any]:
    """One row of the table: the design's key, parameters and metrics (see the module).

    Args:
        design: A design of :meth:`~orthoglide_pin.sweep.spec.SweepSpec.designs`.

    Returns:
        The row, JSON-ready (Python floats, bools and strings); ``status`` is
        ``"ok"``, or ``"invalid"`` with the message in ``error``.
    """
    design = mapping("design", design, "a design of SweepSpec.designs() (a dict)")
    missing = [k for k in DESIGN_KEYS if k not in design]
    if missing:
        allowed = "a design of SweepSpec.designs(), with " + ", ".join(missing)
        raise InvalidParameterError("design", sorted(design), allowed)
    row: dict[str, Any] = {"key": design_key(design), "status": "ok", "error": ""}
    row["mode"] = design["mode"]
    row.update(design["values"])
    row.update({n: design.get(n) for n in ("leg_length", "cube_side")})
    row.update({n: design[n] for n in ("psi_min", "psi_max", "speed", "acceleration")})
    row.update(_corner_columns(design.get("cube_corner")))
    try:
        row.update(_evaluate(design, row))
    except OrthoglideError as exc:
        row.update(status="invalid", error=" ".join(str(exc).split()))
    return {k: (float(v) if isinstance(v, np.floating) else v) for k, v in row.items()}


def evaluate_designs(designs: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """:func:`evaluate_design` of each design, in order (one task of a sweep).

    BLAS runs on one thread meanwhile: a sweep is parallel over designs, and
    the rounding of a multi-threaded BLAS depends on its thread count, so one
    thread everywhere (this process, local workers, Dask workers) gives every
    row the same bits whatever ran it.
    """
    with _one_blas_thread():
        return [evaluate_design(d) for d in designs]


@functools.lru_cache(maxsize=1)
def _thread_pools() -> Any:
    """The thread pools of the loaded native libraries (found once: a scan of them)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextlib.contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Limit BLAS and OpenMP to one thread inside (threadpoolctl)."""
    with _thread_pools().limit(limits=1):
        yield


__all__ = ["evaluate_design", "evaluate_designs", "footprint"]
