"""The ``accuracy`` command: its figures against the API, the files it writes, its errors.

One run of the shipped contour program is shared by the module (``contour_run``).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.cli import main
from orthoglide_pin.machine.digest import design_comment

CUT = str(og.shipped_cut_file())
LIMITS = ("--max-slider-speed", "1.2", "--max-slider-acceleration", "20")
DT = 0.01
#: The lobes at the worst point are on a grid of speeds, the margin at the speed itself:
#: the lobe between two grid speeds (110 rpm apart) is nearly straight.
LOBE_GRID_RTOL = 0.03
#: The CSV's 10 significant digits.
CSV_RTOL = 1e-9
SHORT = "G21 G90 G17\nG0 X-5 Y0 Z5\nG1 Z-2 F600\nG1 X5 F1200\nG0 Z5\nM2\n"


def _close(got: Any, want: Any, where: str) -> None:
    """Equal structures, numbers within rounding."""
    if isinstance(want, dict):
        assert set(got) == set(want), where
        for key in want:
            _close(got[key], want[key], f"{where}.{key}")
    elif isinstance(want, list):
        assert len(got) == len(want), where
        for k, (a, b) in enumerate(zip(got, want, strict=True)):
            _close(a, b, f"{where}[{k}]")
    elif isinstance(want, float):
        assert got == pytest.approx(want, rel=1e-12, abs=1e-15), where
    else:
        assert got == want, where


@pytest.fixture(scope="module")
def contour_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, Any], Path]:
    """``accuracy --example contour`` with a kelvin of temperature rise, once: (JSON, DIR)."""
    out = tmp_path_factory.mktemp("accuracy") / "contour"
    argv = ["accuracy", "--example", "contour", "--cut", CUT, *LIMITS]
    argv += ["--temperature-rise", "1", "--dt", str(DT), "--out", str(out), "--json"]
    buffer, errors = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(buffer), contextlib.redirect_stderr(errors):
        code = main(argv)
    assert code == 0, errors.getvalue()
    assert errors.getvalue() == ""
    return json.loads(buffer.getvalue()), out


@pytest.fixture(scope="module")
def contour_api(params: og.OrthoglideParams) -> tuple[Any, Any]:
    """The same plan and accuracy through the API."""
    from orthoglide_pin.planning.shipped import example_program_text

    program = og.read_program(example_program_text("contour"), axes=og.design_axes(params))
    plan = og.plan_program(
        program, params, og.PlanLimits(slider_speed=1.2, slider_acceleration=20)
    )
    cut = og.read_cut_file(CUT)
    return plan, og.accuracy_along_plan(plan, cut, params, dt=DT, temperature_rise=1.0)


def test_json_matches_the_api(
    contour_run: tuple[dict[str, Any], Path], contour_api: tuple[Any, Any]
) -> None:
    data, _ = contour_run
    plan, result = contour_api
    assert data["cycle_time"] == pytest.approx(plan.cycle_time, rel=1e-12)
    expected = json.loads(json.dumps(result.summary()))
    for key, value in expected.items():
        _close(data[key], value, key)
    assert data["design"] == og.design_digest(og.prototype())
    assert data["program"] == "contour.nc" and data["spindle_speed_from"] == "cut file"
    assert data["cut"]["file"] == Path(CUT).name and len(data["cut"]["digest"]) == 16
    assert set(data["budget"]["max"]) == {"compliance", "thermal"}
    worst = data["surface_error_at"]["peak"]
    assert worst == {k: pytest.approx(v) for k, v in data["worst"].items()}


def test_stability_figures_hold_together(contour_run: tuple[dict[str, Any], Path]) -> None:
    data, _ = contour_run
    st = data["stability"]
    margins = [b["margin"] for b in st["blocks"]]
    assert st["cutting_blocks"] == len(margins) > 0
    assert st["margin_min"] == min(margins) == st["worst"]["margin"]
    assert st["unstable_blocks"] == sum(m <= 1.0 for m in margins)
    for b in st["blocks"]:
        assert b["margin"] == pytest.approx(b["limit"] / b["depth"], rel=1e-12)
    lobes = data["lobes"]
    limit = np.interp(data["spindle_speed_rpm"], lobes["speeds_rpm"], lobes["limit_depth_mm"])
    assert 1e-3 * limit / st["worst"]["depth"] == pytest.approx(
        st["worst"]["margin"], rel=LOBE_GRID_RTOL
    )
    assert lobes["point"] == pytest.approx(st["worst"]["point"])
    assert st["unconditional_limit"] == pytest.approx(1e-3 * lobes["minimum_depth_mm"])


def test_json_keys_are_documented(contour_run: tuple[dict[str, Any], Path]) -> None:
    from test_docs_pages import documented_keys

    assert set(contour_run[0]) == documented_keys("accuracy")


def test_csv_rows_and_columns(contour_run: tuple[dict[str, Any], Path]) -> None:
    data, out = contour_run
    lines = (out / "accuracy.csv").read_text().splitlines()
    assert lines[0] == design_comment(og.prototype()).rstrip("\n")
    header = lines[1].split(",")
    assert header[:4] == ["t", "x", "y", "z"] and "stability_margin" in header
    assert len(lines) - 2 == data["samples"]
    rows = [line.split(",") for line in lines[2:]]
    cutting = np.array([float(r[header.index("cutting")]) for r in rows]) != 0.0
    margin = [r[header.index("stability_margin")] for r in rows]
    assert all((m != "") == c for m, c in zip(margin, cutting, strict=True))
    gen = np.array([float(r[header.index("surface_error_generated")]) for r in rows])
    peak = gen[np.argmax(np.abs(gen))]
    assert peak == pytest.approx(data["surface_error_generated_max"], rel=CSV_RTOL)
    smallest = min(float(m) for m in margin if m)
    assert smallest == pytest.approx(data["stability"]["margin_min"], rel=CSV_RTOL)


def test_page_and_directory(contour_run: tuple[dict[str, Any], Path]) -> None:
    _, out = contour_run
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "accuracy.csv", "accuracy.html", "accuracy.json",
    ]  # fmt: skip
    html = (out / "accuracy.html").read_text()
    assert "Part accuracy of contour.nc" in html
    assert html.count("data:image/png;base64,") == 4
    for heading in ("Stability margin along the path", "Lobes at the point", "Error budget"):
        assert heading in html
    assert "http://" not in html and "https://" not in html


@pytest.mark.slow
def test_a_rerun_into_its_own_directory_needs_no_force(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    out = tmp_path / "o"
    argv = ("accuracy", str(program), "--cut", CUT, *LIMITS, "--out", str(out))
    first = run_json(capsys, *argv)
    assert first["stability"]["cutting_blocks"] >= 1 and first["program"] == "short.nc"
    again = run_json(capsys, *argv)  # the package wrote it: written again
    assert again["surface_error_peak_max"] == first["surface_error_peak_max"]


@pytest.mark.slow
def test_another_design_and_the_programs_spindle_speed(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    program = tmp_path / "short.nc"
    program.write_text(SHORT.replace("G1 Z-2 F600", "S8000 M3\nG1 Z-2 F600"))
    cut = tmp_path / "cut.yaml"
    cut.write_text(Path(CUT).read_text().replace("spindle_speed: 12000", "spindle_speed: program"))
    config = tmp_path / "design.yaml"
    config.write_text("leg_length: 0.34075\n")
    out = tmp_path / "o"
    code, text, err = run(
        capsys, "accuracy", str(program), "--cut", str(cut), *LIMITS, "--config", str(config),
        "--out", str(out),
    )  # fmt: skip
    assert code == 0 and err == ""
    assert "at 8000 rpm (program)" in text and "stability: smallest margin" in text
    assert "0.34075" in (out / "accuracy.csv").read_text().splitlines()[0]
    data = json.loads((out / "accuracy.json").read_text())
    assert data["design"] == og.design_digest(og.prototype().replace(leg_length=0.34075))
    assert data["spindle_speed_rpm"] == pytest.approx(8000.0)
    assert data["spindle_speed_from"] == "program" and data["cut"]["spindle_speed"] is None


@pytest.mark.slow
@pytest.mark.parametrize("leg_length", ["0.31", "0.34075"])
@pytest.mark.parametrize("example", ["pocket", "contour", "helix"])
def test_every_shipped_program_on_two_designs(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, example: str, leg_length: str
) -> None:
    data = run_json(
        capsys, "accuracy", "--example", example, "--cut", CUT, *LIMITS, "--param",
        f"leg_length={leg_length}", "--out", str(tmp_path / "o"),
    )  # fmt: skip
    st = data["stability"]
    assert data["cutting_samples"] > 0 and st["cutting_blocks"] > 0
    assert st["margin_min"] > 0.0 and data["surface_error_generated_max"] > 0.0
    assert data["lobes"]["point"] == pytest.approx(st["worst"]["point"])


@pytest.mark.slow
def test_simulate_gives_the_servo_term(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    drive = tmp_path / "drive.yaml"
    drive.write_text(og.example_drive_text())
    data = run_json(
        capsys, "accuracy", str(program), "--cut", CUT, "--motor", str(drive), "--simulate",
        "--out", str(tmp_path / "o"),
    )  # fmt: skip
    assert data["servo"]["max_contour_error"] > 0.0
    assert "servo" in data["budget"]["max"]
    header = (tmp_path / "o" / "accuracy.csv").read_text().splitlines()[1]
    assert header.endswith("servo_error")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((), "the following arguments are required: --cut"),
        (("--cut", CUT, "--simulate"), "--simulate"),
        (("--cut", CUT, "--temperature-rise", "warm"), "--temperature-rise"),
        (("--cut", CUT, "--temperature-rise", "1000"), "--temperature-rise"),
        (("--cut", CUT, "--dt", "nan"), "--dt"),
        (("--cut", CUT, "--model", "beam"), "invalid choice"),
        (("--cut", CUT, "--example", "pocket"), "PROGRAM.nc or --example"),
    ],
)
def test_bad_options_give_one_line_and_write_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    out = tmp_path / "o"
    code, text, err = run(capsys, "accuracy", str(program), *LIMITS, *args, "--out", str(out))
    assert code == 2 and text == ""
    assert message in err and len(err.strip().splitlines()) == 1, err
    assert err.startswith("orthoglide accuracy: error:")
    assert not out.exists()


@pytest.mark.parametrize(
    "content",
    [
        "tool: {diameter: 10, teeth: 3}\n",  # no material, a 10 m tool
        "tool: [1, 2]\nmaterial: steel\n",
        "spindle_speed: fast\n",
        "{{{",
    ],
)
def test_bad_cut_file_gives_one_line_and_writes_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, content: str
) -> None:
    bad = tmp_path / "cut.yaml"
    bad.write_text(content)
    out = tmp_path / "o"
    code, text, err = run(
        capsys, "accuracy", "--example", "pocket", "--cut", str(bad), *LIMITS, "--out", str(out)
    )
    assert code == 2 and text == "" and len(err.strip().splitlines()) == 1, err
    assert err.startswith("orthoglide accuracy: error:") and not out.exists()


def test_a_program_speed_without_s_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    cut = tmp_path / "cut.yaml"
    cut.write_text(Path(CUT).read_text().replace("spindle_speed: 12000", "spindle_speed: program"))
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    code, _, err = run(
        capsys, "accuracy", str(program), "--cut", str(cut), *LIMITS, "--out", str(tmp_path / "o")
    )
    assert code == 2 and "an S word in the program" in err
    assert not (tmp_path / "o").exists()


def test_a_directory_it_did_not_write_is_kept(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "o"
    out.mkdir()
    (out / "mine.txt").write_text("keep")
    code, _, err = run(capsys, "accuracy", "--example", "contour", "--cut", CUT, *LIMITS,
                       "--out", str(out))  # fmt: skip
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]


def test_spindle_speed_rpm_is_the_cut_files(contour_run: tuple[dict[str, Any], Path]) -> None:
    data, _ = contour_run
    assert data["spindle_speed_rpm"] == pytest.approx(12000.0)
    assert data["spindle_speed"] == pytest.approx(12000.0 * 2.0 * math.pi / 60.0)


@pytest.mark.parametrize("path", ["", "missing.yaml", "."])
def test_a_cut_file_that_is_not_one_is_named(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch, path: str
) -> None:
    monkeypatch.chdir(tmp_path)
    code, text, err = run(
        capsys, "accuracy", "--example", "pocket", "--cut", path, *LIMITS, "--out", "o"
    )
    assert code == 2 and text == "" and len(err.strip().splitlines()) == 1, err
    assert "cut file" in err and not (tmp_path / "o").exists()


def _calibration(tmp_path: Path, params: og.OrthoglideParams) -> Path:
    nominal = og.GeometricModel.nominal(params.leg_length)
    calibration = og.Calibration(nominal, nominal, np.full(18, 1e-5), 1e-6, 1e-4, 1e-5, (), (),
                                 30, "0" * 64, design=og.design_digest(params))  # fmt: skip
    path = tmp_path / "calibration.yaml"
    og.write_calibration(path, calibration)
    return path


def test_a_calibration_of_another_design_is_refused_before_any_work(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    calibration = _calibration(tmp_path, og.prototype())
    code, _, err = run(
        capsys, "accuracy", "--example", "contour", "--cut", CUT, *LIMITS, "--calibration",
        str(calibration), "--param", "leg_length=0.3", "--out", str(tmp_path / "o"),
    )  # fmt: skip
    assert code == 2 and "was made for design" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_a_calibration_gives_the_geometric_term(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    calibration = _calibration(tmp_path, og.prototype())
    data = run_json(
        capsys, "accuracy", str(program), "--cut", CUT, *LIMITS, "--calibration",
        str(calibration), "--out", str(tmp_path / "o"),
    )  # fmt: skip
    assert data["budget"]["max"]["geometric"] > 0.0
    assert data["calibration"] == str(calibration)


def test_the_command_report_and_sweep_agree(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """``accuracy`` (no --motor: the default drive train), the report's and the sweep's routes."""
    from dataclasses import asdict

    from orthoglide_pin._io import read_yaml_mapping
    from orthoglide_pin.report.accuracy import accuracy_dict, accuracy_section
    from orthoglide_pin.sweep.accuracy import accuracy_metrics

    program = tmp_path / "short.nc"
    program.write_text(SHORT)
    data = run_json(
        capsys, "accuracy", str(program), "--cut", CUT, *LIMITS, "--out", str(tmp_path / "o")
    )
    train = og.Drive().train
    assert data["drive_train"] == asdict(train) and not data["limits"]["motor"]
    assert (data["limits"]["slider_speed"], data["limits"]["slider_acceleration"]) == (1.2, 20)
    params = og.prototype()
    plan = og.plan_program(
        og.read_program(SHORT, axes=og.design_axes(params)), params, og.PlanLimits(1.2, 20.0)
    )
    cut = og.read_cut_file(CUT)
    report = accuracy_dict(accuracy_section(params, cut, plan, drive=og.Drive()))
    design = {"drive": asdict(train), "cut": {"conditions": read_yaml_mapping(CUT, "cut")}}
    swept = accuracy_metrics(params, plan, {**design, "program": {"text": SHORT}})
    surface = data["surface_error_generated_max"]
    margin = data["stability"]["margin_min"]
    assert abs(report["surface_error"]["generated"]["max"]) == pytest.approx(surface, rel=1e-12)
    assert swept["surface_error_max"] == pytest.approx(surface, rel=1e-12)
    assert report["stability"]["min"] == pytest.approx(margin, rel=1e-12)
    assert swept["stability_margin_min"] == pytest.approx(margin, rel=1e-12)
    assert report["stability"]["line"] == data["stability"]["worst"]["line"]
