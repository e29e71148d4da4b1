"""Corner blends sampled by arc length in one compiled loop (numba).

:func:`~orthoglide_pin.planning.sample_batch.sample_batch` evaluates the
blends of a section (quintics, :class:`~orthoglide_pin.planning.quintic.Quintic`)
at their samples' arc lengths: the parameter ``w`` of each arc length is found
by Newton's method on the Gauss-Legendre arc length of its span, then the
point, the unit tangent and the curvature vector follow. In arrays each of
those steps makes temporaries of (samples, nodes, 3) numbers;
:func:`blends_compiled` runs the same arithmetic sample by sample, the Gauss
sum in node order, and uses that the samples of a blend come in order and
close together. A sample's span is found by moving on from the previous
sample's; its iteration starts from the previous sample's ``w`` carried along
the curve to second order (``dw/ds = 1/|B'|``, ``d2w/ds2 = -(t . B'')/|B'|^3``)
instead of the linear guess in its span. Each Gauss arc length ``S(w)`` is
then followed by the step ``d`` that solves the arc length's Taylor series at
``w`` to third order (``S' = v = |B'|``, ``S'' = v'``, ``S''' = v''``, from
``B'``, ``B''`` and ``B'''``): when ``d`` is below :data:`TAYLOR` span widths,
the series' remainder (of order ``d^4``) is below rounding and ``w + d`` is
the answer; otherwise a Newton step is taken and the arc length evaluated
again, until a step is below :data:`CONVERGED` span widths. Nearly every
sample costs one Gauss sum (eight speeds) instead of three or four; the
polynomials' coefficients are multiplied out once per blend
(:func:`blends_compiled`). The samples agree with the array version to
rounding (``tests/planning/test_sample_batch.py``). Without numba
(:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE` false) the array
version runs.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import jit
from orthoglide_pin.planning.quintic import _FALLING, _GAUSS_W, _GAUSS_X, NEWTON_STEPS
from orthoglide_pin.planning.reach_compiled import AVAILABLE

FloatArray = NDArray[np.float64]

#: A Newton step below this many span widths ends the iteration [-].
CONVERGED: Final[float] = 1e-9
#: A gap below this many span widths is closed by the arc length's Taylor series [-].
TAYLOR: Final[float] = 1e-4


def _poly(der: FloatArray, order: int, b: int, u: float) -> tuple[float, float, float]:
    """The ``order``-th derivative of blend ``b`` at ``u``, from ``der`` (:func:`blends_compiled`).

    The zeros that pad the higher derivatives' coefficients leave Horner's sums unchanged.
    """
    c = der[order, b]
    x = ((((c[0, 5] * u + c[0, 4]) * u + c[0, 3]) * u + c[0, 2]) * u + c[0, 1]) * u + c[0, 0]
    y = ((((c[1, 5] * u + c[1, 4]) * u + c[1, 3]) * u + c[1, 2]) * u + c[1, 1]) * u + c[1, 0]
    z = ((((c[2, 5] * u + c[2, 4]) * u + c[2, 3]) * u + c[2, 2]) * u + c[2, 1]) * u + c[2, 0]
    return x, y, z


def _speed(d1: FloatArray, b: int, u: float) -> float:
    """``|B'(u)|`` of blend ``b`` from its first derivative's coefficients ``d1`` (m, 3, 5)."""
    x = (((d1[b, 0, 4] * u + d1[b, 0, 3]) * u + d1[b, 0, 2]) * u + d1[b, 0, 1]) * u + d1[b, 0, 0]
    y = (((d1[b, 1, 4] * u + d1[b, 1, 3]) * u + d1[b, 1, 2]) * u + d1[b, 1, 1]) * u + d1[b, 1, 0]
    z = (((d1[b, 2, 4] * u + d1[b, 2, 3]) * u + d1[b, 2, 2]) * u + d1[b, 2, 1]) * u + d1[b, 2, 0]
    return math.sqrt(x * x + y * y + z * z)


def _arc(
    d1: FloatArray,
    b: int,
    lo: float,
    w: float,
    gauss_x: FloatArray,
    gauss_w: FloatArray,
    speeds: FloatArray,
) -> float:
    """The Gauss arc length of blend ``b`` over ``[lo, w]``: nodes apart, then summed in order."""
    half = 0.5 * (w - lo)
    for g in range(gauss_x.size):
        speeds[g] = _speed(d1, b, lo + half * (gauss_x[g] + 1.0))
    inner = 0.0
    for g in range(gauss_x.size):
        inner += speeds[g] * gauss_w[g]
    return half * inner


def _close(der: FloatArray, b: int, w: float, residual: float) -> float:
    """The step ``d`` that zeroes ``residual + S(w + d) - S(w)``, ``S`` to third order at ``w``.

    ``dS/dw = |B'| = v``, ``dv/dw = (B' . B'') / v`` and
    ``d2v/dw2 = (|B''|^2 + B' . B''' - (dv/dw)^2) / v``; the cubic solved by Newton's method.
    """
    x1, y1, z1 = _poly(der, 1, b, w)
    x2, y2, z2 = _poly(der, 2, b, w)
    x3, y3, z3 = _poly(der, 3, b, w)
    v = math.sqrt(x1 * x1 + y1 * y1 + z1 * z1)
    dv = (x1 * x2 + y1 * y2 + z1 * z2) / v
    ddv = (x2 * x2 + y2 * y2 + z2 * z2 + x1 * x3 + y1 * y3 + z1 * z3 - dv * dv) / v
    d = -residual / v
    for _ in range(3):
        gap = residual + d * (v + d * (0.5 * dv + d * ddv / 6.0))
        d -= gap / (v + d * (dv + 0.5 * d * ddv))
    return d


def _invert(
    der: FloatArray,
    first: FloatArray,
    cum: FloatArray,
    bounds: FloatArray,
    s: FloatArray,
    which: NDArray[np.intp],
    rows: NDArray[np.intp],
    p: FloatArray,
    t: FloatArray,
    curv: FloatArray,
    gauss_x: FloatArray,
    gauss_w: FloatArray,
    newton: int,
) -> None:
    """``p``, ``p'``, ``p''`` at local arc lengths ``s`` into rows ``rows`` (see the module)."""
    d1 = der[1]
    n, spans = s.size, bounds.size - 1
    h = 1.0 / spans
    speeds = np.empty(gauss_x.size)
    b_prev, k, s_prev, w_prev, rate, bend = -1, 0, 0.0, 0.0, 0.0, 0.0
    for j in range(n):
        b = which[j]
        length = cum[b, spans]
        sj = min(max(s[j], 0.0), length)
        warm = b == b_prev and sj >= s_prev and math.isfinite(rate + bend)
        if not warm:
            k = 0
        while k < spans - 1 and cum[b, k + 1] <= sj:  # the last span starting at or below sj
            k += 1
        lo, s_lo = bounds[k], cum[b, k]
        if warm:  # w(s) to second order from the previous sample
            ds = sj - s_prev
            w = min(max(w_prev + ds * (rate + 0.5 * ds * bend), lo), lo + h)
        else:
            span = cum[b, k + 1] - s_lo
            w = lo + h * ((sj - s_lo) / span if span > 0.0 else 0.0)
        for _ in range(newton):
            residual = s_lo + _arc(d1, b, lo, w, gauss_x, gauss_w, speeds) - sj
            delta = _close(der, b, w, residual)
            if abs(delta) <= TAYLOR * h and lo <= w + delta <= lo + h:
                w += delta  # the arc length's Taylor series closes the gap to rounding
                break
            step = min(max(w - residual / _speed(d1, b, w), lo), lo + h)
            moved = abs(step - w)
            w = step
            if moved <= CONVERGED * h:  # the next step would move it by rounding only
                break
        if sj >= length:
            w = 1.0
        e1 = _poly(der, 1, b, w)
        e2 = _poly(der, 2, b, w)
        e0 = _poly(der, 0, b, w)
        speed = math.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])
        tx, ty, tz = e1[0] / speed, e1[1] / speed, e1[2] / speed
        along = e2[0] * tx + e2[1] * ty + e2[2] * tz
        sq = speed * speed
        # dw/ds = 1 / |B'| and d2w/ds2 = -(t . B'') / |B'|^3 for the next sample's guess
        b_prev, s_prev, w_prev, rate, bend = b, sj, w, 1.0 / speed, -along / (sq * speed)
        r = rows[j]
        p[r, 0], p[r, 1], p[r, 2] = e0[0] + first[b, 0], e0[1] + first[b, 1], e0[2] + first[b, 2]
        t[r, 0], t[r, 1], t[r, 2] = tx, ty, tz
        curv[r, 0] = (e2[0] - along * tx) / sq
        curv[r, 1] = (e2[1] - along * ty) / sq
        curv[r, 2] = (e2[2] - along * tz) / sq


if AVAILABLE:
    _poly = jit(_poly)
    _speed = jit(_speed)
    _arc = jit(_arc)
    _close = jit(_close)
    _invert = jit(_invert)


def blends_compiled(
    coef: FloatArray,
    first: FloatArray,
    cum: FloatArray,
    bounds: FloatArray,
    s: FloatArray,
    which: NDArray[np.intp],
    *,
    rows: NDArray[np.intp] | None = None,
    out: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``p``, ``p'``, ``p''`` of blends at local arc lengths ``s``, compiled (see the module).

    The coefficients of the derivatives of order 0 to 3 are multiplied out
    first (the products :func:`~orthoglide_pin.planning.quintic.polynomial`
    forms, padded with zeros to six), so that each evaluation is one Horner sum.

    Args:
        coef: The blends' power-basis coefficients about their first points, (m, 6, 3).
        first: Their first control points [m], (m, 3).
        cum: Their arc length at each span bound [m], (m, S + 1).
        bounds: The span bounds of ``w``, (S + 1,).
        s: Local arc lengths [m], (n,).
        which: The blend of each sample, (n,).
        rows: The row of ``out`` of each sample, (n,) (``None``: ``0 .. n - 1``).
        out: Three C-contiguous (N, 3) arrays written at ``rows`` and returned
            (``None``: new (n, 3) arrays).

    Raises:
        RuntimeError: numba is not installed.
    """
    if not AVAILABLE:
        raise RuntimeError(
            "the compiled sampling needs numba (pip install 'orthoglide-pin[plan]')"
        )
    coef = np.asarray(coef, dtype=np.float64)
    der = np.zeros((4, coef.shape[0], 3, 6))  # derivative k's coefficients, zeros above its degree
    for k in range(4):
        der[k, :, :, : 6 - k] = (_FALLING[k, k:, None] * coef[:, k:]).transpose(0, 2, 1)
    n = np.size(s)
    if out is None:
        out = (np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)))
    _invert(
        der,
        np.ascontiguousarray(first, dtype=np.float64),
        np.ascontiguousarray(cum, dtype=np.float64),
        np.ascontiguousarray(bounds, dtype=np.float64),
        np.ascontiguousarray(s, dtype=np.float64),
        np.ascontiguousarray(which, dtype=np.intp),
        np.arange(n, dtype=np.intp) if rows is None else np.ascontiguousarray(rows, dtype=np.intp),
        *out,
        np.ascontiguousarray(_GAUSS_X),
        np.ascontiguousarray(_GAUSS_W),
        NEWTON_STEPS,
    )
    return out
