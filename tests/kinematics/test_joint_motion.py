from __future__ import annotations

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, cube_points

import orthoglide_pin as og
from orthoglide_pin.kinematics.joint_motion import (
    LEG_AXES,
    LEG_JOINTS,
    gather,
    leg_motion,
    scatter,
)
from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: Closed form against Pinocchio-side configuration (same formulas, other code).
CONFIG_TOL = 1e-12
#: Central finite differences, step FD_STEP [s] on a smooth path: O(h^2) error.
FD_STEP = 1e-5
FD_TOL = 1e-7
#: Round trip tool -> sliders -> tool.
ROUND_TRIP_TOL = 1e-10


def _leg_indices(model: ClosedLoopModel) -> np.ndarray:
    pm = model.model
    return np.array(
        [
            [pm.joints[pm.getJointId(f"leg{i}_{s}")].idx_v for s, _, _ in LEG_JOINTS]
            for i in (1, 2, 3)
        ]
    )


def _path(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points well inside the cube, with random velocities and accelerations."""
    rng = np.random.default_rng(seed)
    p = CUBE_CORNER + 0.1 * CUBE_SIDE + 0.8 * CUBE_SIDE * rng.random((n, 3))
    return p, rng.standard_normal((n, 3)), 20.0 * rng.standard_normal((n, 3))


def test_positions_equal_the_configuration_of_the_closed_loop_model(
    model: ClosedLoopModel,
) -> None:
    p = cube_points(50, seed=1)
    zero = np.zeros_like(p)
    motion = leg_motion(p, zero, zero, PROTOTYPE_LEG)
    q = scatter(motion.values, _leg_indices(model))
    np.testing.assert_allclose(q, model.configuration(p), atol=CONFIG_TOL)
    np.testing.assert_allclose(
        motion.values[:, :, 0], og.inverse_kinematics(p, PROTOTYPE_LEG), atol=CONFIG_TOL
    )


def test_rates_and_gradients_match_finite_differences() -> None:
    p, pd, pdd = _path(30, seed=2)
    motion = leg_motion(p, pd, pdd, PROTOTYPE_LEG)
    zero = np.zeros_like(p)

    def values(t: float) -> np.ndarray:
        pt = p + t * pd + 0.5 * t * t * pdd
        return leg_motion(pt, zero, zero, PROTOTYPE_LEG).values

    def rates(t: float) -> np.ndarray:
        pt, vt = p + t * pd + 0.5 * t * t * pdd, pd + t * pdd
        return leg_motion(pt, vt, zero, PROTOTYPE_LEG).rates

    h = FD_STEP
    np.testing.assert_allclose(motion.rates, (values(h) - values(-h)) / (2 * h), atol=FD_TOL)
    scale = np.max(np.abs(motion.accelerations))
    fd_acc = (rates(h) - rates(-h)) / (2 * h)
    assert np.max(np.abs(motion.accelerations - fd_acc)) <= FD_TOL * scale
    # the gradient contracts with the velocity to the rate
    np.testing.assert_allclose(
        np.einsum("nlfw,nw->nlf", motion.gradients, pd), motion.rates, atol=1e-12
    )


def test_slider_rates_follow_the_inverse_jacobian_of_the_paper() -> None:
    p, pd, _ = _path(20, seed=3)
    motion = leg_motion(p, pd, np.zeros_like(p), PROTOTYPE_LEG)
    q_dot = np.einsum("nij,nj->ni", og.inverse_jacobian(p, PROTOTYPE_LEG), pd)
    np.testing.assert_allclose(motion.rates[:, :, 0], q_dot, atol=1e-12)


def test_parallelogram_and_platform_stay_parallel_at_home() -> None:
    """At the isotropic point, a tool speed along e_i moves slider i alone, 1:1."""
    motion = leg_motion(np.zeros((3, 3)), np.eye(3), np.zeros((3, 3)), PROTOTYPE_LEG)
    np.testing.assert_allclose(motion.rates[:, :, 0], np.eye(3), atol=1e-15)
    # leg j turns (theta) at -v / L for a speed along z_l = e_(j+2), opens (phi) along e_(j+1)
    for axis in range(3):
        for leg in range(3):
            theta_rate = -1.0 / PROTOTYPE_LEG if axis == (leg + 2) % 3 else 0.0
            phi_rate = 1.0 / PROTOTYPE_LEG if axis == (leg + 1) % 3 else 0.0
            assert motion.rates[axis, leg, 1] == pytest.approx(theta_rate, abs=1e-15)
            assert motion.rates[axis, leg, 2] == pytest.approx(phi_rate, abs=1e-15)


def test_gather_is_the_transpose_of_scatter(model: ClosedLoopModel) -> None:
    rng = np.random.default_rng(4)
    idx = _leg_indices(model)
    x, y = rng.standard_normal((5, 3, 3)), rng.standard_normal((5, 18))
    lhs = np.einsum("nj,nj->n", scatter(x, idx), y)
    rhs = np.einsum("nlf,nlf->n", x, gather(y, idx))
    np.testing.assert_allclose(lhs, rhs, rtol=1e-13)


def test_tool_motion_from_sliders_inverts_the_joint_motion() -> None:
    p, pd, pdd = _path(40, seed=5)
    motion = leg_motion(p, pd, pdd, PROTOTYPE_LEG)
    q, qd, qdd = (x[:, :, 0] for x in (motion.values, motion.rates, motion.accelerations))
    p2, pd2, pdd2 = og.tool_motion_from_sliders(q, qd, qdd, PROTOTYPE_LEG)
    np.testing.assert_allclose(p2, p, atol=ROUND_TRIP_TOL)
    np.testing.assert_allclose(pd2, pd, atol=ROUND_TRIP_TOL)
    np.testing.assert_allclose(pdd2, pdd, atol=ROUND_TRIP_TOL * 20)


def test_bad_input_is_reported() -> None:
    ok = np.zeros((2, 3))
    with pytest.raises(og.InvalidParameterError):
        leg_motion(ok, np.zeros((3, 3)), ok, PROTOTYPE_LEG)
    with pytest.raises(og.InvalidParameterError):
        leg_motion(ok, ok, np.full((2, 3), np.nan), PROTOTYPE_LEG)
    with pytest.raises(og.InvalidParameterError):
        leg_motion(np.zeros(3), np.zeros(3), np.zeros(3), PROTOTYPE_LEG)
    with pytest.raises(og.UnreachablePointError):
        leg_motion(np.array([[0.0, 0.3, 0.3]]), np.zeros((1, 3)), np.zeros((1, 3)), PROTOTYPE_LEG)
    with pytest.raises(og.NoAssemblyError):
        og.tool_motion_from_sliders(
            np.full((1, 3), -0.5), np.zeros((1, 3)), np.zeros((1, 3)), PROTOTYPE_LEG
        )


#: path_motion against leg_motion: the same formulas in another layout.
LAYOUT_TOL = 1e-12


@pytest.mark.parametrize("leg", [PROTOTYPE_LEG, 0.36])
def test_path_motion_is_leg_motion_leg_by_leg(leg: float) -> None:
    p, t, k = _path(60, seed=9)
    p *= leg / PROTOTYPE_LEG
    ref = leg_motion(p, t, k, leg)
    got = og.path_motion(p, t, k, leg)
    lay = (2, 1, 0)  # (point, leg, function) -> (function, leg, point)
    np.testing.assert_allclose(got.slider, ref.values[:, :, 0].T, rtol=0, atol=LAYOUT_TOL)
    np.testing.assert_allclose(got.first, ref.rates.transpose(1, 2, 0), rtol=0, atol=LAYOUT_TOL)
    np.testing.assert_allclose(
        got.second, ref.accelerations.transpose(1, 2, 0), rtol=0, atol=1e3 * LAYOUT_TOL
    )
    theta, phi = ref.values.transpose(lay)[1:]
    for value, expected in (
        (got.cos_theta, np.cos(theta)),
        (got.sin_theta, np.sin(theta)),
        (got.cos_phi, np.cos(phi)),
        (got.sin_phi, np.sin(phi)),
    ):
        np.testing.assert_allclose(value, expected, rtol=0, atol=LAYOUT_TOL)
    # the gradients along the leg's (y, z) axes; theta and phi have none along x
    for leg_index in range(3):
        axes = LEG_AXES[leg_index]
        grads = ref.gradients[:, leg_index]  # (point, function, world)
        np.testing.assert_allclose(grads[:, 1:, axes[0]], 0.0, atol=0)
        np.testing.assert_allclose(
            got.theta_gradient[leg_index], grads[:, 1, axes[1:]].T, rtol=0, atol=LAYOUT_TOL
        )
        np.testing.assert_allclose(got.phi_gradient[leg_index], grads[:, 2, axes[1]], atol=0)
        np.testing.assert_allclose(grads[:, 2, axes[2]], 0.0, atol=0)


def test_path_motion_takes_curvatures_beyond_accelerations() -> None:
    """A radius of 1 um (curvature 1e6 1/m) is accepted; second derivatives are affine in it."""
    p, t, _ = _path(5, seed=10)
    k = np.zeros_like(p)
    k[:, 1] = 1e6
    zero = og.path_motion(p, t, np.zeros_like(p), PROTOTYPE_LEG)
    curved = og.path_motion(p, t, k, PROTOTYPE_LEG)
    grads = leg_motion(p, t, np.zeros_like(p), PROTOTYPE_LEG).gradients
    expected = zero.second + 1e6 * grads[:, :, :, 1].transpose(1, 2, 0)
    np.testing.assert_allclose(curved.second, expected, rtol=1e-12)


def test_path_motion_names_bad_input() -> None:
    ok = np.zeros((2, 3))
    for kwargs, match in (
        ({"tangents": np.zeros((3, 3))}, "shapes"),
        ({"points": np.full((2, 3), np.nan)}, "points"),
        ({"tangents": np.full((2, 3), 2e3)}, "tangents"),
        ({"curvatures": np.full((2, 3), 2e9)}, "curvatures"),
    ):
        args = {"points": ok, "tangents": ok, "curvatures": ok} | kwargs
        with pytest.raises(og.InvalidParameterError, match=match):
            og.path_motion(**args, leg_length=PROTOTYPE_LEG)
    with pytest.raises(og.UnreachablePointError):
        og.path_motion([[0.0, 0.3, 0.3]], [[1.0, 0, 0]], np.zeros((1, 3)), PROTOTYPE_LEG)
