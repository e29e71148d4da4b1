"""G2 corner blends: arc length, continuity by finite differences, and the tolerance rule."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from scipy.spatial import cKDTree

from orthoglide_pin.planning.blend import (
    ARC_TRIM_ANGLE,
    FIT_TOL,
    MAX_TURN,
    TRIM_SHARE,
    corner_blend,
    line_miss,
    tangent_lengths,
)
from orthoglide_pin.planning.geometry import Piece, arc_piece, line_piece

#: Slack on the truncation bound of a finite difference [-].
FD_SAFETY = 4.0
#: Truncation of the differences straddling a blend's ends, as a share of its curvature [-].
STRADDLE = 1e-3
#: Ends of a blend against its pieces: points [m], tangents [-], curvature vectors [1/m].
END_ATOL = (1e-15, 1e-9, 1e-6)
#: Dense sampling of the tolerance check: ``QUERIES`` points of each curve, and around
#: each one's closest sample on the other curve ``FINE`` samples over +- ``WINDOW`` TOL,
#: ``DENSE_SHARE`` TOL apart. A sampled distance d exceeds the true one by at most
#: (share / 2)^2 (1 + k d) / 2 of it, k the curvature of the sampled curve.
QUERIES = 401
WINDOW = 2.5
FINE = 501
DENSE_SHARE = 2 * WINDOW / (FINE - 1)
#: Peak curvature of two lines' blend against a circular fillet's at the same tolerance.
CURVATURE_RATIO = (1.0, 1.12)
TOL = 1e-5  # [m], the G64 P of most cases


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _arc_from(start: np.ndarray, rng: np.random.Generator, radius: float) -> Piece:
    plane = [(0, 1, 2), (2, 0, 1), (1, 2, 0)][int(rng.integers(3))]
    angle = rng.uniform(0, 2 * math.pi)
    e = np.eye(3)
    centre = start - radius * (math.cos(angle) * e[plane[0]] + math.sin(angle) * e[plane[1]])
    sweep = rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 2.0 * math.pi)
    rise = rng.choice([0.0, rng.uniform(-0.01, 0.01)])
    return arc_piece(1, start, centre, plane, float(sweep), float(rise), 0.05)


def _end(piece: Piece) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    p, t, k = piece.evaluate(np.array([piece.length]))
    return p[0], t[0], k[0]


def _corner(kind: str, rng: np.random.Generator) -> tuple[Piece, Piece]:
    """Two pieces meeting at a corner: ``kind`` is incoming-outgoing."""
    corner = rng.uniform(-0.05, 0.05, 3)
    radius = rng.uniform(2e-3, 0.03)
    if kind.startswith("line"):
        d = _unit(rng.standard_normal(3))
        a = line_piece(0, corner - rng.uniform(1e-3, 0.05) * d, corner, 0.1)
    else:
        a = _arc_from(corner, rng, radius)
        corner = _end(a)[0]
    if kind.endswith("tangent"):  # a line tangent to the arc's end: a curvature step
        b = line_piece(1, corner, corner + rng.uniform(1e-3, 0.05) * _end(a)[1], 0.08)
    elif kind.endswith("line"):
        b = line_piece(
            1, corner, corner + rng.uniform(1e-3, 0.05) * _unit(rng.standard_normal(3)), 0.08
        )
    else:
        b = _arc_from(corner, rng, rng.uniform(2e-3, 0.03))
    return a, b


def _dense_rtol(piece: Piece) -> float:
    k = np.linalg.norm(piece.evaluate(np.linspace(0.0, piece.length, 501))[2], axis=1).max()
    return (0.5 * DENSE_SHARE) ** 2 * (1.0 + 1.1 * k * TOL) / 2


def _closest(x: np.ndarray, curve, lo: float, hi: float, step: float) -> np.ndarray:
    """Distances from points ``x`` to ``curve(t)``, ``lo <= t <= hi``: the closest of samples
    ``step`` apart, then of :data:`FINE` samples within ``WINDOW`` steps of it."""
    n = max(2, math.ceil((hi - lo) / step) + 1)
    t = np.linspace(lo, hi, n)
    i = cKDTree(curve(t)).query(x)[1]
    fine = np.clip(t[i][:, None] + WINDOW * step * np.linspace(-1, 1, FINE), lo, hi)
    pts = curve(fine.ravel()).reshape(x.shape[0], FINE, 3)
    return np.linalg.norm(pts - x[:, None, :], axis=2).min(axis=1)


def _hausdorff(a: Piece, b: Piece, cb) -> float:
    """Two-sided distance between the blend and the replaced ends, by dense sampling.

    The blend is sampled by its Bezier parameter ``w``, ``TOL`` apart at most.
    """
    curve = cb.piece.curve
    w_step = TOL / float(np.linalg.norm(curve.derivative(np.linspace(0, 1, 201), 1), axis=1).max())
    ends = [(a, a.length - cb.trim_in, a.length), (b, 0.0, cb.trim_out)]
    blend = curve.derivative(np.linspace(0.0, 1.0, QUERIES), 0)
    to_path = np.min(
        [_closest(blend, lambda s, p=p: p.evaluate(s)[0], lo, hi, TOL) for p, lo, hi in ends],
        axis=0,
    )
    path = np.concatenate([p.evaluate(np.linspace(lo, hi, QUERIES))[0] for p, lo, hi in ends])
    to_blend = _closest(path, lambda w: curve.derivative(w, 0), 0.0, 1.0, w_step)
    return float(max(to_path.max(), to_blend.max()))


@pytest.mark.parametrize("kind", ["line-line", "line-arc", "arc-line", "arc-arc", "arc-tangent"])
def test_every_kind_of_corner_is_g2_and_within_the_tolerance(kind: str) -> None:
    rng = np.random.default_rng(sum(map(ord, kind)))
    made = 0
    for _ in range(4):
        a, b = _corner(kind, rng)
        cb = corner_blend(a, b, TOL)
        if cb is None:  # a corner that turns back on itself
            turn = math.acos(float(np.clip(_end(a)[1] @ b.start_tangent(), -1, 1)))
            assert turn > MAX_TURN
            continue
        made += 1
        blend = cb.piece
        assert blend.is_blend and not blend.is_arc and blend.block == a.block
        assert blend.feed == min(a.feed, b.feed)
        # trims within the shares of both pieces
        for trim, piece in ((cb.trim_in, a), (cb.trim_out, b)):
            assert 0.0 < trim <= TRIM_SHARE * piece.length
            if piece.is_arc:
                assert trim <= ARC_TRIM_ANGLE * piece.radius * (1 + 1e-12)
        # position, tangent and curvature vector equal at both ends (G2)
        ends_in = a.evaluate(np.array([a.length - cb.trim_in]))
        ends_out = b.evaluate(np.array([cb.trim_out]))
        first = blend.evaluate(np.array([0.0]))
        last = blend.evaluate(np.array([blend.length]))
        for j, atol in enumerate(END_ATOL):
            np.testing.assert_allclose(first[j], ends_in[j], atol=atol, rtol=1e-9)
            np.testing.assert_allclose(last[j], ends_out[j], atol=atol, rtol=1e-9)
        # a second difference straddling a junction gives the mean of the curvature
        # vectors on its two sides, up to h |jump of p'''| / 6: they are one vector
        mid_k = float(np.linalg.norm(blend.evaluate(np.array([0.5 * blend.length]))[2][0]))
        pairs = (
            (first, a, a.length - cb.trim_in, -1.0, 0.0, 1.0),
            (last, b, cb.trim_out, 1.0, blend.length, -1.0),
        )
        for end, piece, s_piece, piece_dir, s_blend, blend_dir in pairs:
            # h small enough that the truncation stays below STRADDLE of the curvature
            jump3 = float(
                np.linalg.norm(blend.third(np.array([s_blend])))
                + np.linalg.norm(piece.third(np.array([s_piece])))
            )
            k_scale = max(mid_k, float(np.linalg.norm(end[2])))
            h = min(1e-3 * blend.length, 6 * STRADDLE * k_scale / (FD_SAFETY * jump3))
            rounding = 4 * 0.1 * np.finfo(float).eps / h**2
            fd_tol = FD_SAFETY * h * jump3 / 6 + rounding
            assert fd_tol < 1e-2 * k_scale, fd_tol
            straddle = (
                piece.evaluate(np.array([s_piece + piece_dir * h]))[0]
                - 2 * end[0]
                + blend.evaluate(np.array([s_blend + blend_dir * h]))[0]
            ) / h**2
            np.testing.assert_allclose(straddle[0], end[2][0], atol=fd_tol)
        # within the tolerance of the replaced path, both ways; the corner used
        gap = _hausdorff(a, b, cb)
        rtol = _dense_rtol(blend)
        assert gap <= TOL * (1 + rtol), (gap, cb)
        assert gap >= (1 - 3 * FIT_TOL) * TOL or max(cb.trim_in, cb.trim_out) == max(
            min(TRIM_SHARE * p.length, ARC_TRIM_ANGLE * p.radius if p.is_arc else math.inf)
            for p in (a, b)
        )
        corner = _end(a)[0]
        w_step = TOL / float(
            np.linalg.norm(blend.curve.derivative(np.linspace(0, 1, 201), 1), axis=1).max()
        )
        miss = float(
            _closest(corner[None, :], lambda w, c=blend.curve: c.derivative(w, 0), 0, 1, w_step)[0]
        )
        assert miss <= TOL * (1 + rtol)
        if kind == "line-line":
            assert miss >= (1 - FIT_TOL) * TOL
    assert made >= 3


def test_two_lines_closest_point_is_the_midpoint() -> None:
    for turn in np.linspace(0.01, MAX_TURN - 1e-9, 25):
        d1 = np.array([1.0, 0.0, 0.0])
        d2 = np.array([math.cos(turn), math.sin(turn), 0.0])
        a = line_piece(0, -0.1 * d1, np.zeros(3), 0.1)
        b = line_piece(1, np.zeros(3), 0.1 * d2, 0.1)
        cb = corner_blend(a, b, TOL)
        assert cb is not None and cb.trim_in == cb.trim_out
        curve = cb.piece.curve
        # an independent minimisation over the Bezier parameter
        res = minimize_scalar(
            lambda w, c=curve: float(np.linalg.norm(c.derivative(np.array([w]), 0)[0])),
            bounds=(0.0, 1.0),
            method="bounded",
            options={"xatol": 1e-12},
        )
        assert res.x == pytest.approx(0.5, abs=1e-5)
        assert res.fun == pytest.approx(cb.trim_in * line_miss(turn), rel=1e-9)
        assert res.fun == pytest.approx(TOL, rel=1e-9)


def test_peak_curvature_is_near_a_circular_fillets() -> None:
    # a circle tangent to both lines, its midpoint TOL from the corner, has
    # curvature (1 / cos(turn / 2) - 1) / TOL: no fillet within TOL turns less
    for turn in np.radians([10.0, 45.0, 90.0, 135.0, 170.0]):
        a = line_piece(0, np.array([-0.1, 0.0, 0.0]), np.zeros(3), 0.1)
        b = line_piece(1, np.zeros(3), 0.1 * np.array([math.cos(turn), math.sin(turn), 0]), 0.1)
        cb = corner_blend(a, b, TOL)
        assert cb is not None
        k = np.linalg.norm(cb.piece.evaluate(np.linspace(0, cb.piece.length, 2001))[2], axis=1)
        circle = (1.0 / math.cos(turn / 2) - 1.0) / TOL
        assert CURVATURE_RATIO[0] <= k.max() / circle <= CURVATURE_RATIO[1]
        assert k[0] == pytest.approx(0.0, abs=1e-6) and k[-1] == pytest.approx(0.0, abs=1e-6)
    assert tangent_lengths(0.0) == pytest.approx(0.58 / 1.58)


def test_reversals_tiny_tolerances_and_short_pieces() -> None:
    a = line_piece(0, np.array([-0.01, 0.0, 0.0]), np.zeros(3), 0.1)
    back = line_piece(1, np.zeros(3), np.array([-0.01, 1e-6, 0.0]), 0.1)
    assert corner_blend(a, back, TOL) is None  # turns back by more than MAX_TURN
    side = line_piece(1, np.zeros(3), np.array([0.0, 0.01, 0.0]), 0.1)
    assert corner_blend(a, side, 1e-12) is None  # trims below MIN_TRIM
    # a piece of 2 um: the trim is capped at half of it, the tolerance is not used up
    short = line_piece(1, np.zeros(3), np.array([0.0, 2e-6, 0.0]), 0.1)
    cb = corner_blend(a, short, TOL)
    assert cb is not None and cb.trim_out == pytest.approx(1e-6, rel=1e-12)
    assert cb.trim_in > cb.trim_out and cb.miss < TOL
    assert _hausdorff(a, short, cb) <= TOL * (1 + _dense_rtol(cb.piece))
