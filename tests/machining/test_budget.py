"""The error budget: the thermal term against the Jacobian, the geometric term, their sums."""

from __future__ import annotations

import numpy as np
import pytest
from elasticity._support import cube_points

import orthoglide_pin as og
from orthoglide_pin.machining.budget import (
    ALUMINIUM_EXPANSION,
    STEEL_EXPANSION,
    error_budget,
    geometric_error,
    thermal_error,
)

SEED = 20261206
#: First-order relations (the Jacobian, the same linear solve), relative.
EXACT_TOL = 1e-10
#: The prototype's screw stroke [m] and what a kelvin grows it by [m] (paper: 257 mm).
STROKE = 0.257
GROWTH_PER_KELVIN = 2.96e-6
GROWTH_TOL = 0.01


@pytest.fixture(scope="module", params=[0.31, 0.34075], ids=["prototype", "340.75 mm legs"])
def machine(request: pytest.FixtureRequest) -> og.OrthoglideParams:
    return og.prototype().replace(leg_length=request.param)


def test_screw_growth_reaches_the_tool_through_the_jacobian(machine: og.OrthoglideParams) -> None:
    points = cube_points(machine, 6, SEED)
    dp = thermal_error(points, machine, 2.0, spindle_expansion=0.0, platform_expansion=0.0)
    q = og.inverse_kinematics(points, machine.leg_length)
    dq = STEEL_EXPANSION * 2.0 * (q - machine.slider_lower)
    expected = np.einsum("nij,nj->ni", og.jacobian(points, machine.leg_length), dq)
    np.testing.assert_allclose(
        dp, expected, rtol=EXACT_TOL, atol=EXACT_TOL * np.abs(expected).max()
    )


def test_a_kelvin_grows_the_prototype_screw_by_three_micrometres() -> None:
    params = og.prototype()
    stroke = params.slider_upper - params.slider_lower
    assert stroke == pytest.approx(STROKE, rel=GROWTH_TOL)
    assert STEEL_EXPANSION * stroke == pytest.approx(GROWTH_PER_KELVIN, rel=GROWTH_TOL)


def test_the_spindle_and_the_platform_grow(machine: og.OrthoglideParams) -> None:
    points = cube_points(machine, 4, SEED)
    spindle = thermal_error(points, machine, 1.0, screw_expansion=0.0, platform_expansion=0.0)
    expected = STEEL_EXPANSION * np.asarray(machine.tool_offset)
    np.testing.assert_allclose(
        spindle, np.broadcast_to(expected, spindle.shape), atol=EXACT_TOL * 1e-6
    )
    home = thermal_error(
        np.zeros((1, 3)), machine, 1.0, screw_expansion=0.0, spindle_expansion=0.0
    )
    growth = ALUMINIUM_EXPANSION * machine.platform_offset  # at home the legs lie along e_i
    np.testing.assert_allclose(home[0], np.full(3, growth), rtol=EXACT_TOL)


def test_the_geometric_term_is_the_parameters_spread_through_the_sensitivities(
    machine: og.OrthoglideParams,
) -> None:
    from orthoglide_pin.calibration.sensitivities import sensitivity

    nominal = og.GeometricModel.nominal(machine.leg_length)
    std = np.random.default_rng(SEED).uniform(1e-6, 2e-5, 18)
    calibration = og.Calibration(nominal, nominal, std, 1e-6, 1e-4, 1e-5, (), (), 30, "0" * 64)
    points = cube_points(machine, 5, SEED)
    got = geometric_error(calibration, points, machine)
    s = sensitivity(machine, points)
    cov = s @ np.diag(std**2) @ np.swapaxes(s, 1, 2)
    np.testing.assert_allclose(got, np.sqrt(np.diagonal(cov, axis1=1, axis2=2)), rtol=EXACT_TOL)


def test_the_terms_combine_worst_case_and_rss_with_the_dominant_one() -> None:
    params = og.prototype()
    points = cube_points(params, 4, SEED)
    deflection = np.array([[3e-6, 0, 0], [0, 1e-5, 0], [0, 0, 1e-9], [0, 0, 0]])
    normals = np.tile([0.0, 1.0, 0.0], (4, 1))
    budget = error_budget(points, params, compliance=deflection, servo=np.full(4, 2e-6),
                          normals=normals, temperature_rise=0.5)  # fmt: skip
    assert set(budget.terms) == {"servo", "compliance", "thermal"}
    np.testing.assert_allclose(budget.terms["servo"], 2e-6 * normals)
    norms = np.stack([np.linalg.norm(v, axis=1) for v in budget.terms.values()], axis=1)
    np.testing.assert_allclose(budget.worst_case, norms.sum(axis=1), rtol=EXACT_TOL)
    np.testing.assert_allclose(budget.rss, np.sqrt((norms**2).sum(axis=1)), rtol=EXACT_TOL)
    names = list(budget.terms)
    assert budget.dominant == tuple(names[k] for k in np.argmax(norms, axis=1))
    assert budget.dominant[1] == "compliance"
    summary = budget.summary()
    assert summary["dominant_count"]["compliance"] >= 1
    empty = error_budget(points, params)
    assert empty.terms == {} and empty.dominant == ("",) * 4
    np.testing.assert_array_equal(empty.worst_case, 0.0)


def test_bad_terms_are_named() -> None:
    points = np.zeros((2, 3))
    with pytest.raises(og.InvalidParameterError, match="compliance"):
        error_budget(points, compliance=np.zeros((3, 3)))
    with pytest.raises(og.InvalidParameterError, match="normals"):
        error_budget(points, servo=np.zeros(2))
    with pytest.raises(og.InvalidParameterError, match="temperature_rise"):
        error_budget(points, temperature_rise=1e4)
