"""Measurement planning: D-optimal poses beat random ones, and predict the fit."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.experiment import (
    candidate_points,
    expected_std,
    information,
    plan_poses,
)
from orthoglide_pin.calibration.identification import identify
from orthoglide_pin.calibration.model import GeometricModel

#: Tracker noise [m].
NOISE = 5e-6
#: Random draws compared with the plan.
DRAWS = 20


@pytest.fixture(scope="module")
def params() -> og.OrthoglideParams:
    return og.prototype().replace(leg_length=0.34)


@pytest.fixture(scope="module")
def plan(params: og.OrthoglideParams):
    return plan_poses(params, 30, noise=NOISE, grid=7)


def test_plan_is_in_the_cube_and_distinct(params, plan) -> None:
    cand = candidate_points(params, 7)
    assert plan.points.shape == (30, 3) and len({tuple(p) for p in plan.points}) == 30
    assert all((cand == p).all(axis=1).any() for p in plan.points)
    q = og.inverse_kinematics(plan.points, params.leg_length)
    np.testing.assert_allclose(plan.q, q, atol=1e-15)
    assert (q >= params.slider_lower - 1e-12).all() and (q <= params.slider_upper + 1e-12).all()


def test_plan_beats_random_poses(params, plan) -> None:
    nominal = GeometricModel.nominal(params.leg_length)
    rng = np.random.default_rng(0)
    lo = np.asarray(params.workspace.corner)
    for _ in range(DRAWS):
        p = rng.uniform(lo, lo + params.workspace.side, (30, 3))
        _, log_det = np.linalg.slogdet(information(nominal, nominal.inverse_kinematics(p)))
        assert log_det < plan.log_det
    worst_random = expected_std(nominal, nominal.inverse_kinematics(p), NOISE)
    assert np.max(plan.expected_std) < np.max(worst_random)


def test_expected_deviations_match_a_monte_carlo_fit(params, plan) -> None:
    nominal = GeometricModel.nominal(params.leg_length)
    rng = np.random.default_rng(3)
    true = GeometricModel.from_vector(nominal.vector() + rng.normal(0, 1e-4, 18))
    q = true.inverse_kinematics(plan.points)
    errors = []
    for _ in range(40):
        m = plan.points + rng.normal(0, NOISE, plan.points.shape)
        errors.append(identify(q, m, nominal).model.vector() - true.vector())
    spread = np.std(errors, axis=0)
    # 40 draws: the sample deviation is within ~25 % of the truth; the expected
    # deviations are at the nominal geometry, a hair from the true one
    np.testing.assert_allclose(spread, plan.expected_std, rtol=0.35)


@pytest.mark.parametrize(("count", "grid"), [(9, 7), (344, 7), (True, 7), (20, 1), (20, 50)])
def test_bad_requests(params, count, grid) -> None:
    with pytest.raises(og.InvalidParameterError):
        plan_poses(params, count, grid=grid)


def test_the_progress_counts_the_poses(params: og.OrthoglideParams) -> None:
    calls: list[tuple[int, int]] = []
    plan_poses(params, 12, grid=4, progress=lambda d, t: calls.append((d, t)))
    assert calls == [(k, 12) for k in range(1, 13)]
