"""The corpus of public programs (tests/program/corpus): LinuxCNC's reading and the built-in one's.

Every program is read as written through LinuxCNC's ``rs274`` (with one tool
table for all: tool ``n`` is ``n`` mm long and 0.5 mm across), and, where the
built-in reader exists, compared with it move by move (:func:`compare_moves`).
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest
from program._builtin import builtin_reader

from orthoglide_pin.program import Move, compare_moves, read_rs274

#: Reading the corpus through rs274 takes a few seconds (one run per program).
pytestmark = pytest.mark.slow

CORPUS = Path(__file__).parent / "corpus"
PROGRAMS = sorted(p.name for p in CORPUS.glob("*.ngc"))
#: The tool table the corpus is read with: number -> (length [m], diameter [m]).
TOOLS = {n: (1e-3 * n, 0.5e-3) for n in range(1, 100)}
#: Least number of programs, and of origins (the repositories in SOURCES.md).
MIN_PROGRAMS = 20
#: LinuxCNC's tolerance on an arc's radius mismatch, at most [m] (0.05 mm and 0.1 % of
#: it, as LinuxCNC's interpreter allows for centre-format arcs).
RADIUS_TOL = 0.05e-3 + 1e-6


def _rows() -> dict[str, list[str]]:
    text = (CORPUS / "SOURCES.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([^`]+)` \| (.+) \|$", text, flags=re.MULTILINE)
    return {name: [c.strip() for c in rest.split("|")] for name, rest in rows}


@pytest.fixture(scope="module")
def readings(rs274: str) -> dict[str, list[Move]]:
    return {name: read_rs274(CORPUS / name, tools=TOOLS) for name in PROGRAMS}


def test_every_program_has_its_source_and_licence() -> None:
    rows = _rows()
    assert len(PROGRAMS) >= MIN_PROGRAMS
    assert sorted(rows) == PROGRAMS
    for name, (repository, path, licence, _) in rows.items():
        assert "/" in repository and path.strip("`"), name
        assert licence in ("GPL-2.0", "GPL-3.0"), name


def test_every_program_is_read_by_linuxcnc(readings: dict[str, list[Move]]) -> None:
    for name, moves in readings.items():
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


def test_corpus_covers_the_language(readings: dict[str, list[Move]]) -> None:
    arcs = [m for moves in readings.values() for m in moves if m.kind == "arc"]
    normals = {tuple(np.round(m.normal, 6)) for m in arcs if m.normal is not None}
    assert {(0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)} <= normals
    full = [m for m in arcs if np.allclose(m.start, m.end, atol=1e-6)]
    assert full, "a full circle"
    assert any(m.kind == "dwell" for moves in readings.values() for m in moves)


@pytest.mark.parametrize("name", PROGRAMS)
def test_builtin_reader_agrees_with_linuxcnc(name: str, readings: dict[str, list[Move]]) -> None:
    read = builtin_reader()
    text = (CORPUS / name).read_text(encoding="utf-8", errors="surrogateescape")
    differences = compare_moves(read(text, tools=TOOLS), readings[name])
    assert not differences, "\n".join(differences)
