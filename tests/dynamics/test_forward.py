from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import random_states

import orthoglide_pin as og
from orthoglide_pin.dynamics.forward import ForwardDynamics, mechanical_energy
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics

#: The issue's round trip: constraintDynamics gives back the accelerations (relative).
ROUND_TRIP_TOL = 1e-8
#: The shared platform is the same machine as the lumped one (relative).
SPLIT_TOL = 1e-12
#: Smallest eigenvalue of the tree's mass matrix, relative to the largest: far from 0.
MIN_RELATIVE_EIGENVALUE = 1e-6


def _mass_matrix(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    upper = pin.crba(model, data, q)  # the upper triangle is filled
    return np.triu(upper) + np.triu(upper, 1).T


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_constraint_dynamics_gives_back_the_accelerations(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(10, seed=1)
    res = dyn.inverse_dynamics(p, pd, pdd)
    fd = ForwardDynamics(dyn)
    a = fd.accelerations(res.q, res.v, res.forces)
    for k in range(len(p)):
        assert _rel(a[k], res.a[k]) <= ROUND_TRIP_TOL


def test_round_trip_with_a_wrench_and_another_gravity(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(6, seed=2)
    gravity = np.array([-9.81, 0.0, 0.0])
    wrench = np.array([120.0, -80.0, 40.0, 5.0, -3.0, 7.0])
    res = dyn.inverse_dynamics(p, pd, pdd, wrench=wrench, gravity=gravity)
    a = ForwardDynamics(dyn, gravity).accelerations(res.q, res.v, res.forces, wrench=wrench)
    for k in range(len(p)):
        assert _rel(a[k], res.a[k]) <= ROUND_TRIP_TOL
    # without the wrench the same forces give other accelerations: the check can fail
    a0 = ForwardDynamics(dyn, gravity).accelerations(res.q[:1], res.v[:1], res.forces[:1])
    assert _rel(a0[0], res.a[0]) > 1e-3


def _lumped_platform(dynamics: ClosedLoopDynamics, model: pin.Model) -> pin.Model:
    """The same machine with the platform's three shares moved onto leg 1's end revolute."""
    out = pin.Model(model)
    platform = model.frames[dynamics.closed_loop.platform_frame]
    for leg in (2, 3):
        closure = model.frames[model.getFrameId(f"leg{leg}_closure")]
        share = closure.placement.actInv(model.inertias[closure.parentJoint])  # platform axes
        out.inertias[platform.parentJoint] += platform.placement.act(share)
        out.inertias[closure.parentJoint] = pin.Inertia.Zero()
    return out


@pytest.mark.parametrize("leg_length", [0.31, 0.36])
def test_the_tree_mass_matrix_is_regular(leg_length: float) -> None:
    """Every jointed body has mass: M(q) of the cut tree is positive definite anywhere."""
    model = og.ClosedLoopModel(og.prototype().replace(leg_length=leg_length)).model
    data = model.createData()
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        eig = np.linalg.eigvalsh(_mass_matrix(model, data, q))
        assert eig[0] > MIN_RELATIVE_EIGENVALUE * eig[-1]
    assert all(model.inertias[j].mass > 0.0 for j in range(1, model.njoints))


def test_the_shared_platform_is_the_same_machine(dyn: ClosedLoopDynamics) -> None:
    """Same total inertia, and the same reduced mass matrix G^T M G on the closed chain
    as the machine whose platform is one body on leg 1 (second route)."""
    cl = dyn.closed_loop
    model = dyn.pinocchio_model()
    lumped = _lumped_platform(dyn, model)
    assert sum(i.mass for i in model.inertias) == pytest.approx(
        sum(i.mass for i in lumped.inertias), rel=SPLIT_TOL
    )
    table = og.inertia_table()
    third = table.by_kind()["platform"].total / 3.0
    for leg in (2, 3):
        end = model.getJointId(f"leg{leg}_end_revolute")
        assert model.inertias[end].mass == pytest.approx(third, rel=SPLIT_TOL)
    platform_joint = lumped.frames[cl.platform_frame].parentJoint
    assert lumped.inertias[platform_joint].mass == pytest.approx(
        table.platform_mass, rel=SPLIT_TOL
    )
    d0, d1 = lumped.createData(), model.createData()
    for q in cl.configuration(random_states(4, seed=3)[0]):
        G = cl.velocity_map(q)
        m0 = G.T @ _mass_matrix(lumped, d0, q) @ G
        m1 = G.T @ _mass_matrix(model, d1, q) @ G
        np.testing.assert_allclose(m1, m0, rtol=SPLIT_TOL, atol=SPLIT_TOL * np.max(np.abs(m0)))
        g0 = G.T @ pin.computeGeneralizedGravity(lumped, d0, q)
        g1 = G.T @ pin.computeGeneralizedGravity(model, d1, q)
        np.testing.assert_allclose(g1, g0, atol=SPLIT_TOL * np.max(np.abs(g0)))


def test_mechanical_energy(dyn: ClosedLoopDynamics) -> None:
    p, pd, pdd = random_states(5, seed=4)
    res = dyn.inverse_dynamics(p, pd, pdd)
    kinetic, potential = mechanical_energy(dyn, res.q, res.v)
    model = dyn.pinocchio_model()
    data = model.createData()
    for k in range(len(p)):
        M = _mass_matrix(model, data, res.q[k])
        assert kinetic[k] == pytest.approx(0.5 * res.v[k] @ M @ res.v[k], rel=1e-12)
        com = pin.centerOfMass(model, data, res.q[k])
        total = sum(i.mass for i in model.inertias)
        assert potential[k] == pytest.approx(-total * dyn.gravity @ com, rel=1e-12)


def test_bad_input_is_reported(dyn: ClosedLoopDynamics) -> None:
    fd = ForwardDynamics(dyn)
    q = np.zeros((2, 18))
    with pytest.raises(og.InvalidParameterError):
        fd.accelerations(q, np.zeros((2, 17)), np.zeros((2, 3)))
    with pytest.raises(og.InvalidParameterError):
        fd.accelerations(q, q, np.zeros((3, 3)))
    with pytest.raises(og.InvalidParameterError):
        mechanical_energy(dyn, q, np.full((2, 18), np.nan))


def test_the_shipped_files_simulate_as_they_are(dyn: ClosedLoopDynamics) -> None:
    """An outside user's route: the shipped URDF and its loop data, plain Pinocchio
    ``RigidConstraintModel`` closures, no change to the model; the package's own
    inverse dynamics must come back from ``constraintDynamics``."""
    urdf = og.prototype_urdf_path()
    loops = og.read_loops(og.loops_path(urdf))
    model = pin.buildModelFromUrdf(str(urdf))
    model.gravity = pin.Motion(np.asarray(dyn.gravity), np.zeros(3))
    data = model.createData()
    local = pin.ReferenceFrame.LOCAL
    constraints = pin.StdVec_RigidConstraintModel()
    for closure in loops.closures:
        f1, f2 = (model.frames[model.getFrameId(n)] for n in (closure.frame1, closure.frame2))
        kind = (
            pin.ContactType.CONTACT_3D if closure.kind == "point" else pin.ContactType.CONTACT_6D
        )
        constraints.append(
            pin.RigidConstraintModel(
                kind, model, f1.parentJoint, f1.placement, f2.parentJoint, f2.placement, local
            )
        )
    datas = pin.StdVec_RigidConstraintData()
    for c in constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(model, data, constraints, datas)
    p, pd, pdd = random_states(5, seed=11)
    res = dyn.inverse_dynamics(p, pd, pdd)
    actuated = [model.joints[model.getJointId(n)].idx_v for n in loops.actuated_joints]
    for k in range(len(p)):
        tau = np.zeros(model.nv)
        tau[actuated] = res.forces[k]
        settings = pin.ProximalSettings(1e-12, 1e-12, 1e-6, 50)
        a = pin.constraintDynamics(
            model, data, res.q[k], res.v[k], tau, constraints, datas, settings
        )
        assert _rel(a, res.a[k]) <= ROUND_TRIP_TOL


def test_the_dynamics_take_the_parameters_of_another_design() -> None:
    other = og.prototype().replace(leg_length=0.36)
    from_params = ClosedLoopDynamics(other)
    assert from_params.closed_loop.params == other
    p, pd, pdd = random_states(4, seed=9)
    res = from_params.inverse_dynamics(p, pd, pdd)
    built = ClosedLoopDynamics(og.ClosedLoopModel(other)).inverse_dynamics(p, pd, pdd)
    np.testing.assert_array_equal(res.forces, built.forces)
    prototype_forces = ClosedLoopDynamics().inverse_dynamics(p, pd, pdd).forces
    assert _rel(res.forces, prototype_forces) > 1e-3  # that design's legs, not the paper's
    energy = mechanical_energy(from_params, res.q, res.v)
    for machine in (other, og.ClosedLoopModel(other), from_params):
        # constraintDynamics gives the accelerations back: the same machine each time
        a = ForwardDynamics(machine).accelerations(res.q, res.v, res.forces)
        assert _rel(a, res.a) <= ROUND_TRIP_TOL
        for got, want in zip(mechanical_energy(machine, res.q, res.v), energy, strict=True):
            np.testing.assert_array_equal(got, want)


def test_what_is_no_machine_is_refused_naming_the_argument() -> None:
    for call in (
        lambda: ForwardDynamics("prototype"),  # type: ignore[arg-type]
        lambda: mechanical_energy({"leg_length": 0.3}, np.zeros((1, 18)), np.zeros((1, 18))),  # type: ignore[arg-type]
        lambda: ClosedLoopDynamics(0.31),  # type: ignore[arg-type]
    ):
        with pytest.raises(og.InvalidParameterError) as info:
            call()
        assert info.value.name in ("dynamics", "model") and "OrthoglideParams" in str(info.value)
