"""The path of a program: sections, blends, zero-length moves and containment."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.path import INSIDE_TOL, build_path, check_inside, sample_section

#: Chords of successive samples against their arc-length spacing: shorter by at most
#: theta^2 / 24 for a sampled angle theta (a fillet of 8 intervals turning 90 degrees).
CHORD_RTOL = 2e-3


def _path(text: str):
    return build_path(read_program(text))


def test_exact_stop_dwell_and_rapid_feed_changes_end_sections() -> None:
    path = _path("G1 X10 F600\nG1 Y10\nG4 P1\nG1 X0\nG0 Y0\n")
    assert [len(s.pieces) for s in path.sections] == [1, 1, 1, 1]
    assert path.sections[1].dwell == 1.0
    assert path.length == pytest.approx(0.04)


def test_blended_corners_are_fillets_within_the_tolerance() -> None:
    path = _path("G64 P0.01\nG1 X10 F600\nG1 Y10\nG1 X0 Z5\nG61\nG1 X-5\n")
    first = path.sections[0]
    kinds = [p.is_arc for p in first.pieces]
    assert kinds == [False, True, False, True, False, True, False]  # G61 acts from its block on
    samples = sample_section(first, 1e-3)
    # continuous: successive samples are about their arc-length spacing apart
    gaps = np.linalg.norm(np.diff(samples.p, axis=0), axis=1)
    ds = np.diff(samples.s)
    assert (gaps <= ds * (1 + 1e-12)).all() and (gaps >= ds * (1 - CHORD_RTOL)).all()
    # the corner at (10, 0, 0) mm is missed by at most the tolerance
    corner = np.array([0.01, 0.0, 0.0])
    dist = np.linalg.norm(sample_section(first, 1e-6).p - corner, axis=1).min()
    assert 0.0099e-3 < dist <= 0.01e-3 * (1 + 1e-9)


def test_arcs_at_an_angle_stop_and_tangent_ones_pass() -> None:
    path = _path("G64\nG1 X10 F600\nG3 X20 Y0 I5 J0\nG1 X30\nG1 Y10\n")
    # the arc leaves the line at a right angle: a stop; the next line is tangent to it? no:
    # a G3 half circle from (10,0) to (20,0) ends heading -y, the line heads +x: a stop too
    assert len(path.sections) == 3
    tangent = _path("G64\nG1 X10 F600\nG3 X20 Y10 I0 J10\nG1 Y30\n")
    assert len(tangent.sections) == 1


def test_zero_length_moves_take_no_room() -> None:
    path = _path("G1 X10 F600\nG1 X10\nG91 G1 X0 Y0\nG90 G1 X20\n")
    assert sum(len(s.pieces) for s in path.sections) == 2


def test_points_on_the_cube_are_inside_and_beyond_it_are_refused() -> None:
    params = og.prototype()
    q1, q2 = params.workspace.q1, params.workspace.q2
    pts = np.array([q1, q2, q1 - 0.5 * INSIDE_TOL])
    check_inside(params, pts, np.array([1, 2, 3]))
    with pytest.raises(ProgramError, match="outside the machine's 200 mm cube") as info:
        check_inside(
            params, np.array([q1, q2 + np.array([0, 0, 3 * INSIDE_TOL])]), np.array([4, 7])
        )
    assert info.value.line == 7
    # valid parameters let the sliders reach the whole cube; a machine whose limits
    # do not (a stand-in with the same fields) has its slider limits checked too
    tight = SimpleNamespace(
        workspace=params.workspace,
        leg_length=params.leg_length,
        slider_lower=-0.08,
        slider_upper=0.05,
    )
    with pytest.raises(ProgramError, match="needs slider 1") as info:
        check_inside(tight, np.array([[0.0, 0, 0], [0.1, 0.0, 0.0]]), np.array([1, 9]))
    assert info.value.line == 9
