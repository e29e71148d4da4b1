"""Lines, arcs and helices: arc-length parametrisation and derivatives by finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.geometry import arc_piece, line_piece, sub_piece
from orthoglide_pin.planning.path import build_path

#: Central-difference step [m]. The differences' errors: truncation h^2 k^2 / 6 on
#: the tangent and h^2 k^3 / 12 on the curvature (k the curvature [1/m]), and
#: rounding |p| eps / h^2 ~ 1e-7 /m on the curvature: bounded with a factor 3.
FD_STEP = 1e-5
FD_SAFETY = 3.0
FD_ROUNDING = 1e-6


def _fd_check(piece) -> None:
    s = np.linspace(2 * FD_STEP, piece.length - 2 * FD_STEP, 50)
    p, dp, ddp = piece.evaluate(s)
    pp, _, _ = piece.evaluate(s + FD_STEP)
    pm, _, _ = piece.evaluate(s - FD_STEP)
    k = float(np.linalg.norm(ddp, axis=1).max())
    tol_1 = FD_SAFETY * FD_STEP**2 * k**2 / 6 + 1e-12
    tol_2 = FD_SAFETY * FD_STEP**2 * k**3 / 12 + FD_ROUNDING
    np.testing.assert_allclose((pp - pm) / (2 * FD_STEP), dp, atol=tol_1)
    np.testing.assert_allclose((pp - 2 * p + pm) / FD_STEP**2, ddp, atol=tol_2)
    np.testing.assert_allclose(np.linalg.norm(dp, axis=1), 1.0, atol=1e-14)  # arc length


def test_a_helix_is_parametrised_by_arc_length() -> None:
    piece = arc_piece(
        0,
        np.array([0.02, 0.0, 0.01]),
        np.array([0.0, 0.0, 0.01]),
        (0, 1, 2),
        -3.0 * math.pi,
        -0.015,
        None,
    )
    assert math.isclose(piece.length, math.hypot(0.02 * 3 * math.pi, 0.015))
    _fd_check(piece)
    end = piece.evaluate(np.array([piece.length]))[0][0]
    np.testing.assert_allclose(end, [-0.02, 0.0, -0.005], atol=1e-15)
    # curvature of a helix: r / (r^2 + c^2), c the rise per radian
    c = 0.015 / (3 * math.pi)
    k = np.linalg.norm(piece.evaluate(np.array([0.01]))[2][0])
    assert math.isclose(k, 0.02 / (0.02**2 + c**2), rel_tol=1e-12)


def test_a_line_and_an_arc_in_each_plane() -> None:
    _fd_check(line_piece(0, np.zeros(3), np.array([0.1, -0.02, 0.03]), 0.1))
    for plane in ((0, 1, 2), (2, 0, 1), (1, 2, 0)):
        start = np.zeros(3)
        start[plane[0]] = 0.01
        piece = arc_piece(0, start, np.zeros(3), plane, 1.0, 0.0, 0.1)
        _fd_check(piece)
        # counter-clockwise about the normal: the tangent turns from axis i towards axis j
        assert piece.start_tangent()[plane[1]] > 0.99


def test_the_third_derivative_by_finite_differences() -> None:
    helix = arc_piece(0, np.array([0.03, 0.0, 0.0]), np.zeros(3), (0, 1, 2), 2.5, 0.02, None)
    s = np.linspace(2 * FD_STEP, helix.length - 2 * FD_STEP, 40)
    ddp_p = helix.evaluate(s + FD_STEP)[2]
    ddp_m = helix.evaluate(s - FD_STEP)[2]
    # truncation h^2 |d5p/ds5| / 6, with |d5p/ds5| = rate^5 r on a helix
    rate = abs(helix.sweep) / helix.length
    tol = FD_SAFETY * FD_STEP**2 * rate**5 * helix.radius / 6 + FD_ROUNDING
    np.testing.assert_allclose((ddp_p - ddp_m) / (2 * FD_STEP), helix.third(s), atol=tol)
    line = line_piece(0, np.zeros(3), np.array([0.01, 0.02, 0.0]), None)
    assert not line.third(s[:3]).any()


def test_a_sub_piece_is_the_same_curve() -> None:
    rng = np.random.default_rng(11)
    pieces = [
        line_piece(2, np.zeros(3), np.array([0.03, -0.01, 0.02]), 0.1),
        arc_piece(3, np.array([0.0, 0.02, 0.0]), np.zeros(3), (1, 2, 0), -4.0, 0.01, None),
    ]
    for piece in pieces:
        for _ in range(5):
            a, b = np.sort(rng.uniform(0.0, piece.length, 2))
            part = sub_piece(piece, a, b)
            assert part.block == piece.block and part.feed == piece.feed
            assert part.length == pytest.approx(b - a, rel=1e-14)
            local = np.linspace(0.0, part.length, 7)
            for mine, theirs in zip(part.evaluate(local), piece.evaluate(a + local), strict=True):
                np.testing.assert_allclose(mine, theirs, atol=1e-15, rtol=1e-12)


def test_a_spiral_is_linuxcncs_from_its_start_to_its_programmed_end() -> None:
    """``G0 X20 Y0`` / ``G2 X20.005 Y0 I-10 J0``: a full turn, radius 10 to 10.005 mm."""
    prog = read_program("G0 X20 Y0\nG2 X20.005 Y0 I-10 J0 F600\n")
    arc = build_path(prog).sections[-1].pieces[0]
    block = prog.blocks[-1]
    assert arc.spiral == pytest.approx(0.005e-3)
    assert abs(arc.sweep) == pytest.approx(2 * math.pi)
    assert arc.length == pytest.approx(2 * math.pi * 10.0025e-3, rel=1e-8)  # and the radial part
    p, dp, ddp = arc.evaluate(np.linspace(0.0, arc.length, 101))
    np.testing.assert_allclose(p[0], block.start, atol=1e-15)
    np.testing.assert_allclose(p[-1], block.end, atol=1e-15)
    radius = np.linalg.norm(p - block.center, axis=1)
    np.testing.assert_allclose(radius, np.linspace(10e-3, 10.005e-3, 101), atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(dp, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(ddp, axis=1) * radius, 1.0, rtol=1e-6)
    half = arc.length / 2  # the sub-piece continues the same spiral
    tail = sub_piece(arc, half, arc.length)
    np.testing.assert_allclose(tail.evaluate(np.array([0.0]))[0][0], p[50], atol=1e-15)
    np.testing.assert_allclose(tail.evaluate(np.array([tail.length]))[0][0], p[-1], atol=1e-15)


#: Finite-difference step along a spiral [m] and the agreement it gives [-].
SPIRAL_STEP = 1e-7
SPIRAL_FD_TOL = 1e-5


def test_a_strong_spiral_is_parametrised_by_its_arc_length() -> None:
    """Radius 0.1 to 0.12 mm (0.02 mm: within LinuxCNC's 0.028 mm), 1.5 turns, rising 0.05 mm."""
    arc = arc_piece(0, np.array([1e-4, 0, 0]), np.zeros(3), (0, 1, 2), 3 * math.pi, 5e-5, 0.1,
                    1.2e-4)  # fmt: skip
    assert arc.spiral == pytest.approx(2e-5)
    s = np.linspace(0.0, arc.length, 41)
    p, dp, ddp = arc.evaluate(s)
    np.testing.assert_allclose(p[0], [1e-4, 0, 0], atol=1e-15)
    np.testing.assert_allclose(p[-1], [-1.2e-4, 0, 5e-5], atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(dp, axis=1), 1.0, atol=1e-12)
    ahead = arc.evaluate(np.clip(s + SPIRAL_STEP, 0.0, arc.length))[0]
    behind = arc.evaluate(np.clip(s - SPIRAL_STEP, 0.0, arc.length))[0]
    inner = slice(1, -1)
    np.testing.assert_allclose(
        ((ahead - behind) / (2 * SPIRAL_STEP))[inner], dp[inner], atol=SPIRAL_FD_TOL
    )  # the tangent is d p / d s: s is the arc length
    second = (ahead - 2 * p + behind) / SPIRAL_STEP**2
    scale = np.linalg.norm(ddp, axis=1).max()
    np.testing.assert_allclose(second[inner] / scale, ddp[inner] / scale, atol=1e-3)
    tail = sub_piece(arc, arc.length / 3, arc.length)
    third = arc.evaluate(np.array([arc.length / 3]))[0][0]
    np.testing.assert_allclose(tail.evaluate(np.array([0.0]))[0][0], third, atol=1e-15)
    np.testing.assert_allclose(tail.evaluate(np.array([tail.length]))[0][0], p[-1], atol=1e-15)
