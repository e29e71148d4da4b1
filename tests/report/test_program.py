"""A part program in the torque-requirement report: its plan, motor demand and verdict rows."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import MotorData, motor_demand
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning import PlanLimits, plan_program
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.sampling import sample_plan
from orthoglide_pin.report.assemble import ReportData, assemble_report
from orthoglide_pin.report.program import PROGRAM_CRITERIA, program_html

pytest.importorskip("toppra")

EXAMPLE_DRIVE = Path(str(og.example_drive_file()))
GRID = {"resolution": 3, "cube_resolution": 2}
#: Rapid moves back and forth along x, then a feed move: the slider limits bind.
RAPIDS = "G21 G90\nG0 X60\nG0 X-60\nG0 X60 Y40\nG1 X0 Y0 Z30 F3000\nM2\n"
#: Short rapids in x and z: the sliders accelerate all the time, the RMS torque is high.
SHUTTLE = "G21 G90\n" + "G0 X25 Z25\nG0 X-25 Z-25\n" * 4
#: Slider speed and acceleration of the report (its v_max and a_max).
V_MAX, A_MAX = 0.9, 12.0
#: The verification's tolerance on a limit's use, as the planner's.
USE_TOL = 1e-3
#: RMS torque from 1 ms samples, or the verification grid's integral, against a dense sampling [-].
RMS_RTOL = 0.01
#: The dense sampling step the RMS routes are held to [s].
DENSE_DT = 1e-5
EXACT_RTOL = 1e-9


@pytest.fixture(scope="module")
def judged(params: og.OrthoglideParams) -> ReportData:
    return assemble_report(
        params,
        og.load_drive(EXAMPLE_DRIVE),
        v_max=V_MAX,
        a_max=A_MAX,
        program=read_program(RAPIDS),
        program_name="rapids.nc",
        **GRID,
    )


def test_the_sliders_run_at_the_reports_limits(judged: ReportData) -> None:
    sec = judged.program
    assert sec is not None and sec.name == "rapids.nc" and sec.blocks == 4
    assert (sec.slider_speed, sec.slider_acceleration) == (V_MAX, A_MAX)
    # a slider reaches v_max on the long rapids and none exceeds it
    assert sec.peak_slider_speed.max() == pytest.approx(V_MAX, rel=USE_TOL)
    assert sec.worst["slider_speed"] <= 1.0 + USE_TOL
    assert sec.worst["slider_acceleration"] <= 1.0 + USE_TOL
    assert "motor_torque" not in sec.worst  # the motor is judged, not a limit
    # the motor turns 1/lead turns per metre of its slider (direct drive)
    train = judged.drive.train
    rpm = sec.peak_slider_speed * 60.0 * train.gear_ratio / train.lead
    np.testing.assert_allclose(sec.statistics.peak_speed_rpm, rpm, rtol=EXACT_RTOL)


def test_rms_torque_agrees_with_the_verification_grid(
    judged: ReportData, params: og.OrthoglideParams, dyn: og.ClosedLoopDynamics
) -> None:
    """The RMS over 1 ms samples and the integral over the plan's own fine grid, each
    against a dense sampling of the same plan (every 10 us: converged to 1e-4)."""
    sec = judged.program
    assert sec is not None
    plan = plan_program(
        read_program(RAPIDS),
        dyn,
        PlanLimits(V_MAX, A_MAX, drive=og.Drive(train=judged.drive.train)),
    )
    assert plan.cycle_time == pytest.approx(sec.cycle_time, rel=EXACT_RTOL)
    integral = 0.0
    for r in plan.sections:
        m = r.motion
        assert m is not None
        tau = motor_demand(m.forces, m.qd, m.qdd, judged.drive.train).torque
        integral += np.trapezoid(tau**2, m.t, axis=0)
    rms = np.sqrt(integral / plan.cycle_time)
    dense = sample_plan(plan, dyn, DENSE_DT)
    tau = np.stack([np.asarray(dense[f"tau{i}"]) for i in (1, 2, 3)], axis=1)
    exact = np.sqrt(np.trapezoid(tau**2, np.asarray(dense["t"]), axis=0) / plan.cycle_time)
    np.testing.assert_allclose(sec.statistics.rms_torque, exact, rtol=RMS_RTOL)
    np.testing.assert_allclose(rms, exact, rtol=RMS_RTOL)


def test_a_dwell_holds_the_tool_against_gravity(
    params: og.OrthoglideParams, dyn: og.ClosedLoopDynamics
) -> None:
    """At rest the torque is the holding torque: its RMS is its peak (another design)."""
    longer = dataclasses.replace(params, leg_length=0.34)
    data = assemble_report(longer, program=read_program("G4 P0.5\n"), **GRID)
    sec = data.program
    assert sec is not None and sec.cycle_time == pytest.approx(0.5)
    d2 = og.ClosedLoopDynamics(og.ClosedLoopModel(longer))
    rest = d2.inverse_dynamics(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)))
    hold = np.abs(motor_demand(rest.forces, np.zeros((1, 3)), np.zeros((1, 3))).torque[0])
    assert hold[2] > 0.1 and hold[:2].max() < 1e-12  # gravity along the vertical slider
    for got in (sec.statistics.peak_torque, sec.statistics.rms_torque):
        np.testing.assert_allclose(got, hold, rtol=EXACT_RTOL, atol=1e-12)
    # without motor data the rows are requirements, with no margin
    rows = [r for r in data.verdict if r.criterion.startswith("program:")]
    assert len(rows) == 9 and all(r.margin is None for r in rows) and data.passed is None


def test_the_verdict_covers_the_program(params: og.OrthoglideParams, judged: ReportData) -> None:
    rows = [r for r in judged.verdict if r.criterion.startswith("program:")]
    names = [c for c, _, _ in PROGRAM_CRITERIA]
    assert {r.criterion for r in rows} <= set(names) and len(rows) >= 9
    assert sorted({r.motor for r in rows}) == [1, 2, 3]
    for r in rows:  # with motor data every row says what is available, the curve's too
        assert r.available is not None and r.margin == pytest.approx(1 - r.required / r.available)
    assert {r.criterion for r in rows} == set(names)
    page = program_html(judged.program)
    assert f"within {1e3 * V_MAX:.4g} mm/s and {A_MAX:g} m/s^2" in page
    assert "peak slider speed [mm/s]" in page and "[m/s]" not in page
    # a motor whose rated torque the program's RMS exceeds fails on that row only
    sec = judged.program
    assert sec is not None and judged.passed is True
    plain = assemble_report(params, judged.drive, v_max=V_MAX, a_max=A_MAX, **GRID)
    shuttle = assemble_report(
        params, judged.drive, v_max=V_MAX, a_max=A_MAX, program=read_program(SHUTTLE), **GRID
    )
    assert shuttle.program is not None and shuttle.program.binding["slider_acceleration"] > 0.9
    cycle_rms = plain.sizing.statistics.rms_torque.max()
    prog_rms = shuttle.program.statistics.rms_torque.max()
    assert prog_rms > 1.5 * cycle_rms  # the shuttle asks more than the standard cycle
    rated = 0.5 * (cycle_rms + prog_rms)
    motor = MotorData(name="rated between", rated_torque=float(rated))
    drive = og.Drive(train=judged.drive.train, motor=motor)
    fails = assemble_report(
        params, drive, v_max=V_MAX, a_max=A_MAX, program=read_program(SHUTTLE), **GRID
    )
    failed = {r.criterion for r in fails.verdict if r.passed is False}
    assert fails.passed is False and failed == {"program: RMS torque vs rated torque"}
    plain = assemble_report(params, drive, v_max=V_MAX, a_max=A_MAX, **GRID)
    assert plain.passed is True and plain.program is None  # the failure is the program's
    assert sum(r.passed is False for r in fails.verdict) == 2  # motors 1 and 3 (y barely moves)


def test_safety_factor_multiplies_the_programs_torques(
    params: og.OrthoglideParams, judged: ReportData
) -> None:
    k = 1.5
    safe = assemble_report(
        params,
        judged.drive,
        v_max=V_MAX,
        a_max=A_MAX,
        program=read_program(RAPIDS),
        safety_factor=k,
        **GRID,
    )
    base = {(r.motor, r.criterion): r.required for r in judged.verdict}
    for r in safe.verdict:
        if r.criterion.startswith("program:"):
            factor = 1.0 if r.unit == "rpm" else k
            assert r.required == pytest.approx(factor * base[(r.motor, r.criterion)])


def test_a_program_outside_the_cube_is_refused(params: og.OrthoglideParams) -> None:
    with pytest.raises(ProgramError, match="program line 2"):
        assemble_report(params, program=read_program("G21\nG0 X400\n"), **GRID)


#: plan, report --program and sweep --program: one cycle time for one program [-].
ROUTES_RTOL = 1e-9


def test_plan_report_and_sweep_give_one_cycle_time(params: og.OrthoglideParams) -> None:
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.report.program import program_section
    from orthoglide_pin.sweep.program import program_metrics

    text = "G21 G90\nG0 X30\nG1 X-20 Y10 F3000\nM2\n"
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    planned = plan_program(
        read_program(text), dyn, PlanLimits(slider_speed=V_MAX, slider_acceleration=A_MAX)
    ).cycle_time
    reported = program_section(
        dyn,
        og.load_drive(EXAMPLE_DRIVE),
        read_program(text),
        v_max=V_MAX,
        a_max=A_MAX,
        gravity=dyn.gravity_vector(None),
    ).cycle_time
    swept = program_metrics(
        params, {"program": {"text": text}, "speed": V_MAX, "acceleration": A_MAX}
    )["cycle_time"]
    assert reported == pytest.approx(planned, rel=ROUTES_RTOL)
    assert swept == pytest.approx(planned, rel=ROUTES_RTOL)
