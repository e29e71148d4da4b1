"""``orthoglide linuxcnc``: the files, the certified limits in the INI, one-line errors."""

from __future__ import annotations

import configparser
from pathlib import Path

import pytest
from conftest import run, run_json
from test_docs_pages import documented_keys

import orthoglide_pin as og
from orthoglide_pin.controller import FILES


def _ini(path: Path) -> configparser.ConfigParser:
    ini = configparser.ConfigParser(inline_comment_prefixes=None)
    ini.read_string(path.read_text())
    return ini


def test_writes_a_configuration(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "cnc"
    data = run_json(capsys, "linuxcnc", "--out", str(out), "--max-slider-acceleration", "15")
    assert set(data) == documented_keys("linuxcnc")
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == sorted(FILES)
    ini = _ini(out / "orthoglide.ini")
    params = og.OrthoglideParams()
    assert float(ini["JOINT_0"]["MAX_VELOCITY"]) == pytest.approx(1200.0)
    assert float(ini["JOINT_2"]["MAX_ACCELERATION"]) == pytest.approx(15000.0)
    assert float(ini["JOINT_1"]["MIN_LIMIT"]) == pytest.approx(1e3 * params.slider_lower)
    assert float(ini["TRAJ"]["MAX_LINEAR_VELOCITY"]) == pytest.approx(1e3 * data["path_speed"])
    assert float(ini["AXIS_X"]["MAX_ACCELERATION"]) == pytest.approx(
        1e3 * data["axis_acceleration"]
    )
    # program Z = -world e3: the cube's Z range is mirrored
    corner, side = 1e3 * params.workspace_corner[2], 1e3 * params.workspace_side
    assert float(ini["AXIS_Z"]["MAX_LIMIT"]) == pytest.approx(-corner, abs=1e-5)
    assert float(ini["AXIS_Z"]["MIN_LIMIT"]) == pytest.approx(-corner - side, abs=1e-5)
    assert ini["KINS"]["KINEMATICS"] == "orthoglide_kins"
    hal = (out / "orthoglide_sim.hal").read_text()
    assert "joint.2.motor-pos-cmd => joint.2.motor-pos-fb" in hal


def test_drive_file_limits_the_speed(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    drive = str(og.example_drive_file())
    data = run_json(capsys, "linuxcnc", "--out", str(tmp_path / "a"), "--motor", drive)
    assert data["slider_speed"] == pytest.approx(5000 / 60 * 0.025)  # 5000 rpm, 25 mm lead
    data = run_json(
        capsys, "linuxcnc", "--out", str(tmp_path / "b"), "--motor", drive,
        "--max-slider-speed", "1",
    )  # fmt: skip
    assert data["slider_speed"] == 1.0


@pytest.mark.parametrize(
    "argv",
    [
        ["--max-slider-speed", "nan"],
        ["--max-slider-acceleration", "-3"],
        ["--max-slider-jerk", "x"],
    ],
)
def test_bad_limits_one_line_nothing_written(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str]
) -> None:
    out = tmp_path / "cnc"
    code, stdout, err = run(capsys, "linuxcnc", "--out", str(out), *argv)
    assert code == 2 and stdout == "" and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_never_overwrites_a_users_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    (tmp_path / "mine.txt").write_text("keep")
    code, _, err = run(capsys, "linuxcnc", "--out", str(tmp_path))
    assert code == 2 and "linuxcnc" in err
    assert (tmp_path / "mine.txt").read_text() == "keep"


def test_a_missing_program_one_line_nothing_written(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "cnc"
    code, _, err = run(capsys, "linuxcnc", "--out", str(out), "--program", str(tmp_path / "no.nc"))
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert not out.exists()
