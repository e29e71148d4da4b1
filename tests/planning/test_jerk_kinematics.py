"""The slider jerk by the chain rule and the third path derivative by differences."""

from __future__ import annotations

import numpy as np

from orthoglide_pin.planning.jerk_kinematics import slider_jerk, third_derivative


def test_the_jerk_formula_on_a_cubic_law() -> None:
    s = np.linspace(0.0, 1.0, 41)
    ddq = np.stack([s**2, -3.0 * s, np.ones_like(s)], axis=1)
    dddq = third_derivative(s, ddq, np.zeros(s.size, dtype=np.intp))
    assert np.allclose(dddq, np.stack([2.0 * s, -3.0 * np.ones_like(s), 0 * s], axis=1))
    one = np.ones(1)
    jerk = slider_jerk(
        np.ones((1, 3)), np.ones((1, 3)), np.ones((1, 3)), 2 * one, 3 * one, 5 * one
    )
    assert np.allclose(jerk, 5.0 + 3.0 * 2.0 * 3.0 + 8.0)
