"""The report's files: JSON and CSV agree with each other and with the dynamics; atomic writes."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin._paths import MARKER_NAME, marker_text
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.report import figures as report_figures
from orthoglide_pin.report.assemble import ReportData, assemble_report
from orthoglide_pin.report.files import CSV_FILES, csv_tables, report_dict, write_report

EXAMPLE_DRIVE = Path(str(og.example_drive_file()))  # shipped in the package
RESOLUTION, CUBE_RESOLUTION = 5, 3
#: CSV numbers carry 12 significant digits.
CSV_RTOL = 1e-11
#: A direct dynamics call against the JSON (full precision).
EXACT_RTOL = 1e-9


@pytest.fixture(scope="module")
def data(params: og.OrthoglideParams) -> ReportData:
    drive = og.load_drive(EXAMPLE_DRIVE)
    return assemble_report(params, drive, resolution=RESOLUTION, cube_resolution=CUBE_RESOLUTION)


@pytest.fixture(scope="module")
def written(data: ReportData, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "report"
    files = write_report(out, data)
    assert files.directory == out and files.passed is True
    return out


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open() as fh:
        return list(csv.DictReader(fh))


def column(rows: list[dict[str, str]], name: str) -> np.ndarray:
    return np.array([float(r[name]) if r[name] else math.nan for r in rows])


def test_every_file_is_there(written: Path) -> None:
    names = sorted(p.name for p in written.iterdir())
    assert names == sorted(["report.html", "report.json", *CSV_FILES, MARKER_NAME])
    siblings = [p.name for p in written.parent.iterdir()]
    assert siblings == ["report"]  # no temporary directory left


def test_json_against_csv(written: Path, data: ReportData) -> None:
    report = json.loads((written / "report.json").read_text())
    cube = read_csv(written / "cube.csv")
    assert len(cube) == CUBE_RESOLUTION**3
    for i in range(3):
        forces = column(cube, f"force_{i + 1}")
        torques = column(cube, f"torque_{i + 1}")
        k = int(np.argmax(forces))
        assert report["worst_case"]["force"]["max"][i] == pytest.approx(forces[k], rel=CSV_RTOL)
        at = [float(cube[k][c]) for c in "xyz"]
        np.testing.assert_allclose(report["worst_case"]["force"]["at"][i], at, rtol=CSV_RTOL)
        assert report["worst_case"]["torque"]["max"][i] == pytest.approx(
            torques.max(), rel=CSV_RTOL
        )
    speed = column(cube, "guaranteed_speed")
    assert report["worst_case"]["guaranteed_speed"]["min"] == pytest.approx(
        speed.min(), rel=CSV_RTOL
    )
    maps = read_csv(written / "maps.csv")
    assert len(maps) == 3 * RESOLUTION**2
    for entry in report["slices"]:
        rows = [r for r in maps if r["slice"] == entry["label"]]
        assert len(rows) == RESOLUTION**2
        np.testing.assert_allclose(column(rows, "z"), entry["value"], rtol=CSV_RTOL)
        top = [column(rows, f"torque_{i + 1}").max() for i in range(3)]
        np.testing.assert_allclose(entry["torque"]["max"], top, rtol=CSV_RTOL)
    cycle = read_csv(written / "cycle.csv")
    assert len(cycle) == report["cycle"]["samples"] == len(data.cycle)
    for i in range(3):
        torque = np.abs(column(cycle, f"torque_{i + 1}")).max()
        assert report["cycle"]["peak_torque"][i] == pytest.approx(torque, rel=CSV_RTOL)
        force = np.abs(column(cycle, f"force_{i + 1}")).max()
        assert report["cycle"]["peak_force"][i] == pytest.approx(force, rel=CSV_RTOL)
    summary = read_csv(written / "summary.csv")
    assert len(summary) == len(report["verdict"]["rows"])
    for row, entry in zip(summary, report["verdict"]["rows"], strict=True):
        assert row["criterion"] == entry["criterion"] and int(row["motor"]) == entry["motor"]
        assert float(row["margin"]) == pytest.approx(entry["margin"], rel=CSV_RTOL)
        assert bool(float(row["passed"])) is entry["passed"]
    assert report["verdict"]["passed"] is True


def test_json_against_a_direct_dynamics_call(written: Path) -> None:
    report = json.loads((written / "report.json").read_text())
    worst = report["worst_case"]
    dyn = og.ClosedLoopDynamics()
    for i, motion in enumerate(worst["worst_motions"]):
        assert motion["point"] == worst["force"]["at"][i]
        res = dyn.inverse_dynamics(motion["point"], motion["velocity"], motion["acceleration"])
        assert abs(res.forces[0, i]) == pytest.approx(worst["force"]["max"][i], rel=EXACT_RTOL)
        assert np.linalg.norm(motion["velocity"]) <= report["specification"]["v_max"] * (1 + 1e-12)
    # and the largest motor speed is the slider's at the point where it is reported
    at = np.array(worst["motor_speed_rpm"]["at"][0])
    row = og.inverse_jacobian(at, PROTOTYPE_LEG)[0]
    res = dyn.inverse_dynamics(at, 1.2 * row / np.linalg.norm(row), [0.0, 0.0, 0.0])
    rpm = og.motor_demand(res.forces, res.slider_velocities, res.slider_accelerations).speed_rpm
    assert rpm[0, 0] == pytest.approx(worst["motor_speed_rpm"]["max"][0], rel=EXACT_RTOL)


def test_json_has_the_machine_and_the_assumptions(written: Path, data: ReportData) -> None:
    report = json.loads((written / "report.json").read_text())
    assert report["machine"]["parameters"]["leg_length"] == 0.31
    assert report["machine"]["stroke"] == pytest.approx(0.2573, abs=5e-5)
    assert report["specification"] == {
        "v_max": 1.2,
        "a_max": 20.0,
        "jerk": 1000.0,
        "gravity": [0.0, 0.0, 9.81],
    }
    assert report["drive"]["motor"]["name"] == "400 W servo motor (illustrative data)"
    assert set(report["assumptions"]) == {"inertia", "drive", "method"}
    assert report["assumptions"]["drive"] == data.drive.train.assumptions()


def test_non_finite_numbers_are_null_and_empty(data: ReportData) -> None:
    motor = og.MotorData(speed_torque_curve=((0.0, 4.0), (3000.0, 3.0)))
    beyond = assemble_report(data.params, og.Drive(motor=motor), resolution=2, cube_resolution=2)
    report = report_dict(beyond)
    json.dumps(report, allow_nan=False)
    rows = [
        r for r in report["verdict"]["rows"] if r["criterion"].startswith("worst case: torque")
    ]
    assert rows and all(r["margin"] is None and r["passed"] is False for r in rows)
    assert report["verdict"]["passed"] is False
    summary = csv_tables(beyond)["summary.csv"]
    assert "inf" not in summary and "nan" not in summary


def test_a_failure_leaves_no_report(
    data: ReportData, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(*_: Any, **__: Any) -> dict[str, bytes]:
        raise RuntimeError("interrupted while drawing")

    monkeypatch.setattr(report_figures, "figures", broken)
    out = tmp_path / "new"
    with pytest.raises(RuntimeError):
        write_report(out, data)
    assert list(tmp_path.iterdir()) == []  # neither the report nor a temporary directory
    # an existing report stays as it was
    old = tmp_path / "old"
    old.mkdir()
    (old / "report.json").write_text("previous")
    (old / MARKER_NAME).write_text(marker_text(["report.json"]))
    with pytest.raises(RuntimeError):
        write_report(old, data)
    assert [p.name for p in tmp_path.iterdir()] == ["old"]
    assert {p.name for p in old.iterdir()} == {"report.json", MARKER_NAME}
    assert (old / "report.json").read_text() == "previous"
    # a successful run replaces it whole (figures stubbed to keep this fast)
    monkeypatch.setattr(report_figures, "figures", lambda *_, **__: {})
    write_report(old, data)
    assert (old / "report.json").read_text() != "previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old"]
    assert (old / "report.html").exists()
    # a file in the way is an error
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputPathError, match="not a directory"):
        write_report(tmp_path / "file", data)
