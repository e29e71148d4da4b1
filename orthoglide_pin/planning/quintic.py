"""Quintic Bezier curves in space, evaluated by their arc length.

A quintic ``B(w) = sum_i C(5, i) w^i (1 - w)^(5 - i) P_i``, ``0 <= w <= 1``,
is held in the power basis about its first control point (so that its
derivatives keep the digits the position would take). Its arc length
``s(w) = integral |B'|`` is computed by Gauss-Legendre quadrature (8 nodes) on
:data:`SUBDIVISIONS` equal spans of ``w``, exact to rounding for this smooth
integrand, and inverted by Newton's method: ``p(s)``, the unit tangent
``p' = B' / |B'|``, the curvature vector ``p'' = (B'' - (B'' . p') p') / |B'|^2``
and the third derivative follow. :func:`distances` gives the distance from
points to the curve (the closest of 33 samples, then Newton's method on
``(B - x) . B' = 0``).
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Spans of the arc-length quadrature, and Newton steps of its inversion.
SUBDIVISIONS: Final[int] = 32
NEWTON_STEPS: Final[int] = 4
#: Newton steps of a projection on a piece or a blend.
PROJECTION_STEPS: Final[int] = 3

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(8)
#: Bernstein to power basis of degree 5: ``c = _TO_POWER @ P``.
_TO_POWER = np.array(
    [[math.comb(5, j) * math.comb(j, i) * (-1) ** (j - i) for i in range(6)] for j in range(6)],
    dtype=float,
)
_SAMPLES = np.linspace(0.0, 1.0, 33)
_BOUNDS = np.linspace(0.0, 1.0, SUBDIVISIONS + 1)
_BOUNDS.flags.writeable = False
_DEGREES = np.arange(6)
#: ``j! / (j - order)!`` for ``j >= order``, else 0: row ``order``.
_FALLING = np.array([[math.perm(j, k) for j in range(6)] for k in range(4)], dtype=float)
_SAMPLE_BASIS = _SAMPLES[:, None] ** _DEGREES


def polynomial(coef: FloatArray, w: FloatArray, order: int) -> FloatArray:
    """The ``order``-th derivative of the power-basis polynomial at ``w``, (n, 3)."""
    w = np.asarray(w, dtype=float)[:, None]
    scaled = _FALLING[order, order:, None] * coef[order:]  # the derivative's coefficients
    out = np.broadcast_to(scaled[-1], (w.shape[0], coef.shape[1])).copy()
    for c in scaled[-2::-1]:  # Horner's scheme: no powers
        out *= w
        out += c
    return np.asarray(out)


def power_coefficients(control: FloatArray) -> FloatArray:
    """Power-basis coefficients of the quintic of ``control`` (6, 3) about its first point."""
    control = np.asarray(control, dtype=float)
    return np.asarray(_TO_POWER @ (control - control[0]))


class Quintic:
    """A quintic Bezier curve in space, evaluated by its arc length.

    Args:
        control: The six control points [m], shape (6, 3).
    """

    def __init__(self, control: FloatArray) -> None:
        self.control = np.array(control, dtype=float)
        # about the first point: the derivatives do not lose the digits of the position
        self._coef = _TO_POWER @ (self.control - self.control[0])
        bounds = _BOUNDS  # shared by every curve: a long program holds many
        h = 1.0 / SUBDIVISIONS
        nodes = bounds[:-1, None] + 0.5 * h * (_GAUSS_X + 1.0)
        speed = self._speed(nodes.ravel()).reshape(nodes.shape)
        spans = 0.5 * h * speed @ _GAUSS_W
        self._bounds = bounds
        self._cum = np.concatenate([[0.0], np.cumsum(spans)])
        self.length = float(self._cum[-1])

    @classmethod
    def made(cls, control: FloatArray, coef: FloatArray, cum: FloatArray) -> Quintic:
        """A curve whose coefficients and arc-length table were computed with others'.

        Args:
            control: The six control points [m], (6, 3).
            coef: Their power-basis coefficients about the first, (6, 3).
            cum: The arc length at each span bound [m], (SUBDIVISIONS + 1,)
                (:mod:`~orthoglide_pin.planning.blend_batch`).
        """
        out = cls.__new__(cls)
        out.control, out._coef, out._bounds, out._cum = control, coef, _BOUNDS, cum
        out.length = float(cum[-1])
        return out

    def derivative(self, w: FloatArray, order: int) -> FloatArray:
        """``d^order B / dw^order`` at parameters ``w``, (n, 3)."""
        out = polynomial(self._coef, np.asarray(w, dtype=float), order)
        return out + self.control[0] if order == 0 else out

    def _speed(self, w: FloatArray) -> FloatArray:
        return np.asarray(np.linalg.norm(self.derivative(w, 1), axis=1))

    def parameter(self, s: FloatArray) -> FloatArray:
        """The parameters ``w`` at arc lengths ``s`` [m] from the start, (n,)."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.length)
        k = np.clip(np.searchsorted(self._cum, s, side="right") - 1, 0, SUBDIVISIONS - 1)
        lo, s_lo = self._bounds[k], self._cum[k]
        span = self._cum[k + 1] - s_lo
        h = 1.0 / SUBDIVISIONS
        w = lo + h * np.where(span > 0.0, (s - s_lo) / np.where(span > 0.0, span, 1.0), 0.0)
        for _ in range(NEWTON_STEPS):
            nodes = lo[:, None] + 0.5 * (w - lo)[:, None] * (_GAUSS_X + 1.0)
            inner = self._speed(nodes.ravel()).reshape(nodes.shape) @ _GAUSS_W
            residual = s_lo + 0.5 * (w - lo) * inner - s
            w = np.clip(w - residual / self._speed(w), lo, lo + h)
        return np.asarray(np.where(s >= self.length, 1.0, w))

    def evaluate(self, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p``, ``p'`` and ``p''`` at arc lengths ``s`` [m], shape (n,): each (n, 3)."""
        w = self.parameter(s)
        d1, d2 = self.derivative(w, 1), self.derivative(w, 2)
        speed = np.linalg.norm(d1, axis=1)[:, None]
        t = d1 / speed
        k = (d2 - np.sum(d2 * t, axis=1)[:, None] * t) / speed**2
        return self.derivative(w, 0), t, k

    def third(self, s: FloatArray) -> FloatArray:
        """``p'''`` at arc lengths ``s`` [1/m^2], (n, 3) (see :meth:`Piece.third`)."""
        w = self.parameter(s)
        d1, d2, d3 = (self.derivative(w, j) for j in (1, 2, 3))
        sig = np.linalg.norm(d1, axis=1)[:, None]
        sig1 = np.sum(d1 * d2, axis=1)[:, None] / sig  # d|B'|/dw
        sig2 = (
            np.sum(d2 * d2, axis=1)[:, None] + np.sum(d1 * d3, axis=1)[:, None] - sig1**2
        ) / sig
        return np.asarray(
            d3 / sig**3
            - 3.0 * d2 * sig1 / sig**4
            - d1 * sig2 / sig**4
            + 3.0 * d1 * sig1**2 / sig**5
        )


def _bases(w: FloatArray) -> FloatArray:
    """The power basis and its first two derivatives at ``w``, (3, n, 6)."""
    powers = np.asarray(w, dtype=float)[:, None] ** _DEGREES
    out = np.zeros((3, *powers.shape))
    out[0] = powers
    out[1][:, 1:] = _FALLING[1, 1:] * powers[:, :-1]
    out[2][:, 2:] = _FALLING[2, 2:] * powers[:, :-2]
    return np.asarray(out)


def distances(coef: FloatArray, x: FloatArray) -> FloatArray:
    """Distances from points ``x`` (n, 3) to the quintic of power coefficients ``coef``."""
    pts = _SAMPLE_BASIS @ coef
    dist = np.linalg.norm(x[:, None, :] - pts[None, :, :], axis=2)
    i = np.argmin(dist, axis=1)
    lo, hi = _SAMPLES[np.maximum(i - 1, 0)], _SAMPLES[np.minimum(i + 1, _SAMPLES.size - 1)]
    w = _SAMPLES[i]
    for _ in range(PROJECTION_STEPS):  # Newton on (B - x) . B' = 0 within the bracket
        r, d1, d2 = _bases(w) @ coef
        r = r - x
        slope = np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", r, d2)
        ok = slope > 0.0
        step = np.where(ok, np.einsum("ij,ij->i", r, d1) / np.where(ok, slope, 1.0), 0.0)
        w = np.clip(w - step, lo, hi)
    best = np.linalg.norm(polynomial(coef, w, 0) - x, axis=1)
    return np.asarray(np.minimum(best, dist[np.arange(x.shape[0]), i]))


_FALLING_LISTS = [_FALLING[k, k:].tolist() for k in range(3)]


def _derivative_rows(c: list[list[float]], order: int) -> list[list[float]]:
    """The coefficients of the ``order``-th derivative, lowest degree first."""
    return [[f * x for x in c[j + order]] for j, f in enumerate(_FALLING_LISTS[order])]


def _at(rows: list[list[float]], w: float) -> tuple[float, float, float]:
    """A polynomial of coefficients ``rows`` at ``w`` (Horner's scheme), three floats."""
    x, y, z = rows[-1]
    for a, b, c in rows[-2::-1]:
        x, y, z = x * w + a, y * w + b, z * w + c
    return x, y, z


def distance(coef: FloatArray, x: FloatArray) -> float:
    """:func:`distances` of one point ``x`` (3,) (plain floats after the samples: faster)."""
    pts = _SAMPLE_BASIS @ coef
    diff = x - pts
    dist = np.sqrt(np.sum(diff * diff, axis=1))
    i = int(np.argmin(dist))
    lo, hi = float(_SAMPLES[max(i - 1, 0)]), float(_SAMPLES[min(i + 1, _SAMPLES.size - 1)])
    w = float(_SAMPLES[i])
    c = coef.tolist()
    r0, r1, r2 = (_derivative_rows(c, k) for k in range(3))
    x0, x1, x2 = x.tolist()
    for _ in range(PROJECTION_STEPS):  # Newton on (B - x) . B' = 0 within the bracket
        p0, p1, p2 = _at(r0, w)
        e0, e1, e2 = p0 - x0, p1 - x1, p2 - x2
        a0, a1, a2 = _at(r1, w)
        b0, b1, b2 = _at(r2, w)
        slope = a0 * a0 + a1 * a1 + a2 * a2 + (e0 * b0 + e1 * b1 + e2 * b2)
        step = (e0 * a0 + e1 * a1 + e2 * a2) / slope if slope > 0.0 else 0.0
        w = min(max(w - step, lo), hi)
    p0, p1, p2 = _at(r0, w)
    e0, e1, e2 = p0 - x0, p1 - x1, p2 - x2
    return min(math.sqrt(e0 * e0 + e1 * e1 + e2 * e2), float(dist[i]))
