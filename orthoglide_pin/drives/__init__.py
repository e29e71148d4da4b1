"""Drives: ball screws, gears and motors, from slider force to motor torque, and their sizing.

* :mod:`~orthoglide_pin.drives.motor`: the drive train (lead, gear, rotor,
  friction), motor data read from YAML, motor demand of slider forces;
* :mod:`~orthoglide_pin.drives.sizing`: cycle statistics (peak, RMS) and the
  motor check with margins and a verdict.
"""

from __future__ import annotations

from orthoglide_pin.drives.motor import (
    Drive,
    DriveTrain,
    MotorData,
    MotorDemand,
    load_drive,
    motor_demand,
)
from orthoglide_pin.drives.sizing import (
    CycleStatistics,
    DriveSizing,
    MotorCheck,
    check_motor,
    cycle_statistics,
    size_drives,
)

__all__ = [
    "CycleStatistics",
    "Drive",
    "DriveSizing",
    "DriveTrain",
    "MotorCheck",
    "MotorData",
    "MotorDemand",
    "check_motor",
    "cycle_statistics",
    "load_drive",
    "motor_demand",
    "size_drives",
]
