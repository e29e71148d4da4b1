"""TOPP-RA's two passes compiled with numba: one loop over the stages, no temporaries.

:func:`~orthoglide_pin.planning.reachability.reach` builds every stage's
polygon for the whole grid in arrays (:func:`~orthoglide_pin.planning.reachability.stage_rows`,
:func:`~orthoglide_pin.planning.reachability.stages`), then runs its two
sequential passes in Python. :func:`reach_compiled` does the same arithmetic
stage by stage in one compiled loop: the rows of stage ``i`` are built from
the points ``i`` and ``i + 1``, its largest and smallest ``x`` found by
eliminating ``y`` row pair by row pair, and the backward step taken at once;
the forward pass reads each stage's lines bounding ``y`` from above as the
backward pass left them (:class:`ReachAgain`, which keeps the room for them
between its calls), or rebuilds them. The helpers are compiled into the
passes (a call passing arrays costs more than a stage's arithmetic). The
operations are those of the array version, in the same order, so the squared
speeds agree with it to rounding (``tests/planning/test_reach_compiled.py``).

numba comes with the ``[plan]`` extra. Without it (:data:`AVAILABLE` false)
the array version runs alone and gives the same plans, slower. The compiled
loop is cached on disk by numba after its first compilation.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin import _compiled
from orthoglide_pin._compiled import jit

FloatArray = NDArray[np.float64]

#: A normalised row whose ``P`` (or ``Q``) is below this bounds ``y`` (or ``x``) alone [-].
FLAT: Final[float] = 1e-12
#: Tolerated violation of a row, in ``x`` [(m/s)^2].
SLACK: Final[float] = 1e-12
#: The padding of the array version's packed rows (never binding).
_BIG: Final[float] = 1e300

#: Whether the compiled loops can run (numba is installed).
AVAILABLE: Final[bool] = _compiled.AVAILABLE


def _rows(
    s: FloatArray,
    a: FloatArray,
    b: FloatArray,
    c: FloatArray,
    x_bound: FloatArray,
    i: int,
    p: FloatArray,
    q: FloatArray,
    g: FloatArray,
) -> None:
    """Stage ``i``'s rows ``P x + Q y <= G``, normalised, into ``p``, ``q``, ``g`` (2m + 4,)."""
    m = a.shape[1]
    two_ds = 2.0 * (s[i + 1] - s[i])
    for k in range(m):
        here, there = a[i, k] / two_ds, a[i + 1, k] / two_ds
        p[k], q[k], g[k] = b[i, k] - here, here, 1.0 - c[i, k]
        p[m + k], q[m + k], g[m + k] = -there, there + b[i + 1, k], 1.0 - c[i + 1, k]
    j = 2 * m
    p[j], q[j], g[j] = -1.0, 0.0, 0.0
    p[j + 1], q[j + 1], g[j + 1] = 1.0, 0.0, x_bound[i]
    p[j + 2], q[j + 2], g[j + 2] = 0.0, -1.0, 0.0
    p[j + 3], q[j + 3], g[j + 3] = 0.0, 1.0, x_bound[i + 1]
    for k in range(j + 4):
        norm = math.hypot(p[k], q[k])
        if norm == 0.0:
            g[k] = math.inf if g[k] >= -SLACK else g[k]
        else:
            p[k], q[k], g[k] = p[k] / norm, q[k] / norm, g[k] / norm


def _next_y(p: FloatArray, q: FloatArray, g: FloatArray, x: float) -> float:
    """``min (G - P x) / Q`` over the rows bounding ``y`` from above (``BIG`` if none)."""
    out = _BIG
    for k in range(p.size):
        if math.isfinite(g[k]) and q[k] > FLAT:
            out = min(out, g[k] / q[k] - p[k] / q[k] * x)
    return out


def _y_range(p: FloatArray, q: FloatArray, g: FloatArray, x: float) -> tuple[float, float]:
    """The range of ``y`` of the stage at ``x`` (the array version's ``y_range``)."""
    lo, hi, y_lo, y_hi = -_BIG, _BIG, -math.inf, math.inf
    for k in range(p.size):
        if not math.isfinite(g[k]):
            continue
        if q[k] > FLAT:
            hi = min(hi, g[k] / q[k] - p[k] / q[k] * x)
        elif q[k] < -FLAT:
            lo = max(lo, g[k] / q[k] - p[k] / q[k] * x)
        if not (p[k] > FLAT or p[k] < -FLAT):
            if q[k] > 0.0:
                y_hi = min(y_hi, g[k] / q[k])
            elif q[k] < 0.0:
                y_lo = max(y_lo, g[k] / q[k])
    lo, hi = max(lo, y_lo), min(hi, y_hi)
    mid = 0.5 * (lo + hi) if lo > hi else lo
    return min(lo, mid), max(hi, mid)


def _lines(p: FloatArray, q: FloatArray, g: FloatArray, y: float, upper: bool) -> float:
    """``min (G - Q y) / P`` over rows with ``P > 0`` (``upper``), else ``max`` over ``P < 0``."""
    out = math.inf if upper else -math.inf
    for k in range(p.size):
        if not math.isfinite(g[k]):
            continue
        if upper and p[k] > FLAT:
            out = min(out, g[k] / p[k] - q[k] / p[k] * y)
        elif not upper and p[k] < -FLAT:
            out = max(out, g[k] / p[k] - q[k] / p[k] * y)
    return out


def _extent(
    p: FloatArray, q: FloatArray, g: FloatArray, ups: NDArray[np.intp], down: FloatArray
) -> tuple[bool, float, float]:
    """Whether the stage is settled, and its largest and smallest ``x`` (Fourier-Motzkin).

    ``ups``: room for the rows bounding ``y`` from above (p.size); ``down``: for
    those bounding it from below, (3, p.size).
    """
    down_p, down_q, down_g = down[0], down[1], down[2]
    x_max, x_min = math.inf, -math.inf
    for k in range(p.size):
        if not math.isfinite(g[k]) or q[k] > FLAT or q[k] < -FLAT:
            continue
        if abs(p[k]) <= FLAT and g[k] < -SLACK:
            return False, 0.0, 0.0
        if p[k] > FLAT:
            x_max = min(x_max, g[k] / p[k])
        elif p[k] < -FLAT:
            x_min = max(x_min, g[k] / p[k])
    n_up = n_down = 0
    for k in range(p.size):  # the rows bounding y from above; those from below, side by side
        if math.isfinite(g[k]):
            if q[k] > FLAT:
                ups[n_up] = k
                n_up += 1
            elif q[k] < -FLAT:
                down_p[n_down], down_q[n_down], down_g[n_down] = p[k], q[k], g[k]
                n_down += 1
    bad = False
    for iu in range(n_up):
        u = ups[iu]
        pu, qu, gu = p[u], q[u], g[u]
        for d in range(n_down):
            cc = qu * down_p[d] - down_q[d] * pu
            rr = qu * down_g[d] - down_q[d] * gu
            bound = rr / cc
            if abs(cc) <= FLAT:
                bad = bad or rr < -SLACK
            elif cc > FLAT:
                x_max = min(x_max, bound)
            else:
                x_min = max(x_min, bound)
    if bad:
        return False, 0.0, 0.0
    if x_min > x_max + SLACK or not math.isfinite(x_max):
        return False, 0.0, 0.0
    return True, x_max, min(x_min, x_max)


def _run(
    s: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray, x_bound: FloatArray,
    start: float, state: FloatArray, dirty: NDArray[np.bool_], line_c: FloatArray,
    line_k: FloatArray,
) -> bool:  # fmt: skip
    """Both passes, in place on ``state`` = ``(high, low, x)`` rows of a previous run (or zeros).

    ``line_c``, ``line_k``: room (n, 2m + 4) for the lines ``y <= c - k x`` of
    the stages taken backward, which the forward pass reads instead of
    building their rows again, or (0, 0): none kept (fresh memory costs about
    what it saves: :class:`ReachAgain` keeps its room between its calls).

    A stage is taken again when a point of its rows is ``dirty`` or what it
    receives from the stage before it in its pass (the bounds of the next
    stage, backward; the speed at its first point, forward) came out otherwise
    than stored; else it keeps the stored result, which the same arithmetic
    on the same inputs would give again. All points dirty, on zeros: every
    stage, the array version's ``reach``. Returns whether it settled.
    """
    n = s.size
    high, low, x = state[0], state[1], state[2]
    moved = np.zeros(n, dtype=np.bool_)  # bounds that came out otherwise than stored
    width = 2 * a.shape[1] + 4
    p, q, g = np.empty(width), np.empty(width), np.empty(width)
    ups, downs = np.empty(width, np.intp), np.empty((3, width))
    lines = np.full(n, -1, dtype=np.intp)  # the lines kept of each stage (-1: none)
    keep = line_c.shape[0] >= n and line_c.shape[1] >= width
    h = l_next = 0.0
    same = True  # the next stage's bounds as stored
    for i in range(n - 2, -1, -1):
        if same and not (dirty[i] or dirty[i + 1]):
            h, l_next = high[i], low[i]
            continue
        _rows(s, a, b, c, x_bound, i, p, q, g)
        ok, x_max, x_min = _extent(p, q, g, ups, downs)
        if not ok:
            return False
        if keep:
            count = 0
            for k in range(width):  # _next_y's lines
                if math.isfinite(g[k]) and q[k] > FLAT:
                    line_c[i, count], line_k[i, count] = g[k] / q[k], p[k] / q[k]
                    count += 1
            lines[i] = count
        peak_a, peak_b = _y_range(p, q, g, x_max)
        trough_a, trough_b = _y_range(p, q, g, x_min)
        y_lo, y_hi = -math.inf, math.inf
        for k in range(width):
            if math.isfinite(g[k]) and not (p[k] > FLAT or p[k] < -FLAT):
                if q[k] > 0.0:
                    y_hi = min(y_hi, g[k] / q[k])
                elif q[k] < 0.0:
                    y_lo = max(y_lo, g[k] / q[k])
        lo_y, hi_y = max(l_next, y_lo), min(h, y_hi)
        if lo_y > hi_y + SLACK:
            return False
        if h >= peak_a and l_next <= peak_b:
            top = x_max
        else:
            y = hi_y if hi_y < peak_a else lo_y
            top = _lines(p, q, g, y, True)
            if _lines(p, q, g, y, False) > top + SLACK:
                return False
        if lo_y <= trough_b and hi_y >= trough_a:
            bottom = x_min
        else:
            bottom = _lines(p, q, g, hi_y if hi_y < trough_a else lo_y, False)
        h, l_next = top, max(bottom, 0.0)
        same = h == high[i] and l_next == low[i]
        moved[i] = not same
        high[i], low[i] = h, l_next
    if l_next > start + SLACK or start > h + SLACK:
        return False
    xi = x[0] = start
    same = True  # the speed at the stage's first point as stored
    for i in range(n - 1):
        if same and not (dirty[i] or dirty[i + 1] or moved[i + 1]):
            xi = x[i + 1]
            continue
        if lines[i] >= 0:  # _next_y from the stage's lines
            y = _BIG
            for k in range(lines[i]):
                y = min(y, line_c[i, k] - line_k[i, k] * xi)
        else:
            _rows(s, a, b, c, x_bound, i, p, q, g)
            y = _next_y(p, q, g, xi)
        y = min(y, high[i + 1])
        if y < low[i + 1] - SLACK:
            return False
        xi = max(y, 0.0)
        same = xi == x[i + 1]
        x[i + 1] = xi
    return True


def _passes(
    s: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray, x_bound: FloatArray, start: float
) -> tuple[bool, FloatArray]:
    """Both passes (the array version's ``reach``); ``(settled, x)``."""
    state = np.zeros((3, s.size))
    dirty, none = np.ones(s.size, dtype=np.bool_), np.empty((0, 0))
    ok = _run(s, a, b, c, x_bound, start, state, dirty, none, none)
    return ok, state[2]


if AVAILABLE:
    _rows = jit(_rows, inline=True)
    _next_y = jit(_next_y, inline=True)
    _y_range = jit(_y_range, inline=True)
    _lines = jit(_lines, inline=True)
    _extent = jit(_extent, inline=True)
    _run = jit(_run)
    _passes = jit(_passes)


def reach_compiled(
    s: FloatArray,
    a: FloatArray,
    b: FloatArray,
    c: FloatArray,
    x_bound: FloatArray,
    start: float = 0.0,
) -> FloatArray | None:
    """:func:`~orthoglide_pin.planning.reachability.reach`, compiled (see the module).

    Args:
        s: Grid, increasing, (n,).
        a: Rows' coefficients of ``u`` at the grid points, (n, m): ``a u + b x + c <= 1``.
        b: Their coefficients of ``x``, (n, m).
        c: Their constants, (n, m).
        x_bound: Upper bound of ``x`` at the points (0 where the path must rest), (n,).
        start: The squared speed at the first point [(m/s)^2].

    Returns:
        The squared path speeds, (n,), or ``None`` when a stage cannot be settled.

    Raises:
        RuntimeError: numba is not installed (:data:`AVAILABLE` is false).
    """
    if not AVAILABLE:
        raise RuntimeError("the compiled passes need numba (pip install 'orthoglide-pin[plan]')")
    s, a, b, c, x_bound = (
        np.ascontiguousarray(v, dtype=np.float64) for v in (s, a, b, c, x_bound)
    )
    ok, x = _passes(s, a, b, c, x_bound, float(start))
    return x if ok else None


class ReachAgain:
    """:func:`reach_compiled` of one grid, planned again: only the stages whose rows changed.

    A window (:mod:`~orthoglide_pin.planning.windows`) re-planned after its
    verification has its rows changed on a few points only
    (:class:`~orthoglide_pin.planning.row_cache.RowCache`): the passes are taken
    again from there and stop where their bounds and speeds come out as before
    (:func:`_run`). Every stage is computed with the same arithmetic on the
    same inputs, so the squared speeds are those of :func:`reach_compiled`.
    """

    def __init__(self) -> None:
        self._last: tuple[FloatArray, ...] | None = None
        self._state: FloatArray | None = None
        self._start = math.nan
        self._room = np.empty((0, 0)), np.empty((0, 0))  # _run's lines, kept between calls
        self.stages = 0  # stages whose rows changed, over the calls (a measure)

    def reach(
        self, s: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray, x_bound: FloatArray,
        start: float = 0.0,
    ) -> FloatArray | None:  # fmt: skip
        """:func:`reach_compiled` (the same arguments and result)."""
        if not AVAILABLE:
            raise RuntimeError(
                "the compiled passes need numba (pip install 'orthoglide-pin[plan]')"
            )
        s, a, b, c, x_bound = (
            np.ascontiguousarray(v, dtype=np.float64) for v in (s, a, b, c, x_bound)
        )
        last, state = self._last, self._state
        dirty = np.ones(s.size, dtype=np.bool_)
        kept = last is not None and state is not None and start == self._start
        if kept and last is not None and last[0].shape == a.shape and np.array_equal(last[4], s):
            dirty = (last[3] != x_bound) | (last[0] != a).any(axis=1)
            dirty |= (last[1] != b).any(axis=1) | (last[2] != c).any(axis=1)
            if state is not None and not dirty.any():
                return np.array(state[2], dtype=np.float64)
        if state is None or dirty.all():
            state = np.zeros((3, s.size))
        self.stages += int(np.count_nonzero(dirty))
        work = state.copy()
        self._last, self._state = None, None
        room = (s.size, 2 * a.shape[1] + 4)
        if self._room[0].shape != room:
            self._room = np.empty(room), np.empty(room)
        if not _run(s, a, b, c, x_bound, float(start), work, dirty, *self._room):
            return None
        self._last, self._state, self._start = (a, b, c, x_bound, s), work, float(start)
        return np.array(work[2], dtype=np.float64)
