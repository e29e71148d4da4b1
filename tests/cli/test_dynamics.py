"""The ``dynamics`` and ``report`` commands, in-process through ``main``."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.cli import dynamics as cli_dynamics
from orthoglide_pin.report import assemble as report
from orthoglide_pin.report import figures as report_figures

EXAMPLE_DRIVE = Path(str(og.example_drive_file()))  # shipped in the package
#: The command and the Python API run the same computation.
SAME_RTOL = 1e-12
ERROR = 2
STATE = (
    "--point", "0.02", "-0.03", "0.05",
    "--velocity", "0.3", "0.4", "-0.2",
    "--acceleration", "0", "-5", "8",
)  # fmt: skip


def assert_error(capsys: pytest.CaptureFixture[str], *argv: str, mentions: str) -> None:
    code, out, err = run(capsys, *argv)
    assert code == ERROR
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and re.match(r"orthoglide [a-z]+: error: ", lines[0]), err
    assert mentions in err


@pytest.fixture(autouse=True)
def no_drawing(monkeypatch: pytest.MonkeyPatch) -> None:
    """The figures are tested elsewhere; here they would only cost time."""
    monkeypatch.setattr(report_figures, "figures", lambda *_, **__: {})


def test_dynamics_json_is_the_python_api(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "dynamics", *STATE, "--wrench", "0", "-50", "120")
    assert set(data) == {"forces", "motor_torques", "motor_speeds_rpm"}
    dyn = og.ClosedLoopDynamics()
    res = dyn.inverse_dynamics(
        [0.02, -0.03, 0.05], [0.3, 0.4, -0.2], [0.0, -5.0, 8.0], wrench=[0.0, -50.0, 120.0]
    )
    demand = og.motor_demand(res.forces, res.slider_velocities, res.slider_accelerations)
    np.testing.assert_allclose(data["forces"], res.forces[0], rtol=SAME_RTOL)
    np.testing.assert_allclose(data["motor_torques"], demand.torque[0], rtol=SAME_RTOL)
    np.testing.assert_allclose(data["motor_speeds_rpm"], demand.speed_rpm[0], rtol=SAME_RTOL)
    # 25 mm lead: a slider at q' m/s turns its motor at q' / 0.025 * 60 rpm
    np.testing.assert_allclose(
        data["motor_speeds_rpm"], res.slider_velocities[0] / 0.025 * 60.0, rtol=SAME_RTOL
    )


def test_dynamics_summary_shows_slider_speeds_in_mm_per_s(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, err = run(capsys, "dynamics", *STATE)
    assert code == 0 and err == ""
    res = og.ClosedLoopDynamics().inverse_dynamics(
        [0.02, -0.03, 0.05], [0.3, 0.4, -0.2], [0.0, -5.0, 8.0]
    )
    line = next(ln for ln in out.splitlines() if "slider speeds" in ln)
    assert line.endswith(" mm/s")
    shown = [float(x) for x in line.split("(")[1].split(")")[0].split(",")]
    np.testing.assert_allclose(shown, 1e3 * res.slider_velocities[0], rtol=1e-5)


def test_dynamics_gravity_motor_and_defaults(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    side = run_json(capsys, "dynamics", *STATE, "--gravity", "-9.81", "0", "0")
    ref = og.ClosedLoopDynamics().inverse_dynamics(
        [0.02, -0.03, 0.05], [0.3, 0.4, -0.2], [0.0, -5.0, 8.0], gravity=(-9.81, 0.0, 0.0)
    )
    np.testing.assert_allclose(side["forces"], ref.forces[0], rtol=SAME_RTOL)
    # the example drive has the default drive train; a gear changes speeds, not forces
    plain = run_json(capsys, "dynamics", *STATE)
    example = run_json(capsys, "dynamics", *STATE, "--motor", str(EXAMPLE_DRIVE))
    assert example == plain
    geared = tmp_path / "geared.yaml"
    geared.write_text(EXAMPLE_DRIVE.read_text().replace("gear_ratio: 1.0", "gear_ratio: 2.0"))
    fast = run_json(capsys, "dynamics", *STATE, "--motor", str(geared))
    assert fast["forces"] == plain["forces"]
    np.testing.assert_allclose(fast["motor_speeds_rpm"], 2 * np.array(plain["motor_speeds_rpm"]))
    assert fast["motor_torques"] != plain["motor_torques"]
    # no velocity and acceleration: the static forces
    still = run_json(capsys, "dynamics", "--point", "0", "0", "0")
    held = og.ClosedLoopDynamics().static_forces([0.0, 0.0, 0.0])[0]
    np.testing.assert_allclose(still["forces"], held, rtol=SAME_RTOL)
    assert still["motor_speeds_rpm"] == [0.0, 0.0, 0.0]
    code, out, _ = run(capsys, "dynamics", *STATE)
    assert code == 0 and "slider forces" in out and "motor torques" in out


def test_dynamics_errors(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert_error(capsys, "dynamics", "--point", "nan", "0", "0", mentions="--point")
    assert_error(capsys, "dynamics", *STATE, "--wrench", "1", "inf", "0", mentions="--wrench")
    assert_error(capsys, "dynamics", "--point", "0.4", "0.4", "0", mentions="unreachable")
    assert_error(capsys, "dynamics", *STATE, "--param", "no_such=1", mentions="no_such")
    missing = tmp_path / "missing.yaml"
    assert_error(capsys, "dynamics", *STATE, "--motor", str(missing), mentions="motor file")
    bad = tmp_path / "bad.yaml"
    bad.write_text("motor: {peak_torque: 4, colour: red}\n")
    assert_error(capsys, "dynamics", *STATE, "--motor", str(bad), mentions="colour")
    alone = tmp_path / "alone.yaml"
    alone.write_text("motor: {peak_torque: 4}\n")  # no rotor inertia: refused, not defaulted
    assert_error(capsys, "dynamics", *STATE, "--motor", str(alone), mentions="rotor_inertia")
    broken = tmp_path / "broken.yaml"
    broken.write_text("motor: [unclosed\n")
    assert_error(capsys, "dynamics", *STATE, "--motor", str(broken), mentions="valid YAML")


def test_report_command(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "out" / "report"
    argv = ("report", "--out", str(out), "--resolution", "3", "--cube-resolution", "2")
    data = run_json(capsys, *argv, "--quiet")
    assert data["passed"] is None and Path(data["report"]) == out / "report.html"
    assert Path(data["report"]).exists() and Path(data["json"]).exists()
    saved = json.loads(Path(data["json"]).read_text())
    assert data["max_force"] == saved["worst_case"]["force"]["max"]
    assert data["max_torque_at"] == saved["worst_case"]["torque"]["at"]
    assert saved["verdict"]["note"] == report.NO_MOTOR_HINT == data["note"]
    assert saved["verdict"]["safety_factor"] == 1.0
    judged = run_json(capsys, *argv, "--motor", str(EXAMPLE_DRIVE))
    assert judged["passed"] is True
    assert sorted(p.name for p in out.parent.iterdir()) == ["report"]
    code, text, _ = run(capsys, *argv, "--quiet")
    assert code == 0 and f"Report written to {out / 'report.html'}" in text
    assert "Verdict: no motor data" in text
    assert "--motor FILE.yaml" in text and "orthoglide drive --example > drive.yaml" in text


def test_report_with_a_cut_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--cut alone: lobes at home, Q1 and Q2; with a program whose speed is unknown: refused."""
    from orthoglide_pin.report import accuracy

    monkeypatch.setattr(accuracy, "REPORT_SPEEDS", accuracy.REPORT_SPEEDS[::10])  # time
    cut = str(og.shipped_cut_file())
    out = tmp_path / "cut"
    argv = ("report", "--out", str(out), "--resolution", "3", "--cube-resolution", "2")
    code, text, _ = run(capsys, *argv, "--quiet", "--cut", cut)
    saved = json.loads((out / "report.json").read_text())["accuracy"]
    assert saved["cut"] == "aluminium_finish.yaml"
    assert [row["point_name"] for row in saved["lobes"]] == ["home", "Q1", "Q2"]
    assert code == 0 and "Part accuracy, cut aluminium_finish.yaml" in text
    assert "lowest limiting depth home" in text
    speedless = tmp_path / "speedless.yaml"
    speedless.write_text(
        Path(cut).read_text().replace("spindle_speed: 12000", "spindle_speed: program")
    )
    program = tmp_path / "line.nc"
    program.write_text("G21 G90\nG1 X10 F1000\n")
    bad = str(tmp_path / "refused")
    assert_error(
        capsys, "report", "--out", bad, "--program", str(program), "--cut", str(speedless),
        mentions="spindle_speed",
    )  # fmt: skip
    assert not Path(bad).exists()
    assert_error(
        capsys, "report", "--out", bad, "--cut", str(tmp_path / "none.yaml"), mentions="cut"
    )
    # the program's S gives the speed of a cut file that says "program"
    program.write_text("G21 G90 G17\nG0 X-20 Y-10 Z5\nG1 Z-2 F600\nG1 X20 F3000 S9000\nG1 Y10\n")
    good = tmp_path / "good"
    argv = ("report", "--out", str(good), "--resolution", "3", "--cube-resolution", "2")
    data = run_json(capsys, *argv, "--quiet", "--program", str(program), "--cut", str(speedless))
    accuracy = data["accuracy"]
    assert accuracy == json.loads((good / "report.json").read_text())["accuracy"]
    assert accuracy["spindle_speed_rpm"] == pytest.approx(9000.0) and accuracy["program"]
    # the blend out of the plunge (line 3) cuts a little, as in `orthoglide accuracy`
    assert [b["line"] for b in accuracy["stability"]["per_block"]] == [3, 4, 5]
    assert accuracy["surface_error"]["peak"]["max"] > 0.0


def test_report_exit_status_follows_the_verdict(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """0 on PASS, 1 on FAIL with the report written all the same, 2 on an error."""
    grid = ("--resolution", "3", "--cube-resolution", "2", "--quiet")
    code, out, err = run(capsys, "report", "--out", str(tmp_path / "pass"), *grid,
                         "--motor", str(EXAMPLE_DRIVE))  # fmt: skip
    assert (code, err) == (0, "") and "Verdict: PASS" in out
    # the example motor's least torque margin is ~45 %: a factor of 2 uses it up
    failing = tmp_path / "fail"
    argv = ("report", "--out", str(failing), *grid, "--motor", str(EXAMPLE_DRIVE))
    code, out, err = run(capsys, *argv, "--safety-factor", "2")
    assert (code, err) == (1, "")
    assert "Verdict: FAIL (required torques x 2, the safety factor)" in out
    saved = json.loads((failing / "report.json").read_text())
    assert saved["verdict"]["passed"] is False and saved["verdict"]["safety_factor"] == 2.0
    assert (failing / "report.html").is_file() and (failing / "summary.csv").is_file()
    mask = os.umask(0o022)
    os.umask(mask)
    assert failing.stat().st_mode & 0o777 == 0o777 & ~mask  # as any tool's output
    assert (failing / "report.json").stat().st_mode & 0o777 == 0o666 & ~mask
    code, out, _ = run(capsys, *argv, "--safety-factor", "2", "--json")
    assert code == 1 and json.loads(out)["passed"] is False
    weak = tmp_path / "weak.yaml"
    weak.write_text(
        "drive_train: {rotor_inertia: 1.2e-4}\nmotor: {name: weak, peak_torque: 0.5}\n"
    )
    assert (
        run(capsys, "report", "--out", str(tmp_path / "weak"), *grid, "--motor", str(weak))[0] == 1
    )
    for bad in ("0.9", "nan", "x"):
        assert_error(capsys, *argv, "--safety-factor", bad, mentions="safety")


def test_report_errors(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = str(tmp_path / "r")
    assert_error(capsys, "report", "--out", out, "--resolution", "1", mentions="resolution")
    assert_error(capsys, "report", "--out", out, "--v-max", "nan", mentions="--v-max")
    assert_error(capsys, "report", "--out", out, "--a-max", "-3", mentions="a_max")
    # a scalar option given a list is refused, not cut to its first number
    for option in ("--v-max", "--min-frequency", "--safety-factor", "--cutting-force"):
        assert_error(capsys, "report", "--out", out, option, "1,2", mentions=option)
    assert_error(capsys, "report", "--out", out, "--param", "leg_length=x", mentions="leg_length")
    assert_error(capsys, "report", "--out", out, "--motor", out + ".yaml", mentions="motor file")
    assert not (tmp_path / "r").exists()
    blocker = tmp_path / "file"
    blocker.write_text("x")
    argv = ("report", "--out", str(blocker), "--resolution", "2", "--cube-resolution", "2")
    assert_error(capsys, *argv, mentions="cannot write")


def test_help_states_the_report_defaults(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli_dynamics.DEFAULT_RESOLUTION == report.DEFAULT_RESOLUTION
    assert cli_dynamics.DEFAULT_CUBE_RESOLUTION == report.DEFAULT_CUBE_RESOLUTION
    code, out, _ = run(capsys, "report", "--help")
    assert code == 0 and f"(default {report.DEFAULT_RESOLUTION})" in out


def test_the_report_names_each_failing_criterion_and_the_least_margin(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    grid = ("--resolution", "3", "--cube-resolution", "2", "--quiet")
    # the example motor slowed to 3000 rpm (rated 1.3 N.m, peak 4 N.m): the worst case
    # over the cube needs about 3533 rpm on every motor
    slow = tmp_path / "slow.yaml"
    slow.write_text(
        "drive_train: {lead: 0.025, rotor_inertia: 1.2e-4}\n"
        "motor: {name: slow, rated_torque: 1.3, peak_torque: 4.0, max_speed: 3000}\n"
    )
    out_dir = tmp_path / "fail"
    argv = ("report", "--out", str(out_dir), *grid, "--motor", str(slow))
    code, out, err = run(capsys, *argv)
    assert (code, err) == (1, "") and "Verdict: FAIL" in out
    saved = json.loads((out_dir / "report.json").read_text())
    failing = [r for r in saved["verdict"]["rows"] if r["passed"] is False]
    assert {r["criterion"] for r in failing} == {"worst case: speed vs maximum speed"}
    lines = out.splitlines()
    start = lines.index("  failing criteria:")
    shown = lines[start + 1 : start + 1 + len(failing)]
    for row, line in zip(failing, shown, strict=True):
        required, available = row["required"], row["available"]
        assert round(required) == 3533 and available == 3000.0
        assert row["margin"] == pytest.approx(1.0 - required / available, rel=SAME_RTOL)
        assert line == (
            f"    motor {row['motor']}, {row['criterion']}: required {required:.4g} rpm, "
            f"available 3000 rpm, margin {100 * row['margin']:+.1f} %"
        )
    data = json.loads(run(capsys, *argv, "--json")[1])
    assert [r["margin"] for r in data["failing"]] == [r["margin"] for r in failing]
    # on PASS, the least margin of every criterion
    passing = tmp_path / "pass"
    code, out, _ = run(
        capsys, "report", "--out", str(passing), *grid, "--motor", str(EXAMPLE_DRIVE)
    )
    assert code == 0 and "Verdict: PASS" in out
    rows = json.loads((passing / "report.json").read_text())["verdict"]["rows"]
    least = min((r for r in rows if r["margin"] is not None), key=lambda r: r["margin"])
    assert f"  least margin: motor {least['motor']}, {least['criterion']}: " in out
    assert f"margin {100 * least['margin']:+.1f} %" in out


def test_the_report_shows_the_machines_criterion(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    grid = ("--resolution", "3", "--cube-resolution", "3", "--quiet")
    data = run_json(capsys, "report", "--out", str(tmp_path / "proto"), *grid)
    assert data["criterion"] == {
        "psi_min": 0.5,
        "psi_max": 2.0,
        "tolerance": 1e-4,
        "from": "machine",
    }
    fr = data["transmission"]
    assert fr["holds"] is False and (round(fr["lowest"], 4), round(fr["highest"], 4)) == (
        0.4989,
        2.0090,
    )
    saved = json.loads((tmp_path / "proto" / "report.json").read_text())
    assert saved["transmission"] == fr and saved["machine"]["parameters"]["psi_max"] == 2.0
    page = (tmp_path / "proto" / "report.html").read_text()
    assert "Transmission factors over the cube" in page and "DOES NOT HOLD" in page
    assert "310.58 mm" in page
    code, text, _ = run(capsys, "report", "--out", str(tmp_path / "proto"), *grid)
    assert code == 0 and "criterion factors in [0.5, 2] (within 0.0001)" in text
    # --psi judges the same machine by another criterion
    wide = run_json(
        capsys, "report", "--out", str(tmp_path / "wide"), *grid, "--psi", "0.45", "2.1"
    )
    assert wide["transmission"]["holds"] is True and wide["criterion"]["from"] == "--psi"


def test_report_with_a_program(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    prog = tmp_path / "shuttle.nc"
    prog.write_text("G21 G90\nG0 X25 Z25\nG0 X-25 Z-25\nG1 X0 Y0 Z0 F3000\nM2\n")
    out = tmp_path / "r"
    grid = ("--resolution", "3", "--cube-resolution", "2", "--quiet")
    argv = ("report", "--out", str(out), *grid, "--motor", str(EXAMPLE_DRIVE))
    code, text, err = run(capsys, *argv, "--program", str(prog), "--v-max", "0.9")
    assert (code, err) == (0, "")
    assert "Program shuttle.nc: cycle time" in text and "within 900 mm/s and 20 m/s^2" in text
    saved = json.loads((out / "report.json").read_text())
    section = saved["program"]
    assert section["name"] == "shuttle.nc" and section["cycle_time"] > 0.1
    assert section["limits"]["slider_speed"] == 0.9
    assert max(section["peak_slider_speed"]) <= 0.9 * (1 + 1e-3)
    rows = [r for r in saved["verdict"]["rows"] if r["criterion"].startswith("program:")]
    assert len(rows) >= 9 and all(r["passed"] for r in rows)
    assert "Part program" in (out / "report.html").read_text()
    assert "program: RMS torque vs rated torque" in (out / "summary.csv").read_text()
    # without --program the report has no program section
    run(capsys, *argv, "--force")
    assert json.loads((out / "report.json").read_text())["program"] is None


def test_report_refuses_a_bad_program(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    out = tmp_path / "r"
    argv = ("report", "--out", str(out), "--resolution", "2", "--cube-resolution", "2")
    missing = str(tmp_path / "none.nc")
    assert_error(capsys, *argv, "--program", missing, mentions="program")
    bad = tmp_path / "bad.nc"
    for text, says in (
        ("G21\nG0 X400\n", "program line 2"),  # out of the cube
        ("G1 X10\n", "program line 1"),  # no feed
        ("G21\nG5 X1\n", "program line 2"),  # unsupported word
    ):
        bad.write_text(text)
        assert_error(capsys, *argv, "--program", str(bad), mentions=says)
    bad.write_text("G43 H1\nG0 X1\n")  # the program's options: a tool table, offsets
    assert_error(capsys, *argv, "--program", str(bad), mentions="tool 1 is not in the tool table")
    far = ("--origin", "2000", "0", "0")
    assert_error(capsys, *argv, "--program", str(bad), *far, mentions="invalid origin=")
    assert not out.exists()
