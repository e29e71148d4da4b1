"""A plan sampled in chunks and written as it comes: the step, the files, the plotting copy."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.planning import PlanLimits, plan_program
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.sampling import (
    DEFAULT_DT,
    MAX_SAMPLES,
    auto_dt,
    csv_text,
    sample_chunks,
    sample_count,
    sample_plan,
)
from orthoglide_pin.planning.trajectory_file import envelope, write_trajectory

pytest.importorskip("toppra")

PROGRAM = "G21 G90\nG0 X20\nG1 Y15 F3000\nG4 P0.05\nG1 X-10 F6000\nM2\n"
LIMITS = PlanLimits(slider_speed=1.0, slider_acceleration=10.0)
DT = 0.003
#: Written with 10 significant digits.
CSV_RTOL = 1e-9


@pytest.fixture(scope="module")
def planned(dyn: og.ClosedLoopDynamics) -> og.Plan:
    return plan_program(read_program(PROGRAM), dyn, LIMITS)


@pytest.mark.parametrize(
    ("cycle", "step"),
    [
        (0.5, DEFAULT_DT),
        (999.0, DEFAULT_DT),
        (1500.0, 0.002),
        (4 * 3600.0, 0.02),
        (1e6 - 10, 1.0),
        (1e6, 2.0),
    ],
)
def test_the_step_follows_the_program_when_none_is_given(cycle: float, step: float) -> None:
    assert auto_dt(cycle) == pytest.approx(step)
    assert np.floor(cycle / auto_dt(cycle)) + 1 <= MAX_SAMPLES


def test_the_chunks_are_the_samples_of_the_whole(planned: og.Plan, dyn) -> None:
    whole = sample_plan(planned, dyn, DT)
    parts = list(sample_chunks(planned, dyn, DT, chunk=37))
    assert len(parts) > 3
    for name, values in whole.items():
        np.testing.assert_allclose(np.concatenate([p[name] for p in parts]), values, atol=1e-12)
    assert whole["t"].size == sample_count(planned, DT)
    assert whole["t"][-1] == pytest.approx(planned.cycle_time)


def test_the_csv_written_in_chunks_is_the_csv_of_the_whole(
    planned: og.Plan, dyn, tmp_path: Path
) -> None:
    whole = sample_plan(planned, dyn, DT)
    total = sample_count(planned, DT)
    written = write_trajectory(
        tmp_path / "t.csv", sample_chunks(planned, dyn, DT, chunk=50), total, first_line="# x\n"
    )
    assert written.samples == total
    assert (tmp_path / "t.csv").read_text() == "# x\n" + csv_text(whole)
    for name in ("path_speed", "qd1", "qd2", "qd3"):  # the page's peaks are the file's
        assert written.plot[name].max() == whole[name].max()
        assert written.plot[name].min() == whole[name].min()


def test_parquet_holds_the_same_columns(planned: og.Plan, dyn, tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    whole = sample_plan(planned, dyn, DT)
    total = sample_count(planned, DT)
    write_trajectory(
        tmp_path / "t.parquet",
        sample_chunks(planned, dyn, DT, chunk=64),
        total,
        first_line="# design\n",
        file_format="parquet",
    )
    table = pq.read_table(tmp_path / "t.parquet")
    assert table.schema.metadata[b"orthoglide"] == b"# design"
    for name, values in whole.items():
        np.testing.assert_allclose(table.column(name).to_numpy(), values, rtol=CSV_RTOL)


def test_the_plotting_copy_keeps_every_extreme() -> None:
    rng = np.random.default_rng(7)
    n = 10_007
    cols = {"t": np.arange(n) * 1.0, "path_speed": rng.normal(size=n), "qd1": rng.normal(size=n)}
    light = envelope(cols, 50)
    assert light["t"].size < n // 10
    assert light["t"][0] == 0.0 and light["t"][-1] == n - 1
    assert np.all(np.diff(light["t"]) > 0)
    for name in ("path_speed", "qd1"):
        assert light[name].max() == cols[name].max() and light[name].min() == cols[name].min()


def test_csv_rows_are_those_numpy_savetxt_writes() -> None:
    import io

    from orthoglide_pin.planning.trajectory_file import _csv_rows

    rng = np.random.default_rng(6)
    table = rng.normal(size=(200, 5)) * 10.0 ** rng.integers(-12, 12, (200, 5))
    table[:3] = [[np.nan, np.inf, -np.inf, -0.0, 0.0], [1.0, 2.0, 1e10, 123456789012.0, -3.0],
                 [1e-300, -1e300, 0.1, 1 / 3, 2.5e-7]]  # fmt: skip
    plain = io.StringIO()
    np.savetxt(plain, table, fmt="%.10g", delimiter=",")
    assert _csv_rows(list(table.T)) == plain.getvalue()
    assert _csv_rows([np.zeros(0)]) == ""
