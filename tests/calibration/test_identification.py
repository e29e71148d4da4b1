"""Identification: simulated machines with known errors and noise, recovered."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.identification import MIN_POSES, identify
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel

#: Tracker noise per axis [m].
NOISE = 5e-6
#: Errors of a built machine, per leg: 0.2 mm, 0.5 mrad, 0.1 mm.
ERROR_SCALE = np.tile([2e-4, 2e-4, 2e-4, 5e-4, 5e-4, 1e-4], 3)
#: Share of identified parameters within 3 standard deviations of the truth.
COVERAGE = 0.95
#: Seeds of the simulated machines.
SEEDS = range(8)


def _machine(leg: float, seed: int) -> tuple[GeometricModel, GeometricModel]:
    nominal = GeometricModel.nominal(leg)
    noise = np.random.default_rng(seed).normal(size=18) * ERROR_SCALE
    return nominal, GeometricModel.from_vector(nominal.vector() + noise)


def _poses(params: og.OrthoglideParams, true: GeometricModel, n: int, seed: int):
    rng = np.random.default_rng(1000 + seed)
    cube = params.workspace
    lo = np.asarray(cube.corner)
    p = rng.uniform(lo, lo + cube.side, (n, 3))
    q = true.inverse_kinematics(p)
    return q, p + rng.normal(0.0, NOISE, p.shape), p


@pytest.mark.parametrize("leg", [0.31, 0.35])
def test_parameters_lie_within_their_standard_deviations(leg: float) -> None:
    params = og.prototype().replace(leg_length=leg)
    inside, total = 0, 0
    for seed in SEEDS:
        nominal, true = _machine(leg, seed)
        q, measured, _ = _poses(params, true, 60, seed)
        result = identify(q, measured, nominal)
        z = np.abs(result.model.vector() - true.vector()) / result.std
        inside += int(np.sum(z <= 3.0))
        total += z.size
        assert result.outliers == ()
        assert result.unidentifiable == ()
        # the noise estimate is the simulated noise (chi-square with ~160 dof)
        assert 0.75 * NOISE < result.noise_estimate < 1.25 * NOISE
        # 0.1 to 0.5 mm off before, at the noise level after
        assert 5e-5 < result.rms_before < 1e-3
        assert result.rms_after < 2.0 * np.sqrt(3) * NOISE
    assert inside / total >= COVERAGE


def test_held_out_prediction_error_is_at_the_noise_level() -> None:
    params = og.prototype()
    nominal, true = _machine(params.leg_length, 11)
    q, measured, _ = _poses(params, true, 60, 11)
    result = identify(q, measured, nominal)
    # 200 new poses, never seen by the fit: commanded from the identified model
    rng = np.random.default_rng(5)
    lo = np.asarray(params.workspace.corner)
    targets = rng.uniform(lo, lo + params.workspace.side, (200, 3))
    reached = true.direct_kinematics(result.model.inverse_kinematics(targets))
    error = np.linalg.norm(reached - targets, axis=1)
    uncompensated = np.linalg.norm(true.direct_kinematics(nominal.inverse_kinematics(targets))
                                   - targets, axis=1)  # fmt: skip
    # the parameters are known to ~std, so the prediction is within a few noise levels
    assert np.sqrt(np.mean(error**2)) < 3.0 * NOISE
    assert np.sqrt(np.mean(uncompensated**2)) > 20.0 * np.sqrt(np.mean(error**2))


def test_planted_outliers_are_found_and_left_out() -> None:
    params = og.prototype()
    nominal, true = _machine(params.leg_length, 21)
    q, measured, _ = _poses(params, true, 80, 21)
    planted = [4, 30, 77]
    keep = np.setdiff1d(np.arange(80), planted)
    clean = identify(q[keep], measured[keep], nominal)  # the same fit without them
    measured[planted] += np.array([[1e-3, 0, 0], [0, -2e-4, 3e-4], [0, 0, 5e-3]])
    result = identify(q, measured, nominal)
    assert result.outliers == tuple(planted)
    np.testing.assert_allclose(result.model.vector(), clean.model.vector(), atol=1e-9)
    assert result.inliers.sum() == 77


def test_planar_and_linear_data_sets_are_refused() -> None:
    params = og.prototype()
    nominal, true = _machine(params.leg_length, 31)
    _, _, p = _poses(params, true, 60, 31)
    p[:, 2] = 0.02  # every pose on one plane
    q = true.inverse_kinematics(p)
    with pytest.raises(og.CalibrationError, match="cannot determine 2 combination"):
        identify(q, p, nominal)
    line = np.linspace(-0.05, 0.1, 30)[:, None] * np.ones(3)
    with pytest.raises(og.CalibrationError, match="cannot determine"):
        identify(true.inverse_kinematics(line), line, nominal)


def test_partial_identification_holds_the_undetermined_combinations() -> None:
    params = og.prototype()
    nominal, true = _machine(params.leg_length, 41)
    rng = np.random.default_rng(41)
    lo = np.asarray(params.workspace.corner)
    p = rng.uniform(lo, lo + params.workspace.side, (60, 3))
    p[:, 2] = 0.02
    q = true.inverse_kinematics(p)
    measured = p + rng.normal(0, NOISE, p.shape)
    result = identify(q, measured, nominal, allow_partial=True)
    assert len(result.unidentifiable) == 2
    assert all(isinstance(c, float) for combo in result.unidentifiable for c in combo.values())
    # the poses themselves are still fitted to the noise level
    assert result.rms_after < 2.0 * np.sqrt(3) * NOISE
    # and the fit moved nothing along the held combinations, in the scaled parameters
    assert set().union(*result.unidentifiable) <= set(PARAMETER_NAMES)


def test_too_few_poses_and_bad_shapes() -> None:
    nominal = GeometricModel.nominal(0.31)
    q = np.zeros((MIN_POSES - 1, 3))
    with pytest.raises(og.CalibrationError, match=f"{MIN_POSES - 1} poses"):
        identify(q, q, nominal)
    with pytest.raises(og.InvalidParameterError, match=r"measured\.shape"):
        identify(np.zeros((12, 3)), np.zeros((12, 2)), nominal)  # an argument of the wrong shape
    with pytest.raises(og.CalibrationError, match="shape"):
        identify(np.zeros((12, 3)), np.zeros((11, 3)), nominal)  # two shapes that disagree
