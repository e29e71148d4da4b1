"""The pages say what the code does: their examples run, their tables match the package.

* The Python examples of every page of ``docs/`` and of the README run as
  written, the blocks of a page one after the other in one namespace.
* The tables of ``docs/reference/formats.md`` list exactly the keys of each
  command's JSON output and the columns of the files it writes.
* The plausible ranges, the layers' tiers and the documented size limits are
  those of the code.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import importlib.util
import io
import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from conftest import run_json
from test_layers import TIERS

import orthoglide_pin as og
from orthoglide_pin.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [*sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts), ROOT / "README.md"]
FORMATS = DOCS / "reference" / "formats.md"
JACOBIAN_TOL = 1e-9


def python_blocks(path: Path) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", path.read_text(), flags=re.DOTALL | re.MULTILINE)


def _page_id(path: Path) -> str:
    return str(path.relative_to(ROOT))


@pytest.mark.parametrize("page", [p for p in PAGES if python_blocks(p)], ids=_page_id)
def test_python_examples_run(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, Any] = {}
    for block in python_blocks(page):
        exec(compile(block, str(page), "exec"), namespace)
    if page.name == "kinematics.md":  # the tour's claims hold
        model, assembly = namespace["model"], namespace["assembly"]
        assert model.constraint_rank(assembly.q) == 15
        assert model.mobility(assembly.q) == 3
        expected = og.jacobian(namespace["points"][1], namespace["L"])
        assert np.max(np.abs(model.jacobian(assembly.q) - expected)) < JACOBIAN_TOL


def test_the_examples_that_make_claims_are_tested() -> None:
    pages = {p.name for p in PAGES if python_blocks(p)}
    assert {"kinematics.md", "machine.md", "design.md", "dynamics.md"} <= pages


# ------------------------------------------------------------------ tables
def _tables_under(text: str, heading: str) -> str:
    """The text of a section (up to the next heading of the same or a higher level)."""
    level = len(heading) - len(heading.lstrip("#"))
    start = text.index(heading + "\n")
    rest = text[start + len(heading) + 1 :]
    ends = [m.start() for m in re.finditer(f"^#{{1,{level}}} ", rest, re.MULTILINE)]
    return rest[: ends[0]] if ends else rest


def _first_column_names(section: str) -> set[str]:
    """Names in the first column of the tables of a section (``name_1..3`` expanded)."""
    out: set[str] = set()
    for line in section.splitlines():
        if not line.startswith("| `"):
            continue
        cell = line.split("|")[1]
        for name in re.findall(r"`([^`]+)`", cell):
            match = re.fullmatch(r"(\w+)_1\.\.3", name)
            out |= {f"{match.group(1)}_{i}" for i in (1, 2, 3)} if match else {name}
    return out


def _first_table(section: str) -> str:
    lines = section.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("|"))
    end = next((i for i in range(start, len(lines)) if not lines[i].startswith("|")), len(lines))
    return "\n".join(lines[start:end])


def documented_keys(command: str) -> set[str]:
    """The keys of the first table of the command's section (its JSON output)."""
    section = _tables_under(FORMATS.read_text(), f"### `orthoglide {command}`")
    return _first_column_names(_first_table(section))


JSON_COMMANDS = {
    "ik": ["ik", "0.05", "0", "0.02"],
    "fk": ["fk", "0", "0", "0"],
    "jacobian": ["jacobian", "0.05", "0", "0"],
    "indices": ["indices", "0.05", "0", "0"],
    "summary": ["summary"],
    "stiffness": ["stiffness", "0", "0", "0"],
    "dynamics": ["dynamics", "--point", "0", "0", "0", "--velocity", "1", "0", "0"],
    "certify": ["certify", "--psi", "0.49", "2.01"],  # the prototype, certified (exit 0)
    "design": ["design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "11"],
    "sensitivity": ["sensitivity", "0.05", "0", "0.02"],
}


@pytest.mark.parametrize("command", sorted(JSON_COMMANDS))
def test_json_keys_are_documented(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, *JSON_COMMANDS[command])
    assert set(data) == documented_keys(command)


def test_json_keys_of_commands_that_write_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    urdf = run_json(capsys, "urdf", "-o", str(tmp_path / "m.urdf"))
    assert set(urdf) == documented_keys("urdf")
    mjcf = run_json(capsys, "mjcf", "-o", str(tmp_path / "m.xml"))
    assert set(mjcf) == documented_keys("mjcf")
    view = run_json(capsys, "view", "--static", str(tmp_path / "v.html"))
    assert set(view) == documented_keys("view")
    out = tmp_path / "map.png"
    found = run_json(
        capsys, "map", "--out", str(out), "--csv", str(tmp_path / "m.csv"), "--resolution", "5"
    )
    assert set(found) == documented_keys("map")
    with open(tmp_path / "m.csv") as f:
        header = next(csv.reader(f))
    section = _tables_under(FORMATS.read_text(), "## Map CSV")
    assert set(header) == set(re.findall(r"`(\w+)`", section.split(" Indices")[0]))


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, Any], Path]:
    """A small report with motor data (every column), and its ``--json`` output."""
    out = tmp_path_factory.mktemp("report") / "r"
    args = ["report", "--out", str(out), "--resolution", "3", "--cube-resolution", "2"]
    args += ["--motor", str(og.example_drive_file()), "--quiet", "--json"]
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(args) == 0
    return json.loads(buf.getvalue()), out


def _csv_header(path: Path) -> list[str]:
    with open(path) as f:  # after the design line of a file that belongs to one machine
        return next(csv.reader(line for line in f if not line.startswith("#")))


def test_report_files_are_documented(report: tuple[dict[str, Any], Path]) -> None:
    data, out = report
    assert set(data) == documented_keys("report")
    text = FORMATS.read_text()
    section = _tables_under(text, "## Report directory")
    files = _first_column_names(section.split("In the CSV files")[0])
    assert files == {p.name for p in out.iterdir()}
    tables = re.split(r"^`(\w+\.csv)`.*:$", section, flags=re.MULTILINE)
    documented = {tables[i]: _first_column_names(tables[i + 1]) for i in range(1, len(tables), 2)}
    assert set(_csv_header(out / "summary.csv")) == documented["summary.csv"]
    assert set(_csv_header(out / "cycle.csv")) == documented["cycle.csv"]
    assert set(_csv_header(out / "vibration.csv")) == documented["vibration.csv"]
    cube = documented["maps.csv"] - {"slice"}
    assert set(_csv_header(out / "cube.csv")) == cube
    assert set(_csv_header(out / "maps.csv")) == cube | {"slice"}
    report_json = json.loads((out / "report.json").read_text())
    sections = re.findall(r"`(\w+)`", section.split("`report.json` has the sections")[1])
    assert set(report_json) <= set(sections)


def test_sweep_files_are_documented(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("pandas")
    out = tmp_path / "sw"
    data = run_json(
        capsys, "sweep", "--leg-length", "0.3,0.31", "--grid", "3", "--requirement-grid", "2",
        "--out", str(out), "--no-progress",
    )  # fmt: skip
    assert set(data) == documented_keys("sweep")
    section = _tables_under(FORMATS.read_text(), "## Sweep directory")
    files, columns = section.split("The table's columns")
    names = _first_column_names(files)
    assert {p.name for p in out.iterdir()} == {n.split("/")[0] for n in names}
    settings = json.loads((out / "sweep.json").read_text())
    described = files.split("the sweep's settings:")[1].split("|")[0]
    assert set(settings) == set(re.findall(r"`(\w+)`", described))
    header = set(_csv_header(out / "results.csv"))
    # the one swept quantity (the "swept quantities" row) and the documented metrics
    assert header == _first_column_names(columns) | {"leg_length"}


# ------------------------------------------------------------------ numbers
def _number(text: str) -> float:
    return float(text.replace(" ", ""))


def test_the_plausible_ranges_are_those_of_the_code() -> None:
    text = (DOCS / "guide" / "machine.md").read_text()
    rows = re.findall(r"^\| (.+?) \| (\S+) to (\S+) \| (\S+) \|$", text, re.MULTILINE)
    seen = set()
    for names, low, high, unit in rows:
        for name in re.findall(r"`(\w+)`", names):
            key = "lead" if "ball-screw" in names else name
            if key == "lead":
                continue  # the drive file's lead, checked by the drives' own tests
            lo, hi, unit_ = og.PLAUSIBLE_RANGES[key]
            assert (_number(low), _number(high), unit) == (lo, hi, unit_), key
            seen.add(key)
    assert seen == set(og.PLAUSIBLE_RANGES)


def test_the_architecture_page_has_the_tiers_of_the_code() -> None:
    text = (DOCS / "architecture.md").read_text()
    rows = re.findall(r"^\| (\d) \| (.+?) \|", text, re.MULTILINE)
    documented = {
        name: int(tier) for tier, names in rows for name in re.findall(r"`(\w+)`", names)
    }
    assert documented == TIERS


def test_the_documented_size_limits_are_those_of_the_code() -> None:
    from orthoglide_pin.cli import design as cli_design
    from orthoglide_pin.kinetostatics import design, workspace
    from orthoglide_pin.motion import trajectory
    from orthoglide_pin.report import assemble
    from orthoglide_pin.report import stiffness as report_stiffness
    from orthoglide_pin.report import vibration as report_vibration
    from orthoglide_pin.sweep import spec
    from orthoglide_pin.viewer import animation, overlays

    text = " ".join((DOCS / "reference" / "errors.md").read_text().split())
    cube_edge = int(workspace.MAX_GRID_POINTS ** (1 / 3) + 1e-9)
    slice_edge = int(workspace.MAX_GRID_POINTS**0.5 + 1e-9)
    expected = [
        f"at most {workspace.MAX_GRID_POINTS // 1_000_000} M points: {cube_edge} per edge "
        f"of a cube, {slice_edge} per side of a slice",
        f"`map --resolution` up to {cli_design.MAX_RESOLUTION}",
        f"`report --resolution` up to {assemble.MAX_RESOLUTION} per slice",
        f"`report --cube-resolution` up to {assemble.MAX_CUBE_RESOLUTION} per edge",
        f"caps its own grids at {report_stiffness.MAX_RESOLUTION} and "
        f"{report_stiffness.MAX_CUBE_RESOLUTION}, its vibration section at "
        f"{report_vibration.MAX_CUBE_RESOLUTION} per edge",
        f"`design --grid` up to {design.MAX_VERIFY_POINTS}",
        f"`sweep --grid` up to {spec.MAX_GRID} and `--requirement-grid` up to "
        f"{spec.MAX_REQUIREMENT_GRID}",
        f"ellipsoid grids up to {overlays.MAX_GRID_EDGE} per edge, {overlays.MAX_ELLIPSOIDS} "
        f"ellipsoids in all; animations up to {animation.MAX_FRAMES} frames",
        f"up to {trajectory.MAX_SAMPLES // 1_000_000} M samples",
    ]
    assert [e for e in expected if e not in text] == []


def test_every_command_has_its_json_output_documented() -> None:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    text = FORMATS.read_text()
    assert [c for c in sub.choices if f"### `orthoglide {c}`" not in text] == []


#: A short program of the subset: a blended corner, an arc, a dwell.
PROGRAM = "G21 G90 G64 P0.01\nG1 X20 F3000\nG1 Y20\nG2 X40 Y0 I0 J-20\nG4 P0.1\nM30\n"


def test_plan_files_are_documented(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    program = tmp_path / "p.nc"
    program.write_text(PROGRAM)
    out = tmp_path / "plan"
    args = ["plan", str(program), "--motor", str(og.example_drive_file()), "--out", str(out)]
    data = run_json(capsys, *args)
    assert set(data) == documented_keys("plan")
    assert set(json.loads((out / "plan.json").read_text())) == documented_keys("plan") - {
        "directory",
        "linuxcnc",
    }
    section = _tables_under(FORMATS.read_text(), "## Plan directory")
    files = _first_column_names(_first_table(section))
    csv_files = files - {"trajectory.parquet"}  # written instead with --trajectory-format
    assert {p.name for p in out.iterdir()} == csv_files | {".orthoglide-output"}
    columns = _first_table(section.split("`trajectory.csv` (SI units")[1])
    assert set(_csv_header(out / "trajectory.csv")) == _first_column_names(columns)
    if importlib.util.find_spec("pyarrow") is not None:
        other = tmp_path / "parquet"
        run_json(capsys, *args[:-1], str(other), "--trajectory-format", "parquet")
        names = {p.name for p in other.iterdir()}
        assert names == files - {"trajectory.csv"} | {".orthoglide-output"}


def test_simulation_files_are_documented(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    pytest.importorskip("mujoco")
    program = tmp_path / "p.nc"
    program.write_text("G21 G90\nG1 X10 F3000\nG0 X0\nM30\n")
    out = tmp_path / "sim"
    args = ["simulate", str(program), "--motor", str(og.example_drive_file()), "--out", str(out)]
    data = run_json(capsys, *args)
    assert set(data) == documented_keys("simulate")
    saved = json.loads((out / "simulation.json").read_text())
    assert set(saved) == documented_keys("simulate") - {"directory"}
    section = _tables_under(FORMATS.read_text(), "## Simulation directory")
    files = _first_column_names(_first_table(section))
    assert {p.name for p in out.iterdir()} == files | {".orthoglide-output"}
    columns = _first_table(section.split("`simulation.csv` (SI units")[1])
    assert set(_csv_header(out / "simulation.csv")) == _first_column_names(columns)


def _measurements(path: Path, count: int = 30) -> None:
    """A built machine off its drawing, measured at planned poses with tracker noise."""
    rng = np.random.default_rng(3)
    params = og.prototype()
    drawing = og.GeometricModel.nominal(params.leg_length)
    errors = rng.normal(0.0, [2e-4, 2e-4, 2e-4, 5e-4, 5e-4, 1e-4] * 3)
    built = og.GeometricModel.from_vector(drawing.vector() + errors)
    q = og.plan_poses(params, count).q
    rows = np.column_stack([q, built.direct_kinematics(q) + rng.normal(0.0, 5e-6, q.shape)])
    path.write_text("q1,q2,q3,x,y,z\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))


def test_calibration_files_are_documented(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    text = FORMATS.read_text()
    measurements = tmp_path / "m.csv"
    _measurements(measurements)
    measured = _first_column_names(_first_table(_tables_under(text, "## Measurement CSV")))
    assert measured == set(_csv_header(measurements))
    out = tmp_path / "cal"
    data = run_json(capsys, "calibrate", str(measurements), "--out", str(out))
    assert set(data) == documented_keys("calibrate")
    section = _tables_under(text, "## Calibration directory")
    assert {p.name for p in out.iterdir()} == _first_column_names(_first_table(section)) | {
        ".orthoglide-output"
    }
    tables = section.split("`calibration.yaml` (SI units")[1].split("`residuals.csv`:")
    saved = yaml.safe_load((out / "calibration.yaml").read_text())
    assert set(saved) == _first_column_names(_first_table(tables[0]))
    assert set(_csv_header(out / "residuals.csv")) == _first_column_names(_first_table(tables[1]))
    plan = tmp_path / "poses"
    data = run_json(capsys, "calibrate", "--plan", "20", "--out", str(plan))
    described = _tables_under(text, "### `orthoglide calibrate`").split("--plan N --out DIR")[1]
    assert set(data) == set(re.findall(r"`(\w+)`", described.split(")", 1)[1]))
    rows = _first_table(_tables_under(text, "## Measurement plan")).splitlines()[2:]
    for row in rows:
        name, columns = row.split("|")[1:3]
        header = _csv_header(plan / name.strip().strip("`"))
        assert set(header) == set(re.findall(r"`(\w+)`", columns)) - {"m", "rad"}


def test_the_cut_file_ranges_are_those_of_the_code() -> None:
    from orthoglide_pin.machining._checks import RANGES

    section = _tables_under((DOCS / "reference" / "errors.md").read_text(), "### Cut files")
    rows = re.findall(
        r"^\| (.+?) \| (\S+) to (\S+)(?: \(.*?\))? \| (\S+) \|", section, re.MULTILINE
    )
    seen = set()
    for names, low, high, unit in rows:
        for name in re.findall(r"`(\w+)`", names):
            lo, hi, unit_, _ = RANGES[name]
            assert _number(low) == pytest.approx(lo, rel=1e-4), name
            assert _number(high) == pytest.approx(hi, rel=1e-4), name
            assert unit == unit_, name
            seen.add(name)
    assert seen == set(RANGES) - {"spindle_speed_rad"}
