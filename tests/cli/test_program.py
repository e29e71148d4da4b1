"""``orthoglide program``: the moves, the words ignored and every refusal, without planning."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from conftest import run, run_json
from test_docs_pages import documented_keys

MM = 1e-3

CAM = """%
O1000
(T1 D=6; flat end mill)
G90 G94 G17 G91.1 G21
T1 M6
S12000 M3
G54 G0 X10 Y5
G43 Z15 H1
G0 Z10
G1 Z-10 F300
G81 X30 Y5 Z-3 R2 F200
G80 M9
M30
"""


def _write(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_a_cam_program_with_its_tools_and_offsets(capsys, tmp_path: Path) -> None:
    prog = _write(tmp_path, "part.nc", CAM)
    tools = _write(tmp_path, "tool.tbl", "T1 P1 Z30 D6\n")
    offsets = _write(tmp_path, "offsets.var", "5221 1\n5222 2\n5223 -40\n")
    data = run_json(capsys, "program", prog, "--tool-table", tools, "--offsets", offsets)
    assert set(data) == documented_keys("program")
    assert data["refusals"] == [] and data["axes"] == [2, 1, -3]
    assert data["counts"] == {
        "rapid": 6,
        "line": 2,
        "arc": 0,
        "dwell": 0,
    }  # the cycle starts below R
    moves = data["moves"]
    assert moves[1]["end"] == pytest.approx([11 * MM, 7 * MM, 5 * MM])  # G43: 15 - 40 + 30 mm
    assert moves[0]["end"] == pytest.approx([11 * MM, 7 * MM, 0])  # G54 (1, 2) mm
    plunge = moves[3]  # G0 Z10 then G1 Z-10: 20 mm nearer the table (world +e3, down)
    assert plunge["kind"] == "line" and plunge["line"] == 10
    assert plunge["end_world"][2] - plunge["start_world"][2] == pytest.approx(20 * MM)
    assert plunge["feed"] == pytest.approx(0.005) and plunge["center"] is None
    words = {i["word"]: (i["count"], i["line"]) for i in data["ignored"]}
    assert words == {
        "O": (1, 2), "G94": (1, 4), "T": (1, 5), "M6": (1, 5), "S": (1, 6), "M3": (1, 6),
        "M9": (1, 12),
    }  # fmt: skip
    code, out, err = run(capsys, "program", prog, "--tool-table", tools)
    assert code == 0 and err == "" and "Read as written." in out
    assert "program axes X -> +e2, Y -> +e1, Z -> -e3" in out


def test_every_refusal_is_listed_and_the_status_is_2(capsys, tmp_path: Path) -> None:
    prog = _write(tmp_path, "bad.nc", "G41 D1\nG1 X1 F100\nG1 X#1\nG43 H3 Z1\n")
    code, out, err = run(capsys, "program", prog)
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("orthoglide program: error: program line 1: 3 refusals:")
    assert [line.split(":")[0] for line in out.splitlines() if line.startswith("Refused")] == [
        "Refused"
    ] * 3
    code, out, _ = run(capsys, "program", prog, "--json")
    assert code == 2 and [r["line"] for r in json.loads(out)["refusals"]] == [1, 3, 4]


def test_a_bad_tool_table_is_one_line(capsys, tmp_path: Path) -> None:
    prog = _write(tmp_path, "part.nc", "G0 X1\n")
    tools = _write(tmp_path, "tool.tbl", "T1 Z1\nT1 Z2\n")
    code, out, err = run(capsys, "program", prog, "--tool-table", tools)
    assert code == 2 and out == "" and err.count("\n") == 1 and "each tool once" in err


#: LinuxCNC's standalone interpreter, where installed.
RS274 = shutil.which("rs274")
needs_rs274 = pytest.mark.skipif(
    RS274 is None,
    reason="rs274 not found on PATH (Debian: apt-get install linuxcnc-uspace): "
    "the LinuxCNC route is not tested",
)
#: A program in LinuxCNC's language: a parameter, an expression and a subroutine.
NGC = """#100 = 5
o100 sub
  G1 X[#100 * 2] F600
o100 endsub
G0 X#100 Y0 Z0
o100 call
G2 X10 Y0 I-5 J0
M2
"""


@needs_rs274
def test_the_linuxcnc_route_reads_the_ngc_language(capsys, tmp_path: Path) -> None:
    prog = _write(tmp_path, "part.ngc", NGC)
    code, _, err = run(capsys, "program", prog)
    assert code == 2 and "needs LinuxCNC's interpreter" in err
    for interpreter in ("linuxcnc", "auto"):
        data = run_json(capsys, "program", prog, "--interpreter", interpreter)
        assert data["interpreter"] == interpreter and data["refusals"] == []
        kinds = [(m["kind"], m["line"]) for m in data["moves"]]
        assert kinds == [("rapid", 5), ("line", 3), ("arc", 7)]
        assert data["moves"][1]["end"] == pytest.approx([10 * MM, 0, 0])
        assert data["moves"][2]["turns"] == -1  # a G2 back to its start: a full circle
        assert data["moves"][2]["center"] == pytest.approx([5 * MM, 0, 0])


@needs_rs274
def test_plan_through_linuxcnc_plans_its_moves(capsys, tmp_path: Path) -> None:
    prog, out = _write(tmp_path, "part.ngc", NGC), tmp_path / "out"
    argv = ("plan", prog, "--out", str(out), "--max-slider-acceleration", "20")
    data = run_json(capsys, *argv, "--interpreter", "linuxcnc")
    assert (out / "plan.json").is_file() and data["cycle_time"] > 0.0
    code, _, err = run(capsys, *argv[:-2], "--out", str(tmp_path / "o2"), "--json")
    assert code == 2 and "needs LinuxCNC's interpreter" in err  # the built-in reader refuses


def test_without_rs274_one_line_names_what_to_install(
    capsys, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    prog = _write(tmp_path, "part.ngc", NGC)
    monkeypatch.setenv("PATH", str(tmp_path))
    for command in ("program", "plan"):
        argv = (command, prog, "--interpreter", "linuxcnc", "--out", str(tmp_path / "o"))
        code, out, err = run(capsys, *(argv if command == "plan" else argv[:4]))
        assert code == 2 and out == "" and err.count("\n") == 1
        assert "rs274" in err and "install linuxcnc-uspace" in err
    assert not (tmp_path / "o").exists()


@needs_rs274
def test_cutter_compensation_through_linuxcnc_takes_the_tool_diameter(
    capsys, tmp_path: Path
) -> None:
    text = "G21 G90 G17\nT1 M6\nG0 X-10 Y-10 Z5\nG41 D1\nG1 X0 Y0 F600\nG1 X20\nG40\nG0 X-10\nM2\n"
    prog = _write(tmp_path, "comp.nc", text)
    tools = _write(tmp_path, "tool.tbl", "T1 P1 Z0 D6\n")
    code, _, err = run(capsys, "program", prog, "--tool-table", tools)
    assert code == 2 and "cutter radius compensation G41" in err
    data = run_json(capsys, "program", prog, "--tool-table", tools, "--interpreter", "auto")
    cut = [m for m in data["moves"] if m["kind"] == "line"][-1]  # X0 to X20, 3 mm to its left
    assert cut["end"] == pytest.approx([20 * MM, 3 * MM, 5 * MM])
    assert cut["start"] == pytest.approx([0, 3 * MM, 5 * MM])
