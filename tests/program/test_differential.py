"""Differential fuzz: random programs of the subset, read by LinuxCNC and the built-in reader.

The programs (seeded, ``tests/program/_fuzz.py``) are all accepted by LinuxCNC's
``rs274``, each block giving the move the generator expects; the built-in
reader, where it exists, must give the same moves (:func:`compare_moves`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from program import _fuzz as fuzz
from program._builtin import builtin_reader

from orthoglide_pin.program import Move, compare_moves, read_rs274_text

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
