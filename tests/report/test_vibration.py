"""The report's vibration section against the models, and the verdict row it adds."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.cli import main
from orthoglide_pin.elasticity.mass import reflected_mass
from orthoglide_pin.report.vibration import (
    CHECK_MODES,
    CRITERION,
    NO_DRIVE,
    VibrationSection,
    vibration_csv,
    vibration_dict,
    vibration_figure,
    vibration_html,
    vibration_rows,
    vibration_section,
)

#: The platform model against the full one on the lowest mode, on the prototype
#: (the elasticity layer's documented agreement).
LOWEST_MODE_RTOL = 0.02
#: The same numbers from a batch and from a single point (rounding).
EXACT_RTOL = 1e-9
CUBE_RESOLUTION = 5


@pytest.fixture(scope="module")
def section(params: og.OrthoglideParams) -> VibrationSection:
    cube = params.workspace
    return vibration_section(params, cube.q1, cube.side, None, CUBE_RESOLUTION, 50.0)


def test_the_lowest_frequency_is_the_models(
    params: og.OrthoglideParams, section: VibrationSection
) -> None:
    data = vibration_dict(section)
    json.dumps(data, allow_nan=False)
    point = np.array(data["worst_point"])
    alone = og.natural_frequencies(params, point)
    assert data["lowest_frequency"] == pytest.approx(alone.frequencies[0], rel=EXACT_RTOL)
    np.testing.assert_allclose(
        data["worst_modes"]["frequencies"], alone.frequencies, rtol=EXACT_RTOL
    )
    assert data["worst_modes"]["shapes"][0]["tool_direction"] == pytest.approx(
        alone.direction[0].tolist(), abs=1e-9
    )
    # the prototype's softest corner: far along x and y, near the z slider
    cube = params.workspace
    np.testing.assert_allclose(point, [cube.q2[0], cube.q2[1], cube.q1[2]], atol=1e-12)
    # the full model there agrees with the platform model on the lowest mode
    full = og.natural_frequencies(params, point, count=CHECK_MODES, model="full")
    np.testing.assert_allclose(data["check"]["frequencies"], full.frequencies, rtol=EXACT_RTOL)
    assert abs(data["check"]["difference"][0]) < LOWEST_MODE_RTOL
    assert data["available"] == min(data["lowest_frequency"], full.frequencies[0])
    assert data["drive"] == NO_DRIVE and data["drive_mass"] == 0.0
    # the slices are the grid's layers: lower face, centre, upper face
    assert [s["z"] for s in data["slices"]] == pytest.approx(
        [cube.q1[2], cube.q1[2] + 0.5 * cube.side, cube.q2[2]]
    )
    assert min(s["lowest_frequency"] for s in data["slices"]) == data["lowest_frequency"]


def test_the_verdict_row(section: VibrationSection) -> None:
    (row,) = vibration_rows(section)
    motor, criterion, required, available, unit, margin = row
    assert motor is None and criterion == CRITERION and unit == "Hz"
    assert required == 50.0 and available == section.available
    assert margin == pytest.approx(1.0 - 50.0 / section.available, rel=EXACT_RTOL) and margin > 0
    none = vibration_section(
        og.prototype(), og.prototype().workspace.q1, og.prototype().workspace.side, None, 3
    )
    assert vibration_rows(none) == () and vibration_dict(none)["passed"] is None


def test_a_drive_lowers_the_frequencies_by_its_reflected_inertia() -> None:
    other = og.prototype().replace(
        leg_length=0.36, workspace_corner=(-0.06, -0.05, -0.07), workspace_side=0.15
    )
    drive = og.load_drive(og.example_drive_file())
    cube = other.workspace
    with_drive = vibration_section(other, cube.q1, cube.side, drive, 4)  # even: raised to 5
    assert with_drive.grid.x.size == 5
    data = vibration_dict(with_drive)
    assert data["drive_mass"] == pytest.approx(reflected_mass(drive), rel=EXACT_RTOL)
    assert "reflected onto each carriage" in data["drive"]
    point = with_drive.worst_point
    grid = with_drive.grid.points().reshape(-1, 3)
    assert np.min(np.linalg.norm(grid - point, axis=1)) == 0.0
    alone = og.natural_frequencies(other, grid, drive, count=1).frequencies[:, 0]
    assert data["lowest_frequency"] == pytest.approx(alone.min(), rel=EXACT_RTOL)
    bare = og.natural_frequencies(other, point, count=1).frequencies[0]
    assert data["lowest_frequency"] < bare


def test_csv_figure_and_page(section: VibrationSection) -> None:
    rows = list(csv.DictReader(vibration_csv(section).splitlines()))
    assert len(rows) == CUBE_RESOLUTION**3
    lowest = np.array([float(r["lowest_frequency"]) for r in rows])
    assert lowest.min() == pytest.approx(section.lowest_frequency, rel=1e-11)
    direction = np.array([[float(r[f"direction_{a}"]) for a in "xyz"] for r in rows])
    np.testing.assert_allclose(np.linalg.norm(direction, axis=1), 1.0, atol=1e-9)
    assert vibration_figure(section).startswith(b"\x89PNG")
    page = vibration_html(section, "<img>")
    assert "PASS" in page and "Hz" in page and "carriages alone" in page and "<img>" in page


@pytest.mark.parametrize("value", [0.0, -5.0, math.nan, math.inf, "fast", [50.0]])
def test_a_bad_minimum_is_refused(params: og.OrthoglideParams, value: Any) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        vibration_section(params, params.workspace.q1, params.workspace.side, None, 3, value)
    assert info.value.name == "min_frequency"


@pytest.mark.usefixtures("no_drawing")
def test_the_report_judges_the_minimum_frequency(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "report"
    args = ["report", "--out", str(out), "--quiet", "--resolution", "3"]
    args += ["--cube-resolution", "3", "--min-frequency", "1000", "--json"]
    assert main(args) == 1  # no motor data, yet a verdict: FAIL
    data = json.loads(capsys.readouterr().out)
    assert data["passed"] is False
    (failing,) = data["failing"]
    vib = data["vibration"]
    assert failing["motor"] is None and failing["unit"] == "Hz"
    assert failing["required"] == 1000.0 and failing["available"] == vib["available"]
    assert failing["margin"] == pytest.approx(1 - 1000.0 / vib["available"], rel=EXACT_RTOL)
    saved = json.loads((out / "report.json").read_text())
    assert saved["vibration"]["lowest_frequency"] == vib["lowest_frequency"]
    rows = list(csv.DictReader((out / "summary.csv").read_text().splitlines()))
    (row,) = [r for r in rows if r["unit"] == "Hz"]
    assert row["motor"] == "" and row["passed"] == "0"
    page = (out / "report.html").read_text()
    assert "Vibration: the lowest natural frequency over the cube" in page
    assert "FAIL" in page and "the motors are not judged" in page
    assert (out / "vibration.csv").is_file()


def test_a_bad_minimum_on_the_command_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "report"
    assert main(["report", "--out", str(out), "--min-frequency", "-3"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "min_frequency" in err
    assert not out.exists()
