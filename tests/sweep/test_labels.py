"""Words and units of a sweep's columns: the report's units for what a person reads."""

from __future__ import annotations

import pytest

from orthoglide_pin.machine.params import field_names
from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES
from orthoglide_pin.sweep.labels import display_unit, label, setting, si_unit, words
from orthoglide_pin.sweep.spec import METRIC_COLUMNS, PARAMETER_COLUMNS

#: The report's units (orthoglide report, its stiffness section): factor from SI.
REPORT_UNITS = {"mm": 1e3, "mm/s": 1e3, "um": 1e6, "N/um": 1e-6}


@pytest.mark.parametrize(
    ("name", "factor", "unit"),
    [
        ("leg_length", 1e3, "mm"),
        ("stroke", 1e3, "mm"),
        ("design_cube_side", 1e3, "mm"),
        ("footprint_z", 1e3, "mm"),
        ("bar_radius", 1e3, "mm"),  # a machine parameter in metres
        ("min_stiffness", 1e-6, "N/um"),
        ("centre_stiffness", 1e-6, "N/um"),
        ("actuator_stiffness", 1e-6, "N/um"),
        ("max_deflection", 1e6, "um"),
        ("speed", 1e3, "mm/s"),  # the required tool speed, as on every page
        ("moving_mass", 1.0, "kg"),
        ("max_motor_torque", 1.0, "N.m"),
        ("footprint_area", 1.0, "m^2"),
        ("ratio", 1.0, "-"),
        ("psi_max", 1.0, "-"),
    ],
)
def test_display_units_are_the_reports(name: str, factor: float, unit: str) -> None:
    assert display_unit(name) == (factor, unit)
    if unit in REPORT_UNITS:
        assert factor == REPORT_UNITS[unit]


def test_every_column_has_a_unit_and_lengths_show_in_mm() -> None:
    for name in (*PARAMETER_COLUMNS, *METRIC_COLUMNS, *field_names()):
        factor, unit = display_unit(name)
        if si_unit(name) == "m" and name != "max_deflection":
            assert (factor, unit) == (1e3, "mm"), name
        assert unit and "_" not in label(name), name
    assert si_unit("density") == PLAUSIBLE_RANGES["density"][2]


def test_settings_read_in_words_and_display_units() -> None:
    assert setting("leg_length", 0.31) == "leg length 310 mm"
    assert setting("psi_max", 2.0) == "upper bound of the transmission factors 2"
    assert setting("actuator_stiffness", 1.5e8) == "actuator stiffness 150 N/um"
    assert words("condition_std") == "spread of the condition number"
