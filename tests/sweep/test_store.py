"""A sweep's directory: its record, the spec it holds, and which parts count as done."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.sweep import store
from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SCHEMA, SweepAxis, SweepSpec, design_key

#: Two designs, one too short for the prototype's cube (an invalid row), coarse grids.
LEGS = "0.2,0.3"
GRID = 5
REQUIREMENT_GRID = 3


def _spec(**changes: Any) -> SweepSpec:
    settings: dict[str, Any] = {
        "axes": (SweepAxis.parse(f"leg_length={LEGS}"),),
        "grid": GRID,
        "requirement_grid": REQUIREMENT_GRID,
        **changes,
    }
    return SweepSpec(**settings)


@pytest.fixture(scope="module")
def done(tmp_path_factory: pytest.TempPathFactory) -> og.SweepResult:
    return run_sweep(_spec(), tmp_path_factory.mktemp("done"), workers=1, progress=False)


def _rows(result: og.SweepResult) -> dict[str, dict[str, Any]]:
    """Key to part, as written."""
    return {p.stem: json.loads(p.read_text()) for p in (result.out / store.PARTS).glob("*.json")}


def _ok_and_invalid(result: og.SweepResult) -> tuple[dict[str, Any], dict[str, Any]]:
    by_status = {row["status"]: row for row in _rows(result).values()}
    return by_status["ok"], by_status["invalid"]


def _design(row: dict[str, Any]) -> dict[str, Any]:
    return next(d for d in _spec().designs() if design_key(d) == row["key"])


# ------------------------------------------------------------ parts
def test_the_written_parts_are_complete(done: og.SweepResult) -> None:
    ok, invalid = _ok_and_invalid(done)
    assert store.part_problem(ok, _design(ok)) is None
    assert store.part_problem(invalid, _design(invalid)) is None
    assert "leg_length" in invalid["error"]  # 0.2 m cannot reach the cube: a message
    assert len(store.load_parts(done.out, _spec().designs())) == 2


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        (lambda r: {"key": r["key"], "status": "ok"}, "error None for status 'ok'"),
        (lambda r: [r], "not a JSON object"),
        (lambda r: {**r, "key": "0" * 16}, "another design"),
        (lambda r: {**r, "status": "done"}, "status 'done'"),
        (lambda r: {**r, "error": "boom"}, "error 'boom' for status 'ok'"),
        (lambda r: {**r, "mode": "redesign"}, "mode 'redesign'"),
        (lambda r: {**r, "leg_length": 0.31}, "leg_length 0.31, not the design's 0.3"),
        (lambda r: {k: v for k, v in r.items() if k != "max_motor_torque"}, "no max_motor_torque"),
        (lambda r: {**r, "stroke": "0.25"}, "stroke '0.25', not a number"),
        (lambda r: {**r, "min_stiffness": True}, "min_stiffness True, not a number"),
        (lambda r: {**r, "bounds_hold": "yes"}, "bounds_hold 'yes', not a boolean"),
        (lambda r: {**r, "bounds_hold": None}, "bounds_hold None, not a boolean"),
        (lambda r: {**r, "stroke": None}, "stroke None, not a finite number"),
    ],
)
def test_an_incomplete_ok_part_is_not_done(
    done: og.SweepResult, change: Any, problem: str
) -> None:
    ok, _ = _ok_and_invalid(done)
    assert problem in (store.part_problem(change(ok), _design(ok)) or "")


def test_an_incomplete_invalid_part_is_not_done(done: og.SweepResult) -> None:
    _, invalid = _ok_and_invalid(done)
    design = _design(invalid)
    assert "error ''" in (store.part_problem({**invalid, "error": ""}, design) or "")
    no_mode = {k: v for k, v in invalid.items() if k != "mode"}
    assert "mode None" in (store.part_problem(no_mode, design) or "")
    no_leg = {k: v for k, v in invalid.items() if k != "leg_length"}
    assert "leg_length None, not the design's 0.2" in (store.part_problem(no_leg, design) or "")
    assert "stroke" in (store.part_problem({**invalid, "stroke": [1]}, design) or "")


def test_a_damaged_part_is_computed_again(done: og.SweepResult, tmp_path: Path) -> None:
    first = run_sweep(_spec(), tmp_path, workers=1, progress=False)
    ok, _ = _ok_and_invalid(first)
    part = tmp_path / store.PARTS / f"{ok['key']}.json"
    part.write_text(json.dumps({"key": ok["key"], "status": "ok"}))  # valid JSON, no metrics
    again = run_sweep(_spec(), tmp_path, workers=1, progress=False)
    assert again.computed == 1 and again.skipped == 1
    pd.testing.assert_frame_equal(again.table, done.table, check_exact=True)
    assert json.loads(part.read_text()) == ok  # the part is whole again
    damaged = {**ok, "max_motor_torque": "1.2"}  # a column of the wrong type
    part.write_text(json.dumps(damaged))
    third = run_sweep(_spec(), tmp_path, workers=1, progress=False)
    assert third.computed == 1
    row = third.table.set_index("key").loc[ok["key"]]
    assert row["max_motor_torque"] == ok["max_motor_torque"]
    pd.testing.assert_frame_equal(third.table, done.table, check_exact=True)


# ------------------------------------------------------------ the record
def test_the_record_is_recognised_by_its_schema(done: og.SweepResult, tmp_path: Path) -> None:
    record = json.loads((done.out / store.SPEC_NAME).read_text())
    assert store.is_record(record) and record["schema"] == SCHEMA
    assert store.read_record(done.out) == record
    assert store.is_earlier_sweep(done.out)
    for broken in (
        {k: v for k, v in record.items() if k != "axes"},
        {**record, "schema": SCHEMA + 1},
        {**record, "schema": True},
        {**record, "mode": "other"},
        {**record, "axes": {"leg_length": ["0.3"]}},
        {**record, "axes": {"leg_length": []}},
        [record],
    ):
        assert not store.is_record(broken)
        (tmp_path / store.SPEC_NAME).write_text(json.dumps(broken))
        assert not store.is_earlier_sweep(tmp_path)
    (tmp_path / store.SPEC_NAME).write_bytes(b"\xff\xfe not text")
    assert store.read_record(tmp_path) is None


def test_the_spec_differences_are_named(done: og.SweepResult) -> None:
    record = store.read_record(done.out)
    assert record is not None
    assert store.spec_differences(_spec(), record) == []
    found = store.spec_differences(_spec(grid=GRID + 1, psi_max=2.5), record)
    assert found == [f"grid: {GRID + 1} now, {GRID} there", "psi_max: 2.5 now, 2.0 there"]
    drive = store.spec_differences(_spec(drive=og.DriveTrain(lead=0.02)), record)
    assert drive == ["drive.lead: 0.02 now, 0.025 there"]
    many = _spec(grid=GRID + 1, requirement_grid=4, psi_min=0.4, psi_max=2.5, mode="redesign")
    with pytest.raises(OutputPathError, match=r"\(and \d+ more\)") as err:
        store.check_spec(done.out, many)
    assert "nothing was written" in str(err.value)
    store.check_spec(done.out, _spec())  # the same spec: carried on


def test_an_earlier_record_of_another_schema_is_another_spec(
    done: og.SweepResult, tmp_path: Path
) -> None:
    run_sweep(_spec(), tmp_path, workers=1, progress=False)
    record = json.loads((tmp_path / store.SPEC_NAME).read_text())
    (tmp_path / store.SPEC_NAME).write_text(json.dumps({**record, "schema": 1}))
    with pytest.raises(OutputPathError, match=f"schema: {SCHEMA} now, 1 there"):
        run_sweep(_spec(), tmp_path, workers=1, progress=False)
    assert math.isfinite(float(done.table["stroke"].iloc[-1]))
