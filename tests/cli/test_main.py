"""The ``orthoglide`` command line, mostly in-process through ``main``."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import run, run_json

from orthoglide_pin.cli import main
from orthoglide_pin.machine.description import CACHE_ENV
from orthoglide_pin.machine.params import OrthoglideParams, prototype

#: Prototype leg length [m] and slider stroke [m] (paper, section 4).
LEG = 0.31
STROKE = 0.2573
STROKE_TOL = 5e-5
#: Prototype cube: lower corner coordinate on each axis [m] and side [m].
CUBE_CORNER = -LEG / math.sqrt(18.0)
CUBE_SIDE = 0.2
#: Round trips through the command line (JSON keeps every digit) [m].
ROUND_TRIP_TOL = 1e-12
#: Closed-form values computed two ways [m] or dimensionless.
EXACT_TOL = 1e-12
#: Closed form vs the Pinocchio loop closure (Jacobian entries).
METHODS_TOL = 1e-9
#: Relative tolerance of mass sums [kg].
MASS_RTOL = 1e-12
#: Exit status of every error.
ERROR = 2


@pytest.fixture(scope="module")
def cache_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("cli-urdf-cache")


@pytest.fixture(autouse=True)
def _isolated_cache(monkeypatch: pytest.MonkeyPatch, cache_dir: Path) -> None:
    monkeypatch.setenv(CACHE_ENV, str(cache_dir))


def closed_form_ik(p: np.ndarray, L: float) -> np.ndarray:
    """Working-branch IK written out independently: q_i = p_i + L - eta_i."""
    x, y, z = p
    return p + L - np.sqrt(L**2 - np.array([y**2 + z**2, z**2 + x**2, x**2 + y**2]))


def numbers(values: Any) -> list[str]:
    """Command-line text of numbers, with every digit (``repr`` of a Python float)."""
    return [repr(float(v)) for v in values]


def cube_points() -> list[tuple[float, float, float]]:
    lo, hi, mid = CUBE_CORNER, CUBE_CORNER + CUBE_SIDE, CUBE_CORNER + CUBE_SIDE / 2
    return [(lo, lo, lo), (hi, hi, hi), (hi, lo, mid), (lo + 0.03, hi - 0.01, lo + 0.12)]


# --------------------------------------------------------------------- ik/fk
def test_ik_at_home_is_zero(capsys: pytest.CaptureFixture[str]) -> None:
    q = run_json(capsys, "ik", "0", "0", "0")["q"]
    np.testing.assert_allclose(q, [0.0, 0.0, 0.0], rtol=0, atol=EXACT_TOL)


def test_ik_fk_round_trip(capsys: pytest.CaptureFixture[str]) -> None:
    p = np.array([0.05, -0.03, 0.02])
    q = run_json(capsys, "ik", *numbers(p))["q"]
    np.testing.assert_allclose(q, closed_form_ik(p, LEG), rtol=0, atol=EXACT_TOL)
    back = run_json(capsys, "fk", *numbers(q))["p"]
    np.testing.assert_allclose(back, p, rtol=0, atol=ROUND_TRIP_TOL)


def test_negative_positionals_and_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "ik", "-0.05", "0", "0")
    assert (code, err) == (0, "")
    assert out.startswith("q = (-0.05, ")
    assert not out.lstrip().startswith("{")
    q = run_json(capsys, "ik", "-5e-2", "-.01", "0")["q"]
    np.testing.assert_allclose(
        q, closed_form_ik(np.array([-0.05, -0.01, 0.0]), LEG), rtol=0, atol=EXACT_TOL
    )


def test_fk_all_branches_at_home(capsys: pytest.CaptureFixture[str]) -> None:
    branches = run_json(capsys, "fk", "0", "0", "0", "--all-branches")["branches"]
    assert np.shape(branches) == (2, 3)
    np.testing.assert_allclose(branches[0], [0.0, 0.0, 0.0], rtol=0, atol=EXACT_TOL)
    other = -(2 * LEG / 3) * np.ones(3)
    np.testing.assert_allclose(branches[1], other, rtol=0, atol=EXACT_TOL)
    assert run_json(capsys, "fk", "0", "0", "0")["p"] == pytest.approx(branches[0], abs=EXACT_TOL)


# ------------------------------------------------------------------ jacobian
@pytest.mark.parametrize("method", ["closed-form", "pinocchio"])
def test_jacobian_at_home_is_identity(capsys: pytest.CaptureFixture[str], method: str) -> None:
    data = run_json(capsys, "jacobian", "0", "0", "0", "--method", method)
    assert data["method"] == method
    np.testing.assert_allclose(data["J"], np.eye(3), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(data["J_inv"], np.eye(3), rtol=0, atol=EXACT_TOL)


@pytest.mark.parametrize("point", cube_points())
def test_jacobian_methods_agree_in_the_cube(
    capsys: pytest.CaptureFixture[str], point: tuple[float, float, float]
) -> None:
    args = ["jacobian", *numbers(point)]
    closed = run_json(capsys, *args, "--method", "closed-form")
    pin = run_json(capsys, *args, "--method", "pinocchio")
    np.testing.assert_allclose(pin["J"], closed["J"], rtol=0, atol=METHODS_TOL)
    np.testing.assert_allclose(pin["J_inv"], closed["J_inv"], rtol=0, atol=METHODS_TOL)
    np.testing.assert_allclose(
        np.asarray(closed["J"]) @ np.asarray(closed["J_inv"]), np.eye(3), rtol=0, atol=EXACT_TOL
    )


# ------------------------------------------------------------- --param/config
def test_param_changes_the_result(capsys: pytest.CaptureFixture[str]) -> None:
    p = np.array([0.05, 0.02, -0.03])
    q_default = run_json(capsys, "ik", *numbers(p))["q"]
    q_long = run_json(capsys, "ik", *numbers(p), "--param", "leg_length=0.35")["q"]
    np.testing.assert_allclose(q_default, closed_form_ik(p, LEG), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(q_long, closed_form_ik(p, 0.35), rtol=0, atol=EXACT_TOL)
    assert np.max(np.abs(np.subtract(q_long, q_default))) > 1e-4


def test_config_file_and_param_override(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    config = (
        prototype()
        .replace(leg_length=0.35, tool_offset=(0.0, 0.0, 0.1))
        .save(tmp_path / "machine.yaml")
    )
    assert OrthoglideParams.load(config).leg_length == 0.35
    p = np.array([0.04, -0.02, 0.01])
    q = run_json(capsys, "ik", *numbers(p), "--config", str(config))["q"]
    np.testing.assert_allclose(q, closed_form_ik(p, 0.35), rtol=0, atol=EXACT_TOL)
    q = run_json(capsys, "ik", *numbers(p), "--config", str(config), "--param", "leg_length=0.33")[
        "q"
    ]
    np.testing.assert_allclose(q, closed_form_ik(p, 0.33), rtol=0, atol=EXACT_TOL)


# ---------------------------------------------------------------------- urdf
def test_urdf_output_loads_in_pinocchio(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    import pinocchio as pin

    target = tmp_path / "out" / "orthoglide.urdf"
    data = run_json(capsys, "urdf", "-o", str(target))
    assert Path(data["path"]).samefile(target)
    model = pin.buildModelFromUrdf(str(target))
    assert model.nq == 18
    code, out, err = run(capsys, "urdf")
    assert (code, err) == (0, "")
    assert "<robot" in out
    assert out.strip() == target.read_text().strip()


# -------------------------------------------------------------------- errors
BAD_INPUTS = [
    (["ik", "0", "0.4", "0"], "0.4"),  # out of reach of leg 1
    (["ik", "0.19", "0", "0"], "0.19"),  # reachable, but q1 = 0.19 m > slider_upper
    (["ik", "nan", "0", "0"], "nan"),
    (["ik", "0", "abc", "0"], "abc"),
    (["jacobian", "0", "0", "-inf"], "-inf"),
    (["ik", "0", "0", "0", "--param", "foo=1"], "foo"),
    (["ik", "0", "0", "0", "--param", "leg_length=-1"], "-1"),
    (["ik", "0", "0", "0", "--param", "leg_length=abc"], "abc"),
    (["ik", "0", "0", "0", "--param", "leg_length"], "leg_length"),
    (["ik", "0", "0", "0", "--param", "tool_offset=0,0"], "tool_offset"),
    (["fk", "0", "0.3", "0"], "0.3"),  # q2 above slider_upper (0.184 m)
    (["fk", "-0.1", "0", "0"], "-0.1"),  # q1 below slider_lower (-0.073 m)
]


def assert_one_error_line(code: int, out: str, err: str, value: str) -> None:
    assert code == ERROR
    assert out == ""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert re.match(r"orthoglide [a-z]+: error: ", lines[0]), lines[0]
    assert value in lines[0]


@pytest.mark.parametrize(("argv", "value"), BAD_INPUTS)
def test_bad_input_exits_2_with_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], value: str
) -> None:
    assert_one_error_line(*run(capsys, *argv), value)
    assert_one_error_line(*run(capsys, *argv, "--json"), value)


def test_slider_limit_errors_name_the_limits(capsys: pytest.CaptureFixture[str]) -> None:
    upper = f"{prototype().slider_upper:.6g}"
    _, _, err = run(capsys, "ik", "0.19", "0", "0")
    assert "outside the limits" in err and upper in err
    _, _, err = run(capsys, "fk", "0", "0.3", "0")
    assert "q2" in err and upper in err


def test_missing_config_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    missing = tmp_path / "no-such-machine.yaml"
    assert_one_error_line(
        *run(capsys, "fk", "0", "0", "0", "--config", str(missing)), missing.name
    )


def test_argparse_usage_errors_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["ik", "0", "0"]) == ERROR
    assert main(["jacobian", "0", "0", "0", "--method", "finite-differences"]) == ERROR
    assert main([]) == ERROR
    capsys.readouterr()
    assert main(["--help"]) == 0
    assert "summary" in capsys.readouterr().out


# ------------------------------------------------------------------- summary
def test_summary_json(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    target = tmp_path / "sub" / "machine.urdf"
    s = run_json(capsys, "summary", "-o", str(target))
    assert s["stroke"] == pytest.approx(STROKE, abs=STROKE_TOL)
    lo, hi = s["slider_limits"]
    assert hi - lo == pytest.approx(s["stroke"], abs=EXACT_TOL)
    assert lo == pytest.approx(CUBE_CORNER, abs=EXACT_TOL)  # Q1 sets the lower limit
    assert s["parameters"]["leg_length"] == {"value": LEG, "unit": "m"}
    assert s["parameters"]["density"]["unit"] == "kg/m^3"
    assert s["parameters"]["spindle_mass"]["unit"] == "kg"
    assert (s["joints"], s["constraint_rows"]) == (18, 21)
    assert (s["constraint_rank"], s["mobility"]) == (15, 3)
    np.testing.assert_allclose(s["jacobian_home"], np.eye(3), rtol=0, atol=EXACT_TOL)
    m = s["masses"]
    assert m["total_moving"] > 0
    assert sum(m["bodies"].values()) == pytest.approx(m["total_moving"], rel=MASS_RTOL)
    grouped = sum(m["carriages"].values()) + sum(m["legs"].values()) + m["platform_and_spindle"]
    assert grouped == pytest.approx(m["total_moving"], rel=MASS_RTOL)
    assert sorted(m["carriages"]) == ["leg1_slider", "leg2_slider", "leg3_slider"]
    assert sorted(m["legs"]) == ["leg1", "leg2", "leg3"]
    assert m["platform_joint"] == "leg1_end_revolute"
    assert m["platform_and_spindle"] > prototype().spindle_mass
    assert s["derived_masses"] == ["bar_mass", "link_mass", "carriage_mass", "platform_mass"]
    assert Path(s["urdf_path"]).samefile(target)
    assert "<robot" in target.read_text()


def test_summary_explicit_masses_are_not_assumptions(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    s = run_json(
        capsys,
        "summary",
        "-o",
        str(tmp_path / "m.urdf"),
        "--param",
        "carriage_mass=1.5",
        "--param",
        "bar_mass=none",
        "--param",
        "tool_offset=0,0,0.1",
    )
    assert s["parameters"]["tool_offset"]["value"] == [0.0, 0.0, 0.1]
    assert s["masses"]["carriages"] == {f"leg{i}_slider": 1.5 for i in (1, 2, 3)}
    assert s["derived_masses"] == ["bar_mass", "link_mass", "platform_mass"]


def test_summary_text_writes_no_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "summary")
    assert (code, err) == (0, "")
    assert list(tmp_path.iterdir()) == []  # no URDF unless -o asks for one
    assert "leg_length" in out and "310.0 mm" in out
    assert "stroke 257.3 mm" in out and "(derived from the cube)" in out
    assert "Workspace: 200 mm cube, lowest corner Q1 (-73.07, -73.07, -73.07) mm" in out
    assert "mobility 3" in out and "rank 15" in out
    assert "derived" in out
    assert "URDF written" not in out


# --------------------------------------------------------------- subprocesses
def test_python_dash_m(tmp_path: Path) -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "orthoglide_pin", "ik", "-0.05", "0", "0", "--json"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=os.environ.copy(),
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    q = json.loads(proc.stdout)["q"]
    np.testing.assert_allclose(
        q, closed_form_ik(np.array([-0.05, 0.0, 0.0]), LEG), rtol=0, atol=EXACT_TOL
    )


def test_console_script(tmp_path: Path) -> None:
    script = Path(sys.executable).parent / "orthoglide"
    if not script.is_file():
        pytest.skip(f"console script not installed at {script}")
    ok = subprocess.run(
        [str(script), "fk", "0", "0", "0", "--json"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        check=False,
    )
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["p"] == pytest.approx([0.0, 0.0, 0.0], abs=EXACT_TOL)
    bad = subprocess.run(
        [str(script), "ik", "0", "0.4", "0"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        check=False,
    )
    assert_one_error_line(bad.returncode, bad.stdout, bad.stderr, "0.4")


def test_rounding_noise_prints_as_zero() -> None:
    from orthoglide_pin.cli import _common as common

    assert common.fmt([2.1e-17, 0.2, -1e-18]) == "(0, 0.2, 0)"
    assert common.fmt([-2.1e-17]) == "(0)"  # alone too, and no "-0"
    assert common.fmt([1e-9, 0.0]) == "(1e-09, 0)"  # a small value is not noise
    assert common.fmt([3e-15, 1e3]) == "(0, 1000)"  # noise relative to the largest
    assert common.fmt([0.0731, -1e-20], 1e3, ".2f") == "(73.10, 0.00)"
