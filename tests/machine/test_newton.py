from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.newton import NODES, path_extrapolation, pinv_rank, step_matrix

#: The lean residual against Pinocchio's per-closure route.
RESIDUAL_TOL = 1e-15
#: Step operator against the SVD pseudo-inverse.
OPERATOR_TOL = 1e-9
#: Lagrange extrapolation of a cubic from four nodes: exact up to rounding.
CUBIC_TOL = 1e-13


@pytest.mark.parametrize("offset", [0.0, 0.03])
def test_residual_and_operator_match_the_constraint_route(offset: float) -> None:
    params = og.prototype().replace(leg_length=0.36, platform_offset=offset)
    model = ClosedLoopModel(params)
    rng = np.random.default_rng(11)
    q = model.configuration(np.array([0.02, -0.03, 0.01])) + 1e-3 * rng.normal(size=model.nv)
    r_ref, k_ref = model.constraint_residual_and_jacobian(q)
    r = model._newton.residual(q).copy()
    np.testing.assert_allclose(r, r_ref, rtol=0, atol=RESIDUAL_TOL)
    assert np.abs(r).max() > 1e-5  # off the closed manifold: the residual is not trivial
    step, velocity = model._newton.operator(q)
    k_pinv, rank = pinv_rank(k_ref[:, model.passive])
    assert rank == 15
    np.testing.assert_allclose(step, -k_pinv, rtol=0, atol=OPERATOR_TOL)
    np.testing.assert_allclose(velocity, -k_pinv @ k_ref[:, model.actuated], atol=OPERATOR_TOL)


def test_step_matrix_falls_back_to_the_pseudo_inverse_when_rank_deficient() -> None:
    rng = np.random.default_rng(2)
    k_p = rng.normal(size=(21, 15))
    k_p[:, 14] = k_p[:, 13]  # two equal columns: rank 14
    step = step_matrix(k_p)
    assert np.all(np.isfinite(step))
    np.testing.assert_allclose(step, -pinv_rank(k_p)[0], atol=OPERATOR_TOL)
    assert pinv_rank(k_p)[1] == 14


def test_extrapolation_weights_are_exact_for_cubics() -> None:
    """On a straight slider path with uneven steps, the weights reproduce cubics of the chord."""
    rng = np.random.default_rng(5)
    chord = np.cumsum(np.concatenate([[0.0], 1e-4 * (1.0 + 0.5 * rng.random(30))]))
    rows = chord[:, None] * np.array([0.6, 0.0, 0.8])
    weights, smooth = path_extrapolation(rows)
    assert not smooth[:NODES].any() and smooth[NODES:].all()
    cubic = 2.0 - 3.0 * chord + 5.0 * chord**2 - 7.0 * chord**3
    for k in range(NODES, chord.size):
        assert weights[k] @ cubic[k - NODES : k] == pytest.approx(cubic[k], abs=CUBIC_TOL)


def test_extrapolation_is_refused_at_a_corner_and_a_repeated_row() -> None:
    line = 1e-4 * np.arange(20)[:, None] * np.array([0.6, 0.0, 0.8])
    turn = line[9] + (line[10:] - line[9]) @ np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]]).T
    _, smooth = path_extrapolation(np.concatenate([line[:10], turn]))
    assert smooth[:10].sum() == 10 - NODES and not smooth[10]
    repeated = np.concatenate([line[:8], line[7:]])  # a zero step
    _, smooth = path_extrapolation(repeated)
    assert not smooth[8 : 8 + NODES].any() and smooth[8 + NODES :].all()
    assert not path_extrapolation(line[:NODES])[1].any()
