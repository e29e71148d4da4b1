"""A sweep's directory: what counts as an earlier sweep, and one spec per directory.

A directory is an earlier sweep only by the package's marker or a
``sweep.json`` of the package's own schema; another spec in it is refused,
naming the difference. (A damaged part is computed again: ``tests/sweep/test_store.py``.)
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import run
from hostile.test_outputs import ERROR, one_error_line, snapshot

import orthoglide_pin as og
from orthoglide_pin._paths import MARKER_NAME
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

#: A quick sweep of two designs.
SWEEP = (
    "sweep",
    "--leg-length",
    "0.3:0.31:2",
    "--workers",
    "1",
    "--grid",
    "5",
    "--requirement-grid",
    "3",
    "--no-plot",
    "--no-progress",
)


# ------------------------------------------------------------ what is an earlier sweep
@pytest.mark.parametrize(
    "record",
    [
        '{"my": "experiment"}',
        "not json at all",
        '{"schema": 2, "mode": "fixed-cube"}',  # some keys of ours, not a record
        json.dumps({"schema": 99, "mode": "fixed-cube", "axes": {}, "base": {}}),
    ],
)
def test_a_foreign_sweep_json_is_not_an_earlier_sweep(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, record: str
) -> None:
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "sweep.json").write_text(record)
    (mine / "results.csv").write_text("my own table\n")
    before = snapshot(tmp_path)
    code, stdout, err = run(capsys, *SWEEP, "--out", str(mine))
    one_error_line(code, stdout, err, str(mine), "--force")
    assert snapshot(tmp_path) == before
    spec = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3:0.31:2"),), grid=5)
    with pytest.raises(OutputPathError, match="not written by orthoglide-pin"):
        og.run_sweep(spec, mine, workers=1)  # the Python call refuses it too
    assert snapshot(tmp_path) == before


def test_a_record_of_ours_without_marker_is_an_earlier_sweep(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    spec = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3:0.31:2"),), grid=5, requirement_grid=3)
    og.run_sweep(spec, tmp_path / "sw", workers=1, progress=False)
    (tmp_path / "sw" / MARKER_NAME).unlink()  # as written before the marker existed
    code, out, err = run(capsys, *SWEEP, "--out", str(tmp_path / "sw"), "--json")
    assert code == 0, err
    assert json.loads(out)["skipped"] == 2


# ------------------------------------------------------------ one directory, one spec
@pytest.mark.parametrize(
    ("other", "named"),
    [
        (("--grid", "6"), "grid: 6 now, 5 there"),
        (
            ("--leg-length", "0.3:0.32:3"),
            "axes.leg_length: [0.3, 0.31, 0.32] now, [0.3, 0.31] there",
        ),
        (("--param", "parallelogram_width=0.1"), "base.parallelogram_width: 0.1 now, 0.08 there"),
    ],
)
def test_another_spec_in_a_sweep_directory_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, other: tuple[str, ...], named: str
) -> None:
    out = tmp_path / "sw"
    code, _, err = run(capsys, *SWEEP, "--out", str(out))
    assert code == 0, err
    before = snapshot(tmp_path)
    code, stdout, err = run(capsys, *SWEEP, *other, "--out", str(out))
    one_error_line(code, stdout, err, str(out), "another spec", named)
    assert snapshot(tmp_path) == before  # the earlier table, parts and record are intact
    for force in ((), ("--force",)):  # the same spec carries on; forcing changes nothing
        code, stdout, err = run(capsys, *SWEEP, *force, "--out", str(out), "--json")
        assert code == 0, err
        assert json.loads(stdout)["skipped"] == 2
    code, stdout, err = run(capsys, *SWEEP, *other, "--force", "--out", str(out))
    assert code == ERROR and "another spec" in err
