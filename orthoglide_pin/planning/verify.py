"""The plan checked again: every limit's use on a grid finer than the planning grid.

Each section's time law is evaluated on a grid :data:`REFINE` times finer than
its planning grid (which it contains), exactly between the planning points
(:meth:`~orthoglide_pin.planning.parametrize.SectionPlan.at_lengths`). The
tool motion ``v = p' s_dot``, ``a = p' s_ddot + p'' s_dot^2`` goes through the
closed-loop inverse dynamics
(:meth:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics.inverse_dynamics`,
:func:`evaluate_motion`) or, in a plan, the path forms evaluated at the fine
grid's own points (:func:`evaluate_forms`: one batch per path, which equals the
point-by-point inverse dynamics to rounding and serves every tightened plan of
the same path) and the drive model
(:func:`~orthoglide_pin.drives.motor.motor_demand`, with its exact efficiency
switch and friction); with numba, :func:`evaluate_forms` makes all of it one
compiled pass (:mod:`~orthoglide_pin.planning.verify_compiled`, the same
numbers). The **use** of a limit is the ratio of the value to the limit (1.0:
at the limit):

* ``slider_speed`` ``max_i |q'_i| / v``; ``slider_acceleration`` ``max_i |q''_i| / A``;
* ``slider_jerk`` ``max_i |q'''_i| / J`` (:func:`~orthoglide_pin.planning.jerk.jerk_use`);
* ``motor_torque`` ``max_i |T_i| / T_av(|w_i|)`` (peak torque and speed-torque curve);
* ``motor_speed`` ``max_i |w_i| / w_max``; ``feed`` ``s_dot / F``.

A limit **binds** where its use is at least :data:`BINDING` (the planner holds
``s_ddot`` constant over each grid interval, so a limit that bounds the motion
is reached at the grid points and may be a few per cent below it between
them); its share of the time is the time it binds over the cycle time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import motor_demand
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.calibrated import CalibratedKinematics, slider_motion
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import SectionPlan
from orthoglide_pin.planning.path import Samples
from orthoglide_pin.planning.reach_compiled import AVAILABLE as COMPILED
from orthoglide_pin.planning.verify_compiled import forms_motion

FloatArray = NDArray[np.float64]

#: Verification grid points per planning-grid interval.
REFINE: Final[int] = 10
#: Largest use accepted [-].
USE_TOL: Final[float] = 1e-3
#: A limit binds where its use is at least this [-].
BINDING: Final[float] = 0.95
#: The limits, in the order of the reports.
LIMIT_NAMES: Final = (
    "slider_speed",
    "slider_acceleration",
    "slider_jerk",
    "motor_torque",
    "motor_speed",
    "feed",
)


@dataclass(frozen=True)
class Motion:
    """The plan of a section evaluated at ``m`` samples (SI units).

    Attributes:
        t: Times from the section's start [s], (m,).
        s: Arc lengths [m], (m,). sd: Path speeds [m/s]. sdd: Path accelerations [m/s^2].
        p: Tool points [m], (m, 3).
        q, qd, qdd: Slider positions [m], speeds [m/s], accelerations [m/s^2], (m, 3).
        forces: Slider forces [N], (m, 3).
        torque: Motor torques [N.m], (m, 3), or ``None`` without a drive.
        speed: Motor speeds [rad/s], (m, 3), or ``None`` without a drive.
        uses: Use of each given limit at each sample [-], name -> (m,).
        qddd: Slider jerks [m/s^3], (m, 3), with a jerk limit
            (:mod:`~orthoglide_pin.planning.jerk`), else ``None``.
    """

    t: FloatArray
    s: FloatArray
    sd: FloatArray
    sdd: FloatArray
    p: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    forces: FloatArray
    torque: FloatArray | None
    speed: FloatArray | None
    uses: dict[str, FloatArray]
    qddd: FloatArray | None = None


def evaluate_motion(
    dyn: ClosedLoopDynamics,
    samples: Samples,
    t: FloatArray,
    sd: FloatArray,
    sdd: FloatArray,
    feed: FloatArray,
    limits: PlanLimits,
    *,
    wrench: FloatArray | None = None,
    gravity: FloatArray | None = None,
    calibration: CalibratedKinematics | None = None,
) -> Motion:
    """Inverse dynamics, motor demand and the use of every limit along samples of a path.

    Args:
        dyn: The closed-loop inverse dynamics.
        samples: The path at the samples.
        t: Times [s], (m,).
        sd: Path speeds [m/s], (m,).
        sdd: Path accelerations [m/s^2], (m,).
        feed: Path-speed cap at the samples [m/s] (``inf`` on rapid moves), (m,).
        limits: The limits.
        wrench: Tool wrench, as :meth:`ClosedLoopDynamics.inverse_dynamics`.
        gravity: Gravity [m/s^2], (3,).
        calibration: The slider commands come from this calibration's kinematics
            (:mod:`~orthoglide_pin.planning.calibrated`); the forces stay the drawing's.
    """
    vel = samples.dp * sd[:, None]
    acc = samples.dp * sdd[:, None] + samples.ddp * (sd * sd)[:, None]
    res = dyn.inverse_dynamics(samples.p, vel, acc, wrench=wrench, gravity=gravity)
    q, qd, qdd = res.slider_positions, res.slider_velocities, res.slider_accelerations
    if calibration is not None:
        q, qd, qdd = slider_motion(calibration, samples.p, vel, acc)
    return _motion(samples, t, sd, sdd, feed, limits, (q, qd, qdd, res.forces))


def evaluate_forms(
    forms: PathForms,
    samples: Samples,
    t: FloatArray,
    sd: FloatArray,
    sdd: FloatArray,
    feed: FloatArray,
    limits: PlanLimits,
    *,
    calibration: CalibratedKinematics | None = None,
) -> Motion:
    """:func:`evaluate_motion` from the path forms at the samples (one batch for any time law).

    The forms (:func:`~orthoglide_pin.dynamics.path_forms.path_forms`, equal to the
    point-by-point closed-loop inverse dynamics to rounding) depend on the path
    alone, so a plan verified again after a tightening reuses them.

    Args:
        forms: The path forms at the samples, with the tool wrench and gravity (the
            drawing's sliders: the calibrated ones come from ``calibration``).
        samples: The path at the samples.
        t: Times [s], (m,).
        sd: Path speeds [m/s], (m,).
        sdd: Path accelerations [m/s^2], (m,).
        feed: Path-speed cap at the samples [m/s] (``inf`` on rapid moves), (m,).
        limits: The limits.
        calibration: As :func:`evaluate_motion`.
    """
    if COMPILED and calibration is None and limits.drive is not None:
        done = _compiled(forms, samples, t, sd, sdd, feed, limits)
        if done is not None:
            return done
    s2 = (sd * sd)[:, None]
    forces = forms.a * sdd[:, None] + forms.b * s2 + forms.c
    if calibration is not None:
        vel = samples.dp * sd[:, None]
        acc = samples.dp * sdd[:, None] + samples.ddp * s2
        q, qd, qdd = slider_motion(calibration, samples.p, vel, acc)
    else:
        q, qd, qdd = forms.q, forms.dq * sd[:, None], forms.dq * sdd[:, None] + forms.ddq * s2
    return _motion(samples, t, sd, sdd, feed, limits, (q, qd, qdd, forces))


def _compiled(
    forms: PathForms,
    samples: Samples,
    t: FloatArray,
    sd: FloatArray,
    sdd: FloatArray,
    feed: FloatArray,
    limits: PlanLimits,
) -> Motion | None:
    """:func:`evaluate_forms` in one pass (:mod:`~orthoglide_pin.planning.verify_compiled`).

    ``None`` when a value is not finite: the array version then names it.
    """
    assert limits.drive is not None
    motor = limits.drive.motor
    peak, curve = (None, None) if motor is None else (motor.peak_torque, motor.speed_torque_curve)
    bounds = (limits.slider_speed, limits.slider_acceleration, limits.motor_speed)
    got = forms_motion(
        (forms.dq, forms.ddq, forms.a, forms.b, forms.c), sd, sdd, limits.drive.train, bounds,
        (peak, None if curve is None else np.asarray(curve), 1.0 - limits.torque_reserve),
    )  # fmt: skip
    if got is None:
        return None
    qd, qdd, forces, torque, speed, per = got
    uses: dict[str, FloatArray] = {}
    if limits.slider_speed is not None:
        uses["slider_speed"] = per[0]
    if limits.slider_acceleration is not None:
        uses["slider_acceleration"] = per[1]
    if limits.limits_torque:
        uses["motor_torque"] = per[2]
    if limits.motor_speed is not None:
        uses["motor_speed"] = per[3]
    _feed_use(uses, sd, feed)
    return Motion(t, samples.s, sd, sdd, samples.p, forms.q, qd, qdd, forces, torque, speed, uses)


def _feed_use(uses: dict[str, FloatArray], sd: FloatArray, feed: FloatArray) -> None:
    """The feed's use, into ``uses``, where some sample has a feed."""
    finite = np.isfinite(feed)
    if finite.any():
        uses["feed"] = np.where(finite, sd / np.where(finite, feed, 1.0), 0.0)


def _motion(
    samples: Samples,
    t: FloatArray,
    sd: FloatArray,
    sdd: FloatArray,
    feed: FloatArray,
    limits: PlanLimits,
    state: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
) -> Motion:
    """The motion and the use of each limit from the sliders' ``q, qd, qdd`` and forces."""
    q, qd, qdd, forces = state
    uses: dict[str, FloatArray] = {}
    if limits.slider_speed is not None:
        uses["slider_speed"] = np.abs(qd).max(axis=1) / limits.slider_speed
    if limits.slider_acceleration is not None:
        uses["slider_acceleration"] = np.abs(qdd).max(axis=1) / limits.slider_acceleration
    torque = speed = None
    if limits.drive is not None:
        demand = motor_demand(forces, qd, qdd, limits.drive.train)
        torque, speed = demand.torque, demand.speed
        w_max = limits.motor_speed
        if limits.limits_torque:
            # the curve read at the speed within its range: the speed's own use is below
            w = np.abs(speed) if w_max is None else np.minimum(np.abs(speed), w_max)
            avail = limits.available_torque(w)
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.where(avail > 0.0, np.abs(torque) / avail, np.inf)
            uses["motor_torque"] = ratio.max(axis=1)
        if w_max is not None:
            uses["motor_speed"] = np.abs(speed).max(axis=1) / w_max
    _feed_use(uses, sd, feed)
    return Motion(
        t,
        samples.s,
        sd,
        sdd,
        samples.p,
        q,
        qd,
        qdd,
        forces,
        torque,
        speed,
        uses,
    )


def check_section(
    dyn: ClosedLoopDynamics,
    fine: Samples,
    plan: SectionPlan,
    feed: FloatArray,
    limits: PlanLimits,
    *,
    wrench: FloatArray | None = None,
    gravity: FloatArray | None = None,
) -> Motion:
    """The section's plan evaluated on its fine grid ``fine`` (see the module)."""
    t, sd, sdd, _ = plan.at_lengths(fine.s)
    return evaluate_motion(dyn, fine, t, sd, sdd, feed, limits, wrench=wrench, gravity=gravity)


def time_weights(t: FloatArray) -> FloatArray:
    """The time each sample stands for [s]: half of each neighbouring interval, (m,)."""
    dt = np.diff(t)
    w = np.zeros_like(t)
    w[:-1] += 0.5 * dt
    w[1:] += 0.5 * dt
    return w


def worst_uses(motions: list[Motion]) -> dict[str, float]:
    """The largest use of each limit over the motions."""
    out: dict[str, float] = {}
    for m in motions:
        for name, use in m.uses.items():
            if use.size:
                out[name] = max(out.get(name, 0.0), float(use.max()))
    return out


def binding_time(motions: list[Motion]) -> dict[str, float]:
    """The time each limit binds [s] (see the module)."""
    out: dict[str, float] = {}
    for m in motions:
        w = time_weights(m.t)
        for name, use in m.uses.items():
            out[name] = out.get(name, 0.0) + float(w[use >= BINDING].sum())
    return out
