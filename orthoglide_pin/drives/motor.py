"""Drives: ball screw, optional gear and motor, from slider forces to motor torques.

Each slider is driven by a ball screw of lead ``l`` [m/rev] turned by a rotary
motor through an optional gear of ratio ``n`` (motor turns per screw turn); the
three drives are identical. For a slider force ``F`` [N] (exerted by the drive
on the carriage along ``+e_i``), speed ``q'`` and acceleration ``q''``:

* screw speed ``w_s = 2 pi q' / l`` [rad/s]; motor speed ``w_m = n w_s``;
* motor torque
  ``T = F l / (2 pi n eta^s) + (J_rotor + J_screw / n^2) w_m' + T_f(w_m)`` [N.m],
  with ``eta^s = eta`` (the efficiency divides) when the motor drives the load
  (``F q' >= 0``, rest included) and ``eta^s = 1 / eta`` (it multiplies) when
  the load back-drives the screw (``F q' < 0``);
* friction at the motor, Coulomb and viscous,
  ``T_f = T_c tanh(w_m / w_eps) + b w_m``: ``tanh`` smooths the Coulomb sign
  over ``|w_m| < w_eps``, so that ``T_f(0) = 0``.

Hence the power balance ``T w_m = F q' / eta^s + J_eq w_m' w_m + T_f w_m``.
The screw's inertia is that of a solid steel cylinder of its diameter and
length unless given. Drive-train defaults are assumptions for the prototype
(stated by :meth:`DriveTrain.assumptions`); motor data are optional and give
margins and a pass/fail verdict (:mod:`orthoglide_pin.drives.sizing`).
:func:`load_drive` reads both from YAML (sections ``drive_train`` and ``motor``).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import read_yaml_mapping
from orthoglide_pin._validation import float_array, instance_of
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.ranges import DRIVE_RANGES, check_plausible

FloatArray = NDArray[np.float64]

#: Revolutions per minute in one rad/s.
RPM_PER_RAD_S: Final[float] = 60.0 / (2.0 * math.pi)
_MAY_BE_ZERO: Final = frozenset(
    {"coulomb_torque", "viscous_coefficient", "rotor_inertia", "screw_inertia"}
)


def _number(name: str, value: Any, *, strict: bool = False) -> float:
    """A finite float ``>= 0`` (``> 0`` if ``strict``), or InvalidParameterError."""
    try:
        out = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and (out > 0.0 or (out == 0.0 and not strict))):
        raise InvalidParameterError(name, value, f"a finite number {'>' if strict else '>='} 0")
    return out


def _finite(name: str, value: ArrayLike, unit: str) -> FloatArray:
    """``value`` as finite floats (any shape, empty too), else an error naming ``name``."""
    arr = float_array(value)
    if not np.isfinite(arr).all():
        raise InvalidParameterError(name, value, f"finite numbers {unit}")
    return arr


def _fields(cls: type, data: Mapping[str, Any], section: str) -> dict[str, Any]:
    if not isinstance(data, Mapping):
        raise InvalidParameterError(section, data, "a mapping of names to values")
    names = [f.name for f in dataclasses.fields(cls)]
    for key in data:
        if key not in names:
            raise InvalidParameterError(f"{section} key", key, "one of " + ", ".join(names))
    return dict(data)


@dataclass(frozen=True)
class DriveTrain:
    """Ball screw, gear and motor rotor of one drive (SI units).

    Attributes:
        lead: Screw lead [m/rev].
        efficiency: Ball-screw efficiency, in (0, 1].
        screw_diameter: Screw diameter [m] (for its inertia).
        screw_length: Screw length [m] (for its inertia).
        screw_density: Screw material density [kg/m^3].
        screw_inertia: Screw inertia about its axis [kg.m^2]; ``None`` derives
            it as a solid cylinder, ``pi rho l d^4 / 32``.
        gear_ratio: Motor turns per screw turn (1: direct drive).
        rotor_inertia: Motor rotor inertia [kg.m^2].
        coulomb_torque: Coulomb friction torque at the motor [N.m].
        viscous_coefficient: Viscous friction at the motor [N.m.s/rad].
        friction_speed: Speed below which the Coulomb sign is smoothed [rad/s].

    Every value must lie in its plausible range
    (:data:`~orthoglide_pin.machine.ranges.DRIVE_RANGES`); a value that a unit
    slip explains is refused with the value meant (a lead of 25 meant 0.025
    m/rev, an efficiency of 90 meant 0.9, a rotor inertia of 1.2 in kg.cm^2
    meant 1.2e-4 kg.m^2).
    """

    lead: float = 0.025
    efficiency: float = 0.9
    screw_diameter: float = 0.016
    screw_length: float = 0.5
    screw_density: float = 7850.0
    screw_inertia: float | None = None
    gear_ratio: float = 1.0
    rotor_inertia: float = 1.2e-4
    coulomb_torque: float = 0.02
    viscous_coefficient: float = 1e-4
    friction_speed: float = 1.0

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if value is None and f.name == "screw_inertia":  # None: derived from the screw
                continue
            strict = f.name not in _MAY_BE_ZERO
            number = _number(f.name, value, strict=strict)
            check_plausible(f.name, number, *DRIVE_RANGES[f.name])  # 25 meant mm/rev
            object.__setattr__(self, f.name, number)

    @property
    def screw_inertia_value(self) -> float:
        """The screw's inertia [kg.m^2], given or derived."""
        if self.screw_inertia is not None:
            return self.screw_inertia
        return math.pi * self.screw_density * self.screw_length * self.screw_diameter**4 / 32.0

    @property
    def reflected_inertia(self) -> float:
        """Inertia seen by the motor, ``J_rotor + J_screw / n^2`` [kg.m^2]."""
        return self.rotor_inertia + self.screw_inertia_value / self.gear_ratio**2

    def motor_speed(self, slider_velocity: ArrayLike) -> FloatArray:
        """Motor speed ``w_m = 2 pi n q' / l`` [rad/s] of a slider speed [m/s]."""
        return _finite("slider_velocity", slider_velocity, "[m/s]") * (
            2.0 * math.pi * self.gear_ratio / self.lead
        )

    def friction(self, motor_speed: ArrayLike) -> FloatArray:
        """Friction torque at the motor ``T_c tanh(w / w_eps) + b w`` [N.m]."""
        w = _finite("motor_speed", motor_speed, "[rad/s]")
        return np.asarray(
            self.coulomb_torque * np.tanh(w / self.friction_speed) + self.viscous_coefficient * w
        )

    def assumptions(self) -> list[str]:
        """The drive's assumptions, one sentence per line, for reports."""
        mm = 1e3
        screw = (
            f"given, {self.screw_inertia:.3g} kg.m^2"
            if self.screw_inertia is not None
            else f"solid cylinder {self.screw_diameter * mm:.0f} mm x "
            f"{self.screw_length * mm:.0f} mm of {self.screw_density:g} kg/m^3, "
            f"{self.screw_inertia_value:.3g} kg.m^2"
        )
        return [
            "The paper gives no drive data: ball screws driven by rotary motors, sized for "
            "1200 mm/s and 20 m/s^2 at the isotropic point; the values below are assumed.",
            f"Ball screw: lead {self.lead * mm:g} mm/rev, efficiency {self.efficiency:g} "
            "(dividing when the motor drives, multiplying when back-driven); "
            f"screw inertia: {screw}.",
            f"Gear ratio {self.gear_ratio:g} (motor turns per screw turn); "
            f"rotor inertia {self.rotor_inertia:.3g} kg.m^2.",
            f"Friction at the motor: Coulomb {self.coulomb_torque:g} N.m "
            f"(smoothed by tanh over {self.friction_speed:g} rad/s), "
            f"viscous {self.viscous_coefficient:g} N.m.s/rad.",
        ]


@dataclass(frozen=True)
class MotorData:
    """Optional data of a motor; any of them may be ``None`` (not checked).

    Torques and speeds must lie in their plausible ranges
    (:data:`~orthoglide_pin.machine.ranges.DRIVE_RANGES`).

    Attributes:
        name: Motor name, for reports.
        rated_torque: Continuous (rated) torque [N.m], compared with the RMS torque.
        peak_torque: Peak torque [N.m], compared with the peak torque.
        max_speed: Maximum speed [rpm], compared with the peak speed.
        speed_torque_curve: Available torque [N.m] against speed [rpm], as
            ``((speed, torque), ...)`` with increasing speeds from 0, compared at
            every sample (no torque beyond the last speed).
    """

    name: str = "motor"
    rated_torque: float | None = None
    peak_torque: float | None = None
    max_speed: float | None = None
    speed_torque_curve: tuple[tuple[float, float], ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", str(self.name))
        for name in ("rated_torque", "peak_torque", "max_speed"):
            value = getattr(self, name)
            if value is not None:
                number = _number(name, value, strict=True)
                check_plausible(name, number, *DRIVE_RANGES[name])
                object.__setattr__(self, name, number)
        curve = self.speed_torque_curve
        if curve is None:
            return
        pts = float_array(curve)
        ok = pts.ndim == 2 and pts.shape[1] == 2 and pts.shape[0] >= 2
        ok = ok and bool(np.isfinite(pts).all()) and bool((pts >= 0.0).all())
        if not ok or pts[0, 0] != 0.0 or not (np.diff(pts[:, 0]) > 0.0).all():
            raise InvalidParameterError(
                "speed_torque_curve",
                curve,
                "two or more [speed rpm, torque N.m] pairs, from speed 0, speeds increasing",
            )
        for column, (name, what) in enumerate((("max_speed", "speed"), ("peak_torque", "torque"))):
            _, high, unit = DRIVE_RANGES[name]
            worst = float(pts[:, column].max())
            check_plausible(f"speed_torque_curve {what}", worst, 0.0, high, unit)
        object.__setattr__(self, "speed_torque_curve", tuple((s, t) for s, t in pts.tolist()))


@dataclass(frozen=True)
class Drive:
    """The drive of each slider (the three are identical).

    Attributes:
        train: Ball screw, gear, rotor inertia and friction.
        motor: Motor data for the margins, or ``None``.
    """

    train: DriveTrain = dataclasses.field(default_factory=DriveTrain)
    motor: MotorData | None = None

    def __post_init__(self) -> None:
        instance_of("train", self.train, DriveTrain, "a DriveTrain")
        if self.motor is not None:
            instance_of("motor", self.motor, MotorData, "MotorData or None")

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Drive:
        """Build from ``{"drive_train": {...}, "motor": {...}}`` (both optional).

        Motor data need the motor's rotor inertia: a ``motor`` section comes
        with a ``drive_train`` section that gives ``rotor_inertia``. A motor
        alone is refused rather than completed with the assumed default rotor.

        Raises:
            InvalidParameterError: Unknown keys, bad values, or a motor without
                its rotor inertia.
        """
        if not isinstance(data, Mapping):
            raise InvalidParameterError("data", data, "a mapping with drive_train and motor")
        for key in data:
            if key not in ("drive_train", "motor"):
                raise InvalidParameterError(
                    "drive key", key, "one of drive_train, motor (the sections of the drive data)"
                )
        train_data = data.get("drive_train") or {}
        train = DriveTrain(**_fields(DriveTrain, train_data, "drive_train"))
        motor_data = data.get("motor")
        motor = (
            None if motor_data is None else MotorData(**_fields(MotorData, motor_data, "motor"))
        )
        if motor is not None and "rotor_inertia" not in train_data:
            raise InvalidParameterError(
                "drive_train.rotor_inertia",
                None,
                "the motor's rotor inertia [kg.m^2] in a drive_train section next to the "
                f"motor section (else the assumed {DriveTrain.rotor_inertia:g} kg.m^2 would "
                "be used for your motor); the lead, gear and screw there too: "
                "`orthoglide drive --example` prints a complete file",
            )
        return cls(train, motor)


def load_drive(path: str | Path) -> Drive:
    """Read a drive (``--motor FILE.yaml``): sections ``drive_train`` and ``motor``.

    The file is read safely (:func:`orthoglide_pin._io.read_yaml_mapping`): at
    most 1 MB of UTF-8, no YAML aliases, string keys only.

    Raises:
        InvalidParameterError: Unreadable, oversized or non-UTF-8 file, invalid
            YAML, unknown keys or bad values.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidParameterError("path", path, "a file path (str or os.PathLike)")
    return Drive.from_dict(read_yaml_mapping(path, "motor file"))


@dataclass(frozen=True)
class MotorDemand:
    """What the three motors must deliver along ``N`` samples.

    Attributes:
        torque: Motor torques [N.m], shape (N, 3).
        speed: Motor speeds [rad/s], shape (N, 3).
        speed_rpm: Motor speeds [rpm], shape (N, 3).
        acceleration: Motor angular accelerations [rad/s^2], shape (N, 3).
        power: Motor mechanical power ``T w_m`` [W], shape (N, 3).
        load_torque: The slider force's share of the torque [N.m], shape (N, 3).
    """

    torque: FloatArray
    speed: FloatArray
    speed_rpm: FloatArray
    acceleration: FloatArray
    power: FloatArray
    load_torque: FloatArray


def motor_demand(
    forces: ArrayLike,
    slider_velocities: ArrayLike,
    slider_accelerations: ArrayLike,
    train: DriveTrain | None = None,
) -> MotorDemand:
    """Motor torques and speeds for slider forces and motion (see module).

    Args:
        forces: Slider forces [N], shape (N, 3) (e.g. ``DynamicsResult.forces``).
        slider_velocities: Slider velocities [m/s], shape (N, 3).
        slider_accelerations: Slider accelerations [m/s^2], shape (N, 3).
        train: The drive train; the default (assumed) one when ``None``.

    Returns:
        The motor demand.

    Raises:
        InvalidParameterError: Non-finite values or mismatched shapes.
    """
    t = DriveTrain() if train is None else instance_of("train", train, DriveTrain, "a DriveTrain")
    arrays = []
    for name, value in (
        ("forces", forces),
        ("slider_velocities", slider_velocities),
        ("slider_accelerations", slider_accelerations),
    ):
        arr = float_array(value)
        if arr.ndim != 2 or arr.shape[1] != 3:
            raise InvalidParameterError(f"{name}.shape", arr.shape, "(N, 3)")
        finite = np.isfinite(arr)
        if not finite.all():
            bad = float(arr.reshape(-1)[int(np.argmin(finite.reshape(-1)))])
            raise InvalidParameterError(name, bad, "finite numbers")
        arrays.append(arr)
    f, qd, qdd = arrays
    if not f.shape == qd.shape == qdd.shape:
        raise InvalidParameterError("shapes", (f.shape, qd.shape, qdd.shape), "one shape (N, 3)")
    speed = t.motor_speed(qd)
    accel = t.motor_speed(qdd)
    driving = f * qd >= 0.0
    screw_torque = f * (t.lead / (2.0 * math.pi * t.gear_ratio))
    load = np.where(driving, screw_torque / t.efficiency, screw_torque * t.efficiency)
    torque = load + t.reflected_inertia * accel + t.friction(speed)
    return MotorDemand(torque, speed, speed * RPM_PER_RAD_S, accel, torque * speed, load)
