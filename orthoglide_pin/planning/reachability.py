"""TOPP-RA's two passes with each stage's linear programme solved in closed form.

TOPP-RA (Pham and Pham, IEEE T-RO 2018) computes, backwards from the end, the
**controllable sets** ``K_i = [l_i, h_i]`` of squared path speeds ``x_i``, then
goes forwards taking at each stage the largest path acceleration ``u_i`` that
keeps ``x_{i+1} = x_i + 2 (s_{i+1} - s_i) u_i`` in ``K_{i+1}``. Each step is a
linear programme in two variables. toppra solves it with one call of its
``seidel`` solver per step, from a Python loop (about 60 us per grid point).

Here the rows of stage ``i`` (the constraints of point ``i`` and, in toppra's
*interpolation* discretisation, those of point ``i + 1`` reached with the same
``u``) are written in the variables ``(x, y)`` with ``y = x_{i+1}``::

    P x + Q y <= G      (normalised: P^2 + Q^2 = 1)

For all stages at once (arrays, no Python loop), the largest and smallest ``x``
of each stage's polygon come from eliminating ``y`` (Fourier-Motzkin: each row
bounding ``y`` from above combined with each row bounding it from below), with
the range of ``y`` where they are reached. The sequential passes then cost a
few comparisons per stage where the next set does not restrict the stage
(``K_{i+1}`` contains that range), and one evaluation of the stage's rows
elsewhere:

* backward: ``h_i = max {x : (x, y) in stage i, l_{i+1} <= y <= h_{i+1}}``,
  the maximum of the concave ``x_hi(y) = min_rows (G - Q y) / P`` (rows with
  ``P > 0``) over that interval, at its peak or at the interval's nearer end;
  ``l_i`` likewise with the convex ``x_lo(y)``;
* forward: ``x_{i+1} = min(h_{i+1}, y_hi(x_i))``, ``y_hi(x) = min_rows (G - P x) / Q``
  (rows with ``Q > 0``).

The result is the same discrete optimum as toppra's (to rounding). A stage the
arithmetic cannot settle (an empty set, or a forward step that leaves
``K_{i+1}`` by more than :data:`SLACK`) returns ``None``: the caller then asks
toppra itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.reach_compiled import AVAILABLE, FLAT, SLACK, reach_compiled

FloatArray = NDArray[np.float64]

#: Stages per block of the pairwise elimination (bounds its temporaries).
BLOCK: Final[int] = 4096
#: Right-hand side of the padding rows (never binding).
_BIG: Final[float] = 1e300


@dataclass(frozen=True)
class Stages:
    """The polygons of the stages in ``(x, y)`` (see the module), ``N`` stages.

    Attributes:
        up_c, up_s: ``x_hi(y) = min(up_c - up_s y)``, (N, R) (``inf`` padding).
        low_c, low_s: ``x_lo(y) = max(low_c - low_s y)``, (N, R) (``-inf`` padding).
        y_lo, y_hi: Rows on ``y`` alone, (N,).
        next_c, next_s: ``y_hi(x) = min(next_c - next_s x)``, (N, U) (padding: ``c`` huge).
        x_max, x_min: The largest and smallest ``x`` of each polygon, (N,).
        peak: The range of ``y`` where ``x_max`` is reached, (N, 2).
        trough: The range of ``y`` where ``x_min`` is reached, (N, 2).
    """

    up_c: FloatArray
    up_s: FloatArray
    low_c: FloatArray
    low_s: FloatArray
    y_lo: FloatArray
    y_hi: FloatArray
    next_c: FloatArray
    next_s: FloatArray
    x_max: FloatArray
    x_min: FloatArray
    peak: FloatArray
    trough: FloatArray


def stage_rows(
    s: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray, x_bound: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The rows ``P x + Q y <= G`` of every stage, normalised, (N, 2m + 4) each.

    Args:
        s: Grid, increasing, (n,).
        a: Rows' coefficients of ``u`` at the grid points, (n, m): ``a u + b x + c <= 1``.
        b: Their coefficients of ``x``, (n, m).
        c: Their constants, (n, m).
        x_bound: Upper bound of ``x`` at the points, (n,).
    """
    two_ds = 2.0 * np.diff(s)[:, None]
    n1 = s.size - 1
    zero, one = np.zeros((n1, 1)), np.ones((n1, 1))
    here, there = a[:-1] / two_ds, a[1:] / two_ds
    p = np.concatenate([b[:-1] - here, -there, -one, one, zero, zero], axis=1)
    q = np.concatenate([here, there + b[1:], zero, zero, -one, one], axis=1)
    g = np.concatenate(
        [1.0 - c[:-1], 1.0 - c[1:], zero, x_bound[:-1, None], zero, x_bound[1:, None]], axis=1
    )
    norm = np.hypot(p, q)
    empty = norm == 0.0
    norm[empty] = 1.0
    return p / norm, q / norm, np.where(empty & (g >= -SLACK), np.inf, g / norm)


def _first(
    mask: NDArray[np.bool_], p: FloatArray, q: FloatArray, g: FloatArray, pad: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The rows where ``mask`` holds, packed to the left (width: the most per stage).

    The padding is the row ``pad y <= BIG`` (``x`` free), which no pair makes binding.
    """
    rank = np.cumsum(mask, axis=1) - 1
    width = max(int(rank[:, -1].max(initial=-1)) + 1, 1)
    rows, cols = np.nonzero(mask)
    slot = rank[rows, cols]
    out_p, out_q = np.zeros((mask.shape[0], width)), np.full((mask.shape[0], width), pad)
    out_g = np.full((mask.shape[0], width), _BIG)
    out_p[rows, slot], out_q[rows, slot], out_g[rows, slot] = (
        p[rows, cols],
        q[rows, cols],
        g[rows, cols],
    )
    return out_p, out_q, out_g


def stages(p: FloatArray, q: FloatArray, g: FloatArray) -> Stages | None:
    """Each stage's bounds and peaks (see the module), or ``None`` when a stage is empty."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        live = np.isfinite(g)
        upper_y, lower_y = live & (q > FLAT), live & (q < -FLAT)
        flat_y = live & ~upper_y & ~lower_y  # rows on x alone: |P| = 1
        if np.any(flat_y & (np.abs(p) <= FLAT) & (g < -SLACK)):
            return None
        x_max = np.where(flat_y & (p > FLAT), g / p, np.inf).min(axis=1)
        x_min = np.where(flat_y & (p < -FLAT), g / p, -np.inf).max(axis=1)
        pu, qu, gu = _first(upper_y, p, q, g, 1.0)
        pd, qd, gd = _first(lower_y, p, q, g, -1.0)
        for blk in range(0, p.shape[0], BLOCK):
            sl = slice(blk, blk + BLOCK)
            # row j (Q_j > 0) times -Q_k plus row k (Q_k < 0) times Q_j: y cancels
            cc = qu[sl, :, None] * pd[sl, None, :] - qd[sl, None, :] * pu[sl, :, None]
            rr = qu[sl, :, None] * gd[sl, None, :] - qd[sl, None, :] * gu[sl, :, None]
            cc, rr = cc.reshape(cc.shape[0], -1), rr.reshape(rr.shape[0], -1)
            flat = np.abs(cc) <= FLAT
            if np.any(flat & (rr < -SLACK)):
                return None
            bound = rr / np.where(flat, 1.0, cc)
            top = np.min(bound, axis=1, initial=np.inf, where=cc > FLAT)
            bottom = np.max(bound, axis=1, initial=-np.inf, where=cc < -FLAT)
            x_max[sl] = np.minimum(x_max[sl], top)
            x_min[sl] = np.maximum(x_min[sl], bottom)
        if np.any(x_min > x_max + SLACK) or not np.all(np.isfinite(x_max)):
            return None
        x_min = np.minimum(x_min, x_max)
        # x_hi(y) = min over P > 0 of (G - Q y) / P, x_lo(y) = max over P < 0
        pos, neg = live & (p > FLAT), live & (p < -FLAT)
        up_c, up_s = np.where(pos, g / p, np.inf), np.where(pos, q / p, 0.0)
        low_c, low_s = np.where(neg, g / p, -np.inf), np.where(neg, q / p, 0.0)
        flat_x = live & ~pos & ~neg  # rows on y alone: |Q| = 1
        y_hi = np.where(flat_x & (q > 0.0), g / q, np.inf).min(axis=1)
        y_lo = np.where(flat_x & (q < 0.0), g / q, -np.inf).max(axis=1)
        # y_hi(x) = min over Q > 0 of (G - P x) / Q (every row bounding y from above)
        # the packed rows: the padding (0 x + y <= BIG, or -y <= BIG) never binds
        next_c, next_s = gu / qu, pu / qu
        low_y_c, low_y_s = gd / qd, pd / qd

        def y_range(x: FloatArray) -> FloatArray:
            lo = np.maximum((low_y_c - low_y_s * x[:, None]).max(axis=1), y_lo)
            hi = np.minimum((next_c - next_s * x[:, None]).min(axis=1), y_hi)
            mid = np.where(lo > hi, 0.5 * (lo + hi), lo)
            return np.stack([np.minimum(lo, mid), np.maximum(hi, mid)], axis=1)

        peak, trough = y_range(x_max), y_range(x_min)
    return Stages(up_c, up_s, low_c, low_s, y_lo, y_hi, next_c, next_s, x_max, x_min, peak, trough)


def reach(
    s: FloatArray,
    a: FloatArray,
    b: FloatArray,
    c: FloatArray,
    x_bound: FloatArray,
    start: float = 0.0,
) -> FloatArray | None:
    """TOPP-RA's squared speeds from ``start`` (rest by default) to rest, or ``None``.

    See the module. The passes run compiled when numba is installed
    (:func:`~orthoglide_pin.planning.reach_compiled.reach_compiled`, the same
    numbers to rounding), else in arrays (:func:`reach_arrays`).

    Args:
        s: Grid, increasing, (n,).
        a: Rows' coefficients of ``u`` at the grid points, (n, m): ``a u + b x + c <= 1``.
        b: Their coefficients of ``x``, (n, m).
        c: Their constants, (n, m).
        x_bound: Upper bound of ``x`` at the points (0 where the path must rest), (n,).
        start: The squared speed at the first point [(m/s)^2]: it must lie in
            the first controllable set (a window's start, :mod:`~orthoglide_pin.planning.windows`).

    Returns:
        The squared path speeds, (n,), or ``None`` when a stage cannot be settled.
    """
    if AVAILABLE:
        return reach_compiled(s, a, b, c, x_bound, start)
    return reach_arrays(s, a, b, c, x_bound, start)


def reach_arrays(
    s: FloatArray,
    a: FloatArray,
    b: FloatArray,
    c: FloatArray,
    x_bound: FloatArray,
    start: float = 0.0,
) -> FloatArray | None:
    """:func:`reach` with the stages' polygons built in arrays, the passes in Python.

    Args:
        s: Grid, increasing, (n,).
        a: Rows' coefficients of ``u`` at the grid points, (n, m): ``a u + b x + c <= 1``.
        b: Their coefficients of ``x``, (n, m).
        c: Their constants, (n, m).
        x_bound: Upper bound of ``x`` at the points (0 where the path must rest), (n,).
        start: The squared speed at the first point [(m/s)^2]: it must lie in
            the first controllable set (a window's start, :mod:`~orthoglide_pin.planning.windows`).

    Returns:
        The squared path speeds, (n,), or ``None`` when a stage cannot be settled.
    """
    st = stages(*stage_rows(s, a, b, c, x_bound))
    if st is None:
        return None
    n = s.size
    high, low = np.zeros(n), np.zeros(n)
    x_max, x_min = st.x_max.tolist(), st.x_min.tolist()
    peak_a, peak_b = st.peak[:, 0].tolist(), st.peak[:, 1].tolist()
    trough_a, trough_b = st.trough[:, 0].tolist(), st.trough[:, 1].tolist()
    y_lo, y_hi = st.y_lo.tolist(), st.y_hi.tolist()
    up, down = _Lines(st.up_c, st.up_s), _Lines(st.low_c, st.low_s)
    h = l_next = 0.0
    for i in range(n - 2, -1, -1):
        lo_y, hi_y = max(l_next, y_lo[i]), min(h, y_hi[i])
        if lo_y > hi_y + SLACK:
            return None
        if h >= peak_a[i] and l_next <= peak_b[i]:
            top = x_max[i]
        else:
            y = hi_y if hi_y < peak_a[i] else lo_y
            top = up.lowest(i, y)
            if down.highest(i, y) > top + SLACK:
                return None
        if lo_y <= trough_b[i] and hi_y >= trough_a[i]:
            bottom = x_min[i]
        else:
            bottom = down.highest(i, hi_y if hi_y < trough_a[i] else lo_y)
        h, l_next = top, max(bottom, 0.0)
        high[i], low[i] = h, l_next
    if l_next > start + SLACK or start > h + SLACK:  # the start cannot reach the end
        return None
    # forward: the largest u, i.e. the largest y, that stays in K_{i+1}
    x = np.zeros(n)
    ahead = (st.next_c - st.next_s * high[:-1, None]).min(axis=1).tolist()
    hs, ls = high.tolist(), low.tolist()
    ahead_of = _Lines(st.next_c, st.next_s)
    xi = x[0] = start
    for i in range(n - 1):
        y = ahead[i] if xi == hs[i] else ahead_of.lowest(i, xi)
        y = min(y, hs[i + 1])
        if y < ls[i + 1] - SLACK:
            return None
        xi = max(y, 0.0)
        x[i + 1] = xi
    return x


class _Lines:
    """Per stage, the lines ``c - k z`` of its rows (padding: ``c`` infinite, ``k`` zero)."""

    def __init__(self, c: FloatArray, k: FloatArray) -> None:
        self._c, self._k = c, k

    def lowest(self, i: int, z: float) -> float:
        """``min (c - k z)`` over stage ``i``'s lines."""
        values = [c - k * z for c, k in zip(self._c[i].tolist(), self._k[i].tolist(), strict=True)]
        return float(min(values))

    def highest(self, i: int, z: float) -> float:
        """``max (c - k z)`` over stage ``i``'s lines."""
        values = [c - k * z for c, k in zip(self._c[i].tolist(), self._k[i].tolist(), strict=True)]
        return float(max(values))
