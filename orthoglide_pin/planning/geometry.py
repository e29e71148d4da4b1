"""Exact path geometry: lines, arcs and helices parametrised by their arc length.

Each piece is evaluated in closed form, vectorised over arc lengths ``s`` [m]
from its start: the point ``p(s)`` [m], the unit tangent ``p'(s)`` [-] and the
curvature vector ``p''(s)`` [1/m]. A helix of radius ``r``, swept angle
``phi`` (signed, about the normal ``n = u x v``) and rise ``h n`` has length
``L = sqrt((r phi)^2 + h^2)``, angle ``theta = theta0 + phi s / L`` and::

    p    = c + r (cos(theta) u + sin(theta) v) + h (s / L) n
    p'   = (phi / L) r (-sin(theta) u + cos(theta) v) + (h / L) n
    p''  = -(phi / L)^2 r (cos(theta) u + sin(theta) v)
    p''' = -(phi / L)^3 r (-sin(theta) u + cos(theta) v)

A circular arc is the helix with ``h = 0``; a line has ``p'' = p''' = 0``.

An arc whose radii to the start ``r0`` and to the end ``r1`` differ (within
LinuxCNC's tolerance, :mod:`orthoglide_pin.program.arcs`) is LinuxCNC's
spiral: ``r = r0 + (r1 - r0) theta / phi``, the rise likewise linear in the
angle. Its arc length ``s(theta)`` is integrated (Gauss-Legendre, exact to
rounding for a spiral's smooth speed) and inverted by Newton's method, so a
spiral too is parametrised by its arc length: the points are on LinuxCNC's
spiral, the tangent is unit and the curvature vector is the spiral's own.
Corner blends (:mod:`~orthoglide_pin.planning.blend`) are pieces of a third
kind, with the same methods.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Gauss-Legendre points of a spiral's length.
GAUSS_POINTS = 16
#: A radius change below this is rounding: the arc is a circle [m].
SPIRAL_MIN = 1e-12
#: Newton steps of a spiral's angle from its arc length (quadratic from a close start).
SPIRAL_NEWTON = 4


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a x b`` of two 3-vectors (``np.cross`` costs ~20 times more on them)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


@dataclass(frozen=True)
class Piece:
    """A line, a helical arc or a corner blend, parametrised by arc length from its start.

    Attributes:
        block: Index of the program block it belongs to.
        length: Its length [m].
        feed: Its path-speed cap [m/s], ``None`` for a rapid move.
        origin: A line's start point, or an arc's centre [m], shape (3,).
        u: A line's unit direction, or the arc frame's first axis (towards the
            start point), shape (3,).
        v: The arc frame's second axis (``None`` for a line), shape (3,).
        radius: Arc radius [m] (0 for a line).
        sweep: Signed swept angle about ``u x v`` [rad] (0 for a line).
        rise: Helix rise along ``u x v`` [m] (0 for a plain arc).
        spiral: Change of the radius from start to end [m] (0 for a circle).
    """

    block: int
    length: float
    feed: float | None
    origin: FloatArray
    u: FloatArray
    v: FloatArray | None = None
    radius: float = 0.0
    sweep: float = 0.0
    rise: float = 0.0
    spiral: float = 0.0

    @property
    def is_arc(self) -> bool:
        """Whether it is an arc or a helix."""
        return self.v is not None

    @property
    def is_blend(self) -> bool:
        """Whether it is a corner blend (:mod:`~orthoglide_pin.planning.blend`)."""
        return False

    def evaluate(self, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p``, ``p'`` and ``p''`` at arc lengths ``s`` [m], shape (n,): each (n, 3)."""
        s = np.asarray(s, dtype=float)[:, None]
        if self.v is None:
            p = self.origin + s * self.u
            return p, np.broadcast_to(self.u, p.shape).copy(), np.zeros_like(p)
        if self.spiral != 0.0:
            return self._spiral(s)
        n = _cross(self.u, self.v)
        rate = self.sweep / self.length
        theta = rate * s
        cos, sin = np.cos(theta), np.sin(theta)
        radial = cos * self.u + sin * self.v
        p = self.origin + self.radius * radial + (self.rise / self.length) * s * n
        dp = rate * self.radius * (-sin * self.u + cos * self.v) + (self.rise / self.length) * n
        ddp = -(rate * rate) * self.radius * radial
        return p, dp, ddp

    def spiral_angle(self, s: FloatArray) -> FloatArray:
        """A spiral's angle [rad] at arc lengths ``s`` [m], same shape (see the module)."""
        phi = self.sweep
        dr, rise = self.spiral / phi, self.rise / phi  # [m/rad]
        x, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
        s = np.asarray(s, dtype=float)
        theta = phi * s / self.length
        for _ in range(SPIRAL_NEWTON):
            t = 0.5 * theta[..., None] * (x + 1.0)
            speed = np.sqrt((self.radius + dr * t) ** 2 + dr * dr + rise * rise)
            length = 0.5 * np.abs(theta) * (speed @ w)
            here = np.sqrt((self.radius + dr * theta) ** 2 + dr * dr + rise * rise)
            theta = theta - np.sign(phi) * (length - s) / here
        return np.asarray(theta, dtype=np.float64)

    def _spiral(self, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p``, ``p'`` and ``p''`` of a spiral (see the module), ``s`` of shape (n, 1)."""
        assert self.v is not None
        n = _cross(self.u, self.v)
        phi = self.sweep
        theta = self.spiral_angle(s)
        cos, sin = np.cos(theta), np.sin(theta)
        radial = cos * self.u + sin * self.v
        across = -sin * self.u + cos * self.v
        dr = self.spiral / phi  # [m/rad]
        r = self.radius + dr * theta
        p = self.origin + r * radial + (self.rise / phi) * theta * n
        d1 = dr * radial + r * across + (self.rise / phi) * n  # dp/dtheta
        d2 = 2.0 * dr * across - r * radial
        speed = np.linalg.norm(d1, axis=1, keepdims=True)
        tangent = d1 / speed
        normal_part = d2 - np.sum(d2 * tangent, axis=1, keepdims=True) * tangent
        return p, tangent, normal_part / speed**2

    def third(self, s: FloatArray) -> FloatArray:
        """``p'''`` at arc lengths ``s`` [m], shape (n,): (n, 3) [1/m^2]."""
        s = np.asarray(s, dtype=float)[:, None]
        if self.v is None:
            return np.zeros((s.shape[0], 3))
        rate = self.sweep / self.length
        theta = rate * s
        tangent = -np.sin(theta) * self.u + np.cos(theta) * self.v
        radius = self.radius + self.spiral * s / self.length  # a spiral's local radius
        return np.asarray(-(rate**3) * radius * tangent)

    def end_tangent(self) -> FloatArray:
        """The unit tangent at the end, shape (3,)."""
        return np.asarray(self.evaluate(np.array([self.length]))[1][0], dtype=np.float64)

    def start_tangent(self) -> FloatArray:
        """The unit tangent at the start, shape (3,)."""
        return np.asarray(self.evaluate(np.array([0.0]))[1][0], dtype=np.float64)


def line_piece(block: int, a: FloatArray, b: FloatArray, feed: float | None) -> Piece:
    """The line from ``a`` to ``b`` [m] (of non-zero length)."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    length = float(np.linalg.norm(d))
    return Piece(block, length, feed, np.array(a, dtype=float), d / length)


def arc_piece(
    block: int,
    start: FloatArray,
    centre: FloatArray,
    plane: tuple[int, int, int],
    sweep: float,
    rise: float,
    feed: float | None,
    end_radius: float | None = None,
) -> Piece:
    """The arc (helix when ``rise != 0``, spiral when the radii differ) of a G2/G3 block.

    Args:
        block: Index of the block.
        start: Start point [m], shape (3,).
        centre: Centre in the start's plane [m], shape (3,).
        plane: The plane's axes and normal, e.g. ``(0, 1, 2)`` for G17.
        sweep: Signed angle about the plane's normal [rad].
        rise: Motion along the normal [m].
        feed: Path-speed cap [m/s] (``None`` for a rapid move).
        end_radius: Radius at the end [m] (``None``: the start's, a circle).
    """
    k = plane[2]
    e = np.eye(3)
    radial = np.asarray(start, dtype=float) - np.asarray(centre, dtype=float)
    radius = float(np.linalg.norm(radial))
    u = radial / radius
    v = np.cross(e[k], u)  # in the plane, a quarter turn counter-clockwise from u
    spiral = 0.0 if end_radius is None else float(end_radius) - radius
    if abs(spiral) <= SPIRAL_MIN:
        spiral = 0.0
        length = math.hypot(radius * sweep, rise)
    if spiral == 0.0:
        length = math.hypot(radius * sweep, rise)
    else:
        x, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
        r = radius + spiral * 0.5 * (x + 1.0)  # along the angle, 0 to sweep
        speed = np.sqrt((r * sweep) ** 2 + spiral**2 + rise**2)  # |dp/dt| for t in [0, 1]
        length = float(0.5 * w @ speed)
    return Piece(
        block, length, feed, np.array(centre, dtype=float), u, v, radius, sweep, rise, spiral
    )


def sub_piece(piece: Piece, start: float, end: float) -> Piece:
    """The part of a line or an arc between arc lengths ``start < end`` [m] from its start."""
    frac = (end - start) / piece.length
    if piece.v is None:
        return Piece(
            piece.block, end - start, piece.feed, piece.origin + start * piece.u, piece.u.copy()
        )
    theta = piece.sweep * start / piece.length
    if piece.spiral != 0.0:
        a, b = (float(x) for x in piece.spiral_angle(np.array([start, end])))
        dr, rise = piece.spiral / piece.sweep, piece.rise / piece.sweep
        cos, sin = math.cos(a), math.sin(a)
        n = _cross(piece.u, piece.v)
        return Piece(
            piece.block, end - start, piece.feed, piece.origin + rise * a * n,
            cos * piece.u + sin * piece.v, -sin * piece.u + cos * piece.v,
            piece.radius + dr * a, b - a, rise * (b - a), dr * (b - a),
        )  # fmt: skip
    cos, sin = math.cos(theta), math.sin(theta)
    n = _cross(piece.u, piece.v)
    return Piece(
        piece.block,
        end - start,
        piece.feed,
        piece.origin + (piece.rise * start / piece.length) * n,
        cos * piece.u + sin * piece.v,
        -sin * piece.u + cos * piece.v,
        piece.radius + piece.spiral * start / piece.length,
        piece.sweep * frac,
        piece.rise * frac,
        piece.spiral * frac,
    )
