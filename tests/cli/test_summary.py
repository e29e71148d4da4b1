"""``orthoglide summary`` of a design with CAD meshes and measured inertias."""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh
from conftest import run, run_json

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
