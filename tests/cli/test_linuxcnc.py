"""``orthoglide linuxcnc``: the files, the certified limits in the INI, one-line errors.

And the optimal route from the plan command, ``orthoglide plan PROGRAM --out
DIR --linuxcnc DIR2``: the joint stream, in the design's program axes.
"""

from __future__ import annotations

import configparser
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json
from test_docs_pages import documented_keys

import orthoglide_pin as og
from orthoglide_pin.controller import FILES, STREAM_FILES

#: A short program (program axes, mm): the stream's last row is its end.
SHORT = "G21 G90\nG1 X10 Y5 Z-3 F600\nM2\n"
#: Agreement of the stream's end with the program's end [mm] (9 decimals written).
END_TOL_MM = 1e-6


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
    # the prototype's program axes: X on +e2, Y on +e1, Z on -e3 (Z's range mirrored)
    corner, side = 1e3 * params.workspace_corner[2], 1e3 * params.workspace_side
    assert float(ini["AXIS_Z"]["MAX_LIMIT"]) == pytest.approx(-corner, abs=1e-5)
    assert float(ini["AXIS_Z"]["MIN_LIMIT"]) == pytest.approx(-corner - side, abs=1e-5)
    assert ini["KINS"]["KINEMATICS"] == "orthoglide_kins"
    hal = (out / "orthoglide_sim.hal").read_text()
    # joint 2's command looped back as its feedback, or the stream's position while it plays
    assert "net j2-cmd joint.2.motor-pos-cmd => og-select-2.in1" in hal
    assert "net q2 streamer.0.pin.2 => og-select-2.in0" in hal
    assert "net j2-pos og-select-2.out => joint.2.motor-pos-fb" in hal
    assert "net og-stream-idle streamer.0.empty => og-select-0.sel" in hal


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


def test_soft_limits_and_kinematics_follow_the_program_axes(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "cnc"
    run_json(capsys, "linuxcnc", "--out", str(out), "--param", "program_axes=1,-2,-3")
    ini = _ini(out / "orthoglide.ini")
    params = og.OrthoglideParams()
    corner, side = 1e3 * params.workspace_corner[1], 1e3 * params.workspace_side
    assert float(ini["AXIS_Y"]["MAX_LIMIT"]) == pytest.approx(-corner, abs=1e-5)  # Y on -e2
    assert float(ini["AXIS_Y"]["MIN_LIMIT"]) == pytest.approx(-corner - side, abs=1e-5)
    comp = (out / "orthoglide_kins.comp").read_text()
    assert "p[0] = pos->tran.x;" in comp and "p[1] = -pos->tran.y;" in comp
    assert "X -> +e1, Y -> -e2, Z -> -e3" in (out / "README.md").read_text()


def test_plan_writes_the_stream_into_the_configuration(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """``plan --linuxcnc``: next to the configuration, ending where the program ends."""
    cnc, program = tmp_path / "cnc", tmp_path / "short.nc"
    program.write_text(SHORT)
    run_json(capsys, "linuxcnc", "--out", str(cnc))
    data = run_json(
        capsys, "plan", str(program), "--out", str(tmp_path / "plan"), "--linuxcnc", str(cnc),
        "--max-slider-speed", "1.2", "--max-slider-acceleration", "20",
    )  # fmt: skip
    assert (
        data["linuxcnc"] == str(cnc)
        and "linuxcnc" not in (tmp_path / "plan/plan.json").read_text()
    )
    assert {p.name for p in cnc.iterdir()} >= {*FILES, *STREAM_FILES}
    rows = (cnc / STREAM_FILES[0]).read_text().splitlines()
    assert len(rows) == len((tmp_path / "plan/trajectory.csv").read_text().splitlines()) - 2
    params = og.OrthoglideParams()
    end = og.direct_kinematics(1e-3 * np.array(rows[-1].split(), float), params.leg_length)
    assert np.abs(1e3 * og.design_axes(params).to_program(end) - [10, 5, -3]).max() <= END_TOL_MM
    assert f"{len(rows)} servo periods" in (cnc / STREAM_FILES[1]).read_text()


def test_plan_stream_in_its_own_directory_or_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    out = tmp_path / "plan"
    code, stdout, err = run(
        capsys, "plan", str(program), "--out", str(out), "--linuxcnc", str(out),
        "--max-slider-acceleration", "20",
    )  # fmt: skip
    assert (
        code == 2 and stdout == "" and len(err.strip().splitlines()) == 1 and "--linuxcnc" in err
    )
    assert not out.exists()
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep")
    code, _, err = run(
        capsys, "plan", str(program), "--out", str(out), "--linuxcnc", str(tmp_path / "mine"),
        "--max-slider-acceleration", "20",
    )  # fmt: skip
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert not out.exists() and [p.name for p in (tmp_path / "mine").iterdir()] == ["notes.txt"]
