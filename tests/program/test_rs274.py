"""LinuxCNC's ``rs274`` as a reader of part programs (skipped where it is not installed)."""

from __future__ import annotations

import itertools
import os
import re
import stat
from pathlib import Path

import numpy as np
import pytest
from program._support import CORPUS, CORPUS_PROGRAMS, CORPUS_REFUSED, CORPUS_TOOLS

from orthoglide_pin.exceptions import InvalidParameterError, MissingExecutableError, ProgramError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.program import Move, read_rs274, read_rs274_text
from orthoglide_pin.program.canon import CanonState
from orthoglide_pin.program.compare import PRINTED_TOL
from orthoglide_pin.program.modes import DEFAULT_TOLERANCE
from orthoglide_pin.program.offsets import make_setup
from orthoglide_pin.program.reader import read_moves
from orthoglide_pin.program.rs274 import find_rs274, numbered

#: Least number of programs of the corpus (with the one LinuxCNC refuses).
MIN_PROGRAMS = 20
#: Least number of repositories the corpus comes from.
MIN_REPOSITORIES = 3
#: LinuxCNC's tolerance on an arc's radius mismatch, at most [m] (0.05 mm and 0.1 % of
#: the radius, as its interpreter allows for centre-format arcs).
RADIUS_TOL = 0.05e-3 + 1e-6

#: A program in the NGC language: parameters, an expression, a subroutine, G18.
NGC = """\
%
G21 G17 G90 (a; comment)
#1 = 10
o100 sub
  G1 X[#1 * 2] Y#2 F600
o100 endsub
G0 X0 Y0 Z5
o100 call [10] [3]
G18 G2 X0 Z5 I-10 K0
G4 P0.25
M2
%
"""


def test_numbered_sets_every_lines_n_word() -> None:
    text = "%\nG0 X1\n/ N0010 G1 X2\nn5G1 X3\n  o100 sub\n%"
    assert numbered(text) == "%\nN2 G0 X1\n/ N3 G1 X2\nN4 G1 X3\n  N5 o100 sub\n%"


def test_numbering_keeps_lines_linuxcnc_reads_within_its_length() -> None:
    long = "G0 X1 (" + "a" * 244 + ")"  # 252 characters: fits, but not with "N2 "
    too_long = "G0 X1 (" + "a" * 250 + ")"
    assert numbered(f"G21\n{long}\n{too_long}") == f"N1 G21\n{long}\nN3 {too_long}"


def test_missing_rs274_names_the_debian_package(tmp_path: Path) -> None:
    with pytest.raises(MissingExecutableError, match="install linuxcnc-uspace") as info:
        find_rs274(tmp_path / "no-such-rs274")
    assert isinstance(info.value, FileNotFoundError) and "\n" not in str(info.value)


def test_an_interpreter_that_stops_silently_is_a_program_error(tmp_path: Path) -> None:
    fake = tmp_path / "rs274"
    fake.write_text("#!/bin/sh\nexit 3\n", encoding="ascii")
    fake.chmod(0o700)
    with pytest.raises(ProgramError, match="stopped without a message"):
        read_rs274_text("G0 X1\n", executable=fake)


def test_bad_offsets_and_tools_are_refused(rs274: str) -> None:
    with pytest.raises(InvalidParameterError, match="work_offsets"):
        read_rs274_text("G0 X1\n", work_offsets={"G60": (0.0, 0.0, 0.0)})
    with pytest.raises(InvalidParameterError, match="tools"):
        read_rs274_text("G0 X1\n", tools={0: (0.01,)})
    with pytest.raises(InvalidParameterError, match="finite"):
        read_rs274_text("G0 X1\n", tools={1: (float("nan"),)})


def test_ngc_language_lines_and_geometry(rs274: str) -> None:
    moves = read_rs274_text(NGC)
    assert [(m.line, m.kind) for m in moves] == [
        (7, "rapid"), (5, "line"), (9, "arc"), (10, "dwell"),
    ]  # fmt: skip
    line, arc = moves[1], moves[2]
    assert np.allclose(line.end, [0.02, 0.003, 0.005]) and line.feed == pytest.approx(0.01)
    assert np.allclose(arc.center, [0.01, 0.003, 0.005], atol=PRINTED_TOL)
    assert np.allclose(arc.normal, [0, 1, 0]) and arc.turns == -1
    assert moves[3].dwell == 0.25


def test_offsets_and_tool_length_give_machine_coordinates(rs274: str) -> None:
    program = "G21 G55 T2 M6 G43 H2\nG0 X1 Y2 Z3\nG92 X0\nG1 X1 F60\nM2\n"
    offsets = {"G55": (0.1, -0.2, 0.05)}
    moves = read_rs274_text(program, work_offsets=offsets, tools={2: (0.04, 0.006)})
    rapid, feed = moves
    assert np.allclose(rapid.start, 0.0)  # rs274 starts at the machine origin
    assert np.allclose(rapid.end, [0.101, -0.198, 0.093], atol=PRINTED_TOL)
    assert np.allclose(feed.end, [0.102, -0.198, 0.093], atol=PRINTED_TOL)


def test_inch_programs_are_converted(rs274: str) -> None:
    (rapid,) = read_rs274_text("G20 G0 X1 Y-2 Z0.5\nM2\n")
    assert np.allclose(rapid.end, np.array([1.0, -2.0, 0.5]) * 0.0254)


#: Path control in both readers' language: before any mode, G61, G64 P (mm and inch),
#: G61.1, and an arc under G64.
MODES = (
    "G21 G90\nG1 X10 F600\nG61\nG1 X20 Y5\nG64 P0.05\nG1 X30\nG1 X30 Y10\n"
    "G20\nG64 P0.002\nG1 X1.5\nG61.1\nG1 X1 Y1\nG64\nG2 X2 Y1 I0.5 J0\nM2\n"
)


def test_path_control_is_read_as_the_built_in_reader_reads_it(rs274: str) -> None:
    """G61, G61.1 and G64 P through LinuxCNC: the built-in reader's tolerances and first line."""
    state = CanonState()
    moves = read_rs274_text(MODES, state=state)
    builtin = read_moves(MODES, make_setup())
    assert [m.line for m in moves] == [m.line for m in builtin.moves]
    assert state.mode_line == builtin.mode_line == 3
    assert state.tolerances == pytest.approx(list(builtin.tolerances), abs=PRINTED_TOL)
    assert state.tolerances[:2] == [None, None]  # the default, then G61
    assert state.tolerances[2] == pytest.approx(0.05e-3)
    assert state.tolerances[4] == pytest.approx(0.002 * 0.0254)
    assert state.tolerances[-1] == DEFAULT_TOLERANCE  # G64 without P
    planned = read_program(MODES, interpreter="linuxcnc")  # and the planner's blocks
    mine = read_program(MODES, interpreter="builtin")
    assert planned.mode_line == mine.mode_line == 3
    assert [b.exact_stop for b in planned.blocks] == [b.exact_stop for b in mine.blocks]
    assert [b.tolerance for b in planned.blocks] == pytest.approx(
        [b.tolerance for b in mine.blocks], abs=PRINTED_TOL
    )


def test_refusal_names_the_line_and_linuxcnc_message(rs274: str) -> None:
    with pytest.raises(ProgramError, match=r"^program line 3: LinuxCNC's interpreter refuses"):
        read_rs274_text("G21\nG0 X1\nG2 X10 Y0 I1 J0 F100\nM2\n")
    with pytest.raises(ProgramError, match=r"line 2: .*G-code out of range"):
        read_rs274_text("G0 X1\nG7000\nM2\n")


def test_program_without_end_is_read_to_its_last_line(rs274: str) -> None:
    moves = read_rs274_text("G21\nG0 X1\nG1 X2 F100")
    assert [m.kind for m in moves] == ["rapid", "line"]
    printing = "G21\n(print, a message on standard error)\nG0 X1\n(debug, another)\n"
    assert len(read_rs274_text(printing)) == 1
    with pytest.raises(ProgramError, match=r"line 3: .*G-code out of range"):
        read_rs274_text("(print, first)\nG0 X1\nG7000\n")


def test_block_delete_switch(rs274: str) -> None:
    text = "G21\n/G0 X1\nG0 Y1\nM2\n"
    assert len(read_rs274_text(text)) == 2
    assert len(read_rs274_text(text, block_delete=True)) == 1


def test_user_file_is_only_read(rs274: str, tmp_path: Path) -> None:
    path = tmp_path / "part.ngc"
    path.write_bytes("G21\r\nG0 X1 (café)\r\nM2\r\n".encode())
    path.chmod(stat.S_IRUSR)
    before = (path.read_bytes(), path.stat().st_mtime_ns)
    moves = read_rs274(path)
    assert len(moves) == 1 and moves[0].line == 2
    assert (path.read_bytes(), path.stat().st_mtime_ns) == before
    assert sorted(os.listdir(tmp_path)) == ["part.ngc"]


def test_files_that_are_not_programs_are_refused(rs274: str, tmp_path: Path) -> None:
    latin1 = tmp_path / "latin1.ngc"
    latin1.write_bytes(b"G0 X1 (caf\xe9)\n")
    with pytest.raises(InvalidParameterError, match="UTF-8"):
        read_rs274(latin1)
    with pytest.raises(InvalidParameterError, match="directory"):
        read_rs274(tmp_path)
    with pytest.raises(InvalidParameterError, match="text"):
        read_rs274_text(b"G0 X1\n")  # type: ignore[arg-type]


def test_endless_loop_is_stopped(rs274: str) -> None:
    loop = "G21\no1 while [1]\nG0 X1\nG0 X0\no1 endwhile\nM2\n"
    with pytest.raises(ProgramError, match="longer than 1 s"):
        read_rs274_text(loop, timeout=1.0)


# The corpus of public programs (tests/program/corpus, sources in SOURCES.md)


def _rows() -> dict[str, list[str]]:
    text = (CORPUS / "SOURCES.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([^`]+)` \| (.+) \|$", text, flags=re.MULTILINE)
    return {name: [c.strip() for c in rest.split("|")] for name, rest in rows}


def test_every_corpus_program_has_its_source_and_licence() -> None:
    rows = _rows()
    assert len(CORPUS_PROGRAMS) >= MIN_PROGRAMS
    assert sorted(rows) == CORPUS_PROGRAMS
    assert len({repository for repository, *_ in rows.values()}) >= MIN_REPOSITORIES
    for name, (repository, path, licence, _) in rows.items():
        assert "/" in repository and path.strip("`"), name
        assert licence in ("GPL-2.0", "GPL-3.0", "MIT"), name


@pytest.mark.slow
def test_every_corpus_program_is_read_by_linuxcnc(corpus: dict[str, list[Move]]) -> None:
    for name, moves in corpus.items():
        lines = (CORPUS / name).read_bytes().count(b"\n") + 1
        assert moves, name
        assert all(1 <= m.line <= lines for m in moves), name
        for before, after in itertools.pairwise(moves):
            assert np.array_equal(before.end, after.start), name
        for m in moves:
            if m.kind in ("line", "arc"):
                assert m.feed is not None and m.feed > 0.0, (name, m.line)
            if m.kind == "arc":
                assert m.center is not None and m.normal is not None and m.turns != 0
                r0 = np.linalg.norm(np.cross(m.start - m.center, m.normal))
                r1 = np.linalg.norm(np.cross(m.end - m.center, m.normal))
                assert abs(r1 - r0) <= RADIUS_TOL + 1e-3 * r0, (name, m.line, r0, r1)


@pytest.mark.slow
def test_corpus_covers_the_language(corpus: dict[str, list[Move]]) -> None:
    arcs = [m for moves in corpus.values() for m in moves if m.kind == "arc"]
    normals = {tuple(np.round(m.normal, 6)) for m in arcs if m.normal is not None}
    assert {(0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)} <= normals
    full = [m for m in arcs if np.allclose(m.start, m.end, atol=1e-6)]
    assert full, "a full circle"
    assert any(m.kind == "dwell" for moves in corpus.values() for m in moves)


@pytest.mark.parametrize(("name", "refusal"), sorted(CORPUS_REFUSED.items()))
def test_corpus_program_refused_by_linuxcnc_names_its_line(
    rs274: str, name: str, refusal: tuple[int, str]
) -> None:
    line, message = refusal
    with pytest.raises(ProgramError, match=f"^program line {line}: .*{message}"):
        read_rs274(CORPUS / name, tools=CORPUS_TOOLS)
