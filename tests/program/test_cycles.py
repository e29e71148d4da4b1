"""Canned cycles expanded into their moves, against moves computed by hand."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.program.reader import check_refusals, read_moves

MM = 1e-3
DELTA = 0.254  # G73 and G83's peck clearance [mm]


def _moves(text: str) -> list[tuple[str, list[float]]]:
    read = check_refusals(read_moves(text))
    return [(m.kind, [round(float(x) / MM, 9) for x in m.end]) for m in read.moves]


def test_g81_with_g99_and_a_second_hole() -> None:
    got = _moves("G0 X0 Y0 Z10\nG99 G81 X5 Y5 Z-3 R2 F120\nX10\nG80\nG0 Z20\n")
    assert got[1:] == [
        ("rapid", [5, 5, 10]),  # XY at the starting height
        ("rapid", [5, 5, 2]),  # down to R
        ("line", [5, 5, -3]),
        ("rapid", [5, 5, 2]),  # G99: back to R
        ("rapid", [10, 5, 2]),  # the next hole from R
        ("line", [10, 5, -3]),
        ("rapid", [10, 5, 2]),
        ("rapid", [10, 5, 20]),  # G80 ended the cycle: G0 again
    ]


def test_g83_pecks_out_to_r_and_g73_breaks_the_chip() -> None:
    got = _moves("G0 X0 Y0 Z5\nG98 G83 X1 Y1 Z-2.5 R1 Q1 F100\n")
    expected = [("rapid", [1, 1, 5]), ("rapid", [1, 1, 1])]
    for depth in (0.0, -1.0, -2.0):
        expected += [("line", [1, 1, depth]), ("rapid", [1, 1, 1])]
        expected += [("rapid", [1, 1, round(depth + DELTA, 9)])]
    expected += [("line", [1, 1, -2.5]), ("rapid", [1, 1, 5])]  # G98: the starting height
    assert got[1:] == expected
    got = _moves("G0 X0 Y0 Z5\nG73 X1 Y1 Z-1.5 R1 Q1 F100\n")
    assert got[1:] == [
        ("rapid", [1, 1, 5]),
        ("rapid", [1, 1, 1]),
        ("line", [1, 1, 0]),
        ("rapid", [1, 1, DELTA]),
        ("line", [1, 1, -1]),
        ("rapid", [1, 1, -1 + DELTA]),
        ("line", [1, 1, -1.5]),
        ("rapid", [1, 1, 5]),
    ]


def test_g98_keeps_the_initial_level_over_the_next_blocks() -> None:
    got = _moves("G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-3 R2 F120\nG0 Z4\nG81 X1 Z-1 R2\nX2\n")
    assert got[5:] == [
        ("rapid", [5, 5, 4]),  # G0 ended the cycles: the next one starts at 4 mm
        ("rapid", [1, 5, 4]),
        ("rapid", [1, 5, 2]),
        ("line", [1, 5, -1]),
        ("rapid", [1, 5, 4]),  # G98: back to the initial level, 4 mm
        ("rapid", [2, 5, 4]),  # the next block keeps it
        ("rapid", [2, 5, 2]),
        ("line", [2, 5, -1]),
        ("rapid", [2, 5, 4]),
    ]


def test_incremental_repeats() -> None:
    got = _moves("G0 X0 Y0 Z5\nG91 G81 X10 Y0 Z-4 R-3 L3 F100\n")
    expected = []
    for x in (10, 20, 30):  # R 3 mm below the start, Z 4 mm below R
        expected += [("rapid", [x, 0, 5]), ("rapid", [x, 0, 2])]
        expected += [("line", [x, 0, -2]), ("rapid", [x, 0, 5])]
    assert got[1:] == expected


@pytest.mark.parametrize(
    ("code", "tail"),
    [
        ("G82 P0.5", [("line", [0, 0, -2]), ("dwell", [0, 0, -2]), ("rapid", [0, 0, 5])]),
        ("G85", [("line", [0, 0, -2]), ("line", [0, 0, 1]), ("rapid", [0, 0, 5])]),
        ("G84", [("line", [0, 0, -2]), ("dwell", [0, 0, -2]), ("line", [0, 0, 5])]),
        ("G86 P1", [("line", [0, 0, -2]), ("dwell", [0, 0, -2]), ("rapid", [0, 0, 5])]),
        (
            "G89 P1",
            [("line", [0, 0, -2]), ("dwell", [0, 0, -2]), ("line", [0, 0, 5])],
        ),
    ],
)
def test_dwell_and_boring_cycles(code: str, tail) -> None:
    got = _moves(f"G0 X0 Y0 Z5\n{code} Z-2 R1 F100\n")
    assert got[1:] == [("rapid", [0, 0, 5]), ("rapid", [0, 0, 1]), *tail]


def test_a_cycle_starting_below_r_rises_first_and_dwells_are_timed() -> None:
    read = check_refusals(read_moves("G0 X0 Y0 Z-1\nG82 X2 Z-3 R1 P0.25 F60\n"))
    ends = [np.round(m.end / MM, 9).tolist() for m in read.moves]
    assert ends[1:4] == [[0, 0, 1], [2, 0, 1], [2, 0, -3]]
    assert read.moves[4].kind == "dwell" and read.moves[4].dwell == 0.25


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("G18 G81 X1 Z-1 R1 F10\n", "needs R and Y where the cycle begins"),  # G18: along Y
        ("G81 X1 Z-1 F10\n", "needs R and Z"),
        ("G81 X1 Z2 R1 F10\n", "R below Z"),
        ("G87 X1 Z-1 R1 F10\n", "back boring"),
        ("G81 X1 Z-1 R1 L0 F10\n", "whole number >= 1"),
    ],
)
def test_what_a_cycle_refuses(text: str, words: str) -> None:
    read = read_moves(text)
    assert read.refusals and words in read.refusals[0].reason


def test_a_cycle_in_the_zx_plane_drills_along_y() -> None:
    """G18: the hole at (Z, X), drilled along Y from R down to the Y word (as LinuxCNC)."""
    read = read_moves("G18 G0 Y5\nG81 Z1 X2 Y-3 R2 F100\n")
    assert not read.refusals
    ends = np.array([m.end for m in read.moves[1:]]) / MM
    assert np.allclose(ends[:, [0, 2]], [2.0, 1.0])  # every move at the hole
    assert [m.kind for m in read.moves[1:]] == ["rapid", "rapid", "line", "rapid"]
    assert np.allclose(ends[:, 1], [5.0, 2.0, -3.0, 5.0])  # to R, feed to Y-3, back to 5
