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


#: A line, a full circle and a rapid move back (mm).
PROGRAM = "G21 G90 G17\nG1 X10 Y5 Z-5 F3000\nG2 X10 Y5 I-5 J0\nG0 X0 Y0 Z0\nM30\n"
#: Contour error of the exact model [m] (the requirement).
CONTOUR_TOL = 1e-6


def _weak_drive(path: Path) -> Path:
    text = Path(DRIVE_FILE).read_text()
    text = text.replace("peak_torque: 3.8", "peak_torque: 1.2").replace("3.8]", "1.2]")
    text = text.replace("[5000, 2.5]", "[5000, 1.0]").replace("400 W servo", "weak servo")
    path.write_text(text)
    return path


def test_simulate_writes_its_files_and_the_viewer_plays_them(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    import json

    import numpy as np

    from orthoglide_pin.viewer.planned import read_trajectory

    program = tmp_path / "p.nc"
    program.write_text(PROGRAM)
    out = tmp_path / "sim"
    data = run_json(capsys, "simulate", str(program), "--motor", DRIVE_FILE, "--out", str(out))
    assert 0.0 < data["max_contour_error"] <= CONTOUR_TOL
    assert data["saturation_time"] == 0.0 and len(data["max_tracking_error"]) == 3
    assert data["motor"] == data["plan_motor"] == "400 W servo motor (illustrative data)"
    assert {p.name for p in out.iterdir()} == {
        "simulation.csv",
        "simulation.json",
        "simulation.html",
        ".orthoglide-output",
    }
    saved = json.loads((out / "simulation.json").read_text())
    assert saved == {k: v for k, v in data.items() if k != "directory"}
    rows = np.loadtxt(out / "simulation.csv", delimiter=",", skiprows=2)  # design, header
    header = (out / "simulation.csv").read_text().splitlines()[1].split(",")
    col = {name: rows[:, k] for k, name in enumerate(header)}
    feed = col["cutting"] == 1.0
    assert 0.0 < data["cutting_share"] < 1.0 and data["cutting_time"] > 0.0
    assert col["contour_error"][feed].max() == pytest.approx(data["max_contour_error"], rel=1e-9)
    at = data["max_contour_error_at"]
    k = int(np.argmin(np.abs(col["t"] - at["t"])))
    assert col["line"][k] == at["line"] == 3  # the circle
    html = (out / "simulation.html").read_text()
    assert html.count("data:image/png;base64,") == 3 and "http" not in html.split("<body>")[1]
    played = read_trajectory(out / "simulation.csv", og.prototype())
    assert played.t.size == rows.shape[0]


def test_simulate_with_a_tool_wrench(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    program = tmp_path / "p.nc"
    program.write_text(PROGRAM)
    wrench = ["30", "-20", "15", "1", "0", "-0.5"]
    out = tmp_path / "sim"
    args = ("simulate", str(program), "--motor", DRIVE_FILE, "--wrench", *wrench)
    data = run_json(capsys, *args, "--out", str(out))
    assert data["wrench"] == [float(v) for v in wrench]
    assert 0.0 < data["max_contour_error"] <= CONTOUR_TOL
    free = run_json(
        capsys, "simulate", str(program), "--motor", DRIVE_FILE, "--out", str(tmp_path / "free")
    )
    assert free["wrench"] is None and free["peak_torque"] != data["peak_torque"]


def test_a_weaker_motor_than_planned_saturates(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    weak = _weak_drive(tmp_path / "weak.yaml")
    out = tmp_path / "sim"
    args = ("simulate", "--example", "contour", "--motor", str(weak), "--plan-motor", DRIVE_FILE)
    code, stdout, err = run(capsys, *args, "--rate", "2000", "--out", str(out))
    assert code == 0, err
    assert "saturated" in stdout and "weak servo" not in err
    import json

    data = json.loads((out / "simulation.json").read_text())
    assert data["saturation_time"] > 0.01
    assert data["motor"] == "weak servo motor (illustrative data)"
    assert max(data["max_contour_error"], data["max_rapid_deviation"]) > 1e-5


#: One rapid move up: a plan at the whole peak torque saturates the motor it was
#: planned for (5.75 ms of its 18 ms), one with the default reserve does not.
RAPID = "G21 G90\nG0 Z5\nM30\n"


def test_the_torque_reserve_removes_the_saturation_at_the_planned_motor(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    from orthoglide_pin.planning.limits import DEFAULT_TORQUE_RESERVE

    program = tmp_path / "p.nc"
    program.write_text(RAPID)
    args = ("simulate", str(program), "--motor", DRIVE_FILE)
    kept = run_json(capsys, *args, "--out", str(tmp_path / "kept"))
    assert kept["torque_reserve"] == DEFAULT_TORQUE_RESERVE
    assert kept["saturation_time"] == 0.0
    none = run_json(capsys, *args, "--torque-reserve", "0", "--out", str(tmp_path / "none"))
    assert none["torque_reserve"] == 0.0
    assert none["saturation_time"] > 0.0
    assert none["cycle_time"] < kept["cycle_time"]


@pytest.mark.parametrize(
    ("extra", "program", "needle"),
    [
        (("--controller", "bang_bang"), PROGRAM, "controller"),
        (("--rate", "0"), PROGRAM, "rate"),
        (("--rate", "fast"), PROGRAM, "rate"),
        (("--encoder", "0"), PROGRAM, "encoder_counts"),
        (("--mass-error", "2"), PROGRAM, "mass_error"),
        (("--wrench", "10", "0"), PROGRAM, "--wrench"),
        (("--wrench", "10", "0", "0", "1"), PROGRAM, "--wrench"),
        (("--wrench", "10", "nan", "0"), PROGRAM, "--wrench"),
        (("--wrench", "1e12", "0", "0"), PROGRAM, "wrench"),
        ((), "G21 G90\nG1 X500 F3000\nM30\n", "line 2"),  # out of the cube: the plan refuses
        (("--torque-reserve", "1"), PROGRAM, "--torque-reserve"),
        (("--torque-reserve", "-0.1"), PROGRAM, "--torque-reserve"),
        (("--torque-reserve", "nan"), PROGRAM, "--torque-reserve"),
        (("--torque-reserve", "ten"), PROGRAM, "--torque-reserve"),
    ],
)
def test_simulate_bad_input_one_line_nothing_written(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    extra: tuple[str, ...],
    program: str,
    needle: str,
) -> None:
    pytest.importorskip("toppra")
    path = tmp_path / "p.nc"
    path.write_text(program)
    out = tmp_path / "sim"
    code, stdout, err = run(
        capsys, "simulate", str(path), "--motor", DRIVE_FILE, "--out", str(out), *extra
    )
    assert code == 2 and stdout == "" and needle in err and err.count("\n") == 1, err
    assert not out.exists()


def test_simulate_reads_the_tool_table_and_offsets(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    program, tools = tmp_path / "p.nc", tmp_path / "tool.tbl"
    program.write_text("G43 H1\n" + PROGRAM)
    tools.write_text("T1 P1 Z2 D6\n")
    args = ("simulate", str(program), "--motor", DRIVE_FILE)
    code, _, err = run(capsys, *args, "--out", str(tmp_path / "no"))
    assert code == 2 and "tool 1 is not in the tool table" in err
    assert not (tmp_path / "no").exists()
    data = run_json(capsys, *args, "--tool-table", str(tools), "--out", str(tmp_path / "sim"))
    assert data["max_contour_error"] <= CONTOUR_TOL


def test_simulate_writes_parquet_with_the_same_figures(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    pq = pytest.importorskip("pyarrow.parquet")
    program = tmp_path / "p.nc"
    program.write_text("G21 G90\nG1 X5 Y2 F3000\nG0 X0 Y0\nM30\n")
    args = ["simulate", str(program), "--motor", DRIVE_FILE]
    as_csv = run_json(capsys, *args, "--out", str(tmp_path / "a"))
    out = tmp_path / "b"
    data = run_json(capsys, *args, "--out", str(out), "--trajectory-format", "parquet")
    assert {p.name for p in out.iterdir()} == {
        "simulation.parquet",
        "simulation.json",
        "simulation.html",
        ".orthoglide-output",
    }
    table = pq.read_table(out / "simulation.parquet")
    assert table.num_rows == data["samples"]
    assert table.schema.metadata[b"orthoglide"].startswith(b"# orthoglide design")
    assert {k: v for k, v in data.items() if k != "directory"} == {
        k: v for k, v in as_csv.items() if k != "directory"
    }
