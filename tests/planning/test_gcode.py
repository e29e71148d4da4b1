"""The planner's reading of a program: the program layer's moves in the world frame.

Program coordinates are mapped by the design's axes (program X on +e2, Y on
+e1, Z on -e3): expectations are written in program axes and mapped with
:func:`world`. Before the program axes existed a program's coordinates were
the world's, so every vertical move was cut mirrored.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.gcode import DEFAULT_TOLERANCE, read_program
from orthoglide_pin.program.axes import ProgramAxes

#: Rounding of coordinates read from text [m].
COORD_ATOL = 1e-15


def world(point: list[float]) -> np.ndarray:
    """The world point of a program-axis point [m]."""
    return ProgramAxes().to_world(point)


def test_lines_units_modes_and_origin() -> None:
    origin = np.array([0.01, 0.0, -0.02])  # world frame
    prog = read_program(
        "%\nN10 G21 G90 G0 X10 Y-5 (a comment) ; another\nG1 Z2.5 F600\nG91 X1\n"
        "G20 G1 Y1\nG4 P0.25\nG64 P0.02\nG1 X-1\nG61 G90 G21 X0 Y0 Z0\nM30\nG1 X5\n",
        origin=origin,
        start=(0.0, 0.0, 0.0),
    )
    kinds = [b.kind for b in prog.blocks]
    assert kinds == ["rapid", "line", "line", "line", "dwell", "line", "line"]
    b = prog.blocks
    z0 = ProgramAxes().to_program(origin)[2]  # the start's Z is kept by the first move
    np.testing.assert_allclose(b[0].end, origin + world([0.01, -0.005, -z0]), atol=COORD_ATOL)
    np.testing.assert_allclose(b[1].end, origin + world([0.01, -0.005, 0.0025]), atol=COORD_ATOL)
    assert b[1].feed == pytest.approx(0.01)  # 600 mm/min
    np.testing.assert_allclose(b[2].end, origin + world([0.011, -0.005, 0.0025]), atol=COORD_ATOL)
    np.testing.assert_allclose(
        b[3].end, origin + world([0.011, -0.005 + 0.0254, 0.0025]), atol=COORD_ATOL
    )
    assert b[3].feed == pytest.approx(0.01)  # F is a speed in program units: unchanged
    assert b[4].dwell == 0.25
    assert b[5].exact_stop is False and b[5].tolerance == pytest.approx(0.02 * 0.0254)
    np.testing.assert_allclose(b[6].end, origin, atol=COORD_ATOL)
    assert b[6].exact_stop and b[0].exact_stop  # G61 is the default
    assert [x.line for x in b] == [2, 3, 4, 5, 6, 8, 9]
    assert prog.lines == 10  # read up to M30


def test_plunge_moves_towards_the_table() -> None:
    """``G0 Z10`` then ``G1 Z-10`` ends 20 mm nearer the table (+e3, down)."""
    a, b = read_program("G0 Z10\nG1 Z-10 F600\n").blocks
    assert b.end[2] - a.end[2] == pytest.approx(0.020)


def test_arcs_by_centre_radius_planes_helix_and_full_circle() -> None:
    prog = read_program(
        "G1 X10 F100\nG3 X0 Y10 I-10 J0\nG2 X10 Y0 R10\nG3 X10 Y0 I-10 Z-3\nG18 G2 X0 Z7 I-10 K0\n"
    )
    a, b, c, d = prog.blocks[1:]
    # the program's Z (normal of G17) is the world's -e3: angles change sign about +e3
    np.testing.assert_allclose(a.center, [0, 0, 0], atol=COORD_ATOL)
    assert a.plane[2] == 2 and a.sweep == pytest.approx(-math.pi / 2)
    np.testing.assert_allclose(b.center, [0, 0, 0], atol=1e-15)
    assert b.sweep == pytest.approx(math.pi / 2)  # clockwise back
    assert c.sweep == pytest.approx(-2 * math.pi)  # full turn, helix down 3 mm
    np.testing.assert_allclose(c.end, world([0.01, 0.0, -0.003]), atol=COORD_ATOL)
    assert d.plane[2] == 0  # G18's normal, program +Y, is the world's +e1
    # G2 in G18 from (10, 0, -3) about (0, 0, -3): clockwise seen from program +Y
    assert d.sweep == pytest.approx(-math.pi / 2)
    np.testing.assert_allclose(d.center, world([0.0, 0.0, -0.003]), atol=1e-15)


def test_radius_form_picks_the_short_or_long_arc() -> None:
    short = read_program("G1 X10 F100\nG2 X20 R5\n").blocks[1]
    long = read_program("G1 X10 F100\nG2 X20 Y0 R-10\n").blocks[1]
    assert abs(short.sweep) == pytest.approx(math.pi)
    assert abs(long.sweep) > math.pi


def test_an_arc_within_the_radius_tolerance_keeps_its_centre() -> None:
    blk = read_program("G1 X10 F100\nG3 X-10.01 I-10\n").blocks[1]
    np.testing.assert_allclose(blk.center, [0, 0, 0], atol=COORD_ATOL)  # as programmed
    r1 = np.linalg.norm(blk.end - blk.center)
    assert r1 == pytest.approx(0.01001)  # LinuxCNC's spiral ends where programmed


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        ("G1 X1 F100\nG41 X2\n", 2, "G41 needs the tool's radius"),
        ("G0 X1\nG1 X2\n", 2, "without a feed"),
        ("G1 X1 F0\n", 1, "it must be > 0"),
        ("G1 X10 F100\nG2 X0 Y10 I-10 J1\n", 2, "differs from the radius"),
        ("G1 X10 F100\nG2 X30 R5\n", 2, "less than half the chord"),
        ("G1 X10 F100\nG2 X10 R5\n", 2, "full circle"),
        ("G1 X1 X2 F10\n", 1, "given twice"),
        ("G1 G2 X1 F10\n", 1, "two motion words"),
        ("X1\n", 1, "before any motion mode"),
        ("G1 X1.2.3 F1\n", 1, "unreadable"),
        ("G1 X1 (open comment\n", 1, "not closed"),
        ("G4\n", 1, "G4 needs P"),
        ("G1 X10 F100\nG17 G2 X0 Y10 I-10 K1\n", 2, "normal to the arc's plane"),
    ],
)
def test_a_bad_program_names_its_line(text: str, line: int, words: str) -> None:
    with pytest.raises(ProgramError, match=words) as info:
        read_program(text)
    assert info.value.line == line
    assert str(info.value).startswith(f"program line {line}: ")
    assert "\n" not in str(info.value)


def test_g64_without_p_uses_the_default_tolerance() -> None:
    blk = read_program("G64\nG1 X1 F100\n").blocks[0]
    assert blk.tolerance == DEFAULT_TOLERANCE and not blk.exact_stop


def test_a_rotated_work_offset_is_planned_but_not_a_tilted_arc_plane() -> None:
    """G10 L2 R turns XY arcs about Z (planned); a G18 arc's plane would tilt: refused."""
    program = read_program("G10 L2 P0 R30\nG0 X10\nG2 X10 Y0 I-5 J0 F600\n")
    arc = program.blocks[-1]
    assert arc.kind == "arc" and math.isclose(abs(arc.sweep), 2 * math.pi)
    with pytest.raises(ProgramError, match="line 3: an arc whose plane is not a plane"):
        read_program("G10 L2 P0 R30\nG0 X10\nG18 G2 X10 Z0 I-5 K0 F600\n")
