"""Stops of a jerk-limited plan where the curvature steps."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.geometry import arc_piece, line_piece
from orthoglide_pin.planning.jerk_stops import split_at_curvature_steps
from orthoglide_pin.planning.path import Path, Section, build_path


def test_a_blended_line_arc_joint_needs_no_stop_an_unblended_one_does() -> None:
    prog = read_program("G64\nG1 X10 F3000\nG1 X20\nG3 X30 Y10 I0 J10\n")
    path = build_path(prog)
    assert any(p.is_blend for p in path.sections[0].pieces)  # the tangent joint is blended
    split, stops = split_at_curvature_steps(path)
    assert stops == 0 and split.sections == path.sections
    # the same joint left unblended (the two blocks laid end to end): one stop
    a = line_piece(0, np.zeros(3), np.array([0.02, 0.0, 0.0]), 0.05)
    b = arc_piece(1, a.evaluate(np.array([a.length]))[0][0], np.array([0.02, 0.01, 0.0]),
                  (0, 1, 2), 0.5 * math.pi, 0.0, 0.05)  # fmt: skip
    offsets = np.array([0.0, a.length, a.length + b.length])
    raw = Path(prog, (Section((a, b), offsets, 0.0, -1),))
    split, stops = split_at_curvature_steps(raw)
    assert stops == 1 and len(split.sections) == 2
    assert split.length == pytest.approx(raw.length)
