"""Comparing two readings of a program; the built-in reader against LinuxCNC's ``rs274``.

:func:`compare_moves` is checked on hand-made moves. Then the differential
tests: the corpus of public programs and 300 seeded random programs of the
subset (``tests/program/_fuzz.py``), all accepted by ``rs274`` block by block;
the built-in reader, where it exists, must give the same moves.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from program import _fuzz as fuzz
from program._support import (
    CORPUS,
    CORPUS_NEEDS_LINUXCNC,
    CORPUS_PROGRAMS,
    CORPUS_REFUSED,
    CORPUS_TOOLS,
    DAISY_OTHERS,
    NEEDS_LINUXCNC,
    builtin_reader,
    read_builtin,
)

from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.program import Move, compare_moves, read_rs274_text
from orthoglide_pin.program.compare import PRINTED_TOL


def _line(line: int, x: float, feed: float | None = 0.01) -> Move:
    kind = "line" if feed is not None else "rapid"
    return Move(line, kind, np.zeros(3), np.array([x, 0.0, 0.0]), feed=feed)


def _arc(turns: int, centre_y: float = 0.01) -> Move:
    start, end = np.zeros(3), np.zeros(3)
    centre, normal = np.array([0.0, centre_y, 0.0]), np.array([0.0, 0.0, 1.0])
    return Move(4, "arc", start, end, feed=0.01, center=centre, normal=normal, turns=turns)


def test_equal_readings_have_no_difference() -> None:
    moves = [_line(1, 0.01, None), _line(2, 0.02), _arc(-1)]
    assert compare_moves(moves, list(moves)) == []


def test_within_printed_precision_is_equal_beyond_is_not() -> None:
    near = [_line(2, 0.02 + 0.9 * PRINTED_TOL)]
    far = [_line(2, 0.02 + 1.1 * PRINTED_TOL)]
    assert compare_moves(near, [_line(2, 0.02)]) == []
    (difference,) = compare_moves(far, [_line(2, 0.02)])
    assert difference.startswith(
        "move 0 (line 2): end (20.0042, 0.0000, 0.0000) mm vs (20.0000, 0.0000, 0.0000) mm"
    )


def test_count_kind_line_turns_centre_feed_and_dwell_are_compared() -> None:
    assert compare_moves([_line(1, 0.0)], []) == ["1 moves vs 0"]
    assert (
        "line of line 1 vs rapid of line 1"
        in compare_moves([_line(1, 0.0)], [_line(1, 0.0, None)])[0]
    )
    assert "turns" in compare_moves([_arc(1)], [_arc(-1)])[0]
    assert "center" in compare_moves([_arc(1, 0.01)], [_arc(1, 0.011)])[0]
    assert "feed" in compare_moves([_line(1, 0.0, 0.01)], [_line(1, 0.0, 0.02)])[0]
    dwell = Move(3, "dwell", np.zeros(3), np.zeros(3), dwell=1.0)
    assert "dwell" in compare_moves([dwell], [dataclasses.replace(dwell, dwell=1.1)])[0]
    many = compare_moves(
        [_line(i, 0.0) for i in range(30)], [_line(i, 1.0) for i in range(30)], limit=5
    )
    assert len(many) == 5


@pytest.mark.parametrize("name", CORPUS_PROGRAMS)
def test_builtin_reader_agrees_with_linuxcnc_on_the_corpus(
    name: str, request: pytest.FixtureRequest
) -> None:
    read = builtin_reader()
    text = (CORPUS / name).read_text(encoding="utf-8", errors="surrogateescape")
    if name in CORPUS_REFUSED:
        with pytest.raises(ProgramError, match=f"line {CORPUS_REFUSED[name][0]}:"):
            read(text, tools=CORPUS_TOOLS)
        return
    corpus: dict[str, list[Move]] = request.getfixturevalue("corpus")
    expected = CORPUS_NEEDS_LINUXCNC.get(name, 0)
    if expected:
        assert corpus[name], "rs274 reads it"
        refusals = read_builtin(text, CORPUS_TOOLS).refusals
        assert len(refusals) == expected, [r.reason for r in refusals]  # all, in one pass
        reasons = (*NEEDS_LINUXCNC, *DAISY_OTHERS)
        assert all(any(part in r.reason for part in reasons) for r in refusals)
        message = f"line {refusals[0].line}: " + (f"{expected} refusals" if expected > 1 else "")
        with pytest.raises(ProgramError, match=message):
            read(text, tools=CORPUS_TOOLS)
        return
    differences = compare_moves(read(text, tools=CORPUS_TOOLS), corpus[name])
    assert not differences, "\n".join(differences)


# Differential fuzz: seeded random programs of the subset


SEED = 20261206
#: Number of random programs (the issue asks for at least 300).
COUNT = 300


@pytest.fixture(scope="module")
def cases(rs274: str) -> list[tuple[fuzz.Generated, list[Move]]]:
    """The programs and rs274's moves of each (one rs274 run for all)."""
    generated = fuzz.programs(SEED, COUNT)
    text, ranges = fuzz.batch(generated)
    moves = read_rs274_text(text)
    out = []
    for g, lines in zip(generated, ranges, strict=True):
        shift = lines.start - 1
        own = [dataclasses.replace(m, line=m.line - shift) for m in moves if m.line in lines]
        out.append((g, own))
    return out


def test_generator_is_seeded_and_covers_the_subset() -> None:
    a, b = fuzz.programs(SEED, 50), fuzz.programs(SEED, 50)
    assert a == b
    text = "".join(g.text for g in fuzz.programs(SEED, COUNT))
    for word in ("G20", "G21", "G90", "G91", "G17 G", "G18 G", "G19 G", " R", " P2", "G4 P"):
        assert word in text, word


def test_linuxcnc_accepts_every_program_block_by_block(
    cases: list[tuple[fuzz.Generated, list[Move]]],
) -> None:
    assert len(cases) == COUNT
    full = 0
    for g, moves in cases:
        assert tuple(m.line for m in moves) == g.move_lines, g.text
        assert np.allclose(moves[0].start, 0.0)
        full += sum(m.kind == "arc" and np.allclose(m.start, m.end, atol=1e-5) for m in moves)
    assert full > 0  # near-full and full circles are cut whole, not as short arcs


def test_batched_reading_equals_one_run_per_program(
    cases: list[tuple[fuzz.Generated, list[Move]]],
) -> None:
    for g, moves in cases[:5]:
        assert not compare_moves(read_rs274_text(g.text), moves, tol=1e-12)


def test_builtin_reader_agrees_with_linuxcnc(
    cases: list[tuple[fuzz.Generated, list[Move]]],
) -> None:
    read = builtin_reader()
    failures = []
    for k, (g, moves) in enumerate(cases):
        differences = compare_moves(read(g.text), moves)
        if differences:
            failures.append(f"program {k}:\n{g.text}" + "\n".join(differences[:3]))
    assert not failures, f"{len(failures)} of {COUNT} differ; first:\n{failures[0]}"
