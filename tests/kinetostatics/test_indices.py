"""Tests of the kinetostatic indices (orthoglide_pin.kinetostatics.indices)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.kinematics.closed_form import inverse_jacobian, jacobian
from orthoglide_pin.kinetostatics.indices import (
    condition_number,
    force_ellipsoid,
    indices_from_jacobian,
    indices_from_model,
    inverse_condition,
    isotropy_residuals,
    kinetostatic_indices,
    manipulability,
    transmission_factors,
    velocity_ellipsoid,
)

# Paper prototype (section 4): leg length [m], prescribed cube (Q1 corner, side) [m].
L = 0.31
CORNER = -L / math.sqrt(18.0)
SIDE = 0.2
SEED = 20240611

#: Identities that hold to rounding.
EXACT_TOL = 1e-12
#: Closed form vs LAPACK, relative.
LAPACK_RTOL = 1e-9
#: Closed form vs the Pinocchio closed-loop Jacobian (its loop-closure accuracy).
PINOCCHIO_RTOL = 1e-8
#: Smallest relative gap between factors for directions to be compared one by one.
DISTINCT_GAP = 1e-3


def cube_points(n: int, seed: int = SEED) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return CORNER + SIDE * rng.random((n, 3))


def test_home_is_isotropic() -> None:
    home = np.zeros(3)
    assert condition_number(home, L) == pytest.approx(1.0, abs=EXACT_TOL)
    assert inverse_condition(home, L) == pytest.approx(1.0, abs=EXACT_TOL)
    assert manipulability(home, L) == pytest.approx(1.0, abs=EXACT_TOL)
    axes, directions = velocity_ellipsoid(home, L)
    np.testing.assert_allclose(axes, 1.0, atol=EXACT_TOL)
    np.testing.assert_allclose(directions @ directions.T, np.eye(3), atol=EXACT_TOL)
    assert isotropy_residuals(home, L).max == 0.0


def test_condition_and_manipulability_against_lapack() -> None:
    points = cube_points(500)
    J = jacobian(points, L)
    s = np.linalg.svd(J, compute_uv=False)
    np.testing.assert_allclose(condition_number(points, L), s[:, 0] / s[:, 2], rtol=LAPACK_RTOL)
    np.testing.assert_allclose(inverse_condition(points, L), s[:, 2] / s[:, 0], rtol=LAPACK_RTOL)
    det = manipulability(points, L)
    np.testing.assert_allclose(det, np.linalg.det(J), rtol=LAPACK_RTOL)
    # positive on the working mode: the product of the transmission factors
    np.testing.assert_allclose(det, transmission_factors(points, L).prod(axis=-1), rtol=1e-12)
    assert (condition_number(points, L) >= 1.0).all()


def test_velocity_ellipsoid_is_the_image_of_the_unit_ball() -> None:
    points = cube_points(300, SEED + 1)
    axes, dirs = velocity_ellipsoid(points, L)
    J = jacobian(points, L)
    eye = np.broadcast_to(np.eye(3), dirs.shape)
    np.testing.assert_allclose(np.swapaxes(dirs, -1, -2) @ dirs, eye, atol=EXACT_TOL)
    np.testing.assert_allclose(np.linalg.det(dirs), 1.0, atol=EXACT_TOL)
    # D diag(a^2) D^T = J J^T
    jjt = (dirs * axes[:, None, :] ** 2) @ np.swapaxes(dirs, -1, -2)
    np.testing.assert_allclose(jjt, J @ np.swapaxes(J, -1, -2), atol=EXACT_TOL)
    # the tips of the semi-axes come from unit slider speeds: |J^-1 (a_k d_k)| = 1
    tips = dirs * axes[:, None, :]
    q_dot = inverse_jacobian(points, L) @ tips
    np.testing.assert_allclose(np.linalg.norm(q_dot, axis=-2), 1.0, rtol=EXACT_TOL)


def test_force_ellipsoid_by_virtual_work() -> None:
    points = cube_points(300, SEED + 2)
    f_axes, f_dirs = force_ellipsoid(points, L)
    v_axes, v_dirs = velocity_ellipsoid(points, L)
    np.testing.assert_allclose(f_axes, 1.0 / v_axes, rtol=EXACT_TOL)
    np.testing.assert_array_equal(f_dirs, v_dirs)
    J = jacobian(points, L)
    forces = f_dirs * f_axes[:, None, :]  # tips of the semi-axes, tool forces [N]
    tau = np.swapaxes(J, -1, -2) @ forces  # actuator forces balancing them
    np.testing.assert_allclose(np.linalg.norm(tau, axis=-2), 1.0, rtol=EXACT_TOL)
    # virtual work: tau . q_dot = f . p_dot for any motion p_dot = J q_dot
    q_dot = np.random.default_rng(SEED).normal(size=(points.shape[0], 3))
    p_dot = np.einsum("nij,nj->ni", J, q_dot)
    np.testing.assert_allclose(
        np.einsum("nik,ni->nk", tau, q_dot),
        np.einsum("nik,ni->nk", forces, p_dot),
        atol=EXACT_TOL,
    )


def test_isotropy_residuals_rebuild_the_paper_matrix() -> None:
    points = cube_points(200, SEED + 3)
    res = isotropy_residuals(points, L)
    k = 1.0 + res.eq5
    np.testing.assert_allclose(res.eq3, k - np.roll(k, -1, axis=-1), atol=EXACT_TOL)
    # N = J^-1 J^-T: diagonal k_i^2, off-diagonal cos(u_i, u_j) k_i k_j
    n = np.einsum("...ij,...kj->...ik", inverse_jacobian(points, L), inverse_jacobian(points, L))
    for i in range(3):
        j = (i + 1) % 3
        np.testing.assert_allclose(n[:, i, i], k[:, i] ** 2, rtol=EXACT_TOL)
        np.testing.assert_allclose(n[:, i, j], res.eq4[:, i] * k[:, i] * k[:, j], atol=EXACT_TOL)
    # zero only at home: away from it, some condition fails
    assert (res.max > 0.0).all()


def test_closed_form_and_lapack_routes_agree() -> None:
    points = cube_points(200, SEED + 4)
    cf = kinetostatic_indices(points, L)
    la = indices_from_jacobian(jacobian(points, L))
    for name in ("transmission_factors", "condition", "manipulability", "force_axes"):
        np.testing.assert_allclose(getattr(cf, name), getattr(la, name), rtol=LAPACK_RTOL)
    distinct = (np.diff(cf.transmission_factors, axis=-1) > DISTINCT_GAP).all(axis=-1)
    dots = np.abs(np.einsum("nik,nik->nk", cf.velocity_directions, la.velocity_directions))
    np.testing.assert_allclose(dots[distinct], 1.0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.det(la.velocity_directions), 1.0, atol=EXACT_TOL)


def test_pinocchio_route_agrees_with_the_closed_form(model: og.ClosedLoopModel) -> None:
    points = np.vstack([cube_points(4, SEED + 5), np.full(3, CORNER), np.full(3, CORNER + SIDE)])
    for p in points:
        assembly = model.solve(og.inverse_kinematics(p, L))
        pin_route = indices_from_model(model, assembly.q)
        cf = kinetostatic_indices(p, L)
        np.testing.assert_allclose(
            pin_route.transmission_factors, cf.transmission_factors, rtol=PINOCCHIO_RTOL
        )
        assert pin_route.condition == pytest.approx(float(cf.condition), rel=PINOCCHIO_RTOL)
        assert pin_route.manipulability == pytest.approx(
            float(cf.manipulability), rel=PINOCCHIO_RTOL
        )
        # same ellipsoid (directions may differ inside a repeated factor's eigenspace)
        shape_pin = (pin_route.velocity_directions * pin_route.velocity_axes**2) @ (
            pin_route.velocity_directions.T
        )
        shape_cf = (cf.velocity_directions * cf.velocity_axes**2) @ cf.velocity_directions.T
        np.testing.assert_allclose(shape_pin, shape_cf, atol=PINOCCHIO_RTOL)


def test_to_dict_is_json() -> None:
    data = json.loads(json.dumps(kinetostatic_indices([0.02, -0.01, 0.05], L).to_dict()))
    assert set(data) >= {"transmission_factors", "condition", "velocity_ellipsoid"}
    # each ellipsoid is a list of axes: a semi-axis and its unit direction (not columns)
    result = kinetostatic_indices([0.02, -0.01, 0.05], L)
    axes = data["force_ellipsoid"]["axes"]
    assert len(axes) == 3
    for k, axis in enumerate(axes):
        assert axis["semi_axis"] == result.force_axes[k]
        assert axis["direction"] == result.force_directions[:, k].tolist()
    several = kinetostatic_indices([[0.02, -0.01, 0.05], [0.0, 0.0, 0.0]], L).to_dict()
    assert several["velocity_ellipsoid"]["axes"][1][2]["semi_axis"] == pytest.approx(1.0)


def test_errors() -> None:
    with pytest.raises(UnreachablePointError):
        velocity_ellipsoid([0.0, 0.3, 0.3], L)
    with pytest.raises(SingularConfigurationError):
        manipulability(np.full(3, L / math.sqrt(3.0)), L)
    with pytest.raises(SingularConfigurationError):
        isotropy_residuals([0.0, L, 0.0], L)
    with pytest.raises(InvalidParameterError):
        indices_from_jacobian(np.eye(2))
    with pytest.raises(InvalidParameterError):
        indices_from_jacobian(np.full((3, 3), np.nan))
    unchecked = manipulability([[0.0, 0.3, 0.3], [0.0, 0.0, 0.0]], L, check=False)
    assert np.isnan(unchecked[0])
    assert unchecked[1] == pytest.approx(1.0, abs=EXACT_TOL)


def test_the_pinocchio_route_takes_the_parameters_of_another_design() -> None:
    other = og.prototype().replace(leg_length=0.36)
    model = og.ClosedLoopModel(other)
    point = np.array([0.03, -0.02, 0.04])
    q = model.solve(og.inverse_kinematics(point, 0.36)).q
    from_params = indices_from_model(other, q)
    np.testing.assert_array_equal(
        from_params.transmission_factors, indices_from_model(model, q).transmission_factors
    )
    np.testing.assert_allclose(
        from_params.transmission_factors,
        kinetostatic_indices(point, 0.36).transmission_factors,
        rtol=PINOCCHIO_RTOL,
    )
    with pytest.raises(InvalidParameterError, match="model"):
        indices_from_model("prototype", q)  # type: ignore[arg-type]


def test_the_pinocchio_route_checks_the_slider_limits(model: og.ClosedLoopModel) -> None:
    params = model.params
    beyond = np.array([0.2, 0.0, 0.0])  # reachable; slider 1 at 0.2 m, past its 0.184 m
    q_a = og.inverse_kinematics(beyond, L)
    assert q_a[0] > params.slider_upper
    q = model.solve(q_a).q
    with pytest.raises(InvalidParameterError) as info:
        indices_from_model(model, q)
    assert info.value.name == "q1" and "slider limits" in str(info.value)
    assert "check_limits=False" in str(info.value)
    # asked not to check: the closed form's indices there
    there = indices_from_model(model, q, check_limits=False)
    np.testing.assert_allclose(
        there.transmission_factors,
        kinetostatic_indices(beyond, L).transmission_factors,
        rtol=PINOCCHIO_RTOL,
    )
    on_limit = model.solve(og.inverse_kinematics(params.workspace.q2, L)).q
    indices_from_model(model, on_limit)  # the cube's corner reaches the limit: accepted
