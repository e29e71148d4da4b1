from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, random_states

import orthoglide_pin as og
from orthoglide_pin.dynamics import inverse as dyn_module
from orthoglide_pin.dynamics.inverse import DEFAULT_GRAVITY, ClosedLoopDynamics
from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: Closed-form route against the projection route on the Pinocchio model (relative).
ROUTES_TOL = 1e-8
#: Power balance along a trajectory (relative to the largest actuator power).
POWER_TOL = 1e-6
#: Central difference step in time [s] for dE/dt and dV/dt.
TIME_STEP = 1e-5
#: Platform-only model against J^T m (a - g) (relative).
PLATFORM_TOL = 1e-10
#: Static forces against the derivative of the potential energy (relative);
#: central differences of step STATIC_STEP [m] along the closed manifold.
STATIC_TOL = 1e-7
STATIC_STEP = 1e-5
#: Constraint consistency of v and a (Pinocchio's constraint models).
CONSTRAINT_TOL = 1e-10
#: Standard gravity of the default orientation [m/s^2].
G0 = 9.81


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def _circle(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A circle of radius 60 mm in a tilted plane of the cube, at a varying speed."""
    centre = np.full(3, CUBE_CORNER + CUBE_SIDE / 2)
    u = np.array([1.0, -1.0, 0.0]) / math.sqrt(2.0)
    w = np.array([1.0, 1.0, -2.0]) / math.sqrt(6.0)
    r, w0, alpha = 0.06, 4.0, 30.0  # [m], [rad/s], [rad/s^2]
    th, thd, thdd = w0 * t + 0.5 * alpha * t * t, w0 + alpha * t, np.full_like(t, alpha)
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    p = centre + r * (c * u + s * w)
    pd = r * thd[:, None] * (-s * u + c * w)
    pdd = r * thdd[:, None] * (-s * u + c * w) - r * (thd**2)[:, None] * (c * u + s * w)
    return p, pd, pdd


def test_closed_form_and_projection_routes_agree(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(12, seed=1)
    rng = np.random.default_rng(2)
    wrench = np.hstack([100.0 * rng.standard_normal((12, 3)), 10.0 * rng.standard_normal((12, 3))])
    fast = dyn.inverse_dynamics(p, pd, pdd, wrench=wrench)
    ref = dyn.inverse_dynamics(p, pd, pdd, wrench=wrench, method="projection")
    for name in ("forces", "q", "v", "a"):
        assert _rel(getattr(fast, name), getattr(ref, name)) <= ROUTES_TOL, name
    np.testing.assert_allclose(fast.slider_positions, og.inverse_kinematics(p, PROTOTYPE_LEG))
    assert fast.method == "closed-form" and ref.method == "projection"


def test_joint_motion_satisfies_the_loop_constraints(
    dyn: ClosedLoopDynamics, model: ClosedLoopModel
) -> None:
    """K v = 0 and K a + gamma = 0, with gamma the drift at (q, v, 0) from Pinocchio."""
    p, pd, pdd = random_states(8, seed=3)
    res = dyn.inverse_dynamics(p, pd, pdd)
    pm, pd_ = model.model, model.data
    for q, v, a in zip(res.q, res.v, res.a, strict=True):
        r, K = model.constraint_residual_and_jacobian(q)
        assert np.max(np.abs(r)) <= CONSTRAINT_TOL
        assert np.max(np.abs(K @ v)) <= CONSTRAINT_TOL * np.max(np.abs(v))
        pin.forwardKinematics(pm, pd_, q, v, a)
        for cm, cd in zip(model.constraint_models, model.constraint_datas, strict=True):
            cm.calc(pm, pd_, cd)
            assert np.max(np.abs(cd.constraint_acceleration_error)) <= CONSTRAINT_TOL * np.max(
                np.abs(a)
            )


def test_power_balance_along_a_circle(dyn: ClosedLoopDynamics) -> None:
    """F . q_a' = dE/dt + dV/dt - f_ext . p' (V potential of gravity, f_ext on the tool).

    Gravity is tilted and a constant cutting force acts, so every term counts.
    """
    gravity = np.array([2.0, -3.0, 9.0])
    force = np.array([40.0, -25.0, 60.0])
    t = np.linspace(0.0, 0.6, 25)
    model = dyn.pinocchio_model(gravity)
    data = model.createData()

    def energies(times: np.ndarray) -> np.ndarray:
        res = dyn.inverse_dynamics(*_circle(times), gravity=gravity)
        return np.array(
            [
                pin.computeKineticEnergy(model, data, q, v)
                + pin.computePotentialEnergy(model, data, q)
                for q, v in zip(res.q, res.v, strict=True)
            ]
        )

    res = dyn.inverse_dynamics(*_circle(t), wrench=force, gravity=gravity)
    actuator_power = np.einsum("ni,ni->n", res.forces, res.slider_velocities)
    d_energy = (energies(t + TIME_STEP) - energies(t - TIME_STEP)) / (2.0 * TIME_STEP)
    external_power = res.p_dot @ force
    residual = actuator_power - (d_energy - external_power)
    assert np.max(np.abs(residual)) <= POWER_TOL * np.max(np.abs(actuator_power))
    assert np.max(np.abs(external_power)) > 0.1 * np.max(np.abs(actuator_power))  # it matters


def test_platform_only_model_gives_j_transpose_m_a_minus_g() -> None:
    params = og.prototype().replace(bar_mass=0.0, link_mass=0.0, carriage_mass=0.0)
    dyn = ClosedLoopDynamics(ClosedLoopModel(params), gravity=(0.0, 4.0, 8.0))
    mass = og.inertia_table(params).platform_mass
    assert mass == pytest.approx(0.08**3 * 2700.0 + 2.0, rel=1e-12)
    p, pd, pdd = random_states(20, seed=4)
    force = np.array([30.0, -10.0, 5.0])
    res = dyn.inverse_dynamics(p, pd, pdd, wrench=force)
    J = og.jacobian(p, PROTOTYPE_LEG)
    expected = np.einsum("nji,nj->ni", J, mass * (pdd - dyn.gravity) - force)
    assert _rel(res.forces, expected) <= PLATFORM_TOL


def test_static_forces_are_the_gradient_of_the_potential_energy(
    dyn: ClosedLoopDynamics, model: ClosedLoopModel
) -> None:
    pm = dyn.pinocchio_model()
    data = pm.createData()

    def potential(q_act: np.ndarray) -> float:
        q = model.configuration(og.direct_kinematics(q_act, PROTOTYPE_LEG))
        return float(pin.computePotentialEnergy(pm, data, q))

    p = random_states(6, seed=5)[0]
    forces = dyn.static_forces(p)
    for point, f in zip(p, forces, strict=True):
        q_act = og.inverse_kinematics(point, PROTOTYPE_LEG)
        grad = np.array(
            [
                (potential(q_act + STATIC_STEP * e) - potential(q_act - STATIC_STEP * e))
                / (2 * STATIC_STEP)
                for e in np.eye(3)
            ]
        )
        assert _rel(f, grad) <= STATIC_TOL


def test_static_forces_at_home_carry_the_weight_on_the_vertical_slider(
    dyn: ClosedLoopDynamics,
) -> None:
    """At home (J = I), with e3 down, slider 3 lifts the platform, carriage 3 and leg 3, and
    half of the bars and the whole end link of legs 1 and 2; sliders 1 and 2 carry nothing.
    """
    table = og.inertia_table()
    each = {k: s.mass_each for k, s in table.by_kind().items()}
    lifted = (
        table.platform_mass
        + each["carriage"]
        + 2 * each["bar"]
        + 2 * each["small_link"]
        + 2 * (2 * 0.5 * each["bar"] + each["small_link"])
    )
    f = dyn.static_forces(np.zeros(3))[0]
    np.testing.assert_allclose(f, [0.0, 0.0, -G0 * lifted], atol=1e-9)
    assert tuple(dyn.gravity) == DEFAULT_GRAVITY
    # a downward cutting force on the tool (+e3, on the tool) adds to the load
    g = dyn.static_forces(np.zeros(3), wrench=[0.0, 0.0, 100.0])[0]
    np.testing.assert_allclose(g - f, [0.0, 0.0, -100.0], atol=1e-9)


def test_a_moment_on_the_tool_loads_no_actuator(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(4, seed=6)
    base = dyn.inverse_dynamics(p, pd, pdd, method="projection").forces
    moment = dyn.inverse_dynamics(p, pd, pdd, wrench=[0, 0, 0, 50, -20, 30], method="projection")
    assert _rel(moment.forces, base) <= ROUTES_TOL


def test_slider_input_gives_the_same_result(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(15, seed=7)
    res = dyn.inverse_dynamics(p, pd, pdd)
    again = dyn.inverse_dynamics_sliders(
        res.slider_positions, res.slider_velocities, res.slider_accelerations
    )
    assert _rel(again.forces, res.forces) <= ROUTES_TOL
    assert _rel(again.p_ddot, pdd) <= ROUTES_TOL
    ref = dyn.inverse_dynamics_sliders(
        res.slider_positions[:3],
        res.slider_velocities[:3],
        res.slider_accelerations[:3],
        method="projection",
    )
    assert _rel(ref.forces, res.forces[:3]) <= ROUTES_TOL


def test_gravity_is_a_parameter_of_each_call(dyn: ClosedLoopDynamics) -> None:
    """Turning the machine turns its static forces: gravity along -e1 loads slider 1."""
    f = dyn.static_forces(np.zeros(3), gravity=(-G0, 0.0, 0.0))[0]
    f3 = dyn.static_forces(np.zeros(3))[0]
    np.testing.assert_allclose(f, [-f3[2], 0.0, 0.0], atol=1e-9)
    assert tuple(dyn.gravity) == DEFAULT_GRAVITY  # the default is untouched


def test_blocks_and_the_python_loop_give_the_same_forces(
    dyn: ClosedLoopDynamics, monkeypatch: pytest.MonkeyPatch
) -> None:
    p, pd, pdd = random_states(25, seed=8)
    whole = dyn.inverse_dynamics(p, pd, pdd).forces
    monkeypatch.setattr(dyn_module, "BLOCK", 7)
    assert _rel(dyn.inverse_dynamics(p, pd, pdd).forces, whole) <= 1e-14
    fresh = ClosedLoopDynamics(dyn.closed_loop)
    fresh.engine().pool = None  # rnea one point at a time
    assert _rel(fresh.inverse_dynamics(p, pd, pdd).forces, whole) <= 1e-14


def test_single_point_input_and_bad_input(dyn: ClosedLoopDynamics) -> None:
    res = dyn.inverse_dynamics(np.zeros(3), np.zeros(3), np.zeros(3))
    assert res.forces.shape == (1, 3) and res.q.shape == (1, 18) and res.wrench.shape == (1, 6)
    z = np.zeros((2, 3))
    for kwargs in (
        {"method": "newton"},
        {"wrench": [1.0, 2.0]},
        {"wrench": np.zeros((3, 6))},
        {"gravity": [0.0, np.nan, 9.81]},
    ):
        with pytest.raises(og.InvalidParameterError):
            dyn.inverse_dynamics(z, z, z, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(og.InvalidParameterError):
        dyn.inverse_dynamics(z, np.zeros((3, 3)), z)
    with pytest.raises(og.InvalidParameterError):
        dyn.inverse_dynamics(np.full((2, 3), np.inf), z, z)
    with pytest.raises(og.UnreachablePointError):
        dyn.inverse_dynamics([0.0, 0.3, 0.3], np.zeros(3), np.zeros(3))


def test_assumptions_cover_the_inertial_model_and_gravity(dyn: ClosedLoopDynamics) -> None:
    lines = dyn.assumptions()
    assert lines[:-1] == og.inertia_assumptions(dyn.closed_loop.params)
    assert lines[-1].startswith("Gravity (0, 0, +9.81) m/s^2") and "e3 points down" in lines[-1]
    turned = ClosedLoopDynamics(dyn.closed_loop, gravity=(-G0, 0.0, 0.0))
    assert turned.assumptions()[-1] == "Gravity (-9.81, 0, 0) m/s^2 in the machine frame (given)."
