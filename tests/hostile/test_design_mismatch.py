"""One machine per file: another design's calibration or trajectory is refused, naming both.

The files are made for a design with 340.75 mm legs and given to the prototype
(310 mm), and the other way round, on the command line (one line, exit 2, no
traceback, nothing written) and in the API (``DesignMismatchError``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import run

import orthoglide_pin as og
from orthoglide_pin.calibration.model import GeometricModel
from orthoglide_pin.calibration.result import Calibration, write_calibration
from orthoglide_pin.machine.digest import design_comment
from orthoglide_pin.viewer.planned import read_trajectory

#: The other design's leg length [m].
OTHER_LEG = 0.34075
#: A short planned trajectory, inside both designs' cubes [m, s, m/s].
ROWS = ["t,x,y,z,path_speed", "0,0,0,0,0", "0.1,0.001,0,0,0.02", "0.2,0.002,0,0,0"]
PROGRAM = "G21 G90\nG1 X5 F3000\nM2\n"


def _other() -> og.OrthoglideParams:
    return og.prototype().replace(leg_length=OTHER_LEG)


def _calibration(params: og.OrthoglideParams, design: str | None) -> Calibration:
    nominal = GeometricModel.nominal(params.leg_length)
    return Calibration(
        model=nominal, nominal=nominal, std=np.zeros(18), noise_estimate=0.0, rms_before=0.0,
        rms_after=0.0, outliers=(), unidentifiable=(), poses=60,
        measurements_sha256="ab" * 32, design=design,
    )  # fmt: skip


@pytest.fixture
def other_cal(tmp_path: Path) -> Path:
    path = tmp_path / "calibration.yaml"
    write_calibration(path, _calibration(_other(), og.design_digest(_other())))
    return path


def _one_line(err: str, *words: str) -> None:
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, (word, err)


def test_ik_refuses_another_designs_calibration(
    capsys: pytest.CaptureFixture[str], other_cal: Path
) -> None:
    code, out, err = run(capsys, "ik", "0.01", "0", "0", "--calibration", str(other_cal))
    assert code == 2 and out == ""
    theirs, ours = og.design_digest(_other()), og.design_digest()
    _one_line(err, "error:", theirs, ours, "340.75 mm", "310 mm", str(other_cal))


@pytest.mark.parametrize(
    "argv",
    [
        ["ik", "0.01", "0", "0"],
        ["fk", "0.01", "0", "0"],
    ],
)
def test_its_own_design_is_accepted_and_the_prototype_refused(
    capsys: pytest.CaptureFixture[str], other_cal: Path, argv: list[str]
) -> None:
    code, out, err = run(capsys, *argv, "--calibration", str(other_cal))
    assert code == 2 and out == ""
    _one_line(err, og.design_digest(_other()), og.design_digest())
    code, out, err = run(capsys, *argv, "--calibration", str(other_cal),
                         "--param", f"leg_length={OTHER_LEG}")  # fmt: skip
    assert code == 0 and err == "" and "(calibrated)" in out
    mine = other_cal.with_name("prototype.yaml")  # the other way round
    write_calibration(mine, _calibration(og.prototype(), og.design_digest()))
    code, out, err = run(capsys, *argv, "--calibration", str(mine),
                         "--param", f"leg_length={OTHER_LEG}")  # fmt: skip
    assert code == 2 and out == ""
    _one_line(err, f"made for design {og.design_digest()} (leg length 310 mm)", "340.75 mm")


def test_plan_refuses_another_designs_calibration(
    capsys: pytest.CaptureFixture[str], other_cal: Path, tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    out = tmp_path / "plan"
    code, _, err = run(capsys, "plan", str(prog), "--max-slider-acceleration", "10",
                       "--calibration", str(other_cal), "--out", str(out))  # fmt: skip
    assert code == 2 and not out.exists()
    _one_line(err, "error:", og.design_digest(_other()), "340.75 mm")
    with pytest.raises(og.DesignMismatchError, match=og.design_digest(_other())):
        og.plan_program(og.read_program(PROGRAM), None,
                        og.PlanLimits(slider_acceleration=10.0),
                        calibration=og.load_calibration(other_cal))  # fmt: skip


def test_a_calibration_without_a_design_gets_the_line_to_add(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    old = tmp_path / "old.yaml"
    write_calibration(old, _calibration(og.prototype(), None))  # as written before
    assert "design" not in yaml.safe_load(old.read_text())
    code, _, err = run(capsys, "ik", "0.01", "0", "0", "--calibration", str(old))
    assert code == 2
    _one_line(err, "records no design", f'design: "{og.design_digest()}"')
    with pytest.raises(og.DesignMismatchError, match="records no design") as info:
        og.load_calibration(old).check_design(None, str(old))
    assert info.value.recorded is None and info.value.expected == og.design_digest()
    # an old file of another leg length is another design, for certain
    write_calibration(old, _calibration(_other(), None))
    code, _, err = run(capsys, "fk", "0", "0", "0", "--calibration", str(old))
    assert code == 2
    _one_line(err, "another design (leg length 340.75 mm)", og.design_digest())
    # the line added, the file is the prototype's
    old.write_text(old.read_text().replace("leg_length: 0.34075", "leg_length: 0.31"))
    old.write_text(old.read_text() + f'design: "{og.design_digest()}"\n')
    assert og.load_calibration(old).design == og.design_digest()


def test_a_malformed_or_numeric_looking_design_is_handled(tmp_path: Path) -> None:
    path = tmp_path / "calibration.yaml"
    digits = "1234567890123456"  # a number in YAML, unless quoted
    write_calibration(path, _calibration(og.prototype(), digits))
    assert f'design: "{digits}"' in path.read_text()
    assert og.load_calibration(path).design == digits
    path.write_text(path.read_text().replace(f'"{digits}"', "1234e5678"))
    with pytest.raises(og.InvalidParameterError, match="invalid design="):
        og.load_calibration(path)


def test_an_identification_keeps_its_design() -> None:
    other = _other()
    nominal = GeometricModel.nominal(OTHER_LEG)
    rng = np.random.default_rng(3)
    lo = np.asarray(other.workspace.corner)
    p = rng.uniform(lo, lo + other.workspace.side, (30, 3))
    q = nominal.inverse_kinematics(p)
    fit = og.identify(q, p + rng.normal(0.0, 5e-6, p.shape), nominal)
    data = og.Measurements(q, p, sha256="ab" * 32)
    cal = og.Calibration.from_identification(fit, data, other)
    assert cal.design == og.design_digest(other)
    cal.check_design(other)
    with pytest.raises(og.DesignMismatchError, match=r"340\.75 mm"):
        cal.check_design(None)
    with pytest.raises(og.DesignMismatchError, match="the identification"):
        og.Calibration.from_identification(fit, data)  # the prototype's legs are 310 mm
    assert cal.legs(other).lengths == pytest.approx([OTHER_LEG] * 3, abs=1e-3)
    with pytest.raises(og.DesignMismatchError, match=og.design_digest(other)):
        og.render_urdf(None, legs=cal.legs())  # its legs on the prototype's drawing


def test_view_refuses_another_designs_trajectory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    csv = tmp_path / "trajectory.csv"
    csv.write_text(design_comment(_other()) + "\n".join(ROWS) + "\n")
    page = tmp_path / "v.html"
    code, out, err = run(capsys, "view", "--trajectory", str(csv), "--static", str(page))
    assert code == 2 and out == "" and not page.exists()
    _one_line(err, "error:", og.design_digest(_other()), og.design_digest(), "340.75 mm")
    with pytest.raises(og.DesignMismatchError):
        read_trajectory(csv)  # the prototype
    assert read_trajectory(csv, _other()).p.shape == (3, 3)
    with pytest.raises(og.InvalidParameterError, match="OrthoglideParams"):
        read_trajectory(csv, _other().workspace)  # a cube cannot say which machine
    csv.write_text("# orthoglide design: " + "z" * 5000 + "\n" + "\n".join(ROWS) + "\n")
    code, _, err = run(capsys, "view", "--trajectory", str(csv), "--static", str(page))
    assert code == 2 and "zzz" not in err  # the file's content is not echoed
    _one_line(err, "first line", str(csv))
    csv.write_text("\n".join(ROWS) + "\n")  # written before designs were recorded
    code, _, err = run(capsys, "view", "--trajectory", str(csv), "--static", str(page))
    assert code == 2 and not page.exists()
    _one_line(err, "records no design", f"# orthoglide design: {og.design_digest()}")


def _parquet(path: Path, comment: str | None) -> None:
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    rows = np.array([[float(v) for v in r.split(",")] for r in ROWS[1:]])
    table = pa.table({c: rows[:, j] for j, c in enumerate(ROWS[0].split(","))})
    if comment is not None:
        table = table.replace_schema_metadata({"orthoglide": comment.rstrip("\n")})
    pq.write_table(table, path)


def test_view_refuses_another_designs_parquet_trajectory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "trajectory.parquet"
    _parquet(path, design_comment(_other()))
    page = tmp_path / "v.html"
    code, out, err = run(capsys, "view", "--trajectory", str(path), "--static", str(page))
    assert code == 2 and out == "" and not page.exists()
    _one_line(err, "error:", og.design_digest(_other()), og.design_digest(), "340.75 mm")
    with pytest.raises(og.DesignMismatchError):
        read_trajectory(path)  # the prototype
    assert read_trajectory(path, _other()).p.shape == (3, 3)
    _parquet(path, "# orthoglide design: " + "z" * 5000)
    code, _, err = run(capsys, "view", "--trajectory", str(path), "--static", str(page))
    assert code == 2 and "zzz" not in err  # the metadata is not echoed
    _one_line(err, "metadata 'orthoglide'", str(path))
    _parquet(path, None)  # no design recorded: the message says what to add, and where
    code, _, err = run(capsys, "view", "--trajectory", str(path), "--static", str(page))
    assert code == 2 and not page.exists()
    _one_line(err, "records no design", "metadata key 'orthoglide'", og.design_digest())
    with pytest.raises(og.DesignMismatchError, match="records no design"):
        read_trajectory(path)


def test_poses_of_another_design_are_refused_as_measurements(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    plan = tmp_path / "plan"
    code, _, err = run(capsys, "calibrate", "--plan", "12", "--out", str(plan),
                       "--param", f"leg_length={OTHER_LEG}")  # fmt: skip
    assert code == 0, err
    poses = plan / "poses.csv"  # measured as planned: q1..q3 and x, y, z, with its design line
    out = tmp_path / "cal"
    code, _, err = run(capsys, "calibrate", str(poses), "--out", str(out), "--allow-partial")
    assert code == 2 and not out.exists()
    _one_line(err, "error:", str(poses), og.design_digest(_other()), og.design_digest())
    data = og.read_measurements(poses)
    assert (data.design, data.leg_length) == (og.design_digest(_other()), OTHER_LEG)
    nominal = GeometricModel.nominal(og.prototype().leg_length)
    fit = og.identify(data.q, data.points, nominal, allow_partial=True)
    with pytest.raises(og.DesignMismatchError, match=r"340\.75 mm"):
        og.Calibration.from_identification(fit, data)
    broken = tmp_path / "broken.csv"
    broken.write_text("# orthoglide design: nothex\n" + poses.read_text().split("\n", 1)[1])
    with pytest.raises(og.CalibrationError, match="first line"):
        og.read_measurements(broken)


def test_a_plan_is_sampled_and_simulated_on_its_own_design_only() -> None:
    pytest.importorskip("toppra")
    from orthoglide_pin.planning.sampling import sample_plan

    other = og.ClosedLoopDynamics(_other())
    limits = og.PlanLimits(slider_acceleration=10.0)
    plan = og.plan_program(og.read_program(PROGRAM), other, limits)
    assert plan.design == og.design_digest(_other())
    assert sample_plan(plan, other, 0.01)["t"].size > 2
    prototype = og.ClosedLoopDynamics(None)
    with pytest.raises(og.DesignMismatchError, match="the plan was made for design"):
        sample_plan(plan, prototype, 0.01)
    pytest.importorskip("mujoco")
    with pytest.raises(og.DesignMismatchError, match=og.design_digest()):
        og.simulate(plan, prototype, og.Drive(), og.ServoSettings(rate=1000.0))


@pytest.mark.slow
def test_poses_calibrated_on_their_own_design_record_it_everywhere(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    plan = tmp_path / "plan"
    param = ["--param", f"leg_length={OTHER_LEG}"]
    assert run(capsys, "calibrate", "--plan", "12", "--out", str(plan), *param)[0] == 0
    done = tmp_path / "done"
    code, _, err = run(capsys, "calibrate", str(plan / "poses.csv"), "--out", str(done),
                       "--allow-partial", *param)  # fmt: skip
    assert code == 0, err
    theirs = og.design_digest(_other())
    assert og.load_calibration(done / "calibration.yaml").design == theirs
    assert f"<td>{theirs}</td>" in (done / "calibration.html").read_text()
