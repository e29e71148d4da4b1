from __future__ import annotations

import math
from pathlib import Path

import pytest
from conftest import run, run_json

import orthoglide_pin as og

mujoco = pytest.importorskip("mujoco")
DRIVE_FILE = str(og.example_drive_file())


def test_mjcf_writes_a_file_mujoco_loads(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "machine.xml"
    data = run_json(capsys, "mjcf", "-o", str(out), "--motor", DRIVE_FILE)
    assert data["path"] == str(out.resolve())
    assert [e["type"] for e in data["equalities"]] == ["connect"] * 3 + ["weld"] * 2
    assert data["force_limit"] == pytest.approx(0.9 * 2 * math.pi / 0.025 * 3.8, rel=1e-15)
    m = mujoco.MjModel.from_xml_path(str(out))
    assert m.actuator_forcerange[0, 1] == data["force_limit"]
    assert m.dof_armature[m.joint("leg2_slider").dofadr[0]] == data["armature"]


def test_mjcf_takes_the_design_and_gravity(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "m.xml"
    args = ("mjcf", "-o", str(out), "--param", "leg_length=0.36", "--gravity", "0", "0", "-9.81")
    data = run_json(capsys, *args)
    assert data["gravity"] == [0.0, 0.0, -9.81] and data["force_limit"] is None
    m = mujoco.MjModel.from_xml_path(str(out))
    assert list(m.opt.gravity) == [0.0, 0.0, -9.81]
    bar = m.body("leg1_bar_a")
    assert m.body_ipos[bar.id][0] == pytest.approx(0.18, abs=1e-12)  # half the 0.36 m bar


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (("--gravity", "0", "nan", "9.81"), "--gravity"),
        (("--param", "leg_length=-1"), "leg_length"),
    ],
)
def test_mjcf_bad_input_one_line_nothing_written(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, extra: tuple[str, ...], needle: str
) -> None:
    out = tmp_path / "m.xml"
    code, stdout, err = run(capsys, "mjcf", "-o", str(out), *extra)
    assert code == 2 and stdout == "" and needle in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_mjcf_non_finite_drive_refused(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    drive = tmp_path / "drive.yaml"
    drive.write_text(Path(DRIVE_FILE).read_text().replace("lead: 0.025", "lead: .nan"))
    out = tmp_path / "m.xml"
    code, stdout, err = run(capsys, "mjcf", "-o", str(out), "--motor", str(drive))
    assert code == 2 and stdout == "" and "lead" in err and err.count("\n") == 1
    assert not out.exists()


def test_mjcf_unwritable_path(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    blocker = tmp_path / "a_file"
    blocker.write_text("kept\n")
    code, _, err = run(capsys, "mjcf", "-o", str(blocker / "m.xml"))  # its folder is a file
    assert code == 2 and err.count("\n") == 1 and "a_file" in err
    code, _, err = run(capsys, "mjcf", "-o", str(tmp_path))  # a directory
    assert code == 2 and err.count("\n") == 1
    assert [p.name for p in tmp_path.iterdir()] == ["a_file"]
    assert blocker.read_text() == "kept\n"
