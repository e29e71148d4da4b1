"""Slider forces and accelerations as forms in the tool motion, against inverse dynamics."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, cube_points, unit_sphere

import orthoglide_pin as og
from orthoglide_pin.dynamics import leg_harmonics as leg_harmonics_module
from orthoglide_pin.dynamics.forward import mechanical_energy
from orthoglide_pin.dynamics.motion_forms import (
    MotionForm,
    RequirementForms,
    function_hessians,
    requirement_forms,
)
from orthoglide_pin.kinematics.joint_motion import leg_motion

#: Forms against a direct inverse-dynamics call and the black-box route (rounding).
FORM_RTOL = 1e-9
#: Absolute floor of the comparisons of forces [N].
FORCE_ATOL = 1e-9
#: Energy route against the mass matrix (two independent Pinocchio routes).
ENERGY_RTOL = 1e-9
#: Central finite differences of the tool-space mass matrix, step [m].
FD_STEP = 1e-5
FD_RTOL = 1e-6
#: Closed-form bounds against brute force: Fibonacci directions this dense
#: come within (1 - cos(half spacing)) of the optimum.
DIRECTIONS = 1500
SAMPLE_RTOL = 2e-3
#: The bound never exceeded (rounding only).
BOUND_SLACK = 1e-9
#: Closed-form Hessians of the joint functions against the joint-motion route.
HESSIAN_ATOL = 1e-12
#: Hessians against central differences of the gradients (step FD_STEP).
HESSIAN_FD_ATOL = 1e-7
#: The tool axes polarised by the black-box route.
PAIRS = ((0, 1), (0, 2), (1, 2))


def _forms_by_evaluations(
    dyn: og.ClosedLoopDynamics, p: np.ndarray, **kwargs: object
) -> tuple[MotionForm, MotionForm]:
    """The forms read off 10 black-box inverse-dynamics evaluations per point.

    Unit accelerations without velocity nor gravity give the linear rows; unit
    velocities the diagonal of the quadratic part and the sums of two of them
    the rest by polarisation; a static call with gravity and wrench the constant.
    """
    n, eye = p.shape[0], np.eye(3)
    dirs = [*eye, *(eye[k] + eye[m] for k, m in PAIRS)]
    acc, vel = np.zeros((9, n, 3)), np.zeros((9, n, 3))
    acc[:3] = eye[:, None, :]
    vel[3:] = np.asarray(dirs)[:, None, :]
    rows = np.broadcast_to(p, (9, n, 3)).reshape(-1, 3)
    res = dyn.inverse_dynamics(rows, vel.reshape(-1, 3), acc.reshape(-1, 3), gravity=(0, 0, 0))
    still = np.zeros_like(p)
    const = dyn.inverse_dynamics(p, still, still, **kwargs).forces  # type: ignore[arg-type]

    def form(values: np.ndarray, constant: np.ndarray) -> MotionForm:
        y = values.reshape(9, n, 3)
        quad = np.empty((n, 3, 3, 3))
        for k in range(3):
            quad[:, :, k, k] = y[3 + k]
        for j, (k, m) in enumerate(PAIRS):
            quad[:, :, k, m] = quad[:, :, m, k] = 0.5 * (y[6 + j] - y[3 + k] - y[3 + m])
        return MotionForm(np.ascontiguousarray(y[:3].transpose(1, 2, 0)), quad, constant)

    return form(res.forces, const), form(res.slider_accelerations, np.zeros_like(p))


@pytest.mark.parametrize("offset", [None, 0.03])
def test_coefficients_match_the_black_box_route(
    dyn: og.ClosedLoopDynamics, offset: float | None
) -> None:
    """The model's mass matrix, gravity and three Coriolis rows give the polarised forms.

    The velocity terms read per leg in (theta', phi') only: the slider rate adds
    none (Galilean invariance), which this checks on two designs.
    """
    if offset is not None:
        params = og.prototype().replace(leg_length=0.36, platform_offset=offset)
        dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params), gravity=(0.5, 9.0, -1.0))
    p = cube_points(30, seed=21) * dyn.leg_length / PROTOTYPE_LEG
    kwargs = {"wrench": [30.0, -20.0, 55.0, 1.0, 2.0, -3.0], "gravity": (1.0, -2.0, 9.81)}
    forms = requirement_forms(dyn, p, check_limits=False, **kwargs)  # type: ignore[arg-type]
    forces, sliders = _forms_by_evaluations(dyn, p, **kwargs)
    for new, ref in ((forms.forces, forces), (forms.slider_accelerations, sliders)):
        for part in ("linear", "quadratic", "constant"):
            expected = getattr(ref, part)
            np.testing.assert_allclose(
                getattr(new, part), expected, rtol=0, atol=FORM_RTOL * np.abs(expected).max()
            )
    assert np.abs(forces.quadratic).max() > 1.0  # velocity terms of some newtons per (m/s)^2


def test_function_hessians_are_the_joint_accelerations_of_a_velocity() -> None:
    rng = np.random.default_rng(23)
    p = cube_points(25, seed=23)
    v = rng.normal(size=(25, 3))
    hess = function_hessians(p, PROTOTYPE_LEG)
    zero = np.zeros_like(p)
    motion = leg_motion(p, v, zero, PROTOTYPE_LEG)
    np.testing.assert_allclose(
        np.einsum("nlfkm,nk,nm->nlf", hess, v, v), motion.accelerations, atol=HESSIAN_ATOL
    )
    # and the derivatives of the gradients, by central differences
    for axis in range(3):
        step = FD_STEP * np.eye(3)[axis]
        plus = leg_motion(p + step, zero, zero, PROTOTYPE_LEG).gradients
        minus = leg_motion(p - step, zero, zero, PROTOTYPE_LEG).gradients
        np.testing.assert_allclose(
            hess[..., axis], (plus - minus) / (2 * FD_STEP), rtol=0, atol=HESSIAN_FD_ATOL
        )


def test_forms_reproduce_inverse_dynamics(dyn: og.ClosedLoopDynamics) -> None:
    rng = np.random.default_rng(11)
    p = cube_points(40, seed=11)
    v = rng.normal(size=(40, 3)) * 0.8
    a = rng.normal(size=(40, 3)) * 12.0
    wrench = [30.0, -20.0, 55.0, 1.0, 2.0, -3.0]
    gravity = (1.0, -2.0, 9.81)
    forms = requirement_forms(dyn, p, wrench=wrench, gravity=gravity)
    ref = dyn.inverse_dynamics(p, v, a, wrench=wrench, gravity=gravity)
    np.testing.assert_allclose(
        forms.forces.evaluate(v, a), ref.forces, rtol=FORM_RTOL, atol=FORCE_ATOL
    )
    np.testing.assert_allclose(
        forms.slider_accelerations.evaluate(v, a),
        ref.slider_accelerations,
        rtol=FORM_RTOL,
        atol=1e-12,
    )
    # the linear part of the slider accelerations is the paper's J^-1 (eq. 2)
    np.testing.assert_allclose(
        forms.slider_accelerations.linear, og.inverse_jacobian(p, PROTOTYPE_LEG), atol=1e-12
    )
    np.testing.assert_allclose(forms.inverse_jacobian, og.inverse_jacobian(p, PROTOTYPE_LEG))
    # the quadratic parts are symmetric
    for form in (forms.forces, forms.slider_accelerations):
        np.testing.assert_array_equal(form.quadratic, np.swapaxes(form.quadratic, -1, -2))


def test_mass_matrix_is_the_kinetic_energy(dyn: og.ClosedLoopDynamics) -> None:
    """``J^-T M_s`` is the tool-space mass matrix: symmetric, and ``E = v^T L v / 2``."""
    rng = np.random.default_rng(12)
    p = cube_points(12, seed=12)
    v = rng.normal(size=(12, 3))
    forms = requirement_forms(dyn, p)
    B = forms.inverse_jacobian
    tool_mass = np.einsum("nki,nkj->nij", B, forms.forces.linear)
    np.testing.assert_allclose(tool_mass, np.swapaxes(tool_mass, 1, 2), rtol=1e-9, atol=1e-12)
    assert (np.linalg.eigvalsh(tool_mass) > 0.0).all()
    state = dyn.inverse_dynamics(p, v, np.zeros_like(v))
    kinetic, _ = mechanical_energy(dyn, state.q, state.v)
    np.testing.assert_allclose(
        0.5 * np.einsum("ni,nij,nj->n", v, tool_mass, v), kinetic, rtol=ENERGY_RTOL
    )


def test_velocity_term_is_the_power_of_the_changing_mass(dyn: og.ClosedLoopDynamics) -> None:
    """With ``a = 0`` and no gravity, ``F . q' = dE/dt = v^T (dL/dt) v / 2``."""
    rng = np.random.default_rng(13)
    p = cube_points(8, seed=13)
    v = rng.normal(size=(8, 3))
    forms = requirement_forms(dyn, p, gravity=(0.0, 0.0, 0.0))

    def tool_mass(points: np.ndarray) -> np.ndarray:
        f = requirement_forms(dyn, points)
        return np.einsum("nki,nkj->nij", f.inverse_jacobian, f.forces.linear)

    d_mass = (tool_mass(p + FD_STEP * v) - tool_mass(p - FD_STEP * v)) / (2 * FD_STEP)
    power = np.einsum(
        "ni,ni->n",
        forms.forces.evaluate(v, 0 * v),
        np.einsum("nij,nj->ni", forms.inverse_jacobian, v),
    )
    np.testing.assert_allclose(power, 0.5 * np.einsum("ni,nij,nj->n", v, d_mass, v), rtol=FD_RTOL)


def test_bounds_against_brute_force(dyn: og.ClosedLoopDynamics) -> None:
    p = np.array([[CUBE_CORNER + CUBE_SIDE] * 3, [CUBE_CORNER] * 3, [0.02, -0.05, 0.09]])
    v_max, a_max = 1.2, 20.0
    forms = requirement_forms(dyn, p)
    lower, upper = forms.forces.bounds(v_max, a_max)
    rng = np.random.default_rng(14)
    # random (v, a) pairs on the spheres and at v = 0, evaluated directly: inside the bounds
    n = 4000
    for k in range(3):
        unit_v, unit_a = (
            x / np.linalg.norm(x, axis=1, keepdims=True) for x in rng.normal(size=(2, n, 3))
        )
        v = v_max * unit_v * (rng.random((n, 1)) > 0.1)
        forces = dyn.inverse_dynamics(np.tile(p[k], (n, 1)), v, a_max * unit_a).forces
        assert (forces <= upper[k] + BOUND_SLACK * np.abs(upper[k])).all()
        assert (forces >= lower[k] - BOUND_SLACK * np.abs(lower[k])).all()
    # dense directions: F(a, v) = F(a, 0) + F(0, v) - F(0, 0), checked, then maximised apart
    dirs = unit_sphere(DIRECTIONS)
    for k in range(3):
        rows = np.tile(p[k], (DIRECTIONS, 1))
        zero = np.zeros_like(rows)
        with_a = dyn.inverse_dynamics(rows, zero, a_max * dirs).forces
        with_v = dyn.inverse_dynamics(rows, v_max * dirs, zero).forces
        rest = dyn.static_forces(p[k])[0]
        both = dyn.inverse_dynamics(rows[:50], v_max * dirs[::-1][:50], a_max * dirs[:50]).forces
        np.testing.assert_allclose(
            both, with_a[:50] + with_v[::-1][:50] - rest, rtol=FORM_RTOL, atol=FORCE_ATOL
        )
        top = with_a.max(axis=0) + np.maximum(with_v.max(axis=0), rest) - rest
        low = with_a.min(axis=0) + np.minimum(with_v.min(axis=0), rest) - rest
        scale = upper[k] - lower[k]
        assert (top <= upper[k] + BOUND_SLACK * scale).all()
        assert (top >= upper[k] - SAMPLE_RTOL * scale).all()
        assert (low >= lower[k] - BOUND_SLACK * scale).all()
        assert (low <= lower[k] + SAMPLE_RTOL * scale).all()


def test_direct_optimisation_at_the_far_corner(dyn: og.ClosedLoopDynamics) -> None:
    """Gradient ascent on the spheres, on the dynamics alone, finds the closed form."""
    p = np.array([CUBE_CORNER + CUBE_SIDE] * 3)
    v_max, a_max, slider = 1.2, 20.0, 2
    forms = requirement_forms(dyn, p)
    lam = np.linalg.eigvalsh(forms.forces.quadratic[0, slider])
    assert lam[-1] > 0.0  # the maximum is on the velocity sphere
    lower, upper = forms.forces.bounds(v_max, a_max)

    def value(x: np.ndarray) -> np.ndarray:
        v = v_max * x[:, :3] / np.linalg.norm(x[:, :3], axis=1, keepdims=True)
        a = a_max * x[:, 3:] / np.linalg.norm(x[:, 3:], axis=1, keepdims=True)
        return dyn.inverse_dynamics(np.tile(p, (len(x), 1)), v, a).forces[:, slider]

    rng = np.random.default_rng(15)
    x = rng.normal(size=6)
    x[:3] /= np.linalg.norm(x[:3])
    x[3:] /= np.linalg.norm(x[3:])
    step, h = 0.5, 1e-6
    for _ in range(300):
        probes = np.vstack([x, x + h * np.eye(6)])
        f = value(probes)
        grad = (f[1:] - f[0]) / h
        trial = x + step * grad / max(np.linalg.norm(grad), 1e-12)
        trial[:3] /= np.linalg.norm(trial[:3])  # stay on the unit spheres
        trial[3:] /= np.linalg.norm(trial[3:])
        if value(trial[None])[0] > f[0]:
            x, step = trial, 1.5 * step
        else:
            step *= 0.5
    assert value(x[None])[0] == pytest.approx(upper[0, slider], rel=1e-7)
    vel, acc = forms.forces.worst_motion(v_max, a_max)
    attained = dyn.inverse_dynamics(p, vel[0, slider], acc[0, slider]).forces[0, slider]
    worst = max(upper[0, slider], lower[0, slider], key=abs)  # gravity loads slider 3
    assert worst == lower[0, slider] < 0.0
    assert attained == pytest.approx(worst, rel=FORM_RTOL)


def test_torque_forms_are_the_drive_model(dyn: og.ClosedLoopDynamics) -> None:
    rng = np.random.default_rng(16)
    p = cube_points(30, seed=16)
    v, a = rng.normal(size=(30, 3)), rng.normal(size=(30, 3)) * 10.0
    train = og.DriveTrain(
        lead=0.02, efficiency=0.85, gear_ratio=1.5, coulomb_torque=0.0, viscous_coefficient=0.0
    )
    forms = requirement_forms(dyn, p)
    res = dyn.inverse_dynamics(p, v, a)
    demand = og.motor_demand(res.forces, res.slider_velocities, res.slider_accelerations, train)
    driving, back = forms.torques(train)
    expected = np.where(
        res.forces * res.slider_velocities >= 0.0, driving.evaluate(v, a), back.evaluate(v, a)
    )
    np.testing.assert_allclose(expected, demand.torque, rtol=FORM_RTOL, atol=1e-12)


def test_form_algebra_and_input_errors(dyn: og.ClosedLoopDynamics) -> None:
    lin = np.arange(9.0).reshape(1, 3, 3)
    quad = np.broadcast_to(np.eye(3), (1, 3, 3, 3)).copy()
    form = MotionForm(lin, quad, np.array([[1.0, -2.0, 0.5]]))
    twice = form.combine(2.0, form, -1.0)
    np.testing.assert_array_equal(twice.linear, lin)
    v, a = np.array([[0.0, 3.0, 4.0]]), np.array([[1.0, 0.0, 0.0]])
    np.testing.assert_allclose(form.evaluate(v, a), [[0.0 + 25 + 1, 3 + 25 - 2, 6 + 25 + 0.5]])
    lower, upper = form.bounds(2.0, 1.0)
    norms = np.linalg.norm(lin[0], axis=1)
    np.testing.assert_allclose(upper[0], norms + 4.0 + [1.0, -2.0, 0.5])
    np.testing.assert_allclose(lower[0], -norms + [1.0, -2.0, 0.5])
    assert isinstance(requirement_forms(None, [0.0, 0.0, 0.0]), RequirementForms)
    for bad in ([[np.nan, 0, 0]], [[0.0, 0.0]], "x"):
        with pytest.raises(og.InvalidParameterError):
            requirement_forms(dyn, bad)
    with pytest.raises(og.UnreachablePointError):
        requirement_forms(dyn, [0.5, 0.5, 0.0])
    with pytest.raises(og.InvalidParameterError):
        requirement_forms("prototype", [0.0, 0.0, 0.0])  # type: ignore[arg-type]


def test_points_beyond_the_slider_limits_are_refused(dyn: og.ClosedLoopDynamics) -> None:
    far = np.full(3, CUBE_CORNER + 1.05 * CUBE_SIDE)  # reachable by the legs, not the sliders
    assert og.inverse_kinematics(far, PROTOTYPE_LEG).max() > dyn.closed_loop.params.slider_upper
    with pytest.raises(og.UnreachablePointError, match="outside the limits"):
        requirement_forms(dyn, far)
    beyond = requirement_forms(dyn, far, check_limits=False)  # asked: computed there
    assert np.isfinite(beyond.forces.linear).all()


def test_the_legs_expansion_gives_pinocchios_forms(monkeypatch: pytest.MonkeyPatch) -> None:
    """The forms from the legs' expansion equal those read from Pinocchio point by point."""
    params = og.prototype().replace(leg_length=0.36, platform_offset=0.03)
    fast = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    slow = og.ClosedLoopDynamics(fast.closed_loop)
    p = cube_points(40, seed=24) * params.leg_length / PROTOTYPE_LEG
    kwargs = {"wrench": [30.0, -20.0, 55.0, 1.0, 2.0, -3.0], "gravity": (1.0, -2.0, 9.81)}
    with_expansion = requirement_forms(fast, p, check_limits=False, **kwargs)  # type: ignore[arg-type]
    monkeypatch.setattr(leg_harmonics_module, "VERIFY_TOL", -1.0)  # no expansion passes
    assert leg_harmonics_module.leg_harmonics(slow) is None
    by_pinocchio = requirement_forms(slow, p, check_limits=False, **kwargs)  # type: ignore[arg-type]
    for form in ("forces", "slider_accelerations"):
        for part in ("linear", "quadratic", "constant"):
            expected = getattr(getattr(by_pinocchio, form), part)
            np.testing.assert_allclose(
                getattr(getattr(with_expansion, form), part),
                expected,
                rtol=0,
                atol=FORM_RTOL * max(np.abs(expected).max(), 1.0),
            )
