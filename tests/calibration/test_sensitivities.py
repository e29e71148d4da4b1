"""Sensitivity indices: finite differences, and where the machine is least sensitive."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel
from orthoglide_pin.calibration.sensitivities import GROUPS, sensitivity, sensitivity_indices

#: Central differences against the closed form (relative).
FD_TOL = 1e-6


def test_against_finite_differences_of_the_commanded_tool() -> None:
    L = 0.32
    p = np.array([0.03, -0.04, 0.05])
    nominal = GeometricModel.nominal(L)
    q = nominal.inverse_kinematics(p)  # the sliders command the drawing's ik
    h = 1e-7
    fd = np.empty((3, 18))
    for k in range(18):
        e = np.zeros(18)
        e[k] = h
        plus = GeometricModel.from_vector(nominal.vector() + e).direct_kinematics(q)
        minus = GeometricModel.from_vector(nominal.vector() - e).direct_kinematics(q)
        fd[:, k] = (plus - minus) / (2 * h)
    np.testing.assert_allclose(sensitivity(L, p), fd, rtol=FD_TOL, atol=FD_TOL)


@pytest.mark.parametrize("leg", [0.31, 0.36])
def test_the_isotropic_point_is_the_least_sensitive(leg: float) -> None:
    params = og.prototype().replace(leg_length=leg)
    lo = np.asarray(params.workspace.corner)
    axis = np.linspace(0.0, params.workspace.side, 11)
    pts = lo + np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    home = sensitivity_indices(leg, np.zeros(3))
    over = sensitivity_indices(leg, pts)
    for group in GROUPS:
        assert home[group] <= over[group].min() + 1e-12
    # at home J = I: each carriage or leg error moves the tool by itself, a tilt not at all
    assert home["carriage position"] == pytest.approx(np.sqrt(3.0))
    assert home["leg length"] == pytest.approx(np.sqrt(3.0))
    assert home["rail orientation"] == pytest.approx(0.0, abs=1e-15)
    assert set(PARAMETER_NAMES) <= set(over)
