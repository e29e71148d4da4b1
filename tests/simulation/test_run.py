"""Planned programs run in MuJoCo: contour within a micrometre, saturation shown, energy kept."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.simulation.outputs import (
    cutting_samples,
    run_contour_error,
    running_blocks,
    simulation_summary,
)
from orthoglide_pin.simulation.run import integrator_motion, prepare, slider_masses
from orthoglide_pin.simulation.slider_drive import drive_terms

pytest.importorskip("mujoco")
pytest.importorskip("toppra")

DRIVE = og.load_drive(str(og.example_drive_file()))
#: The contour error of an exact model with feedforward, on feed moves [m] (the requirement).
CONTOUR_TOL = 1e-6
#: A weak motor's contour error is at least this [m].
WEAK_CONTOUR = 1e-5
#: Energy balance: imbalance over the energy that flows through the actuators [-].
ENERGY_RTOL = 1e-3
#: The imbalance's ratio when the step halves: first order (2), within these bounds.
STEP_ORDER = (1.6, 2.4)
#: Integrator landing on the planned positions [m].
LANDING_TOL = 1e-15
#: A line, a full circle, a rapid move back (mm).
SHORT = "G21 G90 G17\nG1 X10 Y5 Z-5 F3000\nG2 X10 Y5 I-5 J0\nG0 X0 Y0 Z0\nM30\n"


#: A rapid approach, a plunge, a cut (mm).
PLUNGE = "G21 G90\nG0 X10 Z10\nG0 Z2\nG1 Z-5 F300\nG1 X30 F600\nM30\n"
#: How far the tool is put back on the rapid line during the plunge [m].
LAG = 4e-3


def _feed_contour(plan: og.Plan, run: og.SimulationRun) -> float:
    contour = run_contour_error(plan, run)
    return float(simulation_summary(run, contour, plan)["max_contour_error"])


def _shipped(name: str) -> str:
    """The shipped program, shortened where it repeats (the CI's time), unchanged otherwise."""
    text = og.example_program_text(name)
    if name == "helix":  # the first of five identical turns
        head = text.split("G2 X40 Y0 Z5")[0]
        return head + "G0 Z30\nM30\n"
    if name == "pocket":  # the plunge and the first two passes with their blended corners
        head = text.split("G1 Y-20\n")[0]
        return head + "G0 Z10\nM30\n"
    return text


@pytest.fixture(scope="module")
def dyn() -> og.ClosedLoopDynamics:
    return og.ClosedLoopDynamics(og.ClosedLoopModel())


@pytest.mark.slow
@pytest.mark.parametrize("name", ["contour", "helix", "pocket"])
def test_exact_model_follows_the_shipped_programs(name: str, dyn: og.ClosedLoopDynamics) -> None:
    plan = og.plan_program(og.read_program(_shipped(name)), dyn, og.PlanLimits(drive=DRIVE))
    run = og.simulate(plan, dyn, DRIVE)
    worst = _feed_contour(plan, run)
    print(f"{name}: contour error {worst:.3e} m over {run.t.size} periods")
    assert 0.0 < worst <= CONTOUR_TOL


def test_another_design_and_the_feedforward_that_matters() -> None:
    params = og.prototype().replace(leg_length=0.36, bar_mass=0.7)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE))
    exact = og.simulate(plan, dyn, DRIVE)
    assert _feed_contour(plan, exact) <= CONTOUR_TOL
    no_torque = og.simulate(plan, dyn, DRIVE, og.ServoSettings(controller="pd"))
    wrong = og.simulate(plan, dyn, DRIVE, og.ServoSettings(mass_error=0.2, friction_error=0.5))
    for worse in (no_torque, wrong):  # the feedforward is what keeps the error small
        assert np.abs(worse.tracking_error).max() > 3.0 * np.abs(exact.tracking_error).max()
        assert _feed_contour(plan, worse) > _feed_contour(plan, exact)
    assert np.array_equal(no_torque.feedforward, np.zeros_like(no_torque.feedforward))


def test_a_weak_motor_saturates_and_the_error_shows(dyn: og.ClosedLoopDynamics) -> None:
    weak = og.Drive(
        DRIVE.train,
        og.MotorData(name="weak", peak_torque=1.5, speed_torque_curve=((0, 1.5), (5000, 1.0))),
    )
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE))
    run = og.simulate(plan, dyn, weak)
    contour = run_contour_error(plan, run)
    summary = simulation_summary(run, contour, plan)
    assert summary["saturation_time"] > 0.0
    assert summary["saturation_time"] == pytest.approx(
        run.saturated.any(axis=1).sum() * run.settings.period
    )
    assert max(summary["saturation_time_per_slider"]) <= summary["saturation_time"]
    assert np.all(np.abs(run.torque) <= run.available + 1e-12)  # never beyond the curve
    worst = max(summary["max_contour_error"], summary["max_rapid_deviation"])
    assert worst > WEAK_CONTOUR and worst == pytest.approx(contour.maximum)


def test_a_plunge_after_a_rapid_is_measured_against_the_plunge(
    dyn: og.ClosedLoopDynamics,
) -> None:
    """The rapid moves do not count; a tool left on the rapid line is far from the cut."""
    plan = og.plan_program(og.read_program(PLUNGE), dyn, og.PlanLimits(drive=DRIVE))
    run = og.simulate(plan, dyn, DRIVE)
    lines, rapid = running_blocks(plan, run.t)
    cutting = cutting_samples(plan, run.t)
    assert np.array_equal(cutting, ~rapid) and set(lines[cutting]) == {4, 5}
    contour = run_contour_error(plan, run)
    assert set(contour.line[cutting]) <= {4, 5} and contour.line[cutting][0] == 4
    summary = simulation_summary(run, contour, plan)
    assert summary["max_contour_error"] <= CONTOUR_TOL
    timed = {b.line: b.end - b.start for b in plan.blocks}
    assert summary["cutting_time"] == pytest.approx(timed[4] + timed[5], rel=1e-12)
    assert summary["cutting_share"] == pytest.approx(summary["cutting_time"] / plan.cycle_time)
    # the tool held back on the rapid line, LAG above the plunge's start, for its first third
    plunge = np.flatnonzero(lines == 4)[: int(np.sum(lines == 4)) // 3]
    block = next(b for b in plan.path.program.blocks if b.line == 4)
    start, end = block.start, block.end
    back = start - LAG * (end - start) / np.linalg.norm(end - start)
    lagged = run.p.copy()
    lagged[plunge] = back
    held = dataclasses.replace(run, p=lagged)
    old = og.contour_error(plan.path, held.p)  # the whole path: on the rapid line, 0
    assert old.distance[plunge].max() < 1e-9
    contour = run_contour_error(plan, held)
    assert contour.distance[plunge] == pytest.approx(LAG, abs=1e-12)
    assert set(contour.line[plunge]) == {4}
    summary = simulation_summary(held, contour, plan)
    assert summary["max_contour_error"] == pytest.approx(LAG, abs=1e-12)
    assert summary["max_contour_error_at"]["line"] == 4
    # a rapid move far off its line does not count in the contour error
    far = run.p.copy()
    far[rapid] += 0.01
    contour = run_contour_error(plan, dataclasses.replace(run, p=far))
    assert simulation_summary(run, contour, plan)["max_contour_error"] <= CONTOUR_TOL


def test_energy_balance(dyn: og.ClosedLoopDynamics) -> None:
    """Actuator work = change of kinetic and potential energy + losses, MuJoCo's own figures.

    What is left is the integrator's error: it halves when the step halves.
    """
    lossless = og.Drive(dataclasses.replace(DRIVE.train, efficiency=1.0), DRIVE.motor)
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=lossless))
    worst = []
    for rate in (4000.0, 8000.0):
        run = og.simulate(plan, dyn, lossless, og.ServoSettings(rate=rate))
        imbalance = run.work - run.losses - (run.energy - run.energy[0])
        flow = np.abs(np.diff(run.work)).sum()
        worst.append(np.abs(imbalance).max())
        print(f"rate {rate:g} Hz: energy imbalance {worst[-1]:.3e} J of {flow:.3g} J")
        assert flow > 10.0 and run.losses[-1] > 0.1  # energy flows, friction dissipates
        assert worst[-1] < ENERGY_RTOL * flow
    assert STEP_ORDER[0] < worst[0] / worst[1] < STEP_ORDER[1]  # first order in the step


def test_the_integrator_lands_on_the_plan() -> None:
    rng = np.random.default_rng(0)
    q = np.cumsum(np.cumsum(rng.standard_normal((60, 3)), axis=0), axis=0) * 1e-6
    q[1] = q[0]  # from rest
    period = 2.5e-4
    for m in (1, 2, 5):
        a, v = integrator_motion(q, period, m)
        h, x, speed = period / m, q[0].copy(), np.zeros(3)
        for j in range(q.shape[0] - 1):  # MuJoCo's semi-implicit Euler, by hand
            for _ in range(m):
                speed = speed + a[j] * h
                x = x + speed * h
            assert np.abs(x - q[j + 1]).max() < LANDING_TOL
            assert np.abs(speed - v[j + 1]).max() < LANDING_TOL / period


def test_slider_masses_by_a_second_route(dyn: og.ClosedLoopDynamics) -> None:
    """The masses the loops are tuned for: Pinocchio's mass matrix in slider coordinates."""
    import pinocchio as pin

    q = np.array([0.01, -0.02, 0.03])
    res = dyn.inverse_dynamics_sliders(q, np.zeros(3), np.zeros(3))
    model = dyn.pinocchio_model()
    data = model.createData()
    mass = pin.crba(model, data, res.q[0])
    mass = np.triu(mass) + np.triu(mass, 1).T
    g = np.column_stack(
        [
            dyn.inverse_dynamics_sliders(q, np.zeros(3), e).a[0]
            for e in np.eye(3)  # joint accelerations of unit slider accelerations at rest
        ]
    )
    expected = np.diag(g.T @ mass @ g) + drive_terms(DRIVE)["armature"]
    assert np.allclose(slider_masses(dyn, q, DRIVE), expected, rtol=1e-9)


def test_running_blocks_follow_the_plan(dyn: og.ClosedLoopDynamics) -> None:
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE))
    t = np.linspace(0.0, plan.cycle_time, 500)
    lines, rapid = running_blocks(plan, t)
    for b in plan.blocks:
        inside = (t > b.start) & (t < b.end)
        assert np.all(lines[inside] == b.line)
        assert np.all(rapid[inside] == (b.kind == "rapid"))


def test_bad_arguments(dyn: og.ClosedLoopDynamics) -> None:
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE))
    with pytest.raises(InvalidParameterError, match="plan"):
        og.simulate("plan")  # type: ignore[arg-type]
    with pytest.raises(InvalidParameterError, match="settings"):
        og.simulate(plan, dyn, DRIVE, {"rate": 4000})  # type: ignore[arg-type]
    with pytest.raises(InvalidParameterError, match="drive"):
        og.simulate(plan, dyn, "drive.yaml")  # type: ignore[arg-type]


#: A tool wrench: a cutting force [N] and a moment [N.m] at the tool point.
WRENCH = (40.0, -25.0, 30.0, 1.5, -0.8, 2.0)
#: MuJoCo's and our slider forces of the wrench agree to [N].
WRENCH_FORCE_TOL = 1e-8

DESIGNS = {
    "prototype": og.prototype(),
    "longer legs": og.prototype().replace(leg_length=0.36, bar_mass=0.7),
}


@pytest.mark.parametrize("design", list(DESIGNS))
def test_a_tool_wrench_is_followed_within_the_bound(design: str) -> None:
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(DESIGNS[design]))
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE), wrench=WRENCH)
    run = og.simulate(plan, dyn, DRIVE)
    assert _feed_contour(plan, run) <= CONTOUR_TOL
    free = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE))
    other = og.simulate(free, dyn, DRIVE).feedforward  # the cycle times may differ
    n = min(len(run.feedforward), len(other))
    assert not np.allclose(run.feedforward[:n], other[:n])


@pytest.mark.parametrize("design", list(DESIGNS))
def test_mujoco_applies_the_wrench_our_dynamics_balances(design: str) -> None:
    """MuJoCo's generalised force of the wrench, through its loops' Jacobian, vs Pinocchio's.

    The simulation puts the wrench on the platform's centre of mass with its
    moment moved there from the tool point; MuJoCo maps it to the joints
    (``mj_applyFT``, its Jacobians); the sliders balance ``-G^T`` of it, with
    ``G`` the velocities of every joint for unit slider speeds from MuJoCo's
    equality-constraint Jacobian. Ours: the inverse dynamics at rest, no gravity.
    """
    import mujoco

    from orthoglide_pin.simulation.engine import joint_order

    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(DESIGNS[design]))
    plan = og.plan_program(og.read_program(SHORT), dyn, og.PlanLimits(drive=DRIVE), wrench=WRENCH)
    ready = prepare(plan, dyn, DRIVE)
    model, data = ready.model, ready.data
    w = np.asarray(WRENCH)
    for point in ([0.01, 0.005, -0.005], [-0.03, 0.02, 0.04]):
        state = dyn.inverse_dynamics(point, np.zeros(3), np.zeros(3))
        data.qpos[:] = state.q[0][joint_order(model, dyn.closed_loop.model)]
        data.qvel[:] = 0.0
        mujoco.mj_forward(model, data)
        tool, platform = model.body("tool").id, model.body("platform").id
        centre = data.xipos[platform].copy()
        moment = w[3:] + np.cross(data.xpos[tool] - centre, w[:3])
        qfrc = np.zeros(model.nv)
        mujoco.mj_applyFT(model, data, w[:3], moment, centre, platform, qfrc)
        rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
        jac = data.efc_J.reshape(-1, model.nv)[rows]
        sliders = [model.joint(f"leg{i}_slider").dofadr[0] for i in (1, 2, 3)]
        others = [d for d in range(model.nv) if d not in sliders]
        g = np.zeros((model.nv, 3))
        g[sliders] = np.eye(3)
        g[others] = -np.linalg.pinv(jac[:, others], rcond=1e-10) @ jac[:, sliders]
        ours = dyn.inverse_dynamics(point, np.zeros(3), np.zeros(3), wrench=w, gravity=np.zeros(3))
        assert np.abs(ours.forces[0] - (-g.T @ qfrc)).max() < WRENCH_FORCE_TOL
        assert np.abs(ours.forces[0]).max() > 10.0  # the wrench loads the sliders


def test_the_progress_counts_the_periods(dyn: og.ClosedLoopDynamics) -> None:
    plan = og.plan_program(og.read_program("G21\nG0 X5\n"), dyn, og.PlanLimits(drive=DRIVE))
    calls: list[tuple[int, int]] = []
    run = og.simulate(plan, dyn, DRIVE, progress=lambda d, t: calls.append((d, t)))
    assert calls[-1] == (run.t.size, run.t.size) and len(calls) > 10
    done = [d for d, _ in calls]
    assert done == sorted(done)
    with pytest.raises(InvalidParameterError, match="progress"):
        og.simulate(plan, dyn, DRIVE, progress="bar")  # type: ignore[arg-type]


def test_a_run_too_long_for_memory_names_the_rate_but_streams(
    dyn: og.ClosedLoopDynamics,
) -> None:
    from orthoglide_pin.simulation.run import simulate_chunks

    plan = og.plan_program(og.read_program("G1 X40 F6\n"), dyn, og.PlanLimits(drive=DRIVE))
    fast = og.ServoSettings(rate=1e4)  # 400 s at 10 kHz: 4 M periods
    with pytest.raises(InvalidParameterError, match="rate"):
        og.simulate(plan, dyn, DRIVE, fast)
    chunks = simulate_chunks(plan, dyn, DRIVE, fast, chunk=1000)  # streamed: no limit
    first = next(iter(chunks))
    assert first.t.size == 1000 and first.t[-1] == pytest.approx(999e-4)
