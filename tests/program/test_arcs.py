"""Arcs as LinuxCNC cuts them: centres as programmed, spirals, full circles, turns, tolerances."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.program.arcs import (
    SPIRAL_ABS_TOLERANCE_MM,
    arc_geometry,
    centre_r,
    check_ijk,
    swept_angle,
)
from orthoglide_pin.program.reader import read_moves

MM = 1e-3
#: Rounding of coordinates read from text [m].
COORD_ATOL = 1e-12


def _arc(text: str):
    read = read_moves(text)
    assert not read.refusals, read.refusals
    arc = read.moves[-1]
    assert arc.kind == "arc"
    return arc, arc_geometry(arc)


def test_a_near_full_circle_is_a_full_circle_of_its_programmed_centre() -> None:
    arc, (sweep, r0, r1, rise) = _arc("G0 X20 Y0\nG2 X20.005 Y0 I-10 J0 F600\n")
    np.testing.assert_allclose(arc.center, [0.010, 0, 0], atol=COORD_ATOL)  # not moved
    assert arc.turns == -1 and sweep == pytest.approx(-2 * math.pi)
    assert r0 == pytest.approx(10 * MM) and r1 == pytest.approx(10.005 * MM)  # LinuxCNC's spiral
    assert rise == 0.0


@pytest.mark.parametrize(
    ("text", "normal", "sweep"),
    [
        ("G18 G0 X10 Z0\nG2 X10.005 Z0 I-10 K0 F600\n", [0, 1, 0], -2 * math.pi),
        ("G19 G0 Y10 Z0\nG3 Y9.996 Z0 J-10 K0 F600\n", [1, 0, 0], 2 * math.pi),
        # an end 4 um further round is a 0.4 mrad arc, as LinuxCNC cuts it
        ("G19 G0 Y10 Z0\nG3 Y10 Z0.004 J-10 K0 F600\n", [1, 0, 0], 0.0004),
        ("G18 G0 X10 Z0\nG3 X0 Z10 I-10 K0 F600\n", [0, 1, 0], 1.5 * math.pi),
        ("G19 G0 Y10 Z0\nG3 Y0 Z10 J-10 K0 F600\n", [1, 0, 0], 0.5 * math.pi),
    ],
)
def test_g18_and_g19_arcs_keep_their_centre(text: str, normal, sweep: float) -> None:
    arc, (angle, _, _, _) = _arc(text)
    np.testing.assert_array_equal(arc.normal, normal)
    np.testing.assert_allclose(arc.center, [0, 0, 0], atol=COORD_ATOL)
    assert angle == pytest.approx(sweep)


def test_p_turns_and_helices() -> None:
    arc, (sweep, _, _, rise) = _arc("G0 X10 Y0\nG3 X10 Y0 Z-6 I-10 J0 P3 F600\n")
    assert arc.turns == 3 and sweep == pytest.approx(6 * math.pi)
    assert rise == pytest.approx(-6 * MM)
    arc, (sweep, _, _, _) = _arc("G0 X10 Y0\nG2 X0 Y10 I-10 J0 P2 F600\n")
    assert arc.turns == -2 and sweep == pytest.approx(-(1.5 + 2) * math.pi)


def test_the_swept_angle_in_each_direction() -> None:
    assert swept_angle((1, 0), (0, 1), (0, 0), 1) == pytest.approx(math.pi / 2)
    assert swept_angle((1, 0), (0, 1), (0, 0), -1) == pytest.approx(-1.5 * math.pi)
    assert swept_angle((1, 0), (1, 0), (0, 0), -1) == pytest.approx(-2 * math.pi)
    assert swept_angle((1, 0), (1, 0), (0, 0), 3) == pytest.approx(6 * math.pi)
    # an end 1e-9 rad ahead of the start is a 1e-9 rad arc, as LinuxCNC cuts it
    tiny = (math.cos(1e-9), math.sin(1e-9))
    assert swept_angle((1, 0), tiny, (0, 0), 1) == pytest.approx(1e-9)
    assert swept_angle((1, 0), tiny, (0, 0), -1) == pytest.approx(-2 * math.pi)


def test_linuxcncs_tolerances_in_mm_and_inches() -> None:
    """Refused where err > 100 tol, or err > tol and err > 0.1 % of the radius (LinuxCNC 2.9)."""
    tol = SPIRAL_ABS_TOLERANCE_MM
    assert check_ijk((1, 0), (1 + 0.99 * tol, 0), (0, 0), inch=False) is None  # 2.8 %, < tol
    assert check_ijk((40, 0), (40 + 1.01 * tol, 0), (0, 0), inch=False) is None  # 0.07 %
    why = check_ijk((10, 0), (10 + 1.01 * tol, 0), (0, 0), inch=False)  # 0.29 %
    assert why is not None and "differs from the radius to the start" in why
    assert check_ijk((5000, 0), (5002, 0), (0, 0), inch=False) is None  # 2 mm, 0.04 %
    assert check_ijk((10000, 0), (10000 + 101 * tol, 0), (0, 0), inch=False) is not None
    assert check_ijk((20, 0), (20.0025, 0), (0, 0), inch=True) is None  # 0.0028 inch allowed
    assert check_ijk((1, 0), (1.004, 0), (0, 0), inch=True) is not None  # 0.4 %, > tol
    assert "zero radius" in (check_ijk((0, 0), (0, 0.001), (0, 0.001), inch=False) or "")


def test_beyond_the_tolerance_one_line_names_the_line_and_the_mismatch() -> None:
    read = read_moves("G0 X10\nG2 X0 Y10 I-10 J1 F100\n")
    (refusal,) = read.refusals
    assert refusal.line == 2
    # the centre (0, 1) mm: 9 mm to the end, sqrt(101) mm to the start
    assert refusal.reason.startswith(
        "arc radius to the end 9.0000 mm differs from the radius to the start 10.0499 mm "
        "by 1.05 mm"
    )


def test_r_arcs_are_linuxcncs() -> None:
    assert centre_r((0, 0), (10, 0), 5, clockwise=True, inch=False) == pytest.approx((5, 0))
    cx, cy = centre_r((0, 0), (10, 0), 10, clockwise=False, inch=False)  # short, left
    assert cx == pytest.approx(5) and cy == pytest.approx(math.sqrt(75))
    cx, cy = centre_r((0, 0), (10, 0), -10, clockwise=False, inch=False)  # long, right
    assert cy == pytest.approx(-math.sqrt(75))
    assert "less than half the chord" in str(centre_r((0, 0), (10, 0), 4, True, False))
