"""Worst-case requirements and what the motors guarantee, against brute force."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, cube_points, unit_sphere

import orthoglide_pin as og
from orthoglide_pin.dynamics.motion_forms import requirement_forms
from orthoglide_pin.dynamics.requirements import (
    WorstCase,
    available_torque,
    worst_case_on_grid,
    worst_case_over_cube,
    worst_case_requirements,
)

#: Exact closed forms through different routes (rounding).
EXACT_RTOL = 1e-9
#: The bound is never exceeded (rounding only).
BOUND_SLACK = 1e-9
#: Dense Fibonacci directions come this close to the optimum.
DIRECTIONS = 600
SAMPLE_RTOL = 1e-2
#: Default drive: lead 25 mm, so 1.2 m/s of a slider is 2880 rpm.
LEAD = 0.025
V_MAX, A_MAX = 1.2, 20.0


def pair_torques(
    dyn: og.ClosedLoopDynamics, point: np.ndarray, train: og.DriveTrain
) -> np.ndarray:
    """Motor torques of the drive model at every pair of dense directions of ``a`` and ``v``.

    Uses ``F(a, v) = F(a, 0) + F(0, v) - F(0, 0)`` (and likewise for ``q''``),
    checked in test_motion_forms, so that 600^2 pairs cost 1200 calls.
    """
    dirs = unit_sphere(DIRECTIONS)
    rows, zero = np.tile(point, (DIRECTIONS, 1)), np.zeros((DIRECTIONS, 3))
    ra = dyn.inverse_dynamics(rows, zero, A_MAX * dirs)
    rv = dyn.inverse_dynamics(rows, V_MAX * dirs, zero)
    rest = dyn.static_forces(point)[0]
    force = (ra.forces[:, None] + rv.forces[None] - rest).reshape(-1, 3)
    acc = (ra.slider_accelerations[:, None] + rv.slider_accelerations[None]).reshape(-1, 3)
    vel = np.broadcast_to(rv.slider_velocities[None], (DIRECTIONS, DIRECTIONS, 3)).reshape(-1, 3)
    return og.motor_demand(force, vel, acc, train).torque


def test_slider_and_motor_speeds_on_the_prototype(dyn: og.ClosedLoopDynamics) -> None:
    wc = worst_case_over_cube(dyn, resolution=5)
    assert len(wc) == 125
    # |row i of J^-1| = L / eta_i: largest where the other two coordinates are largest
    far = CUBE_CORNER + CUBE_SIDE
    eta = math.sqrt(PROTOTYPE_LEG**2 - 2 * far**2)
    speeds, where = wc.peak("slider_speed")
    np.testing.assert_allclose(speeds, V_MAX * PROTOTYPE_LEG / eta, rtol=EXACT_RTOL)
    for i in range(3):
        expected = np.full(3, far)
        expected[i] = where[i, i]  # any value along the slider's own axis
        np.testing.assert_allclose(where[i], expected, atol=1e-15)
    home = worst_case_requirements(dyn, [0.0, 0.0, 0.0])
    np.testing.assert_allclose(home.slider_speed, [[V_MAX] * 3], rtol=EXACT_RTOL)
    np.testing.assert_allclose(home.motor_speed_rpm, [[V_MAX / LEAD * 60.0] * 3], rtol=1e-12)
    # brute force: no direction drives a slider faster
    dirs = V_MAX * unit_sphere(2000)
    corner = np.array([CUBE_CORNER, far, far])
    res = dyn.inverse_dynamics(np.tile(corner, (2000, 1)), dirs, 0 * dirs)
    top = np.abs(res.slider_velocities[:, 0]).max()
    assert V_MAX * PROTOTYPE_LEG / eta * (1 - SAMPLE_RTOL) < top <= speeds[0] * (1 + BOUND_SLACK)


def test_force_maps_are_the_forms_bounds(dyn: og.ClosedLoopDynamics) -> None:
    p = cube_points(50, seed=21)
    wc = worst_case_requirements(dyn, p, V_MAX, A_MAX)
    lower, upper = requirement_forms(dyn, p).forces.bounds(V_MAX, A_MAX)
    np.testing.assert_array_equal(wc.force_min, lower)
    np.testing.assert_array_equal(wc.force_max, upper)
    np.testing.assert_allclose(wc.force, np.maximum(np.abs(lower), np.abs(upper)))
    # the worst motion reproduces the worst |F_i| through a direct dynamics call
    vel, acc = requirement_forms(dyn, p).forces.worst_motion(V_MAX, A_MAX)
    for i in range(3):
        f = dyn.inverse_dynamics(p, vel[:, i], acc[:, i]).forces[:, i]
        np.testing.assert_allclose(np.abs(f), wc.force[:, i], rtol=EXACT_RTOL)
        assert (np.linalg.norm(acc[:, i], axis=1) <= A_MAX * (1 + 1e-12)).all()
        assert (np.linalg.norm(vel[:, i], axis=1) <= V_MAX * (1 + 1e-12)).all()
    # the peaks and where they are
    values, where = wc.peak("force")
    np.testing.assert_array_equal(values, wc.max_force)
    np.testing.assert_array_equal(where, wc.max_force_at)
    for i in range(3):
        assert values[i] == wc.force[:, i].max()
        assert any(np.array_equal(where[i], q) for q in p[wc.force[:, i] == values[i]])


@pytest.mark.parametrize("index", [0, 1])
def test_torque_bound_against_brute_force(dyn: og.ClosedLoopDynamics, index: int) -> None:
    point = np.array([[CUBE_CORNER + CUBE_SIDE] * 3, [0.03, -0.06, 0.08]])[index]
    real = og.DriveTrain()  # friction and efficiency 0.9
    wc = worst_case_requirements(dyn, point, V_MAX, A_MAX, og.Drive(real))
    torques = np.abs(pair_torques(dyn, point, real)).max(axis=0)
    assert (torques <= wc.torque[0] * (1 + BOUND_SLACK)).all()
    # conservative by at most the friction bound where the driving case dominates
    assert wc.torque_exact.all()
    assert (torques >= (wc.torque[0] - wc.friction[0]) * (1 - SAMPLE_RTOL)).all()
    # without friction the bound is attained (driving case)
    ideal = og.DriveTrain(coulomb_torque=0.0, viscous_coefficient=0.0)
    exact = worst_case_requirements(dyn, point, V_MAX, A_MAX, og.Drive(ideal))
    sampled = np.abs(pair_torques(dyn, point, ideal)).max(axis=0)
    np.testing.assert_allclose(sampled, exact.torque[0], rtol=SAMPLE_RTOL)
    assert (sampled <= exact.torque[0] * (1 + BOUND_SLACK)).all()


def test_guaranteed_speed_and_accelerations(dyn: og.ClosedLoopDynamics) -> None:
    motor = og.MotorData(peak_torque=1.5, max_speed=3000.0)
    drive = og.Drive(og.DriveTrain(), motor)
    p = cube_points(6, seed=23)
    wc = worst_case_requirements(dyn, p, V_MAX, A_MAX, drive)
    g = wc.guarantees
    assert g.speed is not None and g.acceleration_at_rest is not None
    assert g.acceleration_at_speed is not None
    assert (g.acceleration_at_speed <= g.acceleration_at_rest).all()
    for k in range(len(p)):
        # at the guaranteed speed the fastest motor runs exactly at its maximum speed
        at_speed = worst_case_requirements(dyn, p[k], float(g.speed[k]), 0.0, drive)
        assert at_speed.motor_speed_rpm.max() == pytest.approx(3000.0, rel=EXACT_RTOL)
        # at the guaranteed acceleration the worst motor needs exactly its peak torque
        rest = worst_case_requirements(dyn, p[k], 0.0, float(g.acceleration_at_rest[k]), drive)
        assert rest.torque.max() == pytest.approx(1.5, rel=EXACT_RTOL)
        moving = float(g.acceleration_at_speed[k])
        running = worst_case_requirements(dyn, p[k], V_MAX, moving, drive)
        assert running.torque.max() == pytest.approx(1.5, rel=EXACT_RTOL)
    # a little more acceleration than guaranteed, in the worst direction, exceeds the peak
    forms = requirement_forms(dyn, p)
    beyond = 1.02 * g.acceleration_at_rest
    _, acc = forms.torques(drive.train)[0].worst_motion(0.0, 1.0)
    for k in range(len(p)):
        a = beyond[k] * acc[k]  # (3 motors, 3)
        res = dyn.inverse_dynamics(np.tile(p[k], (3, 1)), np.zeros((3, 3)), a)
        demand = og.motor_demand(res.forces, res.slider_velocities, res.slider_accelerations)
        assert np.abs(np.diagonal(demand.torque)).max() > 1.5


def testavailable_torque_and_missing_motor_data(dyn: og.ClosedLoopDynamics) -> None:
    curve = ((0.0, 4.0), (2000.0, 3.0), (3000.0, 1.0))
    rpm = np.array([[0.0, 1000.0, 2500.0], [3000.0, 3500.0, 2000.0]])
    only_curve = available_torque(og.MotorData(speed_torque_curve=curve), rpm)
    np.testing.assert_allclose(only_curve, [[4.0, 3.5, 2.0], [1.0, 0.0, 3.0]])
    capped = available_torque(og.MotorData(peak_torque=3.2, speed_torque_curve=curve), rpm)
    np.testing.assert_allclose(capped, [[3.2, 3.2, 2.0], [1.0, 0.0, 3.0]])
    assert available_torque(og.MotorData(max_speed=3000.0), rpm) is None
    p = cube_points(4, seed=24)
    none = worst_case_requirements(dyn, p).guarantees
    assert none.speed is None and none.acceleration_at_rest is None
    speed_only = worst_case_requirements(
        dyn, p, drive=og.Drive(motor=og.MotorData(max_speed=3000.0))
    )
    assert speed_only.guarantees.speed is not None
    assert speed_only.guarantees.acceleration_at_speed is None
    # a motor too weak to hold the vertical slider against gravity guarantees nothing
    weak = og.Drive(motor=og.MotorData(peak_torque=0.05))
    g = worst_case_requirements(dyn, p, drive=weak).guarantees
    assert g.acceleration_at_rest is not None and (g.acceleration_at_rest == 0.0).all()
    held = dyn.static_forces(p)[:, 2] * LEAD / (2 * math.pi * 0.9)
    assert (np.abs(held) > 0.05).all()


def test_grid_fields_progress_and_json(dyn: og.ClosedLoopDynamics) -> None:
    grid = og.slice_grid("z", 0.0, (-0.05, -0.05), (0.05, 0.05), 4)
    seen: list[int] = []
    motor = og.MotorData(peak_torque=3.0, max_speed=3000.0)
    wc = worst_case_on_grid(dyn, grid, drive=og.Drive(motor=motor), progress=seen.append)
    assert isinstance(wc, WorstCase) and sum(seen) == 16
    assert wc.grid_field("force").shape == (4, 4, 1, 3)
    assert wc.grid_field("speed").shape == (4, 4, 1)
    np.testing.assert_array_equal(wc.grid_field("torque").reshape(-1, 3), wc.torque)
    data = json.loads(json.dumps(wc.to_dict()))
    assert data["force"]["max"] == wc.max_force.tolist()
    assert data["torque"]["at"] == wc.max_torque_at.tolist()
    assert data["guaranteed_speed"]["min"] == float(wc.guarantees.speed.min())  # type: ignore[union-attr]
    with pytest.raises(og.InvalidParameterError):
        wc.peak("power")
    with pytest.raises(og.InvalidParameterError):
        worst_case_requirements(dyn, [0.0, 0.0, 0.0]).grid_field("force")


def test_input_errors(dyn: og.ClosedLoopDynamics) -> None:
    for kwargs in ({"v_max": -1.0}, {"a_max": math.nan}, {"v_max": True}):
        with pytest.raises(og.InvalidParameterError):
            worst_case_requirements(dyn, [0.0, 0.0, 0.0], **kwargs)  # type: ignore[arg-type]
    with pytest.raises(og.InvalidParameterError):
        worst_case_over_cube(dyn, resolution=1)
    with pytest.raises(og.InvalidParameterError):
        worst_case_requirements(dyn, [[0.0, 0.0, math.inf]])
    with pytest.raises(og.UnreachablePointError):
        worst_case_requirements(dyn, [0.4, 0.4, 0.0])


def test_parameters_give_their_own_machine(params: og.OrthoglideParams) -> None:
    longer = params.replace(leg_length=0.34)
    wc = worst_case_over_cube(longer, resolution=3, v_max=V_MAX, a_max=A_MAX)
    corner, side = longer.workspace.q1, longer.workspace.side  # the prototype's 200 mm cube
    assert side == CUBE_SIDE
    np.testing.assert_allclose(wc.points.min(axis=0), corner)
    np.testing.assert_allclose(wc.points.max(axis=0) - corner, side)
    far = corner[0] + side
    eta = math.sqrt(0.34**2 - 2 * far**2)
    np.testing.assert_allclose(wc.peak("slider_speed")[0], V_MAX * 0.34 / eta, rtol=EXACT_RTOL)


def test_a_model_a_dynamics_or_parameters_give_the_same_worst_case(
    params: og.OrthoglideParams,
) -> None:
    longer = params.replace(leg_length=0.34)
    model = og.ClosedLoopModel(longer)
    points = cube_points(6, seed=21)
    given = [longer, model, og.ClosedLoopDynamics(model)]
    cases = [worst_case_requirements(m, points, V_MAX, A_MAX) for m in given]
    for wc in cases[1:]:
        np.testing.assert_array_equal(wc.force, cases[0].force)
        np.testing.assert_array_equal(wc.torque, cases[0].torque)
    grid = og.cube_grid(longer.workspace.q1, longer.workspace.side, 2)
    over = [worst_case_over_cube(m, resolution=2, v_max=V_MAX, a_max=A_MAX) for m in given]
    on = worst_case_on_grid(model, grid, v_max=V_MAX, a_max=A_MAX)
    for wc in over:
        np.testing.assert_array_equal(wc.force, on.force)
    forms = [requirement_forms(m, points).forces.linear for m in given]
    for f in forms[1:]:
        np.testing.assert_array_equal(f, forms[0])
    # the slider speeds are the closed form's of that leg: |J^-1 row| v_max
    speeds = V_MAX * np.linalg.norm(og.inverse_jacobian(points, 0.34), axis=-1)
    np.testing.assert_allclose(cases[1].slider_speed, speeds, rtol=EXACT_RTOL)


def test_points_beyond_the_slider_limits_are_refused(params: og.OrthoglideParams) -> None:
    # given limits that just cover the prototype's cube; the cube 10% larger leaves them
    tight = params.replace(slider_lower=params.slider_lower, slider_upper=params.slider_upper)
    corner = np.asarray(tight.workspace_corner)
    beyond = corner + 1.1 * tight.workspace_side
    q = og.inverse_kinematics(beyond, tight.leg_length)
    assert q.max() > tight.slider_upper  # reachable by the legs, not by the sliders
    with pytest.raises(og.UnreachablePointError, match="outside the limits"):
        worst_case_requirements(tight, beyond, V_MAX, A_MAX)
    with pytest.raises(og.UnreachablePointError, match="check_limits=False"):
        worst_case_over_cube(tight, corner, 1.1 * tight.workspace_side, resolution=3)
    # asked not to check, the forms are computed there (and agree with a point inside)
    wc = worst_case_requirements(tight, [beyond, corner], V_MAX, A_MAX, check_limits=False)
    inside = worst_case_requirements(tight, corner, V_MAX, A_MAX)
    np.testing.assert_allclose(wc.force[1], inside.force[0], rtol=EXACT_RTOL)
    # the machine's own cube is within its limits, corners included
    assert len(worst_case_over_cube(tight, resolution=2)) == 8
