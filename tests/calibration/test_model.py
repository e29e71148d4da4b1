"""The 18-parameter geometric model: nominal = closed form, round trips, derivatives."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel
from orthoglide_pin.kinematics import closed_form

#: Agreement of the nominal model with the closed form [m].
NOMINAL_TOL = 1e-14
#: fk(ik(p)) round trip on an erroneous machine [m] (the issue's 1e-12).
ROUND_TRIP_TOL = 1e-12
#: Pinocchio closed-loop model of an erroneous description against the model [m].
PINOCCHIO_TOL = 1e-9
#: Central finite differences against the analytic derivatives (relative).
FD_TOL = 1e-6
#: Errors of a realistic built machine, per leg: 0.2 mm, 0.5 mrad, 0.1 mm.
ERROR_SCALE = np.tile([2e-4, 2e-4, 2e-4, 5e-4, 5e-4, 1e-4], 3)


def _cube_points(params: og.OrthoglideParams, n: int, seed: int) -> np.ndarray:
    cube = params.workspace
    lo = np.asarray(cube.corner)
    return np.random.default_rng(seed).uniform(lo, lo + cube.side, (n, 3))


def _erroneous(params: og.OrthoglideParams, seed: int) -> GeometricModel:
    nominal = GeometricModel.nominal(params.leg_length)
    noise = np.random.default_rng(seed).normal(size=18) * ERROR_SCALE
    return GeometricModel.from_vector(nominal.vector() + noise)


@pytest.mark.parametrize("leg", [0.31, 0.35])
def test_nominal_model_is_the_closed_form(leg: float) -> None:
    params = og.prototype().replace(leg_length=leg)
    model = GeometricModel.nominal(leg)
    p = _cube_points(params, 200, seed=1)
    q = closed_form.inverse_kinematics(p, leg)
    np.testing.assert_allclose(model.inverse_kinematics(p), q, rtol=0, atol=NOMINAL_TOL)
    np.testing.assert_allclose(model.direct_kinematics(q), p, rtol=0, atol=NOMINAL_TOL)
    np.testing.assert_allclose(
        model.inverse_jacobian(p), closed_form.inverse_jacobian(p, leg), atol=1e-13
    )
    np.testing.assert_allclose(model.jacobian(p), closed_form.jacobian(p, leg), atol=1e-12)


def test_home_is_home() -> None:
    model = GeometricModel.nominal(0.31)
    np.testing.assert_allclose(model.direct_kinematics(np.zeros(3)), np.zeros(3), atol=1e-15)
    np.testing.assert_array_equal(model.jacobian(np.zeros(3)), np.eye(3))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_round_trip_on_an_erroneous_machine(seed: int) -> None:
    params = og.prototype()
    model = _erroneous(params, seed)
    p = _cube_points(params, 500, seed)
    q = model.inverse_kinematics(p)
    np.testing.assert_allclose(model.direct_kinematics(q), p, rtol=0, atol=ROUND_TRIP_TOL)
    # the constraint itself holds: ||P - a_i - q_i u_i|| = L_i
    w = p[:, None, :] - model.anchors - q[:, :, None] * model.directions
    np.testing.assert_allclose(np.linalg.norm(w, axis=2), np.broadcast_to(model.lengths, q.shape))


def test_parameter_vector_round_trip() -> None:
    model = _erroneous(og.prototype(), 3)
    again = GeometricModel.from_vector(model.vector())
    np.testing.assert_array_equal(again.vector(), model.vector())
    assert len(PARAMETER_NAMES) == 18 and len(set(PARAMETER_NAMES)) == 18
    np.testing.assert_allclose(np.linalg.norm(model.directions, axis=1), 1.0, rtol=1e-15)


def test_jacobians_against_finite_differences() -> None:
    params = og.prototype().replace(leg_length=0.35)
    model = _erroneous(params, 4)
    p = _cube_points(params, 20, 4)
    q = model.inverse_kinematics(p)
    h = 1e-7
    # dq/dP
    fd = np.stack(
        [
            (model.inverse_kinematics(p + h * e) - model.inverse_kinematics(p - h * e)) / (2 * h)
            for e in np.eye(3)
        ],
        axis=-1,
    )
    np.testing.assert_allclose(model.inverse_jacobian(p), fd, rtol=FD_TOL, atol=FD_TOL)
    np.testing.assert_allclose(model.jacobian(p) @ fd, np.broadcast_to(np.eye(3), fd.shape),
                               atol=FD_TOL)  # fmt: skip
    # dP/dtheta at fixed q
    theta = model.vector()
    fd_theta = np.empty((len(q), 3, 18))
    for k in range(18):
        e = np.zeros(18)
        e[k] = h
        plus = GeometricModel.from_vector(theta + e).direct_kinematics(q)
        minus = GeometricModel.from_vector(theta - e).direct_kinematics(q)
        fd_theta[:, :, k] = (plus - minus) / (2 * h)
    np.testing.assert_allclose(model.parameter_jacobian(q), fd_theta, rtol=FD_TOL, atol=FD_TOL)


def test_leg_length_error_moves_the_tool_along_the_leg() -> None:
    # At home, a longer leg 1 pushes the tool along +e1 by the same amount; legs
    # 2 and 3 then tilt, which moves it along e2 and e3 by -d^2 / (2 L) (to
    # second order, equally by symmetry).
    L, d = 0.31, 1e-4
    theta = GeometricModel.nominal(L).vector()
    theta[PARAMETER_NAMES.index("L1")] += d
    p = GeometricModel.from_vector(theta).direct_kinematics(np.zeros(3))
    np.testing.assert_allclose(p, [d, -(d**2) / (2 * L), -(d**2) / (2 * L)], rtol=1e-3)


def test_bad_values_are_refused() -> None:
    with pytest.raises(og.InvalidParameterError, match="theta"):
        GeometricModel.from_vector(np.ones(17))
    with pytest.raises(og.InvalidParameterError, match="alpha"):
        GeometricModel(-0.31 * np.eye(3), [0.5, 0, 0], np.zeros(3), np.full(3, 0.31))
    with pytest.raises(og.InvalidParameterError, match="lengths"):
        GeometricModel(-0.31 * np.eye(3), np.zeros(3), np.zeros(3), [0.31, -1, 0.31])
    model = GeometricModel.nominal(0.31)
    with pytest.raises(og.UnreachablePointError):
        model.inverse_kinematics([0.0, 0.4, 0.0])
    with pytest.raises(og.NoAssemblyError):
        model.direct_kinematics([0.0, 0.0, 0.9])


@pytest.mark.parametrize("leg", [0.31, 0.35])
def test_the_description_of_a_built_machine_agrees_with_the_model(leg: float) -> None:
    """Pinocchio's closed loops on the erroneous URDF give the model's tool point."""
    params = og.prototype().replace(leg_length=leg)
    true = _erroneous(params, 17)
    urdf = og.render_urdf(params, legs=true.legs(leg))
    model = og.ClosedLoopModel(params, urdf=urdf)
    p = _cube_points(params, 10, 17)
    for q, point in zip(true.inverse_kinematics(p), p, strict=True):
        assembly = model.solve(q)
        np.testing.assert_allclose(assembly.tool_position, point, rtol=0, atol=PINOCCHIO_TOL)
    # the drawing's model misses the same points by the errors' size
    drawing = og.ClosedLoopModel(params)
    q = true.inverse_kinematics(p[0])
    assert np.linalg.norm(drawing.solve(q).tool_position - p[0]) > 1e-5
