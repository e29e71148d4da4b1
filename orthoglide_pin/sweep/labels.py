"""Words and units of a sweep table's columns, for figures and the terminal.

The table keeps SI units (:mod:`~orthoglide_pin.sweep.spec`). What a person
reads uses the report's units instead (:func:`display_unit`,
:mod:`~orthoglide_pin.report.units`): lengths in mm, speeds in mm/s,
stiffnesses in N/um, deflections and surface errors in um; every other column keeps its SI unit
(kg, N, N.m, m^2, ...). :func:`label` gives an axis label, the column in words
with its display unit (``condition_std`` reads "spread of the condition number
[-]", ``stroke`` "slider stroke [mm]").
"""

from __future__ import annotations

from typing import Final

from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES

#: SI unit of each column ("" for none listed here: see :func:`si_unit`).
UNITS: Final = {
    **{c: "m" for c in ("stroke", "slider_lower", "slider_upper", "design_cube_side")},
    **{c: "m" for c in ("leg_length", "cube_side", "footprint_x", "footprint_y", "footprint_z")},
    **{f"cube_corner_{a}": "m" for a in "xyz"},
    "footprint_area": "m^2",
    "footprint_volume": "m^3",
    "moving_mass": "kg",
    "max_slider_force": "N",
    "max_motor_torque": "N.m",
    "min_stiffness": "N/m",
    "centre_stiffness": "N/m",
    "max_deflection": "m",
    "lowest_frequency": "Hz",
    "speed": "m/s",
    "acceleration": "m/s^2",
    "cycle_time": "s",
    "surface_error_max": "m",
}
#: Words for each column of a sweep table, for the axis labels (units apart);
#: short enough for a panel's height. Factors, conditions and shares are over
#: the design's cube (see :mod:`~orthoglide_pin.sweep.metrics`).
WORDS: Final = {
    "leg_length": "leg length",
    "cube_side": "cube side",
    **{f"cube_corner_{a}": f"corner Q1 of the cube, {a}" for a in "xyz"},
    "psi_min": "lower bound of the transmission factors",
    "psi_max": "upper bound of the transmission factors",
    "speed": "required tool speed",
    "acceleration": "required acceleration",
    "slider_lower": "lower slider limit",
    "slider_upper": "upper slider limit",
    "stroke": "slider stroke",
    "ratio": "cube side over stroke",
    "design_cube_side": "largest certified cube side",
    "psi_min_reached": "smallest factor over the cube",
    "psi_max_reached": "largest factor over the cube",
    "bounds_hold": "factors within bounds (1: yes)",
    "in_bounds_fraction": "share of the cube in bounds",
    "condition_min": "smallest condition number",
    "condition_max": "largest condition number",
    "condition_mean": "mean condition number",
    "condition_std": "spread of the condition number",
    "moving_mass": "moving mass",
    "max_slider_force": "worst-case slider force",
    "max_motor_torque": "worst-case motor torque",
    "footprint_x": "machine size along x",
    "footprint_y": "machine size along y",
    "footprint_z": "machine size along z",
    "footprint_area": "floor area",
    "footprint_volume": "bounding-box volume",
    "min_stiffness": "worst tool stiffness",
    "centre_stiffness": "tool stiffness at the centre",
    "max_deflection": "worst deflection, 100 N",
    "cycle_time": "cycle time of the program",
    "binding_limit": "limit binding longest",
    "lowest_frequency": "lowest natural frequency",
    "surface_error_max": "largest surface error",
    "stability_margin_min": "least chatter stability margin",
}
#: The report's units: SI unit -> (factor from SI, unit shown).
DISPLAY_UNITS: Final = {"m": (1e3, "mm"), "m/s": (1e3, "mm/s"), "N/m": (1e-6, "N/um")}
#: Columns shown in a unit of their own: (factor from SI, unit shown).
DISPLAY_COLUMNS: Final = {"max_deflection": (1e6, "um"), "surface_error_max": (1e6, "um")}


def si_unit(name: str) -> str:
    """SI unit of a column ("-" for a pure number); machine parameters have theirs."""
    if name in UNITS:
        return UNITS[name]
    if name in WORDS:
        return "-"
    return PLAUSIBLE_RANGES[name][2] if name in PLAUSIBLE_RANGES else "-"


def display_unit(name: str) -> tuple[float, str]:
    """``(factor, unit)``: a column's SI values times ``factor`` are in the report's ``unit``.

    Lengths go to mm, stiffnesses to N/um, the deflection to um (``(1e6, "um")``);
    any other column stays in its SI unit (factor 1).
    """
    if name in DISPLAY_COLUMNS:
        return DISPLAY_COLUMNS[name]
    unit = si_unit(name)
    return DISPLAY_UNITS.get(unit, (1.0, unit))


def words(name: str) -> str:
    """A column's name in words, without its unit (``"moving mass"``)."""
    return WORDS.get(name, name.replace("_", " "))


def label(name: str) -> str:
    """An axis label: the column in words and its display unit (``"slider stroke [mm]"``)."""
    return f"{words(name)} [{display_unit(name)[1]}]"


def setting(name: str, value: float) -> str:
    """A value in words and display units: ``"leg length 310 mm"``, ``"... factors 2"``."""
    factor, unit = display_unit(name)
    return f"{words(name)} {factor * value:.4g}" + ("" if unit == "-" else f" {unit}")


__all__ = [
    "DISPLAY_COLUMNS",
    "DISPLAY_UNITS",
    "UNITS",
    "WORDS",
    "display_unit",
    "label",
    "setting",
    "si_unit",
    "words",
]
