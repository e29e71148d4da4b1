"""Plausible ranges of the SI parameters, to catch values given in the wrong unit.

Every machine parameter is in SI units (metres, kilograms, kg/m^3). A value
far outside what any machine of this kind could have is almost always a unit
slip: ``leg_length=310`` meant millimetres, ``density=2.7`` meant g/cm^3. Such
values are refused with a hint, ``expected metres: did you mean 0.31?``,
whenever the value scaled by 1/1000 or 1000 falls in the range.

The ranges are deliberately wide (a desktop machine to a large machine tool);
the README shows the same table. :func:`check_plausible` serves other inputs
too: every value of a drive (:data:`DRIVE_RANGES`, for
:mod:`orthoglide_pin.drives.motor`), where the slips looked for follow the
unit (an inertia in kg.cm^2, an efficiency in percent).
"""

from __future__ import annotations

from typing import Final

from orthoglide_pin.exceptions import InvalidParameterError

#: Words for the units, for the hint.
UNIT_WORDS: Final = {
    "m": "metres",
    "kg": "kilograms",
    "kg/m^3": "kg/m^3",
    "m/rev": "metres per revolution",
    "Pa": "pascals",
    "N/m": "newtons per metre",
    "N.m/rad": "newton-metres per radian",
    "kg.m^2": "kg.m^2",
    "N.m": "newton-metres",
    "N.m.s/rad": "N.m.s/rad",
    "rad/s": "radians per second",
    "rpm": "revolutions per minute",
    "rev/rev": "motor turns per screw turn",
    "": "a ratio",
}

#: Plausible range ``(low, high, unit)`` of each parameter, in SI units. Vector
#: parameters apply the range to each component.
PLAUSIBLE_RANGES: Final[dict[str, tuple[float, float, str]]] = {
    "leg_length": (0.02, 5.0, "m"),
    "parallelogram_width": (0.002, 2.0, "m"),
    "slider_lower": (-5.0, 5.0, "m"),
    "slider_upper": (-5.0, 5.0, "m"),
    "carriage_offset": (0.0, 2.0, "m"),
    "platform_offset": (0.0, 2.0, "m"),
    "tool_offset": (-2.0, 2.0, "m"),
    "bar_radius": (0.0005, 0.5, "m"),
    "bar_wall": (0.0001, 0.5, "m"),
    "link_radius": (0.0005, 0.5, "m"),
    "carriage_size": (0.002, 2.0, "m"),
    "platform_size": (0.002, 2.0, "m"),
    "spindle_radius": (0.001, 1.0, "m"),
    "spindle_length": (0.002, 2.0, "m"),
    "rail_size": (0.002, 1.0, "m"),
    "density": (100.0, 25000.0, "kg/m^3"),
    "youngs_modulus": (1e8, 1.2e12, "Pa"),
    "shear_modulus": (1e8, 6e11, "Pa"),
    "actuator_stiffness": (1e4, 1e11, "N/m"),
    "joint_stiffness": (1e4, 1e11, "N/m"),
    "joint_tilt_stiffness": (1.0, 1e9, "N.m/rad"),
    "spindle_mass": (0.0, 500.0, "kg"),
    "bar_mass": (0.0, 100.0, "kg"),
    "link_mass": (0.0, 100.0, "kg"),
    "carriage_mass": (0.0, 500.0, "kg"),
    "platform_mass": (0.0, 500.0, "kg"),
    "workspace_corner": (-5.0, 5.0, "m"),
    "workspace_side": (0.001, 5.0, "m"),
    # the criterion on the transmission factors (dimensionless; the machine also
    # wants psi_min < 1 < psi_max, and 1e6 is the condition limit of the indices)
    "psi_min": (0.0, 1.0, "-"),
    "psi_max": (1.0, 1e6, "-"),
}
#: Plausible ball-screw lead [m/rev] (1 mm to 200 mm per revolution).
LEAD_RANGE: Final = (0.0005, 0.2, "m/rev")
#: Plausible range ``(low, high, unit)`` of each drive value, in SI units except
#: the motor speeds [rpm] (``""``: a ratio; ``"rev/rev"``: motor turns per screw
#: turn). Zero is allowed where the low end is 0 (no friction, an inertia
#: neglected). A speed-torque curve's speeds and torques lie within the ranges
#: of ``max_speed`` and ``peak_torque``, from 0.
DRIVE_RANGES: Final[dict[str, tuple[float, float, str]]] = {
    "lead": LEAD_RANGE,
    "efficiency": (0.05, 1.0, ""),
    "screw_diameter": (0.002, 0.5, "m"),
    "screw_length": (0.01, 10.0, "m"),
    "screw_density": PLAUSIBLE_RANGES["density"],
    "screw_inertia": (0.0, 10.0, "kg.m^2"),
    "gear_ratio": (0.01, 1000.0, "rev/rev"),
    "rotor_inertia": (0.0, 1.0, "kg.m^2"),
    "coulomb_torque": (0.0, 100.0, "N.m"),
    "viscous_coefficient": (0.0, 10.0, "N.m.s/rad"),
    "friction_speed": (1e-3, 1e4, "rad/s"),
    "rated_torque": (1e-3, 1e4, "N.m"),
    "peak_torque": (1e-3, 1e4, "N.m"),
    "max_speed": (1.0, 1e5, "rpm"),
}
#: The scale factors tried for the hint: a value in mm, g or g/cm^3 by mistake.
_SLIPS: Final = (1e-3, 1e3)
#: Other factors for some units: an inertia in kg.cm^2 (the data sheets' unit),
#: an efficiency in percent; a speed in rpm or a gear ratio has no such slip.
_UNIT_SLIPS: Final[dict[str, tuple[float, ...]]] = {
    "kg.m^2": (1e-4,),
    "": (1e-2,),
    "rpm": (),
    "rev/rev": (),
}


def check_plausible(name: str, value: float, low: float, high: float, unit: str) -> None:
    """Refuse ``value`` outside ``[low, high]``, with a hint when a unit slip explains it.

    Args:
        name: Parameter name, for the message.
        value: The value, in SI units.
        low: Smallest plausible value [unit].
        high: Largest plausible value [unit].
        unit: SI unit of the value (``"m"``, ``"kg"``, ...; ``"-"`` for a ratio,
            which gets no hint, ``""`` for a number without unit).

    Raises:
        InvalidParameterError: Naming the value, the range and, when scaling by
            1/1000 or 1000 brings it in range (1e-4 for kg.m^2, 1/100 for a
            ratio), the value meant.
    """
    if low <= value <= high:
        return
    if unit == "-":  # a ratio: no unit to slip
        raise InvalidParameterError(name, value, f"a value in [{low:g}, {high:g}] (dimensionless)")
    allowed = f"a value in [{low:g}, {high:g}]" + (f" {unit}" if unit else "")
    for factor in _UNIT_SLIPS.get(unit, _SLIPS):
        meant = value * factor
        if meant != 0.0 and low <= meant <= high:
            word = UNIT_WORDS.get(unit, unit)
            allowed = f"{word}: did you mean {meant:.6g}? (plausible: {allowed})"
            break
    raise InvalidParameterError(name, value, allowed)


def check_parameter(name: str, value: float) -> None:
    """:func:`check_plausible` with the range of parameter ``name`` (if it has one)."""
    entry = PLAUSIBLE_RANGES.get(name)
    if entry is not None:
        check_plausible(name, value, *entry)
