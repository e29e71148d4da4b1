"""The slider jerk limit: the S-curve, the jerk by differences, the shipped contour, bad values."""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.jerk import SmoothedPlan
from orthoglide_pin.planning.jerk_stops import (
    BLEND_STOP_SHARE,
    split_at_curvature_steps,
    tight_blend,
)
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import time_law
from orthoglide_pin.planning.path import build_path
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.shipped import example_program_text
from orthoglide_pin.planning.verify import USE_TOL
from orthoglide_pin.program.axes import ProgramAxes

#: Program axes equal to the world axes: the programs here name world points.
WORLD = ProgramAxes((1, 2, 3))

pytest.importorskip("toppra")

#: Cycle time against the closed-form S-curve [-].
S_CURVE_RTOL = 5e-3
#: The jerk against central differences of the accelerations, as a share of the limit [-].
DIFF_TOL = 1e-5
#: Time step of the central differences [s].
DIFF_STEP = 1e-6
V, A, J = 0.3, 10.0, 1000.0


def _line(a: np.ndarray, b: np.ndarray) -> str:
    return "".join(
        f"G0 X{1e3 * p[0]:.12f} Y{1e3 * p[1]:.12f} Z{1e3 * p[2]:.12f}\n" for p in (a, b)
    )


def _s_curve(distance: float, v: float, a: float, j: float) -> float:
    """Fastest rest-to-rest time of one axis under |q'| <= v, |q''| <= a, |q'''| <= j."""
    # time from rest to v: with a constant-acceleration phase, or without (a not reached)
    rise = v / a + a / j if v * j >= a * a else 2.0 * math.sqrt(v / j)
    assert v * rise <= distance, "the move must reach the speed"
    return 2.0 * rise + (distance - v * rise) / v


def test_q1_to_q2_matches_the_seven_segment_s_curve(params: og.OrthoglideParams) -> None:
    a, b = params.workspace.q1, params.workspace.q2
    prog = read_program(_line(a, b), start=a, axes=WORLD)
    plan = plan_program(
        prog, params, PlanLimits(slider_speed=V, slider_acceleration=A, slider_jerk=J)
    )
    q = og.inverse_kinematics(np.stack([a, b]), params.leg_length)
    assert np.allclose(q[1] - q[1, 0], 0.0) and np.allclose(q[0] - q[0, 0], 0.0)  # alike
    reference = _s_curve(float(q[1, 0] - q[0, 0]), V, A, J)
    assert plan.cycle_time == pytest.approx(reference, rel=S_CURVE_RTOL)
    assert plan.cycle_time >= reference * (1.0 - 1e-3)  # never faster than the optimum
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    assert plan.worst["slider_jerk"] == pytest.approx(1.0, abs=1e-2)
    cost = plan.jerk_time_cost
    assert cost is not None and cost["with_jerk"] == plan.cycle_time
    second = plan_program(prog, params, PlanLimits(slider_speed=V, slider_acceleration=A))
    assert cost["second_order"] == pytest.approx(second.cycle_time, rel=1e-12)
    assert cost["ratio"] == pytest.approx(plan.cycle_time / second.cycle_time)


def test_the_jerk_matches_differences_of_the_accelerations(params: og.OrthoglideParams) -> None:
    prog = read_program("G61\nG1 X30 F6000\nG3 X0 Y30 I-30 J0 Z-10\n")  # a helix after a line
    limits = PlanLimits(slider_acceleration=5.0, slider_jerk=200.0)
    plan = plan_program(prog, params, limits)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    for r in plan.sections:
        law, m = r.plan, r.motion
        assert isinstance(law, SmoothedPlan) and m is not None and m.qddd is not None
        t = m.t[1:-1]
        qdd = []
        for dt in (-DIFF_STEP, DIFF_STEP):
            s, sd, sdd = law.at_times(t + dt)
            piece = r.section.pieces[0]
            assert len(r.section.pieces) == 1
            p, dp, ddp = piece.evaluate(s - r.section.offsets[0])
            acc = dp * sdd[:, None] + ddp * (sd * sd)[:, None]
            res = dyn.inverse_dynamics(p, dp * sd[:, None], acc)
            qdd.append(res.slider_accelerations)
        diff = (qdd[1] - qdd[0]) / (2.0 * DIFF_STEP)
        err = np.abs(diff - m.qddd[1:-1]).max(axis=1) / 200.0
        # s''' steps at the filter's knots: a difference across one averages the two sides
        knots = np.concatenate([law.t, law.t + law.window])
        away = np.abs(t[:, None] - knots[None, :]).min(axis=1) > 2.0 * DIFF_STEP
        assert away.mean() > 0.9
        assert err[away].max() < DIFF_TOL, err[away].max()
        assert np.abs(m.qddd).max() <= 200.0 * (1.0 + USE_TOL)


def test_a_smoothed_law_starts_and_ends_at_rest_and_keeps_its_length() -> None:
    s = np.linspace(0.0, 0.1, 51)
    x = np.minimum(2.0 * 5.0 * s, 2.0 * 5.0 * (0.1 - s))  # triangle at 5 m/s^2
    base = time_law(s, x)
    law = SmoothedPlan(base.s, base.x, base.u, base.t, window=0.02)
    assert law.duration == pytest.approx(time_law(s, x).duration + 0.02)
    ends = np.array([0.0, law.duration])
    pos, speed, acc, jerk = law.motion(ends)
    assert np.allclose(pos, [0.0, 0.1]) and np.allclose(speed, 0.0) and np.allclose(acc, 0.0)
    t = np.linspace(0.0, law.duration, 2001)
    pos, speed, acc, jerk = law.motion(t)
    assert np.all(np.diff(pos) >= 0.0) and np.abs(jerk).max() <= 2 * 5.0 / 0.02 + 1e-9
    back = law.time_at(pos)
    assert np.abs(law.motion(back)[0] - pos).max() < 1e-12  # [m]
    moving = speed > 1e-3  # near rest the time at a length is ill-conditioned (s ~ t^3)
    assert np.allclose(back[moving], t[moving], atol=1e-9)


def test_the_shipped_contour_with_jerk_is_verified(params: og.OrthoglideParams) -> None:
    prog = read_program(example_program_text("contour"))
    drive = load_drive(str(example_drive_file()))
    plan = plan_program(
        prog, params, PlanLimits(slider_acceleration=20.0, slider_jerk=500.0, drive=drive)
    )
    assert set(plan.worst) >= {"slider_acceleration", "slider_jerk", "motor_torque", "feed"}
    assert max(plan.worst.values()) <= 1.0 + USE_TOL, plan.worst
    cost = plan.jerk_time_cost
    assert cost is not None and cost["with_jerk"] >= cost["second_order"]
    path = build_path(prog)
    # its G64 corners and line-arc joints are blended by G2 quintics: no curvature step left
    assert split_at_curvature_steps(path)[1] == 0
    # but its tightest blends would crawl under the jerk limit: stops at their ends
    tight = [p for sec in path.sections for p in sec.pieces if tight_blend(p, 500.0, None)]
    _, stops = split_at_curvature_steps(path, 500.0)
    assert cost["curvature_stops"] == stops and 0 < stops <= 2 * len(tight)
    for piece in (p for p in tight if p.feed is not None):  # a rapid blend is always tight
        # the cap from differences of the exact curvature, not from third()
        s = np.linspace(0.0, piece.length, 2001)
        third = np.linalg.norm(np.gradient(piece.evaluate(s)[2], s, axis=0), axis=1).max()
        assert np.cbrt(500.0 / third) < BLEND_STOP_SHARE * piece.feed * (1.0 + 1e-2)
    for r in plan.sections:
        if r.plan is not None:  # rest, with no acceleration, at every section's ends
            _, sd, sdd = r.plan.at_times(np.array([0.0, r.plan.duration]))
            assert np.allclose(sd, 0.0) and np.allclose(sdd, 0.0)


def test_another_design_with_jerk() -> None:
    params = og.prototype().replace(leg_length=0.36)
    c = params.workspace
    half = np.array([0.0, 0.0, 0.5 * c.side])
    a, b = c.q1 + half, c.q2 - half
    prog = read_program(_line(a, b), start=a, axes=WORLD)
    lim = PlanLimits(slider_speed=V, slider_acceleration=A, slider_jerk=J)
    plan = plan_program(prog, params, lim)
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    assert plan.worst["slider_jerk"] == pytest.approx(1.0, abs=1e-2)
    assert plan.jerk_time_cost is not None
    assert plan.cycle_time >= plan.jerk_time_cost["second_order"]


@pytest.mark.parametrize("bad", [0.0, -5.0, math.nan, math.inf, "fast", True])
def test_a_bad_jerk_is_refused_naming_it(bad: object) -> None:
    with pytest.raises(InvalidParameterError, match="slider_jerk"):
        PlanLimits(slider_acceleration=10.0, slider_jerk=bad)  # type: ignore[arg-type]
