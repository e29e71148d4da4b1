"""The path of a program: sections, blends, zero-length moves and containment."""

from __future__ import annotations

import gc
import itertools
from types import SimpleNamespace

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.blend import FIT_TOL
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.path import INSIDE_TOL, build_path, check_inside, sample_section
from orthoglide_pin.program.axes import ProgramAxes

#: Chords of successive samples against their arc-length spacing: shorter by at most
#: theta^2 / 24 for a sampled angle theta (a blend of 8 intervals turning 90 degrees).
CHORD_RTOL = 3e-3
#: Curvature steps left where pieces meet, against the path's curvature [-].
CURVATURE_STEP_RTOL = 1e-6


def _path(text: str):
    return build_path(read_program(text))


def test_exact_stop_dwell_and_rapid_feed_changes_end_sections() -> None:
    path = _path("G1 X10 F600\nG1 Y10\nG4 P1\nG1 X0\nG0 Y0\n")
    assert [len(s.pieces) for s in path.sections] == [1, 1, 1, 1]
    assert path.sections[1].dwell == 1.0
    assert path.length == pytest.approx(0.04)


def test_blended_corners_are_g2_blends_within_the_tolerance() -> None:
    path = _path("G64 P0.01\nG1 X10 F600\nG1 Y10\nG1 X0 Z5\nG61\nG1 X-5\n")
    first = path.sections[0]
    kinds = [p.is_blend for p in first.pieces]
    assert kinds == [False, True, False, True, False, True, False]  # G61 acts from its block on
    samples = sample_section(first, 1e-3)
    # continuous: successive samples are about their arc-length spacing apart
    gaps = np.linalg.norm(np.diff(samples.p, axis=0), axis=1)
    ds = np.diff(samples.s)
    assert (gaps <= ds * (1 + 1e-12)).all() and (gaps >= ds * (1 - CHORD_RTOL)).all()
    # the corner at (10, 0, 0) mm is missed by at most the tolerance, and by all of it
    corner = ProgramAxes().to_world([0.01, 0.0, 0.0])  # program X10
    dist = np.linalg.norm(sample_section(first, 1e-6).p - corner, axis=1).min()
    assert (1 - FIT_TOL) * 0.01e-3 < dist <= 0.01e-3 * (1 + 1e-9)


def _curvature_steps(section) -> float:
    """The largest jump of the curvature vector where two pieces meet [1/m]."""
    jumps = [
        np.linalg.norm(a.evaluate(np.array([a.length]))[2][0] - b.evaluate(np.array([0.0]))[2][0])
        for a, b in itertools.pairwise(section.pieces)
    ]
    return float(max(jumps, default=0.0))


def test_under_g64_the_curvature_is_continuous_lines_and_arcs_alike() -> None:
    # corners line-arc, arc-line, line-line; tangent joints arc-arc (S), line-arc, arc-line
    text = "G64 P0.02\nG1 X10 F600\nG3 X20 Y0 I5 J0\nG2 X30 Y0 I5\nG1 X40 Y10\n"
    text += "G1 Y20\nG3 X35 Y25 I-5 J0\nG1 X20\n"
    path = _path(text)
    assert len(path.sections) == 1
    section = path.sections[0]
    assert sum(p.is_blend for p in section.pieces) == 6
    scale = max(np.linalg.norm(p.evaluate(np.array([0.0]))[2]) for p in section.pieces)
    assert _curvature_steps(section) <= CURVATURE_STEP_RTOL * scale
    # the same program under G61 stops at every block; with G64 at a reversal, stops there
    assert len(_path(text.replace("G64 P0.02", "G61")).sections) == 7
    back = _path("G64\nG1 X10 F600\nG1 X0\nG1 Y10\n")
    assert [len(s.pieces) for s in back.sections] == [1, 3]


def test_short_blocks_are_trimmed_by_half_at_most() -> None:
    # a zig-zag of 4 um steps, blended within 0.01 mm: each blend takes half of a block
    text = "G64 P0.01\nG1 X0.004 F600\n" + "".join(
        f"G1 X{0.004 * (k + 2):.3f} Y{0.004 * ((k + 1) % 2):.3f}\n" for k in range(10)
    )
    path = _path(text)
    assert len(path.sections) == 1
    pieces = path.sections[0].pieces
    assert sum(p.is_blend for p in pieces) == 10
    samples = sample_section(path.sections[0], 1e-7)
    gaps = np.linalg.norm(np.diff(samples.p, axis=0), axis=1)
    assert (gaps <= np.diff(samples.s) * (1 + 1e-9)).all() and gaps.max() < 1e-6
    assert _curvature_steps(path.sections[0]) <= 1e-6 * np.linalg.norm(samples.ddp, axis=1).max()


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


@pytest.mark.parametrize("running", [True, False])
def test_the_garbage_collector_is_left_as_it_was(running: bool) -> None:
    was = gc.isenabled()
    try:
        (gc.enable if running else gc.disable)()
        build_path(read_program("G64 P0.01\nG1 X1 Y1 Z1 F600\nG1 X2 Y1 Z3\n"))
        assert gc.isenabled() is running
        with pytest.raises(ProgramError):
            build_path(read_program("(no move)\n"))
        assert gc.isenabled() is running
    finally:
        (gc.enable if was else gc.disable)()
