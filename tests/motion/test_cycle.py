"""Tests of the standard test cycle of the prototype (orthoglide_pin.motion.cycle)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.motion.cycle import (
    CIRCLE_NORMAL_SHARE,
    CIRCLE_TANGENTIAL_SHARE,
    CYCLE_DWELL,
    standard_cycle,
    standard_cycle_segments,
)
from orthoglide_pin.motion.profiles import MotionLimits

#: The prototype's sizing figures (paper, section 4) and the documented jerk.
V, A, J = 1.2, 20.0, 1000.0
#: Rounding at the cube's faces and at the slider limits [m]; of the bounds (relative).
EXACT_TOL = 1e-12
#: Circles: radius a quarter of the side [m].
RADIUS = CUBE_SIDE / 4


@pytest.fixture(scope="module")
def cycle() -> og.Trajectory:
    return standard_cycle()


def test_stays_in_the_cube_and_spans_it(cycle: og.Trajectory) -> None:
    lo, hi = CUBE_CORNER, CUBE_CORNER + CUBE_SIDE
    assert cycle.p.min() >= lo - EXACT_TOL
    assert cycle.p.max() <= hi + EXACT_TOL
    np.testing.assert_allclose(cycle.p.min(axis=0), lo, atol=EXACT_TOL)
    np.testing.assert_allclose(cycle.p.max(axis=0), hi, atol=EXACT_TOL)
    for corner in itertools.product((lo, hi), repeat=3):  # every corner visited
        assert np.linalg.norm(cycle.p - corner, axis=1).min() < EXACT_TOL
    centre = np.full(3, lo + CUBE_SIDE / 2)
    np.testing.assert_allclose(cycle.p[0], centre, atol=EXACT_TOL)
    np.testing.assert_allclose(cycle.p[-1], centre, atol=EXACT_TOL)


def test_reachable_within_the_slider_limits(
    cycle: og.Trajectory, params: og.OrthoglideParams
) -> None:
    q = inverse_kinematics(cycle.p, params.leg_length)
    assert q.min() >= params.slider_lower - EXACT_TOL
    assert q.max() <= params.slider_upper + EXACT_TOL
    # Q2, the far corner, drives every slider to its upper limit
    assert q.max() == pytest.approx(params.slider_upper, abs=EXACT_TOL)
    q2 = inverse_kinematics(np.full(3, CUBE_CORNER + CUBE_SIDE), PROTOTYPE_LEG)
    np.testing.assert_allclose(q2, params.slider_upper, atol=EXACT_TOL)


def test_slider_speeds_stay_within_the_tool_speed(
    cycle: og.Trajectory, params: og.OrthoglideParams
) -> None:
    q = inverse_kinematics(cycle.p, params.leg_length)
    q_dot = np.einsum("nij,nj->ni", og.inverse_jacobian(cycle.p, params.leg_length), cycle.v)
    # paper eq. 2 against the time derivative of the inverse kinematics
    fd = (q[2:] - q[:-2]) / (2 * cycle.dt)
    q_ddot_top = np.abs(np.diff(q_dot, axis=0)).max() / cycle.dt  # Lipschitz constant
    assert np.abs(fd - q_dot[1:-1]).max() <= q_ddot_top * cycle.dt / 2
    assert np.abs(q_dot).max() <= V * (1 + EXACT_TOL)


def test_runs_at_the_paper_figures(cycle: og.Trajectory) -> None:
    speed, acc = cycle.speed, np.linalg.norm(cycle.a, axis=1)
    assert speed.max() == pytest.approx(V, rel=EXACT_TOL)
    assert acc.max() <= A * (1 + EXACT_TOL)
    assert acc.max() == pytest.approx(A, rel=1e-6)
    # the diagonal Q1 -> Q2 at full speed, in D / V + V / A + A / J
    diag = cycle.where("diagonal Q1-Q2")
    assert speed[diag].max() == pytest.approx(V, rel=EXACT_TOL)
    seg = cycle.labels.index("diagonal Q1-Q2")
    length = CUBE_SIDE * math.sqrt(3)
    expected = length / V + V / A + A / J
    duration = cycle.segment_times[seg + 1] - cycle.segment_times[seg]
    assert duration == pytest.approx(expected, rel=EXACT_TOL)
    diagonal = standard_cycle_segments()[1]
    q1 = np.full(3, -PROTOTYPE_LEG / math.sqrt(18))
    np.testing.assert_allclose(diagonal.start, q1, rtol=EXACT_TOL)
    np.testing.assert_allclose(diagonal.end, q1 + CUBE_SIDE, rtol=EXACT_TOL)
    # the jerk bound holds on every straight move
    straight = ~np.isin(cycle.labels, ["circle xy", "circle yz", "circle zx"])[cycle.segment]
    assert np.abs(cycle.j[straight]).max() <= J * (1 + EXACT_TOL)


def test_circles_and_square_in_the_mid_planes(cycle: og.Trajectory) -> None:
    centre = np.full(3, CUBE_CORNER + CUBE_SIDE / 2)
    v_circle = math.sqrt(CIRCLE_NORMAL_SHARE * A * RADIUS)
    assert math.isclose(CIRCLE_TANGENTIAL_SHARE**2 + CIRCLE_NORMAL_SHARE**2, 1.0)
    for name, axis in (("circle xy", 2), ("circle yz", 0), ("circle zx", 1)):
        on = cycle.where(name)
        rel = cycle.p[on] - centre
        np.testing.assert_allclose(np.linalg.norm(rel, axis=1), RADIUS, rtol=EXACT_TOL)
        np.testing.assert_allclose(rel[:, axis], 0.0, atol=EXACT_TOL)
        speed = cycle.speed[on]
        assert speed.max() == pytest.approx(v_circle, rel=EXACT_TOL)
        centripetal = -np.einsum("ij,ij->i", cycle.a[on], rel) / RADIUS
        np.testing.assert_allclose(centripetal, speed**2 / RADIUS, atol=1e-9)
        assert np.linalg.norm(cycle.a[on], axis=1).max() <= A * (1 + EXACT_TOL)
        # a whole turn: the chords add up to the circumference
        chords = np.linalg.norm(np.diff(cycle.p[on], axis=0), axis=1).sum()
        assert chords == pytest.approx(2 * math.pi * RADIUS, rel=1e-4)
    square = np.concatenate([cycle.p[cycle.where(f"square {k}")] for k in range(1, 5)])
    np.testing.assert_allclose(square[:, 2], centre[2], atol=EXACT_TOL)
    np.testing.assert_allclose(np.abs(square[:, :2] - centre[:2]).max(), CUBE_SIDE / 4)


def test_samples_are_derivatives_of_each_other(cycle: og.Trajectory) -> None:
    h = cycle.dt
    a_top, j_top = np.linalg.norm(cycle.a, axis=1).max(), np.abs(cycle.j).max()
    fd_v = (cycle.p[2:] - cycle.p[:-2]) / (2 * h)
    fd_a = (cycle.v[2:] - cycle.v[:-2]) / (2 * h)
    assert np.abs(fd_v - cycle.v[1:-1]).max() <= a_top * h / 2
    assert np.abs(fd_a - cycle.a[1:-1]).max() <= j_top * h / 2


def test_duration_adds_up(cycle: og.Trajectory) -> None:
    segments = standard_cycle_segments()
    assert len(segments) == 23
    moves = math.fsum(s.duration for s in segments)
    assert cycle.duration == pytest.approx(moves + CYCLE_DWELL * 22, rel=EXACT_TOL)
    edges = [s for s in segments if s.label.startswith("edge")]
    for edge in edges:  # 0.2 m along one axis
        assert edge.duration == pytest.approx(CUBE_SIDE / V + V / A + A / J, rel=EXACT_TOL)
    axes = [s.label[-3:-1] for s in edges]
    assert sorted(axes) == sorted(["+x", "+x", "-x", "-x", "+y", "-y", "+z", "-z"])
    # a trapezoidal cycle is faster, by at most a_max / J per move
    quick = standard_cycle(limits=MotionLimits(V, A))
    assert 0 < cycle.duration - quick.duration <= len(segments) * A / J + 2 * cycle.dt


def test_adapts_to_another_design() -> None:
    design = og.design_from_workspace(0.2, 1 / 3, 3.0)
    params = design.to_params()
    traj = standard_cycle(params, corner=design.cube_corner, side=design.cube_side)
    assert traj.p.min() >= design.cube_corner[0] - EXACT_TOL
    assert traj.p.max() <= design.cube_corner[0] + design.cube_side + EXACT_TOL
    q = inverse_kinematics(traj.p, params.leg_length)
    assert q.min() >= params.slider_lower - EXACT_TOL
    assert q.max() <= params.slider_upper + EXACT_TOL
    # by default the cycle runs the machine's own cube, and so does it with another leg
    assert np.array_equal(standard_cycle(params).p, traj.p)
    longer = standard_cycle(og.prototype().replace(leg_length=0.35))
    assert longer.p.min() == pytest.approx(og.prototype().workspace_corner[0], abs=EXACT_TOL)
    # a cube beyond the machine's (given) slider limits is refused
    fixed = og.prototype().replace(slider_lower=-0.08, slider_upper=0.19)
    with pytest.raises(InvalidParameterError, match="slider limits"):
        standard_cycle_segments(fixed, side=0.25)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"corner": [0.0, 0.0]}, "corner"),
        ({"corner": [0.0, math.nan, 0.0]}, "corner"),
        ({"side": -0.1}, "side"),
        ({"side": True}, "side"),
        ({"side": 0.25}, "side"),
        ({"dt": 0.0}, "dt"),
        ({"limits": (1.2, 20.0)}, "limits"),
    ],
)
def test_bad_input_names_the_value(kwargs: dict, name: str) -> None:
    with pytest.raises(InvalidParameterError) as info:
        standard_cycle(**kwargs)
    assert info.value.name == name
