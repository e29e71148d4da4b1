"""A design of one's own, end to end: one machine, one cube, the same numbers everywhere.

The path a user takes with a design that is not the prototype: ``design
--write-config``, then ``summary``, ``urdf``, ``report``, ``sweep`` and ``view
--static`` on that file. Every command reads the design's cube from the file,
and the report, a sweep row and the Python API give the same worst case.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import run, run_json

import orthoglide_pin as og

#: The report, a sweep row and the API compute the same closed forms on the same
#: grid: they agree to rounding.
AGREE_RTOL = 1e-9
#: Points per cube edge of the worst case, the same in the three routes.
CUBE_GRID = "5"
#: The design of the walk: the paper's 200 mm cube with wider bounds (not the prototype).
SIDE, PSI = "0.2", ("0.5", "3")
#: Its leg [m], from the closed form of the design method (L = Lw / (f2 - f1)).
WIDE_LEG = 0.2817855371393
LEG_TOL = 1e-12


def _report(capsys: pytest.CaptureFixture[str], out: Path, *extra: str) -> dict[str, object]:
    argv = ("report", "--out", str(out), "--quiet", "--resolution", "3")
    return run_json(capsys, *argv, "--cube-resolution", CUBE_GRID, *extra)


def _sweep_row(
    capsys: pytest.CaptureFixture[str], out: Path, *extra: str
) -> tuple[dict[str, object], pd.Series]:
    argv = ("sweep", "--out", str(out), "--grid", "5", "--requirement-grid", CUBE_GRID)
    data = run_json(capsys, *argv, "--workers", "1", "--no-plot", "--no-progress", *extra)
    assert data["invalid"] == 0
    table = pd.read_parquet(out / "results.parquet")  # exact floats (the CSV rounds)
    assert len(table) == 1
    return data, table.iloc[0]


def test_own_design_end_to_end(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    config = tmp_path / "d.yaml"
    design = run_json(
        capsys, "design", "--workspace", SIDE, "--psi", *PSI, "--write-config", str(config)
    )
    assert design["leg_length"] == pytest.approx(WIDE_LEG, abs=LEG_TOL)
    params = og.OrthoglideParams.load(config)
    assert params.workspace == og.Cube(tuple(design["cube_corner"]), 0.2)
    assert (params.slider_lower, params.slider_upper) == tuple(design["slider_limits"])

    summary = run_json(capsys, "summary", "--config", str(config))
    assert summary["workspace"] == params.workspace.to_dict()
    assert summary["slider_limits"] == design["slider_limits"]
    assert summary["urdf_path"] is None and sorted(p.name for p in tmp_path.iterdir()) == [
        "d.yaml"
    ]

    urdf = run_json(capsys, "urdf", "--config", str(config), "-o", str(tmp_path / "d.urdf"))
    text = Path(urdf["path"]).read_text()
    lower, upper = design["slider_limits"]
    # the slider joints' limits are the design's (written exactly, with repr)
    assert text.count(f'lower="{params.slider_lower!r}" upper="{params.slider_upper!r}"') == 3

    report = _report(capsys, tmp_path / "report", "--config", str(config))
    assert report["cube"] == params.workspace.to_dict()
    page_text = Path(str(report["report"])).read_text()
    assert "200 mm cube, lowest corner Q1 (-84.96, -84.96, -84.96) mm" in page_text
    assert "(derived from the cube)" in page_text  # the slider limits, on the page too
    saved = json.loads(Path(str(report["json"])).read_text())
    np.testing.assert_array_equal(saved["cube"]["corner"], design["cube_corner"])

    sweep, row = _sweep_row(capsys, tmp_path / "sweep", "--config", str(config))
    assert sweep["cube"] == params.workspace.to_dict()  # the design's cube, said
    assert row["leg_length"] == params.leg_length
    assert row["cube_side"] == 0.2 and row["cube_corner_x"] == design["cube_corner"][0]
    assert (row["slider_lower"], row["slider_upper"]) == pytest.approx((lower, upper), rel=1e-15)

    api = og.worst_case_over_cube(params, resolution=int(CUBE_GRID))
    force = [
        float(np.max(report["max_force"])),
        row["max_slider_force"],
        float(api.max_force.max()),
    ]
    torque = [
        float(np.max(report["max_torque"])),
        row["max_motor_torque"],
        float(api.max_torque.max()),
    ]
    np.testing.assert_allclose(force, force[0], rtol=AGREE_RTOL)
    np.testing.assert_allclose(torque, torque[0], rtol=AGREE_RTOL)

    page = tmp_path / "view.html"
    code, out, err = run(capsys, "view", "--config", str(config), "--static", str(page))
    assert (code, err) == (0, "")
    assert "200 mm cube, lowest corner Q1 (-84.96, -84.96, -84.96) mm" in out
    assert page.stat().st_size > 0


@pytest.mark.usefixtures("no_drawing")
def test_the_papers_design_and_another_leg_report(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    config = tmp_path / "paper.yaml"
    run_json(
        capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--write-config", str(config)
    )
    paper = _report(capsys, tmp_path / "paper", "--config", str(config))
    assert paper["cube"]["side"] == 0.2
    # the prototype with a longer leg keeps the paper's cube: the sweep's fixed cube
    longer = _report(capsys, tmp_path / "longer", "--param", "leg_length=0.35")
    assert longer["cube"] == og.prototype().workspace.to_dict()
    _, row = _sweep_row(capsys, tmp_path / "sweep", "--leg-length", "0.35")
    assert float(np.max(longer["max_torque"])) == pytest.approx(
        row["max_motor_torque"], rel=AGREE_RTOL
    )
    assert float(np.max(longer["max_force"])) == pytest.approx(
        row["max_slider_force"], rel=AGREE_RTOL
    )


@pytest.mark.usefixtures("no_drawing")
def test_report_and_map_take_another_cube(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    corner = ("-0.05", "-0.06", "-0.04")
    data = _report(capsys, tmp_path / "r", "--workspace", "0.12", "--corner", *corner)
    assert data["cube"] == {"corner": [-0.05, -0.06, -0.04], "side": 0.12}
    api = og.worst_case_over_cube(
        og.prototype().replace(workspace_corner=(-0.05, -0.06, -0.04), workspace_side=0.12),
        resolution=int(CUBE_GRID),
    )
    np.testing.assert_allclose(data["max_torque"], api.max_torque, rtol=AGREE_RTOL)
    png = tmp_path / "map.png"
    out = run_json(
        capsys,
        "map",
        "--out",
        str(png),
        "--resolution",
        "5",
        "--workspace",
        "0.12",
        "--corner",
        *corner,
    )
    assert out["cube"] == data["cube"] and png.is_file()
    # a cube the given slider limits cannot serve is refused, naming the cube and the fix
    code, out_text, err = run(
        capsys, "report", "--out", str(tmp_path / "x"), "--quiet",
        "--param", "slider_upper=0.19", "--workspace", "0.25",
    )  # fmt: skip
    assert code == 2 and out_text == ""
    assert "250 mm cube" in err and "omit slider_lower and slider_upper" in err
    assert not (tmp_path / "x").exists()


def test_a_length_in_millimetres_is_refused_with_a_hint(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, err = run(capsys, "summary", "--param", "leg_length=310")
    assert (code, out) == (2, "")
    assert "expected metres: did you mean 0.31?" in err


def test_the_sweep_takes_its_cube_from_the_machine(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    cube = ("--param", "workspace_corner=-0.05,-0.05,-0.05", "--param", "workspace_side=0.1")
    data, row = _sweep_row(capsys, tmp_path / "s", *cube, "--leg-length", "0.3")
    assert data["cube"] == {"corner": [-0.05, -0.05, -0.05], "side": 0.1}
    machine = og.prototype().replace(
        leg_length=0.3, workspace_corner=(-0.05, -0.05, -0.05), workspace_side=0.1
    )
    assert (row["slider_lower"], row["slider_upper"]) == (
        machine.slider_lower,
        machine.slider_upper,
    )
    # the side is swept as a setting of the sweep, not as a machine parameter
    code, out, err = run(capsys, "sweep", "--param", "workspace_side=0.1:0.2:3", "--out", "x")
    assert (code, out) == (2, "") and "cube_side=START:STOP:N" in err


@pytest.mark.usefixtures("no_drawing")
def test_one_criterion_and_consistent_verdicts_through_every_command(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """design -> summary -> certify -> sweep -> report on a 250 mm cube, [0.4, 2.5]."""
    config = tmp_path / "d.yaml"
    argv = ("design", "--workspace", "0.25", "--psi", "0.4", "2.5", "--grid", "5")
    design = run_json(capsys, *argv, "--write-config", str(config))
    criterion = {"psi_min": 0.4, "psi_max": 2.5, "tolerance": og.CRITERION_TOL}
    machine = {**criterion, "from": "machine"}
    assert design["criterion"] == criterion
    assert design["bounds_hold"] is True and design["certified"] is True

    summary = run_json(capsys, "summary", "--config", str(config), "--grid", "5")
    assert summary["criterion"] == machine and summary["factor_range"]["holds"] is True

    code, out, err = run(capsys, "certify", "--config", str(config), "--json")
    assert (code, err) == (0, "")
    certified = json.loads(out)
    assert certified["criterion"] == machine
    assert certified["status"] == "certified" and certified["margin"] >= 0.0

    sweep, row = _sweep_row(capsys, tmp_path / "sweep", "--config", str(config))
    assert sweep["criterion"] == machine
    assert (row["psi_min"], row["psi_max"]) == (0.4, 2.5) and bool(row["bounds_hold"])

    report = _report(capsys, tmp_path / "report", "--config", str(config))
    assert report["criterion"] == machine and report["transmission"]["holds"] is True
    saved = json.loads(Path(str(report["json"])).read_text())
    assert saved["machine"]["parameters"]["psi_min"] == 0.4

    # one range of factors: the design's grid, the summary, the sweep row, the report
    # and the points certify evaluated (the extremes are at the corners Q1 and Q2)
    lows = [
        design["psi_min_found"],
        summary["factor_range"]["lowest"],
        row["psi_min_reached"],
        report["transmission"]["lowest"],
        certified["attained"][0],
    ]
    highs = [
        design["psi_max_found"],
        summary["factor_range"]["highest"],
        row["psi_max_reached"],
        report["transmission"]["highest"],
        certified["attained"][1],
    ]
    np.testing.assert_allclose(lows, 5.0 / 11.0, rtol=AGREE_RTOL)  # 1 / (1 + 2 r) at Q2
    np.testing.assert_allclose(highs, 2.5, rtol=AGREE_RTOL)
    lo, hi = certified["factor_bounds"]
    assert lo <= min(lows) and max(highs) <= hi <= 2.5 + og.CRITERION_TOL

    # and the words: every command names the same criterion, every verdict is positive
    texts = {
        "design": run(capsys, *argv),
        "summary": run(capsys, "summary", "--config", str(config), "--grid", "5"),
        "certify": run(capsys, "certify", "--config", str(config)),
        "sweep": run(
            capsys, "sweep", "--out", str(tmp_path / "sweep"), "--config", str(config),
            "--grid", "5", "--requirement-grid", CUBE_GRID, "--no-progress", "--no-plot",
        ),
        "report": run(
            capsys, "report", "--out", str(tmp_path / "report"), "--config", str(config),
            "--quiet", "--resolution", "3", "--cube-resolution", CUBE_GRID,
        ),
    }  # fmt: skip
    for name, (code, out, err) in texts.items():
        assert (code, err) == (0, ""), name
        assert "[0.4, 2.5]" in out, name
    assert "certified      yes" in texts["design"][1]
    assert "holds over the cube" in texts["summary"][1]
    assert "CERTIFIED" in texts["certify"][1]
    assert "1 already done" in texts["sweep"][1] and "    yes  " in texts["sweep"][1]
    assert ": holds (not part of the motors' verdict)" in texts["report"][1]
