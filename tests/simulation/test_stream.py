"""A run streamed to disk a chunk at a time: the file and the figures of the whole run."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.simulation.outputs import (
    COLUMNS,
    run_contour_error,
    simulation_columns,
    simulation_summary,
)
from orthoglide_pin.simulation.stream import PLOTTED, write_simulation

pytest.importorskip("mujoco")
pytest.importorskip("toppra")

DRIVE = og.load_drive(str(og.example_drive_file()))
#: A cut, a blended corner, an arc, a rapid move back (mm).
PROGRAM = "G21 G90 G64 P0.05\nG1 X10 Y5 Z-5 F3000\nG1 Y10\nG2 X10 Y0 I0 J-5\nG0 X0 Y0 Z0\nM30\n"
#: Periods per chunk: several chunks, the last one short.
CHUNK = 613
#: The contour error of a chunk agrees with the whole run's to its projection's tolerance [m].
CONTOUR_TOL = 1e-15
#: Sums of squares added by chunks: the RMS figures agree to rounding [-].
RMS_RTOL = 1e-12


@pytest.fixture(scope="module")
def setup() -> tuple[og.Plan, og.ClosedLoopDynamics]:
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel())
    plan = og.plan_program(og.read_program(PROGRAM), dyn, og.PlanLimits(drive=DRIVE))
    return plan, dyn


def _read(path: Path) -> dict[str, np.ndarray]:
    with open(path) as fh:
        first = fh.readline()
        assert first.startswith("# orthoglide design")
        rows = list(csv.reader(fh))
    table = np.array(rows[1:], dtype=float)
    return {name: table[:, k] for k, name in enumerate(rows[0])}


def test_the_streamed_file_is_the_run_held_in_memory(setup, tmp_path: Path) -> None:
    plan, dyn = setup
    run = og.simulate(plan, dyn, DRIVE)
    contour = run_contour_error(plan, run)
    whole = simulation_columns(run, contour, plan)
    summary = simulation_summary(run, contour, plan)
    assert run.t.size > 3 * CHUNK
    out = write_simulation(
        tmp_path / "simulation.csv", plan, dyn, DRIVE, chunk=CHUNK,
        first_line="# orthoglide design: test\n",
    )  # fmt: skip
    got = _read(tmp_path / "simulation.csv")
    assert list(got) == list(COLUMNS) and out.samples == run.t.size
    for name in COLUMNS:
        expected = np.array([float(f"{v:.10g}") for v in whole[name]])
        if name == "contour_error":
            np.testing.assert_allclose(got[name], expected, rtol=1e-9, atol=CONTOUR_TOL)
        else:  # to the last digit written, the path speed across the chunks' edges too
            assert np.array_equal(got[name], expected), name
    for key, value in summary.items():
        if key.startswith("rms_"):
            np.testing.assert_allclose(out.summary[key], value, rtol=RMS_RTOL)
        elif key in ("max_contour_error", "max_rapid_deviation"):
            assert out.summary[key] == pytest.approx(value, abs=CONTOUR_TOL)
        else:
            assert out.summary[key] == value, key


def test_the_plot_keeps_every_peak_in_few_rows(setup, tmp_path: Path, monkeypatch) -> None:
    from orthoglide_pin.planning import trajectory_file

    monkeypatch.setattr(trajectory_file, "PLOT_SAMPLES", 50)  # buckets of about 100 periods
    plan, dyn = setup
    out = write_simulation(tmp_path / "s.csv", plan, dyn, DRIVE, chunk=CHUNK)
    got = _read_plain(tmp_path / "s.csv")
    buckets = -(-got["t"].size // -(-got["t"].size // 50))
    assert out.plot["t"].size <= buckets * (1 + 2 * len(PLOTTED)) + 1 < got["t"].size / 2
    for name in PLOTTED:  # the file's 10 digits
        assert float(f"{out.plot[name].max():.10g}") == got[name].max(), name
        assert float(f"{out.plot[name].min():.10g}") == got[name].min(), name
    assert out.plot["t"][0] == 0.0 and out.plot["t"][-1] == got["t"][-1]


def _read_plain(path: Path) -> dict[str, np.ndarray]:
    with open(path) as fh:
        rows = list(csv.reader(fh))
    table = np.array(rows[1:], dtype=float)
    return {name: table[:, k] for k, name in enumerate(rows[0])}


def test_parquet_holds_the_same_columns(setup, tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    plan, dyn = setup
    csv_out = write_simulation(tmp_path / "s.csv", plan, dyn, DRIVE, chunk=CHUNK)
    out = write_simulation(
        tmp_path / "s.parquet", plan, dyn, DRIVE, chunk=CHUNK, file_format="parquet",
        first_line="# line\n",
    )  # fmt: skip
    table = pq.read_table(tmp_path / "s.parquet")
    assert table.column_names == list(COLUMNS) and table.num_rows == out.samples
    assert table.schema.metadata[b"orthoglide"] == b"# line"
    written = _read_plain(tmp_path / "s.csv")
    for name in COLUMNS:
        values = table.column(name).to_numpy()
        np.testing.assert_allclose(values, written[name], rtol=1e-9, atol=1e-300)
    assert out.summary == csv_out.summary
