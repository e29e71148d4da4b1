"""Sizing of the drives over a cycle: per-motor statistics, margins and verdict.

From the motor demand of :func:`orthoglide_pin.drives.motor.motor_demand` along a
cycle (a trajectory sampled in time), each motor gets its peak and RMS torque,
peak speed and peak power (:func:`cycle_statistics`). With motor data
(:class:`orthoglide_pin.drives.motor.MotorData`) they are compared with the rated and
peak torques, the maximum speed and the speed-torque curve
(:func:`check_motor`): a margin is ``1 - required / available``, the share of
the motor's capacity left, and the cycle passes when no margin is negative.
A safety factor ``k >= 1`` multiplies the required torques (RMS, peak, and
every sample against the speed-torque curve) before they are compared; the
speeds are compared as they are.
:func:`size_drives` chains it all from an inverse-dynamics result.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import float_array, instance_of
from orthoglide_pin.drives.motor import Drive, MotorData, MotorDemand, motor_demand
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]


def safety_factor_value(value: float) -> float:
    """A safety factor: a finite number ``>= 1``, or InvalidParameterError."""
    try:
        out = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and out >= 1.0):
        raise InvalidParameterError(
            "safety_factor", value, "a finite number >= 1 (it multiplies the required torques)"
        )
    return out


#: What :func:`size_drives` reads of an inverse-dynamics result.
_MOTION = ("forces", "slider_velocities", "slider_accelerations")


class SliderMotion(Protocol):
    """Slider forces and motion along a cycle, each shape (N, 3).

    :class:`orthoglide_pin.dynamics.inverse.DynamicsResult` is one; the drives
    need nothing else of the dynamics.
    """

    @property
    def forces(self) -> FloatArray:
        """Slider forces [N]."""

    @property
    def slider_velocities(self) -> FloatArray:
        """Slider speeds [m/s]."""

    @property
    def slider_accelerations(self) -> FloatArray:
        """Slider accelerations [m/s^2]."""


@dataclass(frozen=True)
class CycleStatistics:
    """Per-motor figures over a cycle, each shape (3,).

    Attributes:
        peak_torque: ``max |T|`` [N.m].
        rms_torque: Root mean square torque over the duration [N.m].
        peak_speed_rpm: ``max |w_m|`` [rpm].
        peak_power: ``max |T w_m|`` [W].
    """

    peak_torque: FloatArray
    rms_torque: FloatArray
    peak_speed_rpm: FloatArray
    peak_power: FloatArray


def cycle_statistics(demand: MotorDemand, time: ArrayLike | None = None) -> CycleStatistics:
    """Peak and RMS torque, peak speed and power of each motor over a cycle.

    Args:
        demand: The motor demand along the cycle.
        time: Sample times [s], shape (N,), increasing; the RMS is then
            ``sqrt(int T^2 dt / duration)`` (trapezoidal rule). Without it the
            samples are taken as evenly spaced: ``sqrt(mean(T^2))``.

    Returns:
        The statistics.

    Raises:
        InvalidParameterError: ``time`` not increasing or of the wrong size.
    """
    T = instance_of("demand", demand, MotorDemand, "a MotorDemand (motor_demand)").torque
    if time is None:
        rms = np.sqrt(np.mean(T * T, axis=0))
    else:
        t = float_array(time)
        if t.shape != (T.shape[0],) or T.shape[0] < 2 or not (np.diff(t) > 0.0).all():
            raise InvalidParameterError("time", t.shape, f"{T.shape[0]} increasing times [s]")
        sq = T * T
        integral = np.sum(0.5 * (sq[1:] + sq[:-1]) * np.diff(t)[:, None], axis=0)
        rms = np.sqrt(integral / (t[-1] - t[0]))
    return CycleStatistics(
        peak_torque=np.max(np.abs(T), axis=0),
        rms_torque=rms,
        peak_speed_rpm=np.max(np.abs(demand.speed_rpm), axis=0),
        peak_power=np.max(np.abs(demand.power), axis=0),
    )


@dataclass(frozen=True)
class MotorCheck:
    """Margins of each motor against its data, and the verdict.

    A margin is ``1 - required / available``: the share of the motor's
    capacity left (0: at the limit, negative: exceeded). Checks without data
    are absent.

    Attributes:
        margins: Per check (``rms_torque``, ``peak_torque``, ``speed``,
            ``speed_torque_curve``), the margin of each motor, shape (3,).
        passed: Every margin of every motor is ``>= 0``.
    """

    margins: dict[str, FloatArray]
    passed: bool

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (a margin of ``-inf``, torque needed where none is left, is None)."""
        return {
            "margins": {
                k: [float(x) if math.isfinite(x) else None for x in v]
                for k, v in self.margins.items()
            },
            "passed": self.passed,
        }


def check_motor(
    motor: MotorData,
    stats: CycleStatistics,
    demand: MotorDemand | None = None,
    *,
    safety_factor: float = 1.0,
) -> MotorCheck:
    """Compare a cycle with the motor data.

    Args:
        motor: The motor data.
        stats: Cycle statistics.
        demand: The samples, for the speed-torque curve check (skipped without).
        safety_factor: Multiplies the required torques (RMS, peak, samples),
            ``>= 1``; speeds are not multiplied.

    Returns:
        Margins and verdict (see :class:`MotorCheck`).

    Raises:
        InvalidParameterError: A safety factor below 1 or not finite.
    """
    instance_of("motor", motor, MotorData, "MotorData")
    instance_of("stats", stats, CycleStatistics, "CycleStatistics (cycle_statistics)")
    if demand is not None:
        instance_of("demand", demand, MotorDemand, "a MotorDemand (motor_demand) or None")
    k = safety_factor_value(safety_factor)
    margins: dict[str, FloatArray] = {}
    for key, required, available in (
        ("rms_torque", k * stats.rms_torque, motor.rated_torque),
        ("peak_torque", k * stats.peak_torque, motor.peak_torque),
        ("speed", stats.peak_speed_rpm, motor.max_speed),
    ):
        if available is not None:
            margins[key] = 1.0 - required / available
    if motor.speed_torque_curve is not None and demand is not None:
        sp, tq = np.array(motor.speed_torque_curve).T
        avail = np.interp(np.abs(demand.speed_rpm), sp, tq, right=0.0)
        need = k * np.abs(demand.torque)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(need > 0.0, need / avail, 0.0)
        margins["speed_torque_curve"] = 1.0 - np.max(ratio, axis=0)
    passed = all(bool((m >= 0.0).all()) for m in margins.values())
    return MotorCheck(margins, passed)


@dataclass(frozen=True)
class DriveSizing:
    """The drives along one cycle.

    Attributes:
        drive: The drive (drive train and optional motor data).
        demand: Motor torques, speeds and powers at every sample.
        statistics: Per-motor peak and RMS figures.
        check: Margins and verdict, or ``None`` without motor data.
    """

    drive: Drive
    demand: MotorDemand
    statistics: CycleStatistics
    check: MotorCheck | None


def size_drives(
    result: SliderMotion,
    drive: Drive | None = None,
    time: ArrayLike | None = None,
    *,
    safety_factor: float = 1.0,
) -> DriveSizing:
    """Motor demand, cycle statistics and motor check for an inverse-dynamics result.

    Args:
        result: Inverse dynamics along the cycle
            (:meth:`orthoglide_pin.dynamics.inverse.ClosedLoopDynamics.inverse_dynamics`).
        drive: The drive; the default (assumed) drive train without motor data
            when ``None``.
        time: Sample times [s], shape (N,), for the RMS (see :func:`cycle_statistics`).
        safety_factor: Multiplies the required torques in the motor check
            (:func:`check_motor`); the demand and statistics are as computed.

    Returns:
        The sizing of the three drives.
    """
    drive = Drive() if drive is None else instance_of("drive", drive, Drive, "a Drive or None")
    if not all(hasattr(result, name) for name in _MOTION):
        raise InvalidParameterError("result", result, "a DynamicsResult (inverse_dynamics)")
    demand = motor_demand(
        result.forces, result.slider_velocities, result.slider_accelerations, drive.train
    )
    stats = cycle_statistics(demand, time)
    k = safety_factor_value(safety_factor)
    check = (
        None if drive.motor is None else check_motor(drive.motor, stats, demand, safety_factor=k)
    )
    return DriveSizing(drive, demand, stats, check)
