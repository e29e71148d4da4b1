"""The ``design``, ``indices`` and ``map`` commands, in-process through ``main``."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og

#: The paper's prototype design (section 4), rounded as published.
PAPER_LEG = 0.3106
PAPER_STROKE = 0.2570
PAPER_LENGTH_TOL = 5e-5
#: Closed-form values through JSON (every digit kept).
EXACT_TOL = 1e-12
#: Closed form vs the Pinocchio closed-loop Jacobian.
METHODS_TOL = 1e-8
#: Exit status of every error.
ERROR = 2
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def assert_error(capsys: pytest.CaptureFixture[str], *argv: str, mentions: str) -> None:
    code, out, err = run(capsys, *argv)
    assert code == ERROR
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and re.match(rf"orthoglide {argv[0]}: error: ", lines[0])
    assert mentions in err


def test_design_reproduces_the_prototype(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2")
    for key in ("leg_length", "stroke", "slider_limits", "Q1", "Q2", "ratio"):
        assert key in data
    assert "q1" not in data and "factors_Q1" in data  # points, not slider values
    assert data["leg_length"] == pytest.approx(PAPER_LEG, abs=PAPER_LENGTH_TOL)
    assert data["stroke"] == pytest.approx(PAPER_STROKE, abs=PAPER_LENGTH_TOL)
    assert data["psi_min_found"] == pytest.approx(0.5, rel=EXACT_TOL)
    assert data["psi_max_found"] == pytest.approx(2.0, rel=EXACT_TOL)
    assert data["bounds_hold"] is True
    assert data["config"] is None
    expected = og.design_from_workspace(0.2, 0.5, 2.0).to_dict()
    assert data["Q1"] == expected["q1"] and data["slider_limits"] == expected["slider_limits"]
    code, out, _ = run(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2")
    assert code == 0
    assert "leg_length" in out and "310.58 mm" in out and "ratio" in out
    assert "  Q1  " in out and "  q1  " not in out


def test_design_writes_the_machine(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "designed.yaml"
    data = run_json(
        capsys,
        "design",
        "--workspace",
        "0.15",
        "--psi",
        "0.6",
        "1.5",
        "--param",
        "spindle_mass=3",
        "--write-config",
        str(path),
    )
    assert data["config"] == str(path.resolve())
    assert [p.name for p in tmp_path.iterdir()] == ["designed.yaml"]
    params = og.OrthoglideParams.load(path)
    assert params.leg_length == data["leg_length"]
    assert (params.slider_lower, params.slider_upper) == tuple(data["slider_limits"])
    assert params.spindle_mass == 3.0
    # the file holds the design's cube, and derives the limits from it (null in the file)
    assert params.workspace == og.Cube(tuple(data["cube_corner"]), 0.15)
    text = path.read_text()
    assert "slider_lower: null" in text and "workspace_side: 0.15" in text
    # the written machine is usable at once: its Q2 is within its slider limits
    ik = run_json(capsys, "ik", *map(str, data["Q2"]), "--config", str(path))
    expected = og.inverse_kinematics(data["Q2"], params.leg_length)
    np.testing.assert_allclose(ik["q"], expected, rtol=0, atol=EXACT_TOL)


@pytest.mark.parametrize(
    ("psi", "side", "mentions"),
    [
        (("1", "2"), "0.2", "psi_min=1.0"),
        (("0.5", "1"), "0.2", "psi_max=1.0"),
        (("0.5", "0.9"), "0.2", "psi_max=0.9"),
        (("0.5", "2"), "-0.2", "side=-0.2"),
        (("0.5", "2"), "0", "side=0.0"),
        (("0.5", "2"), "nan", "--workspace"),
    ],
)
def test_design_rejects_impossible_inputs(
    capsys: pytest.CaptureFixture[str], psi: tuple[str, str], side: str, mentions: str
) -> None:
    assert_error(capsys, "design", "--workspace", side, "--psi", *psi, mentions=mentions)


def test_indices_at_home(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "indices", "0", "0", "0")
    np.testing.assert_allclose(data["transmission_factors"], 1.0, atol=EXACT_TOL)
    assert data["condition"] == pytest.approx(1.0, abs=EXACT_TOL)
    assert data["manipulability"] == pytest.approx(1.0, abs=EXACT_TOL)
    for kind in ("velocity_ellipsoid", "force_ellipsoid"):
        semi = [axis["semi_axis"] for axis in data[kind]["axes"]]
        np.testing.assert_allclose(semi, 1.0, atol=EXACT_TOL)
    assert np.abs(np.array(data["isotropy_residuals"]["eq4"])).max() == 0.0


def test_indices_both_methods_agree(capsys: pytest.CaptureFixture[str]) -> None:
    point = ("0.05", "-0.02", "0.1")
    cf = run_json(capsys, "indices", *point)
    pin = run_json(capsys, "indices", *point, "--method", "pinocchio")
    assert (cf["method"], pin["method"]) == ("closed-form", "pinocchio")
    for key in ("transmission_factors", "condition", "manipulability"):
        np.testing.assert_allclose(pin[key], cf[key], rtol=METHODS_TOL)
    expected = og.kinetostatic_indices([0.05, -0.02, 0.1], 0.31)
    np.testing.assert_allclose(cf["transmission_factors"], expected.transmission_factors, rtol=0)
    axes = cf["velocity_ellipsoid"]["axes"]  # a list of axes, one direction each
    dirs = np.array([axis["direction"] for axis in axes])
    np.testing.assert_allclose(dirs @ dirs.T, np.eye(3), atol=EXACT_TOL)
    np.testing.assert_allclose(
        [axis["semi_axis"] for axis in axes], expected.velocity_axes, rtol=0
    )
    code, out, _ = run(capsys, "indices", *point)
    assert code == 0 and "transmission_factors" in out and "force_ellipsoid" in out


def test_indices_errors(capsys: pytest.CaptureFixture[str]) -> None:
    assert_error(capsys, "indices", "0.3", "0.3", "0.3", mentions="unreachable")
    t = str(0.31 / math.sqrt(3.0))
    # also beyond the sliders (q = L there): the singularity is said first, as by jacobian
    assert_error(capsys, "indices", t, t, t, mentions="parallel singularity")


@pytest.mark.parametrize("method", ["closed-form", "pinocchio"])
def test_indices_checks_the_slider_limits_as_ik_does(
    capsys: pytest.CaptureFixture[str], method: str
) -> None:
    # reachable by the legs; slider 1 at 0.2 m, beyond the prototype's 0.184 m
    beyond = ("0.2", "0", "0")
    code, _, ik_err = run(capsys, "ik", *beyond)
    assert code == ERROR and "outside the limits" in ik_err
    code, out, err = run(capsys, "indices", *beyond, "--method", method)
    same = ik_err.replace("orthoglide ik:", "orthoglide indices:", 1)
    assert (code, out, err) == (ERROR, "", same)  # the same one line, named by its command
    # a design whose limits reach further computes there
    longer = ("--param", "slider_upper=0.25")
    data = run_json(capsys, "indices", *beyond, "--method", method, *longer)
    expected = og.kinetostatic_indices([0.2, 0.0, 0.0], 0.31).transmission_factors
    np.testing.assert_allclose(data["transmission_factors"], expected, rtol=METHODS_TOL)


def test_map_writes_png_and_csv(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    png, csv = tmp_path / "map.png", tmp_path / "map.csv"
    data = run_json(capsys, "map", "--out", str(png), "--csv", str(csv), "--resolution", "41")
    assert data["out"] == str(png.resolve()) and data["csv"] == str(csv.resolve())
    assert data["index"] == "condition"
    assert data["slice"] == {"axis": "z", "value": 0.0}
    assert png.read_bytes()[:8] == PNG_MAGIC
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    assert rows.size == 41 * 41
    assert set(rows.dtype.names or ()) >= {"x", "y", "z", "reachable", "condition"}
    reach = rows["reachable"] == 1
    assert 0 < reach.sum() < rows.size
    assert data["min"] == pytest.approx(np.nanmin(rows["condition"][reach]), rel=1e-9)
    assert data["min"] == pytest.approx(1.0, abs=1e-9)  # the isotropic point is on the grid
    assert np.linalg.norm(data["min_at"]) < 1e-9
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.csv", "map.png"]


def test_map_other_slice_and_index(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    png = tmp_path / "psi.png"
    data = run_json(
        capsys,
        "map",
        "--out",
        str(png),
        "--slice",
        "x=0.05",
        "--index",
        "psi_max",
        "--resolution",
        "21",
        "--extent",
        "-0.2",
        "0.2",
    )
    assert data["slice"] == {"axis": "x", "value": 0.05}
    assert data["extent"] == [-0.2, 0.2]
    assert data["max_at"][0] == 0.05
    expected = og.transmission_factors(data["max_at"], 0.31)[2]
    assert data["max"] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("args", "mentions"),
    [
        (("--slice", "w=0"), "--slice"),
        (("--slice", "z"), "--slice"),
        (("--index", "nonsense"), "invalid choice"),
        (("--resolution", "1"), "--resolution"),
        (("--extent", "0.1", "-0.1"), "--extent MAX"),
    ],
)
def test_map_errors(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, args: tuple[str, ...], mentions: str
) -> None:
    assert_error(capsys, "map", "--out", str(tmp_path / "m.png"), *args, mentions=mentions)
    assert list(tmp_path.iterdir()) == []
