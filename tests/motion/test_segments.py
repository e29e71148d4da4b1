"""Tests of the trajectory segments (orthoglide_pin.motion.segments)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.profiles import MotionLimits
from orthoglide_pin.motion.segments import (
    ArcMove,
    LineMove,
    circle_move,
    dwell,
    line_move,
    polygon_moves,
)

#: The prototype's sizing figures (paper, section 4) and the cycle's jerk.
LIMITS = MotionLimits(1.2, 20.0, 1000.0)
TRAPEZOID = MotionLimits(1.2, 20.0)
#: Rounding of exact geometric identities [m], [m/s], [m/s^2].
EXACT_TOL = 1e-12
#: Step of the central finite differences [s] and their rounding (values ~1e3 at most).
FD_STEP = 1e-6
FD_ROUNDING = 1e-6
#: Samples per segment.
N_SAMPLES = 4001


def local_times(segment: LineMove | ArcMove) -> np.ndarray:
    return np.linspace(0.0, segment.duration, N_SAMPLES)


def check_derivatives(segment: LineMove | ArcMove, seed: int) -> None:
    """v, a, jerk against central differences of p, v, a (Lipschitz bounds)."""
    rng = np.random.default_rng(seed)
    tau, h = rng.uniform(FD_STEP, segment.duration - FD_STEP, 3000), FD_STEP
    _, v, a, j = segment.evaluate(tau)
    p1, v1, a1, _ = segment.evaluate(tau + h)
    p0, v0, a0, _ = segment.evaluate(tau - h)
    # bounds from the largest next derivative seen on the segment
    _, _, a_all, j_all = segment.evaluate(local_times(segment))
    a_top, j_top = np.abs(a_all).max(), np.abs(j_all).max()
    assert np.abs((p1 - p0) / (2 * h) - v).max() <= a_top * h + FD_ROUNDING
    assert np.abs((v1 - v0) / (2 * h) - a).max() <= j_top * h + FD_ROUNDING
    fd_j = (a1 - a0) / (2 * h)
    close = np.abs(fd_j - j).max(axis=1) < 1e-4 * j_top  # all but samples near a switch
    assert close.mean() > 0.98


def test_line_runs_along_the_segment() -> None:
    start, end = np.array([-0.07, -0.07, -0.07]), np.array([0.13, 0.13, 0.13])
    move = line_move(start, end, LIMITS, label="diagonal")
    u = (end - start) / np.linalg.norm(end - start)
    p, v, a, _ = move.evaluate(local_times(move))
    np.testing.assert_allclose(p[0], start, atol=EXACT_TOL)
    np.testing.assert_allclose(p[-1], end, atol=EXACT_TOL)
    assert move.profile.distance == pytest.approx(0.2 * math.sqrt(3), rel=EXACT_TOL)
    # on the line, velocity and acceleration along it
    off_line = (p - start) - np.outer((p - start) @ u, u)
    assert np.abs(off_line).max() < EXACT_TOL
    assert np.abs(np.cross(v, u)).max() < EXACT_TOL
    assert np.abs(np.cross(a, u)).max() < EXACT_TOL
    assert np.linalg.norm(v, axis=1).max() == pytest.approx(1.2, rel=1e-6)
    assert move.label == "diagonal"
    check_derivatives(move, seed=3)


@pytest.mark.parametrize("arc", [2 * math.pi, -math.pi / 2, 3 * math.pi])
def test_circle_geometry_and_accelerations(arc: float) -> None:
    rng = np.random.default_rng(4)
    center, normal = rng.uniform(-0.05, 0.05, 3), rng.normal(size=3)
    radius = 0.05
    move = circle_move(center, normal, radius, LIMITS.scaled(0.8, 12.0), start_angle=0.3, arc=arc)
    n = normal / np.linalg.norm(normal)
    np.testing.assert_allclose(move.normal, n, atol=EXACT_TOL)
    p, v, a, _ = move.evaluate(local_times(move))
    rel = p - center
    np.testing.assert_allclose(np.linalg.norm(rel, axis=1), radius, rtol=EXACT_TOL)
    assert np.abs(rel @ n).max() < EXACT_TOL  # in the plane
    assert np.abs(np.einsum("ij,ij->i", v, rel)).max() < EXACT_TOL  # tangent
    speed = np.linalg.norm(v, axis=1)
    # centripetal component v^2 / r, tangential component the law's acceleration
    radial = -np.einsum("ij,ij->i", a, rel) / radius
    np.testing.assert_allclose(radial, speed**2 / radius, atol=1e-9)
    tangential = move.profile.sample(local_times(move)).a
    np.testing.assert_allclose(
        np.einsum("ij,ij->i", a, v) / np.maximum(speed, 1e-300), tangential, atol=1e-9
    )
    # turning sense about n, and the length run by the law is r |arc|
    turn = np.einsum("ij,j->i", np.cross(rel, v), n)
    assert np.all(np.sign(turn[speed > 1e-6]) == np.sign(arc))
    chords = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
    assert chords == pytest.approx(radius * abs(arc), rel=1e-5)
    np.testing.assert_allclose(p[0], move.start, atol=EXACT_TOL)
    np.testing.assert_allclose(p[-1], move.end, atol=EXACT_TOL)
    check_derivatives(move, seed=5)


def test_circle_frame_conventions() -> None:
    center = np.array([0.01, 0.02, 0.03])
    flat = circle_move(center, [0, 0, 2], 0.05, LIMITS)
    np.testing.assert_allclose(flat.u, [1, 0, 0])
    np.testing.assert_allclose(flat.w, [0, 1, 0])
    np.testing.assert_allclose(flat.start, center + np.array([0.05, 0, 0]), atol=EXACT_TOL)
    np.testing.assert_allclose(flat.end, flat.start, atol=EXACT_TOL)  # full turn
    half = circle_move(center, [0, 0, 1], 0.05, LIMITS, arc=math.pi, reference=[0, 1, 1])
    np.testing.assert_allclose(half.start, center + np.array([0, 0.05, 0]), atol=EXACT_TOL)
    np.testing.assert_allclose(half.end, center - np.array([0, 0.05, 0]), atol=EXACT_TOL)
    quarter = circle_move(center, [1, 0, 0], 0.05, LIMITS, start_angle=math.pi / 2)
    np.testing.assert_allclose(quarter.start, center + 0.05 * np.cross([1, 0, 0], quarter.u))


def test_polygon_stops_at_each_vertex() -> None:
    square = np.array([[0, 0, 0], [0.1, 0, 0], [0.1, 0.1, 0], [0, 0.1, 0]], dtype=float)
    edges = polygon_moves(square, TRAPEZOID, label="square")
    assert [e.label for e in edges] == ["square 1", "square 2", "square 3", "square 4"]
    ring = np.vstack([square, square[:1]])
    for k, edge in enumerate(edges):
        p, v, _, _ = edge.evaluate(np.array([0.0, edge.duration]))
        np.testing.assert_allclose(p, ring[k : k + 2], atol=EXACT_TOL)
        np.testing.assert_array_equal(v, 0.0)
        assert edge.duration == pytest.approx(0.1 / 1.2 + 1.2 / 20.0, rel=EXACT_TOL)
    assert len(polygon_moves(square, TRAPEZOID, closed=False)) == 3


def test_dwell_rests() -> None:
    rest = dwell([0.01, 0.0, -0.02], 0.5)
    p, v, a, j = rest.evaluate(np.linspace(0.0, 0.5, 7))
    np.testing.assert_array_equal(p, np.tile([0.01, 0.0, -0.02], (7, 1)))
    for values in (v, a, j):
        np.testing.assert_array_equal(values, 0.0)
    assert rest.duration == 0.5
    assert rest.label == "dwell"


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: line_move([0, 0, 0], [0, 0, 0], LIMITS), "end"),
        (lambda: line_move([0, 0, math.nan], [0, 0, 1], LIMITS), "start"),
        (lambda: line_move([0, 0], [0, 0, 1], LIMITS), "start"),
        (lambda: line_move([0, 0, 0], [0, 0, 1], (1.2, 20.0)), "limits"),
        (lambda: circle_move([0, 0, 0], [0, 0, 0], 0.05, LIMITS), "normal"),
        (lambda: circle_move([0, 0, 0], [0, 0, 1], -0.05, LIMITS), "radius"),
        (lambda: circle_move([0, 0, 0], [0, 0, 1], 0.05, LIMITS, arc=0.0), "arc"),
        (
            lambda: circle_move([0, 0, 0], [0, 0, 1], 0.05, LIMITS, start_angle=math.inf),
            "start_angle",
        ),
        (
            lambda: circle_move([0, 0, 0], [0, 0, 1], 0.05, LIMITS, reference=[0, 0, 3]),
            "reference",
        ),
        (lambda: polygon_moves([[0, 0, 0], [1, 0, 0]], LIMITS), "vertices.shape"),
        (lambda: polygon_moves([[0, 0, 0], [0, 0, 0], [1, 0, 0]], LIMITS), "end"),
        (lambda: dwell([0, 0, 0], 0.0), "duration"),
    ],
)
def test_bad_input_names_the_value(call: object, name: str) -> None:
    with pytest.raises(InvalidParameterError) as info:
        call()  # type: ignore[operator]
    assert info.value.name == name
