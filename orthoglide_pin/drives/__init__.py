"""Drives: ball screws, gears and motors, from slider force to motor torque, and their sizing.

* :mod:`~orthoglide_pin.drives.motor`: the drive train (lead, gear, rotor,
  friction), motor data read from YAML, motor demand of slider forces;
* :mod:`~orthoglide_pin.drives.sizing`: cycle statistics (peak, RMS) and the
  motor check with margins, a safety factor on the torques and a verdict;
* :mod:`~orthoglide_pin.drives.shipped`: the example drive files shipped with
  the package (``orthoglide drive --example``).
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
from orthoglide_pin.drives.shipped import EXAMPLE_DRIVES, example_drive_file, example_drive_text
from orthoglide_pin.drives.sizing import (
    CycleStatistics,
    DriveSizing,
    MotorCheck,
    check_motor,
    cycle_statistics,
    safety_factor_value,
    size_drives,
)

__all__ = [
    "EXAMPLE_DRIVES",
    "CycleStatistics",
    "Drive",
    "DriveSizing",
    "DriveTrain",
    "MotorCheck",
    "MotorData",
    "MotorDemand",
    "check_motor",
    "cycle_statistics",
    "example_drive_file",
    "example_drive_text",
    "load_drive",
    "motor_demand",
    "safety_factor_value",
    "size_drives",
]
