"""``orthoglide plan``: outputs of a program, examples, and bad programs (one line, exit 2)."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.drives.motor import RPM_PER_RAD_S
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning.sampling import COLUMNS

pytest.importorskip("toppra")

PROGRAM = "G21 G90 G64 P0.02\nG0 X20 Y0 Z0\nG1 Y20 F6000\nG1 X-20\nG4 P0.1\nG2 X-20 Y20 I10\nM2\n"
DT = 0.002


def test_plan_writes_its_files_and_prints_the_summary(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    out = tmp_path / "plan"
    data = run_json(
        capsys, "plan", str(prog), "--motor", str(example_drive_file()),
        "--max-slider-acceleration", "15", "--dt", str(DT), "--out", str(out),
    )  # fmt: skip
    assert {"cycle_time", "blocks", "length", "limits", "binding", "per_block"} <= set(data)
    assert data["blocks"] == 5 and data["length"] > 0.08
    names = {row["name"] for row in data["limits"]}
    assert {"slider_acceleration", "motor_torque", "motor_speed", "feed"} <= names
    assert all(row["peak_use"] <= 1.001 for row in data["limits"])
    lines = [b["line"] for b in data["per_block"]]
    assert lines == [2, 3, 4, 5, 6]
    dwell = data["per_block"][3]
    assert dwell["end"] - dwell["start"] == pytest.approx(0.1)
    assert data["per_block"][-1]["end"] == pytest.approx(data["cycle_time"])
    with open(out / "trajectory.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][0] == f"# orthoglide design: {og.design_digest()}"  # the machine
    rows = rows[1:]
    assert tuple(rows[0]) == COLUMNS
    times = [float(r[0]) for r in rows[1:]]
    assert times[1] == pytest.approx(DT) and times[-1] == pytest.approx(data["cycle_time"])
    html = (out / "plan.html").read_text()
    assert "data:image/png;base64," in html and "http" not in html.replace("http-equiv", "")
    assert json.loads((out / "plan.json").read_text())["cycle_time"] == data["cycle_time"]


def test_the_terminal_and_the_page_show_the_same_values_in_the_same_units(
    tmp_path: Path, capsys
) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    out = tmp_path / "plan"
    code, text, err = run(
        capsys, "plan", str(prog), "--motor", str(example_drive_file()),
        "--max-slider-speed", "0.5", "--max-slider-acceleration", "15",
        "--dt", str(DT), "--out", str(out),
    )  # fmt: skip
    assert code == 0 and err == ""
    html = (out / "plan.html").read_text()
    values = {r["name"]: r["value"] for r in json.loads((out / "plan.json").read_text())["limits"]}
    shown = [
        "500 mm/s",
        "15 m/s^2",
        f"{values['motor_torque']:.4g} N.m",
        f"{values['motor_speed'] * RPM_PER_RAD_S:.4g} rpm",  # rad/s in the JSON
        "F up to 6000 mm/min",
    ]
    for value in shown:
        assert value in text and f"<td>{value}</td>" in html
    peaks = re.search(r"peak feed (\d+) mm/min, peak slider speed [\d.]+ mm/s", text)
    assert peaks is not None and peaks.group(0) in html
    with open(out / "trajectory.csv") as fh:  # its first line records the design
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        feed = max(float(r["path_speed"]) for r in rows)
    assert int(peaks.group(1)) == round(6e4 * feed)  # the CSV in m/s, the words in mm/min
    assert "rad/s" not in html and "rad/s" not in text


def test_without_a_drive_there_are_no_torque_columns(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text("G1 X10 F3000\n")
    out = tmp_path / "o"
    run_json(capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out))
    header = (out / "trajectory.csv").read_text().splitlines()[1].split(",")
    assert header == list(COLUMNS[:-3])


def test_a_plunge_goes_towards_the_table(tmp_path: Path, capsys) -> None:
    """``G0 Z10`` then ``G1 Z-10``: the tool ends 20 mm nearer the table (world +e3, down)."""
    prog = tmp_path / "plunge.nc"
    prog.write_text("G0 Z10\nG1 Z-10 F600\n")
    out = tmp_path / "o"
    run_json(capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out))
    with open(out / "trajectory.csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    z = [float(r["z"]) for r in rows]
    assert z[-1] == pytest.approx(0.010) and min(z) == pytest.approx(-0.010)
    assert z[-1] - min(z) == pytest.approx(0.020)  # from Z10 (above the part) to Z-10


def test_example_prints_a_program(capsys) -> None:
    code, out, err = run(capsys, "plan", "--example", "helix")
    assert code == 0 and err == "" and "G2" in out and out.startswith("%")


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("G1 X10 F3000\nG1 X10 Y10 G41\n", "program line 2: cutter radius compensation G41"),
        ("G1 X10 F3000\nG1 X200\n", "program line 2: the point"),
        ("G1 X10\n", "program line 1: G1 without a feed"),
    ],
)
def test_a_bad_program_is_one_line_and_nothing_is_written(
    tmp_path: Path, capsys, text: str, needle: str
) -> None:
    prog = tmp_path / "bad.nc"
    prog.write_text(text)
    out = tmp_path / "never"
    code, stdout, err = run(
        capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out)
    )
    assert code == 2 and stdout == ""
    assert err.count("\n") == 1 and needle in err
    assert not out.exists()


def test_a_program_without_any_limit_is_refused(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "p.nc"
    prog.write_text("G0 X10\n")
    code, _, err = run(capsys, "plan", str(prog), "--out", str(tmp_path / "o"))
    assert code == 2 and "no limit bounds this move's acceleration" in err


@pytest.mark.parametrize(
    ("data", "needle"),
    [
        (b"G1 X10 F100\nG2 X0 Y10 I-10 J1\n", "program line 2: arc radius"),
        (b"G1 X1 F0\n", "program line 1: feed F0: it must be > 0"),
        (b"", "program line 1: the program has no move and no dwell"),
        (b"(a comment)\n%\n", "program line 2: the program has no move and no dwell"),
        (b"G1 X10 F600\n\xff\xfe G1 Y2\n", "expected a UTF-8 text file"),
        (b"G1 X10 F3000\nG1 X10 Y10 Z95\n", "program line 2: the point"),  # 95 mm up
    ],
)
def test_hostile_programs_leave_the_output_untouched(
    tmp_path: Path, capsys, data: bytes, needle: str
) -> None:
    prog = tmp_path / "bad.nc"
    prog.write_bytes(data)
    fresh = tmp_path / "never"
    kept = tmp_path / "kept"
    kept.mkdir()
    (kept / "mine.txt").write_text("the user's file\n")
    for out, extra in ((fresh, ()), (kept, ("--force",))):
        code, stdout, err = run(
            capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out), *extra
        )
        assert code == 2 and stdout == "" and err.count("\n") == 1 and needle in err, err
    assert not fresh.exists()
    assert sorted(p.name for p in kept.iterdir()) == ["mine.txt"]
    assert (kept / "mine.txt").read_text() == "the user's file\n"


def test_a_directory_as_the_program_is_refused(tmp_path: Path, capsys) -> None:
    out = tmp_path / "never"
    code, stdout, err = run(
        capsys, "plan", str(tmp_path), "--max-slider-acceleration", "10", "--out", str(out)
    )
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "directory" in err
    assert not out.exists()


def test_a_jerk_limit_reports_its_time_cost_and_a_jerk_figure(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text("G64\nG1 X20 F6000\nG3 X30 Y10 I0 J10\n")  # tangent: blended, no stop
    out = tmp_path / "plan"
    args = ["plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out)]
    data = run_json(capsys, *args, "--max-slider-jerk", "300")
    rows = {row["name"]: row for row in data["limits"]}
    assert rows["slider_jerk"]["value"] == 300.0 and rows["slider_jerk"]["peak_use"] <= 1.001
    cost = data["jerk_time_cost"]
    assert cost["with_jerk"] == data["cycle_time"] and cost["curvature_stops"] == 0
    assert cost["ratio"] == pytest.approx(cost["with_jerk"] / cost["second_order"])
    second = run_json(capsys, *args, "--force")
    assert second["jerk_time_cost"] is None
    assert second["cycle_time"] == pytest.approx(cost["second_order"], rel=1e-9)
    run_json(capsys, *args, "--force", "--max-slider-jerk", "300")
    assert "Slider jerks" in (out / "plan.html").read_text()


@pytest.mark.parametrize("bad", ["0", "-3", "nan", "inf", "fast"])
def test_a_bad_jerk_is_one_line_and_nothing_is_written(tmp_path: Path, capsys, bad: str) -> None:
    prog = tmp_path / "p.nc"
    prog.write_text("G1 X10 F3000\n")
    out = tmp_path / "never"
    code, stdout, err = run(
        capsys, "plan", str(prog), "--max-slider-acceleration", "10",
        "--max-slider-jerk", bad, "--out", str(out),
    )  # fmt: skip
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "--max-slider-jerk" in err
    assert not out.exists()
