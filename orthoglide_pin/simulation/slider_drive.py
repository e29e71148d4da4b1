"""The drive as the slider of the simulated machine sees it: force, inertia, friction, limits.

Each slider is driven by a ball screw (:mod:`orthoglide_pin.drives.motor`):
``k = 2 pi n / lead`` motor radians per metre of slider. The rotor and screw
inertia ``J`` and the motor friction (Coulomb ``T_c``, viscous ``b``) are
carried by the slider joint of the MJCF (:mod:`~orthoglide_pin.simulation.mjcf`)
as ``armature = J k^2`` [kg], ``frictionloss = T_c k`` [N] and
``damping = b k^2`` [N.s/m]. The screw's efficiency ``eta`` has no MJCF
counterpart; the simulation applies it exactly, as the motor-torque model of
the planner does (:func:`~orthoglide_pin.drives.motor.motor_demand`): with
``eta^s = eta`` while the motor drives the load and ``1 / eta`` while the load
back-drives it, the thrust on the carriage is
``F = eta^s (k T - J k^2 q'' - k T_f)``, which is the slider joint of the MJCF
with its armature, friction loss and damping multiplied by ``eta^s`` and the
actuator force ``eta^s k T`` (:func:`plant_terms`). The motor torque is
bounded by the peak torque and the speed-torque curve at the motor's speed
(:func:`available_torque`; none beyond the curve's last speed).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.drives.motor import RPM_PER_RAD_S, Drive, DriveTrain

FloatArray = NDArray[np.float64]


def slider_ratio(train: DriveTrain) -> float:
    """Motor radians per metre of slider, ``k = 2 pi n / lead`` [rad/m]."""
    return 2.0 * math.pi * train.gear_ratio / train.lead


def slider_force_limit(drive: Drive) -> float | None:
    """Largest slider force [N] the motor gives, ``eta k T_peak``; ``None`` without data.

    The peak torque is the motor's ``peak_torque``, else the top of its
    speed-torque curve.
    """
    motor = drive.motor
    if motor is None:
        return None
    peak = motor.peak_torque
    if peak is None and motor.speed_torque_curve is not None:
        peak = max(t for _, t in motor.speed_torque_curve)
    if peak is None:
        return None
    return drive.train.efficiency * slider_ratio(drive.train) * peak


def drive_terms(drive: Drive) -> dict[str, float | None]:
    """What the drive puts on each slider joint and actuator of the MJCF.

    Returns:
        ``armature`` [kg], ``frictionloss`` [N], ``damping`` [N.s/m] and
        ``force_limit`` [N] (``None``: no limit).
    """
    t, k = drive.train, slider_ratio(drive.train)
    return {
        "armature": t.reflected_inertia * k * k,
        "frictionloss": t.coulomb_torque * k,
        "damping": t.viscous_coefficient * k * k,
        "force_limit": slider_force_limit(drive),
    }


def available_torque(drive: Drive, motor_speed: ArrayLike) -> FloatArray:
    """Torque [N.m] the motor gives at speeds ``|w|`` [rad/s] (``inf`` without motor data)."""
    speeds, torques, peak = torque_curve(drive)
    w = np.abs(np.asarray(motor_speed, dtype=float))
    return np.asarray(np.minimum(np.interp(w, speeds, torques, right=0.0), peak))


def torque_curve(drive: Drive) -> tuple[FloatArray, FloatArray, float]:
    """The motor's speed-torque curve and peak torque, for :func:`numpy.interp`.

    Returns:
        ``(speeds, torques, peak)``: the curve's speeds [rad/s] and torques
        [N.m] and the peak torque [N.m] (``inf`` when not given); the torque
        available at ``|w|`` is ``min(interp(|w|, speeds, torques, right=0), peak)``
        (:func:`available_torque`). Without a curve, one flat segment of ``peak``.
    """
    motor = drive.motor
    peak = math.inf if motor is None or motor.peak_torque is None else motor.peak_torque
    if motor is None or motor.speed_torque_curve is None:
        return np.array([0.0, math.inf]), np.array([peak, peak]), peak
    curve = np.asarray(motor.speed_torque_curve, dtype=float)
    return curve[:, 0] / RPM_PER_RAD_S, curve[:, 1], peak


def efficiency_factor(train: DriveTrain, driving: ArrayLike) -> FloatArray:
    """``eta^s``: ``eta`` where the motor drives the load, ``1 / eta`` where it is back-driven."""
    eta = train.efficiency
    return np.where(np.asarray(driving, dtype=bool), eta, 1.0 / eta)


def plant_terms(drive: Drive, driving: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The slider joints' armature [kg], friction loss [N] and damping [N.s/m] under ``eta^s``.

    Args:
        drive: The drive.
        driving: Whether each motor drives its load, shape (3,).

    Returns:
        ``(armature, frictionloss, damping)``, each (3,): the MJCF's values times ``eta^s``.
    """
    terms = drive_terms(drive)
    e = efficiency_factor(drive.train, driving)
    return (
        e * float(terms["armature"] or 0.0),
        e * float(terms["frictionloss"] or 0.0),
        e * float(terms["damping"] or 0.0),
    )


def screw_input(
    drive: Drive, torque: ArrayLike, velocity: ArrayLike, acceleration: ArrayLike
) -> FloatArray:
    """The torque that enters the screw, ``T - J w' - T_c sign(w) - b w`` [N.m].

    Its sign times the slider's velocity tells whether the motor drives the load
    (``>= 0``) or is back-driven: the thrust ``F = eta^s k`` times it has its sign.

    Args:
        drive: The drive.
        torque: Motor torques [N.m], shape (..., 3).
        velocity: Slider velocities [m/s], same shape.
        acceleration: Slider accelerations [m/s^2], same shape.
    """
    t, k = drive.train, slider_ratio(drive.train)
    w = k * np.asarray(velocity, dtype=float)
    friction = t.coulomb_torque * np.sign(w) + t.viscous_coefficient * w
    return np.asarray(
        np.asarray(torque, dtype=float)
        - t.reflected_inertia * k * np.asarray(acceleration, dtype=float)
        - friction
    )


def feedforward_torque(
    drive: Drive,
    force: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    *,
    mass_scale: float = 1.0,
    friction_scale: float = 1.0,
    load: ArrayLike | None = None,
) -> FloatArray:
    """Motor torque [N.m] that makes the slider follow a motion under a load.

    ``T = F / (k eta^s) + J k q'' + T_c sign(w) + b w`` with ``w = k q'``: the
    inverse of the simulated drive, whose Coulomb friction is MuJoCo's
    ``frictionloss`` (a sign, not the planner's smoothed one).

    Args:
        drive: The drive the controller believes in.
        force: Thrusts on the carriages [N] (the closed-loop inverse dynamics),
            shape (..., 3).
        velocity: Slider velocities [m/s], same shape.
        acceleration: Slider accelerations [m/s^2], same shape.
        mass_scale: Factor on the inertial and gravity terms (a model error) [-].
        friction_scale: Factor on the friction terms (a model error) [-].
        load: Thrusts [N] that balance a known external load (the tool wrench),
            added to ``mass_scale * force`` unscaled, same shape; none by default.
    """
    t, k = drive.train, slider_ratio(drive.train)
    f = mass_scale * np.asarray(force, dtype=float)
    if load is not None:
        f = f + np.asarray(load, dtype=float)
    v = np.asarray(velocity, dtype=float)
    a = np.asarray(acceleration, dtype=float)
    w = k * v
    e = efficiency_factor(t, f * v >= 0.0)
    friction = t.coulomb_torque * np.sign(w) + t.viscous_coefficient * w
    return np.asarray(
        f / (k * e) + mass_scale * t.reflected_inertia * k * a + friction_scale * friction
    )
