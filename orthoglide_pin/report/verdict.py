"""The verdict's rows: each criterion, what is required, what is available, the margin.

:class:`VerdictRow` is one criterion; :func:`motor_rows` gives those of the
motors (the standard cycle's and the worst case's over the cube, see
:mod:`orthoglide_pin.report.assemble`). A part program
(:mod:`~orthoglide_pin.report.program`) and the machine's lowest natural
frequency (:mod:`~orthoglide_pin.report.vibration`) add their own rows. The
margin of every row is ``1 - required / available``: the share left,
negative when the criterion fails. A row against the speed-torque curve is
taken at the sample where the margin is least (:func:`curve_point`): the torque
required there and the torque the curve gives at that sample's speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import Drive, MotorData, MotorDemand
from orthoglide_pin.drives.sizing import DriveSizing
from orthoglide_pin.dynamics.requirements import WorstCase, available_torque

__all__ = ["VerdictRow", "curve_point", "margin_value", "motor_rows"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class VerdictRow:
    """One criterion of the verdict: of one motor, or of the whole machine.

    Attributes:
        motor: Motor index, 1 to 3; ``None`` for a criterion of the whole
            machine (its lowest natural frequency).
        criterion: What is compared.
        required: The requirement (unit below).
        available: The motor's (or the machine's) figure, or ``None`` (no
            motor datum).
        unit: Unit of both.
        margin: ``1 - required / available`` (``-inf`` where nothing is
            available), or ``None`` without motor data.
    """

    motor: int | None
    criterion: str
    required: float
    available: float | None
    unit: str
    margin: float | None

    @property
    def passed(self) -> bool | None:
        """``margin >= 0``, or ``None`` without motor data."""
        return None if self.margin is None else self.margin >= 0.0


def margin_value(required: float, available: float) -> float:
    """``1 - required / available``; ``-inf`` where nothing is available (``<= 0``)."""
    return 1.0 - required / available if available > 0.0 else -math.inf


def curve_point(
    motor: MotorData, demand: MotorDemand, safety_factor: float = 1.0
) -> tuple[FloatArray, FloatArray] | None:
    """Each motor's sample nearest its speed-torque curve: required and available torque.

    The sample is where ``required / available`` is largest, the one that sets
    the margin of :func:`~orthoglide_pin.drives.sizing.check_motor`
    (``speed_torque_curve``), so ``1 - required / available`` is that margin.

    Returns:
        ``(required, available)`` [N.m], each (3,) (the required torque times
        ``safety_factor``), or ``None`` without a curve or samples.
    """
    if motor.speed_torque_curve is None or demand.torque.shape[0] == 0:
        return None
    sp, tq = np.array(motor.speed_torque_curve).T
    avail = np.interp(np.abs(demand.speed_rpm), sp, tq, right=0.0)
    need = safety_factor * np.abs(demand.torque)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(need > 0.0, need / avail, 0.0)
    k, cols = np.argmax(ratio, axis=0), np.arange(need.shape[1])
    return need[k, cols], avail[k, cols]


def motor_rows(
    drive: Drive, cube: WorstCase, sizing: DriveSizing, safety_factor: float = 1.0
) -> tuple[VerdictRow, ...]:
    """Criteria per motor: the cycle's (margins of the motor check) and the worst case's.

    The required torques are multiplied by ``safety_factor`` (the motor check of
    ``sizing`` must have been made with the same factor).
    """
    motor, stats, factor = drive.motor, sizing.statistics, safety_factor
    margins = {} if sizing.check is None else sizing.check.margins
    available = None if motor is None else available_torque(motor, cube.motor_speed_rpm)
    curve = None if motor is None else curve_point(motor, sizing.demand, factor)
    rows: list[VerdictRow] = []
    for i in range(3):
        cycle = [
            ("cycle: RMS torque vs rated torque", "rms_torque", factor * stats.rms_torque, "N.m"),
            (
                "cycle: peak torque vs peak torque",
                "peak_torque",
                factor * stats.peak_torque,
                "N.m",
            ),
            ("cycle: peak speed vs maximum speed", "speed", stats.peak_speed_rpm, "rpm"),
            (
                "cycle: torque vs speed-torque curve",
                "speed_torque_curve",
                factor * stats.peak_torque if curve is None else curve[0],
                "N.m",
            ),
        ]
        limits = {
            "rms_torque": None if motor is None else motor.rated_torque,
            "peak_torque": None if motor is None else motor.peak_torque,
            "speed": None if motor is None else motor.max_speed,
            "speed_torque_curve": None if curve is None else float(curve[1][i]),
        }
        for criterion, key, required, unit in cycle:
            if key == "speed_torque_curve" and key not in margins:
                continue
            margin = float(margins[key][i]) if key in margins else None
            rows.append(
                VerdictRow(i + 1, criterion, float(required[i]), limits[key], unit, margin)
            )
        torque = factor * cube.torque[:, i]
        criterion = "worst case: torque vs torque available"
        if available is None:
            rows.append(VerdictRow(i + 1, criterion, float(torque.max()), None, "N.m", None))
        else:
            each = np.array(
                [margin_value(t, a) for t, a in zip(torque, available[:, i], strict=True)]
            )
            k = int(np.argmin(each))
            row = VerdictRow(
                i + 1, criterion, float(torque[k]), float(available[k, i]), "N.m", float(each[k])
            )
            rows.append(row)
        speed = float(cube.motor_speed_rpm[:, i].max())
        top = None if motor is None else motor.max_speed
        margin = None if top is None else margin_value(speed, top)
        rows.append(
            VerdictRow(i + 1, "worst case: speed vs maximum speed", speed, top, "rpm", margin)
        )
    return tuple(rows)
