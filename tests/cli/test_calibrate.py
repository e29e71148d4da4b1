"""``orthoglide calibrate``, ``sensitivity`` and ``fk/ik --calibration``, end to end."""

from __future__ import annotations

import csv as csv_module
import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel

#: Tracker noise of the simulated measurements [m].
NOISE = 5e-6
#: Errors of the simulated built machine, per leg: 0.2 mm, 0.5 mrad, 0.1 mm.
ERROR_SCALE = np.tile([2e-4, 2e-4, 2e-4, 5e-4, 5e-4, 1e-4], 3)
#: A design other than the prototype.
OTHER_LEG = 0.35


def _true_machine(leg: float, seed: int) -> GeometricModel:
    nominal = GeometricModel.nominal(leg)
    noise = np.random.default_rng(seed).normal(size=18) * ERROR_SCALE
    return GeometricModel.from_vector(nominal.vector() + noise)


def _write(path: Path, q: np.ndarray, m: np.ndarray, header: str = "q1,q2,q3,x,y,z") -> Path:
    rows = "".join(
        ",".join(repr(float(v)) for v in (*a, *b)) + "\n" for a, b in zip(q, m, strict=True)
    )
    path.write_text(header + "\n" + rows)
    return path


def _measurements(tmp_path: Path, leg: float, n: int = 60, seed: int = 0, planar: bool = False):
    params = og.prototype().replace(leg_length=leg)
    true = _true_machine(leg, seed)
    rng = np.random.default_rng(seed + 100)
    lo = np.asarray(params.workspace.corner)
    p = rng.uniform(lo, lo + params.workspace.side, (n, 3))
    if planar:
        p[:, 2] = 0.01
    q = true.inverse_kinematics(p)
    m = p + rng.normal(0.0, NOISE, p.shape)
    return _write(tmp_path / "meas.csv", q, m), true


@pytest.mark.parametrize("leg", [0.31, OTHER_LEG])
def test_calibration_compensates_ik(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, leg: float
) -> None:
    csv, true = _measurements(tmp_path, leg)
    out = tmp_path / "cal"
    data = run_json(capsys, "calibrate", str(csv), "--out", str(out), "--param",
                    f"leg_length={leg}", "--json")  # fmt: skip
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "calibration.html", "calibration.yaml", "residuals.csv"
    ]  # fmt: skip
    assert data["outliers"] == [] and data["unidentifiable"] == []
    assert data["rms_before"] > 50 * data["rms_after"]
    assert 0.7 * NOISE < data["noise_estimate"] < 1.3 * NOISE
    assert set(data["parameters"]) == set(PARAMETER_NAMES)
    calibration = og.load_calibration(out / "calibration.yaml")
    np.testing.assert_array_equal(
        calibration.model.vector(),
        [data["parameters"][n]["value"] for n in PARAMETER_NAMES],
    )  # the file holds the full precision
    # the compensated ik puts the real tool where asked, to the parameters' accuracy
    target = np.array([0.04, -0.02, 0.03])
    q = np.array(run_json(capsys, "ik", *map(str, target), "--calibration",
                          str(out / "calibration.yaml"), "--param", f"leg_length={leg}",
                          "--json")["q"])  # fmt: skip
    assert np.linalg.norm(true.direct_kinematics(q) - target) < 3 * NOISE
    q_nominal = og.inverse_kinematics(target, leg)
    assert np.linalg.norm(true.direct_kinematics(q_nominal) - target) > 30 * NOISE
    p = run_json(capsys, "fk", *map(str, q), "--calibration", str(out / "calibration.yaml"),
                 "--param", f"leg_length={leg}", "--json")["p"]  # fmt: skip
    np.testing.assert_allclose(p, target, atol=1e-12)
    residuals = (out / "residuals.csv").read_text().splitlines()
    assert residuals[0].startswith("row,q1,q2,q3,x,y,z,outlier,before_x") and len(residuals) == 61
    html = (out / "calibration.html").read_text()
    assert html.count("data:image/png;base64,") == 3 and "http" not in html
    assert "<td>none of 60 poses</td>" in html


def test_outliers_are_reported_by_row(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    csv, _ = _measurements(tmp_path, 0.31, seed=5)
    lines = csv.read_text().splitlines()
    for row in (3, 41):
        cells = lines[row + 1].split(",")
        cells[4] = repr(float(cells[4]) + 2e-3)
        lines[row + 1] = ",".join(cells)
    csv.write_text("\n".join(lines) + "\n")
    data = run_json(capsys, "calibrate", str(csv), "--out", str(tmp_path / "o"), "--json")
    assert data["outliers"] == [3, 41]
    # the count first, then the rows, named as rows, on the terminal and on the page
    code, out, err = run(capsys, "calibrate", str(csv), "--out", str(tmp_path / "t"))
    said = "2 of 60 poses: rows 3, 41 (residuals.csv's row column, from 0)"
    assert code == 0 and err == "" and f"outliers left out of the fit: {said}" in out
    html = (tmp_path / "t" / "calibration.html").read_text()
    assert f"<td>{said.replace(chr(39), '&#x27;')}</td>" in html
    with open(tmp_path / "t" / "residuals.csv") as fh:
        flagged = [int(r["row"]) for r in csv_module.DictReader(fh) if r["outlier"] == "1"]
    assert flagged == [3, 41]


def _bad(tmp_path: Path, name: str) -> Path:
    csv, _ = _measurements(tmp_path, 0.31, n=20, seed=9)
    text = csv.read_text().splitlines()
    if name == "missing column":
        text[0] = "q1,q2,q3,x,y,w"
    elif name == "nan":
        text[5] = text[5].replace(text[5].split(",")[3], "nan", 1)
    elif name == "millimetres":
        text[1:] = [",".join(repr(1e3 * float(v)) for v in ln.split(",")) for ln in text[1:]]
    elif name == "too few rows":
        text = text[:9]
    elif name == "duplicated rows":
        text.append(text[4])
    elif name == "not a number":
        text[2] = "a,b,c,d,e,f"
    csv.write_text("\n".join(text) + "\n")
    return csv


@pytest.mark.parametrize(
    ("case", "words"),
    [
        ("missing column", "missing column(s) z"),
        ("nan", "row 4, column x: nan"),
        ("millimetres", "millimetres"),
        ("too few rows", "8 rows, at least 10"),
        ("duplicated rows", "rows 3 and 20 are identical"),
        ("not a number", "row 1, column q1: 'a' is not a number"),
    ],
)
def test_bad_measurement_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, case: str, words: str
) -> None:
    csv = _bad(tmp_path, case)
    out = tmp_path / "out"
    code, stdout, err = run(capsys, "calibrate", str(csv), "--out", str(out))
    assert (code, stdout) == (2, "")
    assert (
        words in err and err.count("\n") == 1 and err.startswith("orthoglide calibrate: error: ")
    )
    assert not out.exists()


def test_planar_poses_are_refused_unless_partial(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    csv, _ = _measurements(tmp_path, 0.31, planar=True)
    out = tmp_path / "out"
    code, stdout, err = run(capsys, "calibrate", str(csv), "--out", str(out))
    assert (code, stdout) == (2, "") and "cannot determine 2 combination" in err
    assert "--allow-partial" in err and not out.exists()
    data = run_json(capsys, "calibrate", str(csv), "--out", str(out), "--allow-partial",
                    "--json")  # fmt: skip
    assert len(data["unidentifiable"]) == 2 and data["rms_after"] < 3 * NOISE


def test_slider_values_beyond_the_limits_are_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    csv, _ = _measurements(tmp_path, 0.31)
    lines = csv.read_text().splitlines()
    lines[8] = "0.4," + lines[8].split(",", 1)[1]  # beyond the upper limit of 0.184 m
    csv.write_text("\n".join(lines) + "\n")
    code, _, err = run(capsys, "calibrate", str(csv), "--out", str(tmp_path / "o"))
    assert code == 2 and "row 7, q1" in err and "within the limits" in err


def test_plan_writes_poses_and_expected_deviations(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "plan"
    data = run_json(capsys, "calibrate", "--plan", "24", "--noise", "1e-5", "--out", str(out),
                    "--param", f"leg_length={OTHER_LEG}", "--json")  # fmt: skip
    design = og.design_digest(og.prototype().replace(leg_length=OTHER_LEG))
    assert (out / "poses.csv").read_text().startswith(f"# orthoglide design: {design}, ")
    poses = np.loadtxt(out / "poses.csv", delimiter=",", skiprows=2)  # the design, the header
    assert poses.shape == (24, 6)
    np.testing.assert_allclose(poses[:, 3:], og.inverse_kinematics(poses[:, :3], OTHER_LEG),
                               atol=1e-15)  # fmt: skip
    params = og.prototype().replace(leg_length=OTHER_LEG)
    lo = np.asarray(params.workspace.corner)
    assert (poses[:, :3] >= lo - 1e-12).all() and (poses[:, :3] <= lo + 0.2 + 1e-12).all()
    assert len({tuple(r) for r in poses}) == 24
    assert set(data["expected_std"]) == set(PARAMETER_NAMES) and data["noise"] == 1e-5
    std = (out / "expected_std.csv").read_text().splitlines()
    assert std[0] == "parameter,expected_std,unit" and len(std) == 19


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--plan", "5"], "from 10 to"),
        (["--plan", "ten"], "whole number"),
        (["--plan", "20", "--noise", "-1"], "noise"),
        (["--noise", "1e-5", "m.csv"], "only with --plan"),
        ([], "either MEASUREMENTS.csv or --plan"),
    ],
)
def test_bad_calibrate_arguments(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], words: str
) -> None:
    code, out, err = run(capsys, "calibrate", *argv, "--out", str(tmp_path / "o"))
    assert (code, out) == (2, "") and words in err and err.count("\n") == 1


def test_sensitivity_at_home(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "sensitivity", "0", "0", "0", "--json")
    # at home each carriage and leg error moves the tool by its own amount along e_i
    assert data["parameters"]["a1_x"] == pytest.approx(1.0)
    assert data["parameters"]["L2"] == pytest.approx(1.0)
    assert data["groups"]["rail orientation"] == pytest.approx(0.0, abs=1e-15)
    json.dumps(data, allow_nan=False)
    code, _, err = run(capsys, "sensitivity", "0", "0", "0.3")
    assert code == 2 and err.count("\n") == 1
