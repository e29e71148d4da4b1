"""TOPP-RA's passes in closed form against toppra's own solver on the same rows."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning import parametrize as pz
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import X_CAP, PlanLimits, Scales, rows, speed_bound
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.reachability import reach
from orthoglide_pin.program.axes import ProgramAxes

#: Program axes equal to the world axes: the programs here name world points.
WORLD = ProgramAxes((1, 2, 3))

pytest.importorskip("toppra")

#: Squared speeds against toppra's, relative to the largest [-]: toppra's stages
#: keep up to about 3e-6 inside their rows (its solver's own margins), so its
#: profile wanders from the tight one by about that much.
X_RTOL = 1e-5
#: Largest violation of a row by the closed form [-] (rows read ``... <= 1``).
ROW_TOL = 1e-12
#: Durations against toppra's [-].
DURATION_RTOL = 1e-6
#: A corner-blended polyline and an arc, at a feed, and a rapid move.
PROGRAM = (
    "G21 G90 G64 P0.05\nG1 X20 Y5 F9000\nG1 X35 Y-10 Z15\nG1 X10 Y-30\n"
    "G3 X-10 Y-10 I0 J20\nG0 X0 Y0 Z0\n"
)


def _problem(
    dyn: og.ClosedLoopDynamics, limits: PlanLimits
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """``(s, a, b, c, x_bound)`` of each section of :data:`PROGRAM`, as the planner builds them."""
    out = []
    for section in build_path(read_program(PROGRAM, axes=WORLD)).sections:
        if not section.pieces:
            continue
        grid = sample_section(section, 2e-3)
        forms = path_forms(dyn, grid.p, grid.dp, grid.ddp)
        feed = np.array([np.inf if p.feed is None else p.feed for p in section.pieces])
        bound = np.minimum(speed_bound(limits, forms, feed[grid.piece], Scales()), X_CAP)
        a, b, c = rows(limits, forms, bound, 0.25 * bound, Scales())
        bound[[0, -1]] = 0.0
        out.append((grid.s, a, b, c, bound))
    return out


def _feasible(problem: tuple[np.ndarray, ...], x: np.ndarray) -> None:
    """Every row at both ends of every interval, and the bounds, hold at ``x``."""
    s, a, b, c, bound = problem
    u = np.diff(x) / (2.0 * np.diff(s))
    for k in (slice(None, -1), slice(1, None)):
        assert np.all(a[k] * u[:, None] + b[k] * x[k, None] + c[k] <= 1.0 + ROW_TOL)
    assert np.all(x >= 0.0) and np.all(x <= bound)


def _against_toppra(problem: tuple[np.ndarray, ...]) -> None:
    s = problem[0]
    ours = reach(*problem)
    theirs = pz._solve_by_toppra(*problem)
    assert ours is not None and theirs is not None
    ours[[0, -1]] = 0.0
    _feasible(problem, ours)
    np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=X_RTOL * theirs.max())
    assert pz.time_law(s, ours).duration == pytest.approx(
        pz.time_law(s, theirs).duration, rel=DURATION_RTOL
    )


@pytest.fixture(scope="module")
def motors() -> PlanLimits:
    return PlanLimits(drive=load_drive(str(example_drive_file())))


def test_motor_torque_rows_on_the_prototype(dyn: og.ClosedLoopDynamics, motors) -> None:
    problems = _problem(dyn, motors)
    assert len(problems) >= 2  # the feed moves, then the rapid move
    for problem in problems:
        _against_toppra(problem)


def test_slider_rows_on_another_design() -> None:
    params = og.prototype().replace(leg_length=0.35, platform_offset=0.035)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    limits = PlanLimits(slider_speed=1.2, slider_acceleration=20.0)
    for problem in _problem(dyn, limits):
        _against_toppra(problem)


def test_sections_laid_end_to_end_are_planned_each_from_rest(
    dyn: og.ClosedLoopDynamics, motors
) -> None:
    problems = _problem(dyn, motors)
    parts = [(a, b, c) for _, a, b, c, _ in problems]
    joined = pz._solve_joined([p[0] for p in problems], parts, [p[4] for p in problems])
    assert joined is not None
    for x, problem in zip(joined, problems, strict=True):
        alone = reach(*problem)
        assert alone is not None
        alone[[0, -1]] = 0.0
        np.testing.assert_allclose(x, alone, rtol=0.0, atol=X_RTOL * alone.max())


def test_an_impossible_stage_is_none_and_toppra_agrees(dyn: og.ClosedLoopDynamics, motors) -> None:
    s, a, b, c, bound = _problem(dyn, motors)[0]
    c = c.copy()
    c[len(s) // 2] = 1.5  # a point where no speed and no acceleration meet the rows
    assert reach(s, a, b, c, bound) is None
    assert pz._solve_by_toppra(s, a, b, c, bound) is None
    assert pz._solve(s, a, b, c, bound) is None


def test_what_the_closed_form_cannot_settle_goes_to_toppra(
    dyn: og.ClosedLoopDynamics, motors, monkeypatch: pytest.MonkeyPatch
) -> None:
    problem = _problem(dyn, motors)[0]
    expected = pz._solve_by_toppra(*problem)
    monkeypatch.setattr(pz, "reach", lambda *args: None)
    np.testing.assert_array_equal(pz._solve(*problem), expected)


def test_sections_end_to_end_that_fail_are_not_sent_to_toppra_together(
    dyn: og.ClosedLoopDynamics, motors, monkeypatch: pytest.MonkeyPatch
) -> None:
    problems = _problem(dyn, motors)
    asked: list[int] = []
    monkeypatch.setattr(pz, "reach", lambda *args: None)
    monkeypatch.setattr(pz, "_solve_by_toppra", lambda s, *rest: asked.append(s.size))
    parts = [(a, b, c) for _, a, b, c, _ in problems]
    assert pz._solve_joined([p[0] for p in problems], parts, [p[4] for p in problems]) is None
    assert asked == []  # the caller plans each alone, and toppra confirms each
    assert pz._solve_joined([problems[0][0]], parts[:1], [problems[0][4]]) is None
    assert asked == [problems[0][0].size]
