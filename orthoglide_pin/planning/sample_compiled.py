"""Corner blends sampled by arc length in one compiled loop (numba).

:func:`~orthoglide_pin.planning.sample_batch.sample_batch` evaluates the
blends of a section (quintics, :class:`~orthoglide_pin.planning.quintic.Quintic`)
at their samples' arc lengths: the parameter ``w`` of each arc length is found
by Newton's method on the Gauss-Legendre arc length of its span, then the
point, the unit tangent and the curvature vector follow. In arrays each of
those steps makes temporaries of (samples, nodes, 3) numbers;
:func:`blends_compiled` runs the same arithmetic sample by sample, the Gauss
sum in node order, so it agrees with the array version to rounding
(``tests/planning/test_sample_batch.py``). Without numba
(:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE` false) the array
version runs.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.quintic import _FALLING, _GAUSS_W, _GAUSS_X, NEWTON_STEPS
from orthoglide_pin.planning.reach_compiled import AVAILABLE, jit

FloatArray = NDArray[np.float64]


def _derivative(
    coef: FloatArray, b: int, w: float, order: int, falling: FloatArray
) -> tuple[float, float, float]:
    """The ``order``-th derivative of blend ``b``'s power-basis polynomial at ``w``."""
    top = coef.shape[1] - 1
    x = falling[order, top] * coef[b, top, 0]
    y = falling[order, top] * coef[b, top, 1]
    z = falling[order, top] * coef[b, top, 2]
    for j in range(top - 1, order - 1, -1):
        x = x * w + falling[order, j] * coef[b, j, 0]
        y = y * w + falling[order, j] * coef[b, j, 1]
        z = z * w + falling[order, j] * coef[b, j, 2]
    return x, y, z


def _speed(coef: FloatArray, b: int, w: float, falling: FloatArray) -> float:
    x, y, z = _derivative(coef, b, w, 1, falling)
    return math.sqrt(x * x + y * y + z * z)


def _invert(
    coef: FloatArray,
    first: FloatArray,
    cum: FloatArray,
    bounds: FloatArray,
    s: FloatArray,
    which: NDArray[np.intp],
    falling: FloatArray,
    gauss_x: FloatArray,
    gauss_w: FloatArray,
    newton: int,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``p``, ``p'``, ``p''`` of the blends at local arc lengths ``s`` (see the module)."""
    n, spans = s.size, bounds.size - 1
    h = 1.0 / spans
    p, t, curv = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    for j in range(n):
        b = which[j]
        length = cum[b, spans]
        sj = min(max(s[j], 0.0), length)
        k = -1
        for i in range(spans + 1):
            if cum[b, i] <= sj:
                k += 1
        k = min(max(k, 0), spans - 1)
        lo, s_lo = bounds[k], cum[b, k]
        span = cum[b, k + 1] - s_lo
        w = lo + h * ((sj - s_lo) / span if span > 0.0 else 0.0)
        for _ in range(newton):
            inner = 0.0
            for g in range(gauss_x.size):
                inner += (
                    _speed(coef, b, lo + 0.5 * (w - lo) * (gauss_x[g] + 1.0), falling) * gauss_w[g]
                )
            residual = s_lo + 0.5 * (w - lo) * inner - sj
            step = min(max(w - residual / _speed(coef, b, w, falling), lo), lo + h)
            if step == w:  # converged: the later steps would not move it
                break
            w = step
        if sj >= length:
            w = 1.0
        d1 = _derivative(coef, b, w, 1, falling)
        d2 = _derivative(coef, b, w, 2, falling)
        d0 = _derivative(coef, b, w, 0, falling)
        speed = math.sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2])
        tx, ty, tz = d1[0] / speed, d1[1] / speed, d1[2] / speed
        along = d2[0] * tx + d2[1] * ty + d2[2] * tz
        sq = speed * speed
        p[j, 0], p[j, 1], p[j, 2] = d0[0] + first[b, 0], d0[1] + first[b, 1], d0[2] + first[b, 2]
        t[j, 0], t[j, 1], t[j, 2] = tx, ty, tz
        curv[j, 0] = (d2[0] - along * tx) / sq
        curv[j, 1] = (d2[1] - along * ty) / sq
        curv[j, 2] = (d2[2] - along * tz) / sq
    return p, t, curv


if AVAILABLE:
    _derivative = jit(_derivative)
    _speed = jit(_speed)
    _invert = jit(_invert)


def blends_compiled(
    coef: FloatArray,
    first: FloatArray,
    cum: FloatArray,
    bounds: FloatArray,
    s: FloatArray,
    which: NDArray[np.intp],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``p``, ``p'``, ``p''`` of blends at local arc lengths ``s``, compiled (see the module).

    Args:
        coef: The blends' power-basis coefficients about their first points, (m, 6, 3).
        first: Their first control points [m], (m, 3).
        cum: Their arc length at each span bound [m], (m, S + 1).
        bounds: The span bounds of ``w``, (S + 1,).
        s: Local arc lengths [m], (n,).
        which: The blend of each sample, (n,).

    Raises:
        RuntimeError: numba is not installed.
    """
    if not AVAILABLE:
        raise RuntimeError(
            "the compiled sampling needs numba (pip install 'orthoglide-pin[plan]')"
        )
    return _invert(
        np.ascontiguousarray(coef, dtype=np.float64),
        np.ascontiguousarray(first, dtype=np.float64),
        np.ascontiguousarray(cum, dtype=np.float64),
        np.ascontiguousarray(bounds, dtype=np.float64),
        np.ascontiguousarray(s, dtype=np.float64),
        np.ascontiguousarray(which, dtype=np.intp),
        _FALLING,
        np.ascontiguousarray(_GAUSS_X),
        np.ascontiguousarray(_GAUSS_W),
        NEWTON_STEPS,
    )
