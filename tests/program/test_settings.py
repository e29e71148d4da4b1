"""Modes and offsets a block sets: path control, units, arc centres, G10 and G92's checks."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.program.modes import DEFAULT_TOLERANCE
from orthoglide_pin.program.reader import check_refusals, read_moves

MM = 1e-3


def test_path_control_per_move() -> None:
    read = check_refusals(
        read_moves("G1 X1 F10\nG64 X2\nG64 P0.05 X3\nG61.1 X4\nG20 G64 P0.001 X1\n")
    )
    inch = pytest.approx(0.001 * 25.4 * MM)
    assert read.tolerances == (None, DEFAULT_TOLERANCE, pytest.approx(0.05 * MM), None, inch)


def test_absolute_arc_centres_g90_1() -> None:
    read = check_refusals(read_moves("G10 L2 P1 X5\nG0 X15 Y0\nG90.1 G3 X-15 Y0 I0 J0 F100\n"))
    arc = read.moves[-1]
    np.testing.assert_allclose(arc.center / MM, [5, 0, 0], atol=1e-9)  # I0 J0 from G54's zero


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("G92\n", "G92 without an axis word"),
        ("G10 L2 P10 X1\n", "P0 (the active offset) to P9"),
        ("G10 L2 P0 R30\nG92 X1\n", "G92 under a rotated work offset"),
        ("G10 L2 P0 R30\nG10 L20 P0 X1\n", "G10 L20 under a rotated"),
        ("G10 L2 P0 R30\nG81 X1 Z-1 R1 F10\n", "canned cycle G81 under a rotated"),
        ("G91 G53 G0 X1\n", "G53 under incremental"),
        ("G64 P-1\n", "must be in [0, 1000] m"),
        ("T1.5\n", "whole number"),
        ("G43 H2\n", "not in the tool table"),
    ],
)
def test_what_settings_refuse(text: str, words: str) -> None:
    read = read_moves(text)
    assert read.refusals and words in read.refusals[0].reason


def test_g43_without_h_takes_the_loaded_tool_and_g43_1_a_length() -> None:
    from orthoglide_pin.program.offsets import make_setup

    setup = make_setup(tools={2: 10 * MM})
    read = check_refusals(read_moves("T2 M6\nG43\nG0 Z0\nG43.1 Z3\nG0 Z0\nG49 G0 Z0\n", setup))
    assert [round(m.end[2] / MM, 9) for m in read.moves] == [10, 3, 0]


def test_a_rotated_work_offset_turns_the_program_about_z() -> None:
    """``G10 L2 R``: program points turned about Z, then offset (as LinuxCNC places them)."""
    read = read_moves("G10 L2 P0 X2 Y1 R90\nG0 X1 Y0 Z3\nG91 G0 Y1\nG90 G3 X-1 Y1 I-1 J0 F600\n")
    assert not read.refusals
    ends = [m.end / MM for m in read.moves]
    assert np.allclose(ends[0], [2.0, 2.0, 3.0])  # X1 turned to +Y, then the offset (2, 1)
    assert np.allclose(ends[1], [1.0, 2.0, 3.0])  # an increment in Y turned to -X
    arc = read.moves[2]
    assert np.allclose(arc.end / MM, [1.0, 0.0, 3.0]) and np.allclose(arc.center / MM, [1, 1, 3])
    assert np.allclose(arc.normal, [0.0, 0.0, 1.0]) and arc.turns == 1
