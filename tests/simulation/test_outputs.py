"""The columns and summary of a run: consistent with the run and its contour error."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.simulation.outputs import (
    COLUMNS,
    csv_text,
    cutting_samples,
    run_contour_error,
    running_blocks,
    simulation_columns,
    simulation_summary,
)
from orthoglide_pin.viewer.planned import KNOWN_COLUMNS, REQUIRED_COLUMNS

pytest.importorskip("mujoco")
pytest.importorskip("toppra")

PROGRAM = "G21 G90\nG1 X10 Y4 F3000\nG4 P0.05\nG0 X0 Y0\nM30\n"


@pytest.fixture(scope="module")
def case() -> tuple[og.Plan, og.SimulationRun, og.ContourError]:
    drive = og.load_drive(str(og.example_drive_file()))
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel())
    plan = og.plan_program(og.read_program(PROGRAM), dyn, og.PlanLimits(drive=drive))
    run = og.simulate(plan, dyn, drive, og.ServoSettings(encoder_counts=2**17))
    return plan, run, run_contour_error(plan, run)


def test_columns_and_csv(case: tuple[og.Plan, og.SimulationRun, og.ContourError]) -> None:
    plan, run, contour = case
    cols = simulation_columns(run, contour, plan)
    assert tuple(cols) == COLUMNS
    assert set(COLUMNS) <= set(KNOWN_COLUMNS) and set(REQUIRED_COLUMNS) <= set(COLUMNS)
    rows = np.loadtxt(io.StringIO(csv_text(cols)), delimiter=",", skiprows=1)
    assert rows.shape == (run.t.size, len(COLUMNS))
    assert np.allclose(rows[:, COLUMNS.index("e2")], run.q[:, 1] - run.q_ref[:, 1], atol=1e-15)
    central = (run.p[2:] - run.p[:-2]) / (run.t[2:] - run.t[:-2])[:, None]  # by hand
    assert np.allclose(cols["path_speed"][1:-1], np.linalg.norm(central, axis=1), rtol=1e-9)
    lines = set(cols["line"].astype(int))
    assert lines == {2, 3, 4}  # the line, the dwell, the rapid move
    assert set(cols["line"][cols["cutting"] == 1.0].astype(int)) == {2}


def test_summary_is_strict_and_consistent(
    case: tuple[og.Plan, og.SimulationRun, og.ContourError],
) -> None:
    plan, run, contour = case
    summary = simulation_summary(run, contour, plan)
    json.dumps(summary, allow_nan=False)
    lines, rapid = running_blocks(plan, run.t)
    cutting = cutting_samples(plan, run.t)
    assert set(lines[cutting]) == {2}  # the line: not the dwell, not the rapid move
    assert summary["max_contour_error"] == pytest.approx(contour.distance[cutting].max())
    assert summary["max_rapid_deviation"] == pytest.approx(contour.distance[rapid].max())
    at = summary["max_contour_error_at"]
    k = int(np.argmin(np.abs(run.t - at["t"])))
    assert np.allclose([at["x"], at["y"], at["z"]], run.p[k]) and at["line"] == 2
    line = next(b for b in plan.blocks if b.line == 2)
    assert summary["cutting_time"] == pytest.approx(line.end - line.start, rel=1e-12)
    assert 0.0 < summary["cutting_share"] < 1.0
    err = np.abs(run.q - run.q_ref)
    assert summary["max_tracking_error"] == pytest.approx(list(err.max(axis=0)))
    assert summary["encoder_counts"] == 2**17 and summary["samples"] == run.t.size
    resolution = 0.025 / 2**17  # one count of the encoder, at the slider [m]
    assert max(summary["max_tracking_error"]) > 0.1 * resolution  # the counts show
