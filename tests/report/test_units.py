"""The display units: one convention for every page, terminal summary and legend."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.verify import LIMIT_NAMES
from orthoglide_pin.report.units import DISPLAY, LIMIT_KINDS, label, quantity, shown, unit


def test_the_convention() -> None:
    assert unit("length") == "mm" and unit("feed") == "mm/min" and unit("speed") == "mm/s"
    assert unit("motor_speed") == "rpm" and unit("acceleration") == "m/s^2"
    assert quantity("feed", 0.05, ".0f") == "3000 mm/min"  # F3000
    assert quantity("speed", 1.2) == "1200 mm/s"
    assert quantity("motor_speed", 2.0 * np.pi) == "60 rpm"  # one turn a second
    assert quantity("length", 0.2) == "200 mm"
    assert label("slider speed", "speed") == "slider speed [mm/s]"
    np.testing.assert_allclose(shown("feed", np.array([0.0, 0.1])), [0.0, 6000.0])


def test_every_limit_of_a_plan_has_its_unit() -> None:
    assert set(LIMIT_KINDS) == set(LIMIT_NAMES)
    assert set(LIMIT_KINDS.values()) <= set(DISPLAY)


def test_an_unknown_kind_is_refused() -> None:
    with pytest.raises(InvalidParameterError, match="kind"):
        unit("furlongs")
