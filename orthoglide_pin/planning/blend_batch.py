"""The corner blends of a whole program, those of two lines computed together.

:func:`~orthoglide_pin.planning.blend.corner_blend` blends one corner in
plain arithmetic; a 3D relief of 100,000 short lines has as many corners, and
a Python call for each (its control points, the distance from the corner to
the curve, the curve's arc-length table) cost about 0.2 ms. :func:`corner_blends`
takes the corners of two lines in arrays: the equal trims in closed form where
they fit, else the trims at their caps (half of each line) and the corner's
distance to that curve (the closest of 33 samples refined by Newton's method,
as :func:`~orthoglide_pin.planning.quintic.distance`), and every curve's
arc-length table at once. A corner of two lines whose capped blend misses the
corner by more than the tolerance, and every corner with an arc or a blend, is
blended one by one by :func:`~orthoglide_pin.planning.blend.corner_blend`. The
blends are those of :func:`~orthoglide_pin.planning.blend.corner_blend`, to
rounding (``tests/planning/test_blend_batch.py``).

With numba (the ``[plan]`` extra, :data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE`)
the arc-length tables are summed curve by curve in one compiled loop
(:func:`arc_tables`), the Gauss sum in node order, without the (curves, 256, 3)
temporaries of the array version; the two agree to rounding.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import jit
from orthoglide_pin.planning.blend import (
    MAX_TURN,
    MIN_TRIM,
    SHAPE,
    TRIM_SHARE,
    BlendPiece,
    CornerBlend,
    corner_blend,
)
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.quintic import (
    _BOUNDS,
    _FALLING,
    _GAUSS_W,
    _GAUSS_X,
    _SAMPLE_BASIS,
    _SAMPLES,
    _TO_POWER,
    PROJECTION_STEPS,
    SUBDIVISIONS,
    Quintic,
)
from orthoglide_pin.planning.reach_compiled import AVAILABLE

FloatArray = NDArray[np.float64]

#: A corner to blend: the incoming piece, the outgoing piece, the ``G64 P`` tolerance [m].
Corner = tuple[Piece, Piece, float]
#: Corners of two lines blended together at most (their temporaries about 25 MB).
CHUNK: Final[int] = 4096


def _is_line(piece: Piece) -> bool:
    return piece.v is None and not piece.is_blend


def _poly(coef: FloatArray, w: FloatArray, order: int) -> FloatArray:
    """The ``order``-th derivative of curve ``i`` at ``w[i]``: coef (m, 6, 3), w (m, k)."""
    scaled = _FALLING[order, order:, None] * coef[:, order:]  # (m, 6 - order, 3)
    out = np.broadcast_to(scaled[:, None, -1], (*w.shape, 3)).copy()
    for j in range(scaled.shape[1] - 2, -1, -1):
        out *= w[:, :, None]
        out += scaled[:, None, j]
    return np.asarray(out)


def _distances(coef: FloatArray, x: FloatArray) -> FloatArray:
    """Distance from ``x[i]`` (m, 3) to curve ``i`` (about its first point), (m,)."""
    m = coef.shape[0]
    pts = _SAMPLE_BASIS @ coef
    diff = x[:, None, :] - pts
    dist = np.sqrt(np.sum(diff * diff, axis=2))
    i = np.argmin(dist, axis=1)
    last = _SAMPLES.size - 1
    lo, hi = _SAMPLES[np.maximum(i - 1, 0)], _SAMPLES[np.minimum(i + 1, last)]
    w = _SAMPLES[i]
    for _ in range(PROJECTION_STEPS):  # Newton on (B - x) . B' = 0 within the bracket
        wk = w[:, None]
        r = _poly(coef, wk, 0)[:, 0] - x
        d1, d2 = _poly(coef, wk, 1)[:, 0], _poly(coef, wk, 2)[:, 0]
        slope = np.sum(d1 * d1, axis=1) + np.sum(r * d2, axis=1)
        ok = slope > 0.0
        step = np.where(ok, np.sum(r * d1, axis=1) / np.where(ok, slope, 1.0), 0.0)
        w = np.minimum(np.maximum(w - step, lo), hi)
    e = _poly(coef, w[:, None], 0)[:, 0] - x
    return np.asarray(np.minimum(np.sqrt(np.sum(e * e, axis=1)), dist[np.arange(m), i]))


def _tables_compiled(
    coef: FloatArray, bounds: FloatArray, gauss_x: FloatArray, gauss_w: FloatArray
) -> FloatArray:
    """The arc length at each span bound of each curve, (m, S + 1): one loop, no temporaries."""
    m, spans = coef.shape[0], bounds.size - 1
    h = 1.0 / spans
    cum = np.empty((m, spans + 1))
    for i in range(m):
        total = 0.0
        cum[i, 0] = 0.0
        for k in range(spans):
            inner = 0.0
            for g in range(gauss_x.size):
                w = bounds[k] + 0.5 * h * (gauss_x[g] + 1.0)
                x = 5.0 * coef[i, 5, 0]
                y = 5.0 * coef[i, 5, 1]
                z = 5.0 * coef[i, 5, 2]
                for j in range(4, 0, -1):  # Horner's scheme on B' (coefficients j c_j)
                    x = x * w + j * coef[i, j, 0]
                    y = y * w + j * coef[i, j, 1]
                    z = z * w + j * coef[i, j, 2]
                inner += math.sqrt(x * x + y * y + z * z) * gauss_w[g]
            total += 0.5 * h * inner
            cum[i, k + 1] = total
    return cum


if AVAILABLE:
    _tables_compiled = jit(_tables_compiled)


def arc_tables(coef: FloatArray, *, compiled: bool = AVAILABLE) -> FloatArray:
    """The arc length of quintics at their span bounds (Gauss-Legendre on each span).

    Args:
        coef: Power-basis coefficients about each first point, (m, 6, 3).
        compiled: Sum them in the compiled loop (needs numba), else in arrays.

    Returns:
        The arc length [m] at each of :data:`~orthoglide_pin.planning.quintic.SUBDIVISIONS`
        + 1 span bounds, (m, SUBDIVISIONS + 1).
    """
    if compiled:
        return np.asarray(
            _tables_compiled(
                np.ascontiguousarray(coef, dtype=np.float64), _BOUNDS, _GAUSS_X, _GAUSS_W
            )
        )
    h = 1.0 / SUBDIVISIONS
    nodes = (_BOUNDS[:-1, None] + 0.5 * h * (_GAUSS_X + 1.0)).ravel()
    d1 = _poly(coef, np.broadcast_to(nodes, (coef.shape[0], nodes.size)), 1)
    speed = np.sqrt(np.sum(d1 * d1, axis=2)).reshape(coef.shape[0], SUBDIVISIONS, -1)
    spans = 0.5 * h * speed @ _GAUSS_W
    return np.concatenate([np.zeros((coef.shape[0], 1)), np.cumsum(spans, axis=1)], axis=1)


def _curves(control: FloatArray) -> list[Quintic]:
    """The quintics of control points (m, 6, 3), their arc-length tables made together."""
    if not control.shape[0]:
        return []
    coef = _TO_POWER @ (control - control[:, :1])
    cum = arc_tables(coef)
    return [Quintic.made(c, k, t) for c, k, t in zip(control, coef, cum, strict=True)]


def _lines_together(corners: list[Corner]) -> list[CornerBlend | bool | None]:
    """The blends of corners of two lines; ``False`` where one must be fitted one by one."""
    a_o = np.array([a.origin for a, _, _ in corners])
    a_u = np.array([a.u for a, _, _ in corners])
    b_o = np.array([b.origin for _, b, _ in corners])
    b_u = np.array([b.u for _, b, _ in corners])
    a_len = np.array([a.length for a, _, _ in corners])
    b_len = np.array([b.length for _, b, _ in corners])
    tol = np.array([t for _, _, t in corners])
    corner = a_o + a_len[:, None] * a_u
    turn = np.arccos(np.clip(np.sum(a_u * b_u, axis=1), -1.0, 1.0))
    half = np.cos(0.5 * turn)
    ratio = SHAPE * half / (SHAPE + half)
    unit = (16.0 - 25.0 * ratio) / 16.0 * np.sin(0.5 * turn)
    cap_a, cap_b = TRIM_SHARE * a_len, TRIM_SHARE * b_len
    with np.errstate(divide="ignore"):
        equal = np.where(unit > 0.0, tol / unit * (1.0 - 1e-12), np.inf)
    closed = equal <= np.minimum(cap_a, cap_b)
    # closed form: equal trims; else the trims at their caps (gap(top) of corner_blend)
    trim_a, trim_b = np.where(closed, equal, cap_a), np.where(closed, equal, cap_b)
    p0 = np.where(closed[:, None], 0.0, a_o + (a_len - trim_a)[:, None] * a_u)
    p5 = np.where(closed[:, None], 0.0, b_o + trim_b[:, None] * b_u)
    t0, t1 = a_u, b_u
    a0, a1 = ratio * trim_a, ratio * trim_b
    capped = np.stack(
        [p0, p0 + a0[:, None] * t0, p0 + (2.0 * a0)[:, None] * t0 + 0.0,
         p5 - (2.0 * a1)[:, None] * t1 + 0.0, p5 - a1[:, None] * t1, p5],
        axis=1,
    )  # fmt: skip
    shape = np.stack([-np.ones_like(ratio), ratio - 1.0, 2.0 * ratio - 1.0], axis=1)[:, :, None]
    length = np.where(closed, equal, 0.0)[:, None, None]
    sides = np.concatenate([shape * t0[:, None, :], -shape[:, ::-1] * t1[:, None, :]], axis=1)
    closed_ctrl = corner[:, None, :] + length * sides
    control = np.where(closed[:, None, None], closed_ctrl, capped)
    coef = _TO_POWER @ (capped - capped[:, :1])
    miss = np.where(closed, equal * unit, _distances(coef, corner - capped[:, 0]))
    fits = closed | (miss <= tol)
    dead = (turn > MAX_TURN) | ~(tol > 0.0)
    short = np.minimum(trim_a, trim_b) < MIN_TRIM
    keep = np.flatnonzero(fits & ~dead & ~short)
    out: list[CornerBlend | bool | None] = [None if bad else False for bad in (dead | fits)]
    for k, curve in zip(keep.tolist(), _curves(control[keep]), strict=True):
        a, b, _ = corners[k]
        feeds = [f for f in (a.feed, b.feed) if f is not None]
        piece = BlendPiece(
            a.block, curve.length, min(feeds) if feeds else None, control[k, 0].copy(),
            t0[k].copy(), curve=curve,
        )  # fmt: skip
        out[k] = CornerBlend(float(trim_a[k]), float(trim_b[k]), piece, float(miss[k]))
    return out


def corner_blends(corners: list[Corner]) -> list[CornerBlend | None]:
    """:func:`~orthoglide_pin.planning.blend.corner_blend` of each corner (see the module)."""
    out: list[CornerBlend | None] = [None] * len(corners)
    lines = [k for k, (a, b, _) in enumerate(corners) if _is_line(a) and _is_line(b)]
    got: list[CornerBlend | bool | None] = []
    for lo in range(0, len(lines), CHUNK):  # bounded temporaries: (CHUNK, 256, 3) at most
        got += _lines_together([corners[k] for k in lines[lo : lo + CHUNK]])
    done = dict(zip(lines, got, strict=True))
    for k, (a, b, tolerance) in enumerate(corners):
        blend = done.get(k, False)
        out[k] = corner_blend(a, b, tolerance) if blend is False else blend  # type: ignore[assignment]
    return out
