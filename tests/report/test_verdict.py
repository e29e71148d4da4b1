"""The verdict's rows: margins, and a criterion of the whole machine."""

from __future__ import annotations

import math

import pytest

from orthoglide_pin.report.verdict import VerdictRow, margin_value


@pytest.mark.parametrize(
    ("required", "available", "expected"),
    [(1.0, 4.0, 0.75), (5.0, 4.0, -0.25), (4.0, 4.0, 0.0), (1.0, 0.0, -math.inf)],
)
def test_the_margin_is_the_share_left(required: float, available: float, expected: float) -> None:
    assert margin_value(required, available) == expected


def test_a_row_passes_on_a_margin_of_zero_and_up() -> None:
    machine = VerdictRow(
        None,
        "vibration: lowest natural frequency vs minimum",
        120.0,
        99.6,
        "Hz",
        margin_value(120.0, 99.6),
    )
    assert machine.passed is False and machine.motor is None
    assert VerdictRow(2, "cycle: peak speed vs maximum speed", 3000.0, 5000.0, "rpm", 0.4).passed
    assert (
        VerdictRow(1, "cycle: RMS torque vs rated torque", 1.0, None, "N.m", None).passed is None
    )
