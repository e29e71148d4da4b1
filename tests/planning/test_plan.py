"""Whole programs planned and verified: every limit's worst use within 1 + 1e-3."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import orthoglide_pin as og
import orthoglide_pin.planning.plan as plan_module
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning import EXAMPLE_PROGRAMS, example_program_text, read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.verify import USE_TOL
from orthoglide_pin.program.axes import ProgramAxes

#: Program axes equal to the world axes: the programs here name world points.
WORLD = ProgramAxes((1, 2, 3))

pytest.importorskip("toppra")

SLIDERS = PlanLimits(slider_speed=1.2, slider_acceleration=20.0)
#: A program of many sections planned in runs against all at once (the same
#: sections planned alike; only their batching differs) [-].
RUNS_RTOL = 1e-9
#: Their binding shares [-]: a fine sample at the threshold may flip with the last digit.
RUNS_BINDING_ATOL = 1e-3


@pytest.fixture(scope="module")
def motor_limits() -> PlanLimits:
    return PlanLimits(drive=load_drive(str(example_drive_file())))


def _verified(plan) -> None:
    assert plan.worst, "no limit was checked"
    assert max(plan.worst.values()) <= 1.0 + USE_TOL, plan.worst
    assert plan.cycle_time > 0.0
    times = [(b.start, b.end) for b in plan.blocks]
    assert all(t0 <= t1 + 1e-12 for t0, t1 in times)
    assert all(a[1] <= b[0] + 1e-9 for a, b in itertools.pairwise(times))  # in order
    assert times[-1][1] == pytest.approx(plan.cycle_time)


#: Arcs of radius 0.01 mm, each a half turn of 0.02 mm chord, alternating in y.
TINY_ARCS = "".join(
    f"G3 X{10 + 0.001 * (k + 1):.4f} Y{0.001 * (k % 2):.4f} R0.01\n" for k in range(20)
)
AWKWARD = {
    "lines": "G64 P0.05\nG1 X20 F6000\nG1 Y20\nG1 X-20 Z10\nG61\nG1 X0 Y0 Z0\n",
    "arcs": "G1 X20 F9000\nG3 X0 Y20 I-20 J0\nG2 X-20 Y0 R-20\nG18 G2 X0 Z20 I20 K0\n",
    "tiny_arcs": "G64\nG1 X10 F3000\n" + TINY_ARCS,
    "zero_length": "G1 X10 F3000\nG1 X10\nG91 G1 X0 Y0 Z0\nG0 X0\nG90 G1 X0\nG4 P0\n",
    "full_circles": "G1 X30 F6000\nG3 X30 Y0 I-30 J0\nG2 X30 Y0 I-15 J0 Z-10\n"
    "G19 G2 Y0 Z-10 J10\n",
    "incremental": "G91 G64 P0.02\nG1 X10 F6000\n"
    + "G1 X5 Y5\nG1 X-5 Y5\nG1 X-5 Y-5\nG1 X5 Y-5\n" * 5
    + "G2 X10 Y0 R5\nG90 G0 X0 Y0\n",
}


@pytest.mark.parametrize("name", sorted(AWKWARD))
def test_awkward_programs_are_verified(name: str, params, motor_limits) -> None:
    prog = read_program(AWKWARD[name])
    for limits in (SLIDERS, motor_limits):
        _verified(plan_program(prog, params, limits))


@pytest.mark.parametrize("name", sorted(EXAMPLE_PROGRAMS))
def test_each_shipped_example_is_verified(name: str, params, motor_limits) -> None:
    prog = read_program(example_program_text(name))
    plan = plan_program(prog, params, motor_limits)
    _verified(plan)
    assert plan.worst["motor_torque"] == pytest.approx(1.0, abs=USE_TOL)  # it binds
    assert plan.worst["feed"] == pytest.approx(1.0, abs=USE_TOL)
    assert plan.grid_points > 100


def test_the_motor_limits_bind_on_a_fast_move(params, motor_limits) -> None:
    prog = read_program("G0 X100 Y100 Z100\n", axes=WORLD)
    plan = plan_program(prog, params, motor_limits)
    _verified(plan)
    assert plan.worst["motor_speed"] == pytest.approx(1.0, abs=USE_TOL)
    assert plan.binding["motor_speed"] > 0.2 and plan.binding["motor_torque"] > 0.2
    # a heavier tool wrench against the vertical slider costs time
    heavy = plan_program(prog, params, motor_limits, wrench=(0.0, 0.0, 300.0))
    _verified(heavy)
    assert heavy.cycle_time > plan.cycle_time


@pytest.mark.slow
def test_a_program_of_5000_blocks_is_verified(params) -> None:
    rng = np.random.default_rng(5)
    pts = rng.uniform(-60.0, 110.0, size=(5000, 3))
    text = "G64 P0.01\nF30000\n" + "".join(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f}\n" for x, y, z in pts)
    plan = plan_program(read_program(text, axes=WORLD), params, SLIDERS)
    _verified(plan)
    assert len(plan.blocks) == 5000


def test_a_move_without_acceleration_limit_is_refused(params) -> None:
    prog = read_program("G1 X10 F600\nG1 Y10\n")
    with pytest.raises(ProgramError, match="no limit bounds this move") as info:
        plan_program(prog, params, PlanLimits(slider_speed=1.0))
    assert info.value.line == 1


def test_a_point_outside_the_cube_is_refused_with_its_line(params) -> None:
    prog = read_program("G1 X10 F600\nG1 X127\n")
    with pytest.raises(ProgramError, match="outside the machine's") as info:
        plan_program(prog, params, SLIDERS)
    assert info.value.line == 2


def test_motors_too_weak_for_gravity_are_refused(params) -> None:
    weak = og.Drive(og.DriveTrain(), og.MotorData(peak_torque=0.01))
    with pytest.raises(ProgramError, match="no motion meets the limits"):
        plan_program(read_program("G1 X10 F600\n"), params, PlanLimits(drive=weak))


#: Lines, a full circle, an S of two arcs, a reversal and a helix, blended within 0.02 mm.
BLENDED = (
    "G64 P0.02\nG1 X20 F6000\nG3 X20 Y0 I-10 J0\nG2 X40 Y0 I10\nG1 Y20\n"
    "G2 X20 Y40 R20 Z-5\nG1 X0 Z10\nG19 G3 Y20 Z30 J-20 K0\n"
)


@pytest.mark.parametrize("leg_length", [None, 0.36])
def test_blended_arcs_are_verified_on_two_designs(leg_length, params, motor_limits) -> None:
    design = params if leg_length is None else params.replace(leg_length=leg_length)
    prog = read_program(BLENDED)
    for limits in (SLIDERS, motor_limits):
        plan = plan_program(prog, design, limits)
        _verified(plan)
    sections = plan.path.sections
    assert len(sections) == 2  # the tool stops only where it turns back (line 5)
    pieces = [p for s in sections for p in s.pieces]
    assert sum(p.is_blend for p in pieces) == 5  # every joint but the reversal
    # each blend has an arc on one side at least
    assert all(
        a.is_arc or c.is_arc
        for a, b, c in zip(pieces, pieces[1:], pieces[2:], strict=False)
        if b.is_blend
    )


def test_many_sections_are_planned_in_runs_that_keep_only_their_laws(
    monkeypatch: pytest.MonkeyPatch, params
) -> None:
    lines = ["G21 G90 G61", "G0 X-20 Y0 Z10", "F3000"]
    lines += [f"G1 X{-20 + 0.3 * k:.4f} Y{0.1 * (k % 4):.4f}" for k in range(1, 61)]
    lines += ["G4 P0.5", "G1 X0 Y5"]
    prog = read_program("\n".join(lines) + "\n")
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0)
    told: list[tuple[int, int]] = []
    kept = plan_program(prog, params, limits)
    monkeypatch.setattr(plan_module, "RUN_POINTS", 100)  # runs of about 10 sections
    runs = plan_program(prog, params, limits, progress=lambda *a: told.append(a))
    assert runs.cycle_time == pytest.approx(kept.cycle_time, rel=RUNS_RTOL)
    assert runs.grid_points == kept.grid_points
    assert runs.worst == pytest.approx(kept.worst, rel=RUNS_RTOL)
    assert runs.binding == pytest.approx(kept.binding, abs=RUNS_BINDING_ATOL)
    for mine, theirs in zip(runs.blocks, kept.blocks, strict=True):
        assert mine.end == pytest.approx(theirs.end, rel=RUNS_RTOL)
    moving = [r for r in runs.sections if r.plan is not None]
    assert len(moving) == 62 and all(r.grid is None and r.motion is None for r in moving)
    assert all(r.grid is not None for r in kept.sections if r.plan is not None)
    assert told[-1] == (len(prog.blocks), len(prog.blocks))
