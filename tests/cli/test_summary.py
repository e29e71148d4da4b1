"""``orthoglide summary`` of a design with CAD meshes and measured inertias."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh
from conftest import run, run_json

import orthoglide_pin as og

CAD = """leg_length: 0.33
meshes:
  carriage: {file: cad/carriage.stl, scale: 0.001}
inertias:
  platform: {mass: 3.2, com: [0.004, -0.006, 0.011], inertia: [4.1e-3, 0, 0, 3.6e-3, 0, 5.2e-3]}
  spindle: {mass: 2.6, com: [0, 0, 0], inertia: [5e-3, 0, 0, 5e-3, 0, 1e-3]}
"""


@pytest.fixture
def design(tmp_path: Path) -> Path:
    (tmp_path / "cad").mkdir()
    trimesh.creation.box((100.0, 100.0, 40.0)).export(tmp_path / "cad" / "carriage.stl")  # mm
    path = tmp_path / "d.yaml"
    path.write_text(CAD)
    return path


def test_summary_says_which_masses_are_measured(
    capsys: pytest.CaptureFixture[str], design: Path
) -> None:
    code, out, err = run(capsys, "summary", "--config", str(design))
    assert (code, err) == (0, "")
    lines = {line.split()[0]: line for line in out.splitlines() if line.startswith("  ")}
    assert lines["platform_mass"].endswith("3.2 kg, measured (CAD)")
    assert lines["spindle_mass"].endswith("2.6 kg, measured (CAD)")
    assert lines["bar_mass"].endswith("derived from sizes and density")
    assert lines["meshes"].endswith("carriage: carriage.stl")
    assert "measured (CAD): platform, spindle" in out


def test_summary_json_carries_the_cad_data(
    capsys: pytest.CaptureFixture[str], design: Path
) -> None:
    data = run_json(capsys, "summary", "--config", str(design))
    mesh = data["parameters"]["meshes"]["value"]["carriage"]
    assert mesh["file"] == str(design.parent / "cad" / "carriage.stl")
    assert mesh["scale"] == [0.001] * 3
    assert data["parameters"]["inertias"]["value"]["platform"]["mass"] == 3.2
    assert "platform_mass" not in data["derived_masses"]
    # Pinocchio's body of leg 1's end revolute: its third of the CAD platform, and the spindle.
    assert data["masses"]["platform_and_spindle"] == pytest.approx(3.2 / 3 + 2.6, rel=1e-12)


def test_summary_shows_the_factor_range_and_the_criterion(
    capsys: pytest.CaptureFixture[str],
) -> None:
    data = run_json(capsys, "summary", "--grid", "5")
    assert data["criterion"] == {
        "psi_min": 0.5,
        "psi_max": 2.0,
        "tolerance": 1e-4,
        "from": "machine",
    }
    fr = data["factor_range"]
    # the prototype: the paper's 310 mm legs miss its [0.5, 2] at Q2
    assert (round(fr["lowest"], 4), round(fr["highest"], 4)) == (0.4989, 2.0090)
    assert fr["holds"] is False and fr["grid_points"] == 5
    assert "310.58 mm" in data["note"]
    code, out, err = run(capsys, "summary", "--grid", "5")
    assert (code, err) == (0, "")
    assert "Criterion: factors in [0.5, 2] (within 0.0001), the machine's psi_min and " in out
    assert "DOES NOT HOLD over the cube" in out and "[0.498888, 2.008957]" in out
    assert "note: the prototype's 310 mm legs" in out
    # --psi judges it by another criterion, and says so
    wider = run_json(capsys, "summary", "--grid", "5", "--psi", "0.45", "2.1")
    assert wider["factor_range"]["holds"] is True and wider["criterion"]["from"] == "--psi"
    assert wider["note"] is None


def test_a_hand_written_file_whose_cube_breaks_its_criterion_shows_at_once(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "mine.yaml"
    path.write_text(
        "leg_length: 0.36\npsi_min: 0.4\npsi_max: 2.5\n"
        "workspace_corner: [-0.1, -0.1, -0.1]\nworkspace_side: 0.28\n"
    )
    data = run_json(capsys, "summary", "--config", str(path), "--grid", "9")
    assert data["criterion"]["psi_min"] == 0.4 and data["criterion"]["psi_max"] == 2.5
    fr = data["factor_range"]
    assert fr["holds"] is False and fr["highest"] > 2.5 + 1e-4
    machine = og.OrthoglideParams.load(path)
    assert fr["highest"] == og.factor_range(machine, grid_points=9).highest
    text = run(capsys, "summary", "--config", str(path), "--grid", "9")[1]
    assert "Criterion: factors in [0.4, 2.5]" in text and "DOES NOT HOLD" in text
    # certify agrees: a counterexample, exit 1
    assert run(capsys, "certify", "--config", str(path))[0] == 1


def test_summary_refuses_a_bad_criterion_or_grid(capsys: pytest.CaptureFixture[str]) -> None:
    for argv, mentions in (
        (("--psi", "1.2", "2"), "psi_min"),
        (("--psi", "0.5", "x"), "--psi MAX"),
        (("--param", "psi_max=0.9"), "psi_max"),
        (("--grid", "1"), "grid_points"),
    ):
        code, out, err = run(capsys, "summary", *argv)
        assert (code, out) == (2, "") and len(err.strip().splitlines()) == 1
        assert mentions in err
