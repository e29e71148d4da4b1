"""Reading LinuxCNC's canonical calls (as ``rs274 -g`` prints them) into moves."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.program.canon import CanonState, read_canon
from orthoglide_pin.program.modes import DEFAULT_TOLERANCE

#: Exact arithmetic on printed decimals, up to float rounding [m].
TOL = 1e-12

#: What rs274 prints for: G10 L2 P1 X1 Y2 Z3 (inch), G43.1, G92, arcs in three planes.
OUTPUT = """\
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    3 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    4 N..... SET_XY_ROTATION(0.0000)
    5 N2     STRAIGHT_TRAVERSE(10.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)
    6 N3     SET_FEED_RATE(600.0000)
    7 N3     STRAIGHT_FEED(10.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
    8 N4     ARC_FEED(10.0050, 0.0000, 5.0000, 0.0000, -1, -1.0000, 0.0000, 0.0000, 0.0000)
    9 N5     DWELL(0.5000)
   10 N6     USE_LENGTH_UNITS(CANON_UNITS_INCHES)
   11 N7     SET_G5X_OFFSET(2, 1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
   12 N8     USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 2.0000, 0.0000 0.0000 0.0000, 0 0 0)
   13 N9     SET_G92_OFFSET(0.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
   14 N10    STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
   15 N11    SELECT_PLANE(CANON_PLANE_XZ)
   16 N12    ARC_FEED(1.0000, 0.0000, 0.5000, 0.0000, 2, 0.0000, 0.0000, 0.0000, 0.0000)
   17 N13    SELECT_PLANE(CANON_PLANE_YZ)
   18 N123456ARC_FEED(0.0000, 0.0000, 0.0000, 0.5000, 1, 0.0000, 0.0000, 0.0000, 0.0000)
   19 N..... PROGRAM_END()
"""


def test_moves_lines_kinds_and_units() -> None:
    moves = read_canon(OUTPUT)
    assert [m.line for m in moves] == [2, 3, 4, 5, 10, 12, 123456]
    assert [m.kind for m in moves] == ["rapid", "line", "arc", "dwell", "rapid", "arc", "arc"]
    assert np.allclose(moves[0].start, 0.0) and np.allclose(moves[0].end, [0.01, 0, 0.005])
    assert moves[1].feed == pytest.approx(0.01)  # 600 mm/min
    assert moves[3].dwell == 0.5 and np.array_equal(moves[3].start, moves[3].end)


def test_arc_centre_normal_turns_in_each_plane() -> None:
    xy, xz, yz = (m for m in read_canon(OUTPUT) if m.kind == "arc")
    assert np.allclose(xy.center, [0.005, 0.0, -0.001], atol=TOL)  # in the start's plane
    assert np.allclose(xy.normal, [0, 0, 1]) and xy.turns == -1
    assert np.allclose(xz.normal, [0, 1, 0]) and xz.turns == 2
    assert np.allclose(yz.normal, [1, 0, 0]) and yz.turns == 1
    # G18: (first, second) = (Z, X); G19: (Y, Z); all offsets and the tool in inches.
    origin = np.array([1.5, 2.0, 5.0]) * 0.0254  # G92 X0.5 + G55 (1, 2, 3) + tool Z 2
    assert np.allclose(xz.center, origin + np.array([0.0, 0.0, 0.5]) * 0.0254, atol=TOL)
    assert np.allclose(xz.end, origin + np.array([0.0, 0.0, 1.0]) * 0.0254, atol=TOL)
    assert np.allclose(yz.center, origin + np.array([0.0, 0.0, 0.5]) * 0.0254, atol=TOL)


def test_offsets_change_machine_not_position() -> None:
    moves = read_canon(OUTPUT)
    # The rapid after new offsets starts where the dwell was: offsets move no tool.
    assert np.allclose(moves[4].start, moves[3].end)
    assert np.allclose(moves[4].end, np.array([1.5, 2.0, 5.0]) * 0.0254, atol=TOL)


def test_xy_rotation_turns_points_and_normals() -> None:
    out = (
        "1 N1 SET_XY_ROTATION(90.0000)\n"
        "2 N2 SELECT_PLANE(CANON_PLANE_XZ)\n"
        "3 N3 SET_FEED_RATE(60.0000)\n"
        "4 N4 ARC_FEED(0.0000, 2.0000, 0.0000, 1.0000, 1, 0.0000, 0.0, 0.0, 0.0)\n"
    )
    (arc,) = read_canon(out)
    assert np.allclose(arc.normal, [-1, 0, 0], atol=TOL)  # +Y turned 90 degrees about Z
    assert np.allclose(arc.end, [0.0, 0.002, 0.0], atol=TOL)


@pytest.mark.parametrize(
    ("call", "words"),
    [
        ("STRAIGHT_PROBE(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)", "probing"),
        ("RIGID_TAP(1.0, 0.0, 0.0)", "tapping"),
        ("NURBS_G5_FEED(4, ...)", "NURBS"),
        ("START_SPEED_FEED_SYNC(0.500000,0)", "spindle-synchronised"),
    ],
)
def test_unplannable_motions_are_refused_with_their_line(call: str, words: str) -> None:
    with pytest.raises(ProgramError, match=f"line 7: .*{words}"):
        read_canon(f"   3 N7     {call}\n")


def test_feed_per_revolution_and_missing_feed_are_refused() -> None:
    with pytest.raises(ProgramError, match="line 2: feed per revolution"):
        read_canon(
            "1 N1 SET_FEED_MODE(0, 1)\n2 N2 SET_FEED_RATE(0.1)\n3 N2 STRAIGHT_FEED(1, 0, 0)\n"
        )
    with pytest.raises(ProgramError, match="line 4: a cutting move with no feed"):
        read_canon("1 N4 STRAIGHT_FEED(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)\n")
    with pytest.raises(ProgramError, match="line 3: NURBS"):
        read_canon("1 N3 saicanon NURBS_G6_FEED_(5, ...)\n")


def test_unreadable_numbers_and_units_are_refused() -> None:
    with pytest.raises(ProgramError, match="unreadable STRAIGHT_TRAVERSE"):
        read_canon("1 N1 STRAIGHT_TRAVERSE(nan, 0.0, 0.0)\n")
    with pytest.raises(ProgramError, match="unknown length units"):
        read_canon("1 N1 USE_LENGTH_UNITS(UNKNOWN)\n")
    with pytest.raises(ProgramError, match="only XY, XZ and YZ"):
        read_canon("1 N1 SELECT_PLANE(CANON_PLANE_UV)\n2 N2 ARC_FEED(1, 0, 0, 0, 1, 0)\n")


#: rs274's path-control calls: G64 P0.05 (mm), G61, G64 P0.002 (inch), G64, G61.1.
MODES = """\
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    2 N2     SET_FEED_RATE(600.0000)
    2 N2     STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    3 N3     SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.050000)
    4 N3     SET_NAIVECAM_TOLERANCE(0.0000)
    5 N4     STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    6 N5     SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)
    7 N6     STRAIGHT_FEED(3.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    8 N7     USE_LENGTH_UNITS(CANON_UNITS_INCHES)
    9 N8     SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.002000)
   10 N9     DWELL(0.5000)
   11 N10    SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.000000)
   12 N11    STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
   13 N12    SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)
   14 N13    STRAIGHT_TRAVERSE(0.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
"""


def test_path_control_gives_each_move_its_tolerance() -> None:
    state = CanonState()
    moves = read_canon(MODES, state)
    assert [m.line for m in moves] == [2, 4, 6, 9, 11, 13]
    assert state.mode_line == 3
    assert state.tolerances[0] is None and state.tolerances[2] is None  # default, G61
    assert state.tolerances[1] == pytest.approx(0.05e-3, abs=TOL)
    assert state.tolerances[3] == pytest.approx(0.002 * 0.0254, abs=TOL)  # the dwell's
    assert state.tolerances[4] == DEFAULT_TOLERANCE  # P0: no tolerance given
    assert state.tolerances[5] is None  # G61.1


@pytest.mark.parametrize(
    ("args", "match"),
    [("CANON_CONTINUOUS, -1.0", "tolerance must be in"), ("CANON_SOMETHING", "unknown path")],
)
def test_bad_path_control_is_refused_with_its_line(args: str, match: str) -> None:
    text = f"    1 N7     SET_MOTION_CONTROL_MODE({args})\n"
    with pytest.raises(ProgramError, match=f"^program line 7: .*{match}"):
        read_canon(text)
