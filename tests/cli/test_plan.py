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


#: Largest distance of a sampled stop from where the tool stops [m] (10 m/s^2, 1 ms).
SAMPLED_STOP = 5e-6


def test_a_plunge_goes_towards_the_table(tmp_path: Path, capsys) -> None:
    """``G0 Z10`` then ``G1 Z-10``: the tool ends 20 mm nearer the table (world +e3, down)."""
    prog = tmp_path / "plunge.nc"
    prog.write_text("G61\nG0 Z10\nG1 Z-10 F600\n")  # exact stop: the reversal is not blended
    out = tmp_path / "o"
    run_json(capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out", str(out))
    with open(out / "trajectory.csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    z = [float(r["z"]) for r in rows]
    # sampled every millisecond: the stop at Z10 falls between two samples, within
    # a dt^2 / 2 = 5 um at 10 m/s^2
    assert z[-1] == pytest.approx(0.010) and min(z) == pytest.approx(-0.010, abs=SAMPLED_STOP)
    assert z[-1] - min(z) == pytest.approx(0.020, abs=SAMPLED_STOP)  # from Z10 to Z-10


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


def _raster(lines: int, feed: float) -> str:
    """A slow raster: long lines along x at ``feed`` [mm/min], 1 mm apart in y."""
    out = ["G21 G90 G64 P0.01", "G1 X-70 Y-70 F6000", f"F{feed:g}"]
    for k in range(lines):
        out += [f"G1 X{70 if k % 2 == 0 else -70}", f"G1 Y{-69 + k}"]
    return "\n".join([*out, "M2", ""])


#: A cycle of four hours and more [s].
FOUR_HOURS = 4 * 3600.0


@pytest.mark.slow
def test_a_four_hour_program_plans_and_writes_its_files(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "raster.nc"
    prog.write_text(_raster(103, 60))
    out = tmp_path / "plan"
    code, text, err = run(
        capsys, "plan", str(prog), "--max-slider-speed", "1", "--max-slider-acceleration",
        "10", "--out", str(out),
    )  # fmt: skip
    assert code == 0, err
    data = json.loads((out / "plan.json").read_text())
    assert data["cycle_time"] > FOUR_HOURS
    assert data["dt"] == pytest.approx(0.02)  # the smallest 1-2-5 step within 1 M samples
    assert data["samples"] - int(data["cycle_time"] / data["dt"]) in (1, 2)
    assert "the step follows the program" in text
    with open(out / "trajectory.csv") as fh:
        assert sum(1 for _ in fh) == data["samples"] + 2  # design line, header
    assert (out / "plan.html").stat().st_size < 1_000_000  # plotted from a light copy


def test_a_progress_bar_on_a_terminal_only(tmp_path: Path, capsys, monkeypatch) -> None:
    import sys

    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)  # a terminal
    args = ("plan", str(prog), "--max-slider-acceleration", "15", "--out", str(tmp_path / "p"))
    code, _, err = run(capsys, *args)
    assert code == 0 and "planning" in err and "blocks" in err
    code, _, err = run(capsys, *args, "--force", "--json")
    assert code == 0 and "planning" not in err  # quiet under --json
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    code, _, err = run(capsys, *args, "--force")
    assert code == 0 and "planning" not in err  # quiet off a terminal


def test_the_summary_tells_the_mode_the_overrides_and_the_stops(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text("G21\nG0 X20\nG1 Y20 F3000\nG1 X-20\nG4 P0.1\nG1 Y0\n")
    out = tmp_path / "p"
    code, text, err = run(
        capsys, "plan", str(prog), "--max-slider-speed", "1", "--max-slider-acceleration", "15",
        "--feed-override", "0.5", "--rapid-override", "0.25", "--blend", "0.05",
        "--out", str(out),
    )  # fmt: skip
    assert code == 0, err
    assert "path control: G64 P0.05 mm (blended): the default mode" in text
    assert "overrides: feed 50 %, rapid 25 %" in text
    assert "the tool stops 3 times: rapid/feed change 1, dwell 1, end 1" in text
    data = json.loads((out / "plan.json").read_text())
    assert data["stops"]["total"] == 3 and data["controller"]["blend"] == pytest.approx(5e-5)
    assert data["controller"]["feed_override"] == 0.5


@pytest.mark.parametrize(
    ("option", "value"),
    [("--feed-override", "3"), ("--rapid-override", "0"), ("--blend", "-1"), ("--dt", "0")],
)
def test_bad_controller_options_one_line(tmp_path: Path, capsys, option: str, value: str) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    out = tmp_path / "p"
    code, _, err = run(
        capsys, "plan", str(prog), "--max-slider-acceleration", "15", option, value,
        "--out", str(out),
    )  # fmt: skip
    assert code == 2 and option in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_the_torque_reserve_lowers_the_torque_the_plan_may_use(tmp_path: Path, capsys) -> None:
    from orthoglide_pin.drives.motor import load_drive

    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90\nG0 Z5\nM30\n")
    args = ("plan", str(prog), "--motor", str(example_drive_file()))
    kept = run_json(capsys, *args, "--out", str(tmp_path / "kept"))
    whole = run_json(capsys, *args, "--torque-reserve", "0", "--out", str(tmp_path / "whole"))
    peak = load_drive(str(example_drive_file())).motor.peak_torque  # type: ignore[union-attr]
    torque = {d["torque_reserve"]: d for d in (kept, whole)}
    assert set(torque) == {0.1, 0.0}
    for reserve, data in torque.items():
        row = next(r for r in data["limits"] if r["name"] == "motor_torque")
        assert row["value"] == pytest.approx((1.0 - reserve) * peak, rel=1e-12)
        assert row["peak_use"] <= 1.001
    assert kept["cycle_time"] > whole["cycle_time"]
    free = run_json(capsys, "plan", str(prog), "--max-slider-acceleration", "10", "--out",
                    str(tmp_path / "free"))  # fmt: skip
    assert free["torque_reserve"] is None  # no motor torque, no reserve


@pytest.mark.parametrize("bad", ["1", "-0.1", "nan", "inf", "ten", "1e400"])
def test_a_bad_torque_reserve_is_one_line_and_nothing_is_written(
    tmp_path: Path, capsys, bad: str
) -> None:
    prog = tmp_path / "p.nc"
    prog.write_text("G1 X10 F3000\n")
    out = tmp_path / "never"
    code, stdout, err = run(
        capsys, "plan", str(prog), "--motor", str(example_drive_file()),
        "--torque-reserve", bad, "--out", str(out),
    )  # fmt: skip
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "--torque-reserve" in err
    assert "Traceback" not in err and "from 0 to below 1" in err
    assert not out.exists()


def test_a_section_planned_slower_is_reported_in_the_summary_and_plan_json(
    tmp_path: Path, capsys, monkeypatch: pytest.MonkeyPatch
) -> None:
    import orthoglide_pin.planning.plan as plan_module

    monkeypatch.setattr(plan_module, "MAX_ROUNDS", 1)  # local tightening cut short
    prog = tmp_path / "corner.nc"
    prog.write_text("G64 P0.01\nG1 X60 F60000\nG1 X60 Y60\nG1 X0 Y60\n")
    argv = ("plan", str(prog), "--motor", str(example_drive_file()), "--dt", "0.01")
    code, out, err = run(capsys, *argv, "--out", str(tmp_path / "a"))
    assert code == 0, err
    assert re.search(r"line [23]: local tightening did not settle \(motor_torque", out)
    data = run_json(capsys, *argv, "--out", str(tmp_path / "b"))
    (fall,) = data["fallbacks"]
    assert fall["limit"] == "motor_torque" and 0.0 < fall["factor"] < 1.0
    assert json.loads((tmp_path / "b" / "plan.json").read_text())["fallbacks"] == [fall]


def test_a_four_hour_program_of_few_blocks_plans_light_files(
    tmp_path: Path, capsys, monkeypatch
) -> None:
    """Four long passes at F2: a cycle over four hours, its step chosen for it, a light page.

    The samples the step is chosen for are fewer here (the same rule as for 1 M samples).
    """
    from orthoglide_pin.planning import sampling

    monkeypatch.setattr(sampling, "MAX_SAMPLES", 20_000)
    prog = tmp_path / "slow.nc"
    passes = "\n".join(f"G1 X{70 if k % 2 == 0 else -70}\nG1 Y{-69 + k}" for k in range(4))
    prog.write_text(f"G21 G90\nG1 X-70 Y-70 F6000\nF2\n{passes}\nM2\n")
    out = tmp_path / "plan"
    code, text, err = run(capsys, "plan", str(prog), "--max-slider-speed", "1",
                          "--max-slider-acceleration", "10", "--out", str(out))  # fmt: skip
    assert code == 0, err
    data = json.loads((out / "plan.json").read_text())
    assert data["cycle_time"] > FOUR_HOURS
    assert data["dt"] == pytest.approx(1.0)  # the smallest 1-2-5 step within the samples
    assert "the step follows the program" in text
    with open(out / "trajectory.csv") as fh:
        assert sum(1 for _ in fh) == data["samples"] + 2  # design line, header
    assert (out / "plan.html").stat().st_size < 1_000_000  # plotted from a light copy
