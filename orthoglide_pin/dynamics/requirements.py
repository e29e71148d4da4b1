"""Worst-case requirements at workspace points, over every direction of the tool motion.

The slider forces and motor load torques at a point are affine-quadratic forms
in the tool acceleration ``a`` and velocity ``v``
(:mod:`orthoglide_pin.dynamics.motion_forms`), so their worst case over
``|a| <= a_max`` and ``|v| <= v_max`` (every direction, independent bounds;
by default the paper's 1.2 m/s and 20 m/s^2) is in closed form.

What is exact and what is a bound:

* **Slider forces** (:attr:`WorstCase.force`) and **speeds**: exact.
* **Motor torques** (drive of :mod:`orthoglide_pin.drives.motor`, ratio
  ``r = l / (2 pi n)``, reflected inertia ``I``):
  ``T_i = s F_i + (I / r) q''_i + T_f(q'_i / r)``, with ``s = r / eta`` when
  the motor drives (``F q' >= 0``, rest included) and ``s = r eta`` when it is
  back-driven. The load part is a form for each ``s``, with an exact worst case;
  the bound takes the larger of the two cases. ``F`` and ``q''`` are even in
  ``v`` and ``q'`` is odd, so ``v`` or ``-v`` is a driving motion: the load part
  is attained when the driving case is the larger (:attr:`WorstCase.torque_exact`,
  the usual case) and conservative otherwise.
* **Friction** is bounded by its value at the largest slider speed at the point,
  ``v_max |b_i|`` (``b_i`` the row ``i`` of ``J^-1``), added with the sign of the
  load: a conservative bound (by at most the friction torque).

The inverse question (:class:`Guarantees`, with motor data), in the worst
direction at each point:

* the **tool speed** every slider follows within the motor's maximum speed,
  ``min_i q'_max / |b_i|`` (exact);
* the **tool acceleration** guaranteed in every direction, at rest and at any
  velocity up to ``v_max``: the largest ``A`` with ``A |mu_i| + beta_i + T_f <=
  T_available`` for every motor and efficiency case (only the driving one at
  rest), with ``mu_i`` the torque form's linear row, ``beta_i`` its worst
  velocity and constant part and ``T_available`` the peak torque capped by the
  speed-torque curve up to the motor's largest speed there. 0 where nothing is
  left. Built on the torque bound, these values are on the safe side.

Points must be within the machine's slider limits, as for ``orthoglide ik``:
a point the sliders cannot reach is refused (``check_limits=False`` computes
the forms there anyway, e.g. to study a cube larger than the stroke). The cube
of :func:`worst_case_over_cube` is by default the machine's prescribed cube
(:attr:`~orthoglide_pin.machine.params.OrthoglideParams.workspace`), the one
the ``report`` and ``sweep`` commands use, so the three give the same numbers.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    MAX_ACCELERATION,
    MAX_SPEED,
    bounded_number,
    finite_rows,
    flag,
    instance_of,
    integer,
    optional_callable,
)
from orthoglide_pin.drives.motor import RPM_PER_RAD_S, Drive, DriveTrain, MotorData
from orthoglide_pin.dynamics.motion_forms import (
    Machine,
    RequirementForms,
    as_dynamics,
    requirement_forms,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.workspace import Grid, cube_grid
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.motion.cycle import CYCLE_A_MAX, CYCLE_V_MAX

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Default tool speed of the worst case [m/s] (the paper's figure).
DEFAULT_V_MAX: Final[float] = CYCLE_V_MAX
#: Default tool acceleration of the worst case [m/s^2] (the paper's figure).
DEFAULT_A_MAX: Final[float] = CYCLE_A_MAX
#: Default points per edge of :func:`worst_case_over_cube` (corners included).
DEFAULT_CUBE_RESOLUTION: Final[int] = 11
#: Points per block (forms, bounds and guarantees held at once).
BLOCK_POINTS: Final[int] = 2048

Progress = Callable[[int], object]


def _limit(name: str, value: float) -> float:
    """``v_max`` in ``[0, MAX_SPEED]`` or ``a_max`` in ``[0, MAX_ACCELERATION]``."""
    if name == "v_max":
        return bounded_number(name, value, MAX_SPEED, "[m/s]", allow_zero=True)
    return bounded_number(name, value, MAX_ACCELERATION, "[m/s^2]", allow_zero=True)


@dataclass(frozen=True)
class Guarantees:
    """What the motors guarantee in every direction of the tool motion, per point.

    Each array has shape (N,); ``None`` when the motor data lack the datum.

    Attributes:
        speed: Largest tool speed every slider follows in every direction [m/s]
            (needs ``max_speed``).
        acceleration_at_rest: Largest tool acceleration in every direction from
            rest [m/s^2] (needs ``peak_torque`` or a speed-torque curve).
        acceleration_at_speed: Likewise at any velocity up to ``v_max`` [m/s^2].
    """

    speed: FloatArray | None
    acceleration_at_rest: FloatArray | None
    acceleration_at_speed: FloatArray | None


def available_torque(motor: MotorData, rpm: FloatArray) -> FloatArray | None:
    """Torque available over ``[0, rpm]``: peak torque capped by the curve's minimum [N.m]."""
    out = None if motor.peak_torque is None else np.full(rpm.shape, motor.peak_torque)
    if motor.speed_torque_curve is not None:
        speeds, torques = np.array(motor.speed_torque_curve).T
        low = np.interp(rpm, speeds, torques, right=0.0)
        for s, t in zip(speeds, torques, strict=True):
            low = np.where(rpm >= s, np.minimum(low, t), low)
        out = low if out is None else np.minimum(out, low)
    return out


def _guarantees(
    forms: RequirementForms,
    motor: MotorData | None,
    train: DriveTrain,
    v_max: float,
    friction: FloatArray,
) -> Guarantees:
    """The inverse question at the points of ``forms`` (see the module)."""
    if motor is None:
        return Guarantees(None, None, None)
    rows = np.linalg.norm(forms.inverse_jacobian, axis=-1)
    speed = None
    if motor.max_speed is not None:
        limit = motor.max_speed / (RPM_PER_RAD_S * train.motor_speed(1.0))  # slider [m/s]
        speed = np.asarray(np.min(limit / rows, axis=1))
    accels: list[FloatArray | None] = []
    for v, f, cases in ((0.0, 0.0 * friction, 1), (v_max, friction, 2)):
        available = available_torque(motor, train.motor_speed(v * rows) * RPM_PER_RAD_S)
        if available is None:
            accels.append(None)
            continue
        best = np.full(rows.shape[0], np.inf)
        for form in forms.torques(train)[:cases]:  # at rest the motor drives
            lower, upper = form.bounds(v, 0.0)
            slope = np.linalg.norm(form.linear, axis=-1)
            with np.errstate(divide="ignore"):
                room = (available - np.maximum(upper, -lower) - f) / slope
            best = np.minimum(best, np.min(room, axis=1))
        accels.append(np.maximum(best, 0.0))
    return Guarantees(speed, accels[0], accels[1])


#: The fields of :class:`WorstCase` that :meth:`WorstCase.peak` reads.
PEAK_FIELDS: Final = ("force", "torque", "slider_speed", "motor_speed_rpm")
#: The fields of :class:`WorstCase` that are not one value per point.
_NOT_PER_POINT: Final = frozenset({"v_max", "a_max", "guarantees", "drive", "grid"})


@dataclass(frozen=True)
class WorstCase:
    """Worst-case requirements over every direction, at ``N`` points (see the module).

    Per-point arrays have shape (N, 3): one column per slider (or motor).

    Attributes:
        points: Tool points [m], shape (N, 3).
        v_max: Tool speed bound [m/s].
        a_max: Tool acceleration bound [m/s^2].
        force_min: Smallest slider force [N] (exact).
        force_max: Largest slider force [N] (exact).
        force: Largest ``|F_i|`` [N] (exact).
        torque: Bound on the largest ``|T_i|`` [N.m], friction included.
        torque_exact: Whether the load part of ``torque`` is attained (driving case).
        friction: Friction torque bound at the largest motor speed [N.m].
        slider_speed: Largest ``|q'_i|`` [m/s] (exact).
        motor_speed_rpm: Largest motor speed [rpm] (exact).
        guarantees: The inverse question, with motor data.
        drive: The drive used.
        grid: The grid of the points (C order), if they came from one.
    """

    points: FloatArray
    v_max: float
    a_max: float
    force_min: FloatArray
    force_max: FloatArray
    force: FloatArray
    torque: FloatArray
    torque_exact: BoolArray
    friction: FloatArray
    slider_speed: FloatArray
    motor_speed_rpm: FloatArray
    guarantees: Guarantees
    drive: Drive
    grid: Grid | None = None

    def peak(self, name: str) -> tuple[FloatArray, FloatArray]:
        """Largest value of a per-point field over the points, per column, and where.

        Args:
            name: ``"force"``, ``"torque"``, ``"slider_speed"`` or ``"motor_speed_rpm"``.

        Returns:
            ``(values (3,), points (3, 3) [m])``.
        """
        if not isinstance(name, str) or name not in PEAK_FIELDS:
            raise InvalidParameterError("name", name, "one of " + ", ".join(PEAK_FIELDS))
        values = np.asarray(getattr(self, name))
        idx = np.argmax(values, axis=0)
        return values[idx, np.arange(3)], self.points[idx]

    @property
    def max_force(self) -> FloatArray:
        """Largest ``|F_i|`` over the points [N], shape (3,)."""
        return self.peak("force")[0]

    @property
    def max_force_at(self) -> FloatArray:
        """Where [m], one row per slider, shape (3, 3)."""
        return self.peak("force")[1]

    @property
    def max_torque(self) -> FloatArray:
        """Largest ``|T_i|`` bound over the points [N.m], shape (3,)."""
        return self.peak("torque")[0]

    @property
    def max_torque_at(self) -> FloatArray:
        """Where [m], one row per motor, shape (3, 3)."""
        return self.peak("torque")[1]

    def grid_field(self, name: str) -> FloatArray:
        """A per-point field reshaped to the grid, ``(nx, ny, nz, ...)``."""
        if self.grid is None:
            raise InvalidParameterError("grid", None, "a WorstCase computed on a grid")
        own = [f.name for f in fields(self) if f.name not in _NOT_PER_POINT]
        names = own + [f.name for f in fields(self.guarantees)]
        if not isinstance(name, str) or name not in names:
            raise InvalidParameterError("name", name, "one of " + ", ".join(names))
        values = getattr(self, name) if name in own else getattr(self.guarantees, name)
        if values is None:
            raise InvalidParameterError(name, None, "a field computed (motor data given)")
        arr = np.asarray(values)
        return arr.reshape(*self.grid.shape, *arr.shape[1:])

    def to_dict(self) -> dict[str, Any]:
        """Maxima and their locations (JSON-ready, SI units)."""
        out: dict[str, Any] = {"v_max": self.v_max, "a_max": self.a_max, "points": len(self)}
        for name in ("force", "torque", "slider_speed", "motor_speed_rpm"):
            values, where = self.peak(name)
            out[name] = {"max": values.tolist(), "at": where.tolist()}
        out["torque_exact_at_max"] = self.torque_exact[
            np.argmax(self.torque, axis=0), np.arange(3)
        ].tolist()
        for name in ("speed", "acceleration_at_rest", "acceleration_at_speed"):
            g = getattr(self.guarantees, name)
            if g is not None:
                i = int(np.argmin(g))
                out[f"guaranteed_{name}"] = {"min": float(g[i]), "at": self.points[i].tolist()}
        return out

    def __len__(self) -> int:
        return int(self.points.shape[0])


def worst_case_requirements(
    machine: Machine,
    points: ArrayLike,
    v_max: float = DEFAULT_V_MAX,
    a_max: float = DEFAULT_A_MAX,
    drive: Drive | None = None,
    *,
    wrench: ArrayLike | None = None,
    gravity: ArrayLike | None = None,
    progress: Progress | None = None,
    grid: Grid | None = None,
    check_limits: bool = True,
) -> WorstCase:
    """Worst-case slider forces and motor torques at tool points (block by block).

    Args:
        machine: Inverse dynamics, a closed-loop model, parameters, or ``None``
            for the prototype.
        points: Tool points [m], shape (N, 3) or (3,).
        v_max: Bound on the tool speed [m/s], in every direction.
        a_max: Bound on the tool acceleration [m/s^2], in every direction.
        drive: The drive (default: the default drive train, no motor data).
        wrench: Constant external wrench on the tool (force [N], moment [N.m]).
        gravity: Gravity [m/s^2]; the dynamics' default when ``None``.
        progress: Called with the number of points done after each block.
        grid: The grid the points come from, kept for :meth:`WorstCase.grid_field`.
        check_limits: Refuse points beyond the slider limits (see the module).

    Returns:
        The worst case (and, with motor data, the guarantees).

    Raises:
        UnreachablePointError: A point beyond the slider limits (with
            ``check_limits``) or out of reach of a leg.
    """
    dyn, p = as_dynamics(machine), finite_rows("points", points, 3, "[m]")
    progress = optional_callable("progress", progress, "a function of the points done, or None")
    if flag("check_limits", check_limits):
        check_slider_limits(dyn.closed_loop.params, p)
    v, a = _limit("v_max", v_max), _limit("a_max", a_max)
    drive = (
        Drive() if drive is None else instance_of("drive", drive, Drive, "a Drive (load_drive)")
    )
    parts: dict[str, list[FloatArray]] = {}
    for start in range(0, p.shape[0], BLOCK_POINTS):
        forms = requirement_forms(  # the limits were checked above, once
            dyn,
            p[start : start + BLOCK_POINTS],
            wrench=wrench,
            gravity=gravity,
            check_limits=False,
        )
        f_lo, f_hi = forms.forces.bounds(v, a)
        driving, back = (
            np.maximum(-lo, hi) for lo, hi in (t.bounds(v, a) for t in forms.torques(drive.train))
        )
        if v == 0.0:  # at rest the motor drives
            back = driving
        speed = forms.slider_speed(v)
        friction = drive.train.friction(drive.train.motor_speed(speed))
        g = _guarantees(forms, drive.motor, drive.train, v, friction)
        block = {
            "force_min": f_lo,
            "force_max": f_hi,
            "force": np.maximum(-f_lo, f_hi),
            "torque": np.maximum(driving, back) + friction,
            "torque_exact": driving >= back,
            "friction": friction,
            "slider_speed": speed,
            "motor_speed_rpm": drive.train.motor_speed(speed) * RPM_PER_RAD_S,
        }
        for key in ("speed", "acceleration_at_rest", "acceleration_at_speed"):
            if getattr(g, key) is not None:
                block[key] = getattr(g, key)
        for key, value in block.items():
            parts.setdefault(key, []).append(value)
        if progress is not None:
            progress(forms.points.shape[0])
    out = {k: np.concatenate(vals) for k, vals in parts.items()}
    guarantees = Guarantees(
        *(out.pop(k, None) for k in ("speed", "acceleration_at_rest", "acceleration_at_speed"))
    )
    return WorstCase(p, v, a, guarantees=guarantees, drive=drive, grid=grid, **out)  # type: ignore[arg-type]


def worst_case_on_grid(machine: Machine, grid: Grid, **kwargs: Any) -> WorstCase:
    """:func:`worst_case_requirements` at every point of ``grid`` (C order; same keywords)."""
    instance_of("grid", grid, Grid, "a Grid (cube_grid or slice_grid)")
    return worst_case_requirements(machine, grid.points().reshape(-1, 3), grid=grid, **kwargs)


def worst_case_over_cube(
    machine: Machine = None,
    corner: ArrayLike | None = None,
    side: float | None = None,
    *,
    resolution: int = DEFAULT_CUBE_RESOLUTION,
    **kwargs: Any,
) -> WorstCase:
    """Worst case on a ``resolution^3`` grid of a cube (corners included).

    Args:
        machine: Inverse dynamics, a closed-loop model, parameters, or ``None``
            for the prototype.
        corner: Lowest corner [m], shape (3,); by default the machine's
            prescribed cube (``params.workspace``).
        side: Side [m]; likewise.
        resolution: Points per edge (>= 2).
        **kwargs: ``v_max``, ``a_max``, ``drive``, ``wrench``, ``gravity``,
            ``progress``, ``check_limits``.

    Returns:
        The worst case on the grid: :attr:`WorstCase.max_force`,
        :attr:`WorstCase.max_torque` and their locations give the maxima over the cube.
    """
    dyn = as_dynamics(machine)
    cube = dyn.closed_loop.params.workspace
    grid = cube_grid(
        cube.q1 if corner is None else corner,
        cube.side if side is None else side,
        integer("resolution", resolution, 2),
    )
    return worst_case_on_grid(dyn, grid, **kwargs)
