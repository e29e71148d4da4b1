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
Corner blends (:mod:`~orthoglide_pin.planning.blend`) are pieces of a third
kind, with the same methods.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


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
        n = _cross(self.u, self.v)
        rate = self.sweep / self.length
        theta = rate * s
        cos, sin = np.cos(theta), np.sin(theta)
        radial = cos * self.u + sin * self.v
        p = self.origin + self.radius * radial + (self.rise / self.length) * s * n
        dp = rate * self.radius * (-sin * self.u + cos * self.v) + (self.rise / self.length) * n
        ddp = -(rate * rate) * self.radius * radial
        return p, dp, ddp

    def third(self, s: FloatArray) -> FloatArray:
        """``p'''`` at arc lengths ``s`` [m], shape (n,): (n, 3) [1/m^2]."""
        s = np.asarray(s, dtype=float)[:, None]
        if self.v is None:
            return np.zeros((s.shape[0], 3))
        rate = self.sweep / self.length
        theta = rate * s
        tangent = -np.sin(theta) * self.u + np.cos(theta) * self.v
        return np.asarray(-(rate**3) * self.radius * tangent)

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
) -> Piece:
    """The arc (helix when ``rise != 0``) of a G2/G3 block.

    Args:
        block: Index of the block.
        start: Start point [m], shape (3,).
        centre: Centre in the start's plane [m], shape (3,).
        plane: The plane's axes and normal, e.g. ``(0, 1, 2)`` for G17.
        sweep: Signed angle about the plane's normal [rad].
        rise: Motion along the normal [m].
        feed: Path-speed cap [m/s] (``None`` for a rapid move).
    """
    k = plane[2]
    e = np.eye(3)
    radial = np.asarray(start, dtype=float) - np.asarray(centre, dtype=float)
    radius = float(np.linalg.norm(radial))
    u = radial / radius
    v = np.cross(e[k], u)  # in the plane, a quarter turn counter-clockwise from u
    length = math.hypot(radius * sweep, rise)
    return Piece(block, length, feed, np.array(centre, dtype=float), u, v, radius, sweep, rise)


def sub_piece(piece: Piece, start: float, end: float) -> Piece:
    """The part of a line or an arc between arc lengths ``start < end`` [m] from its start."""
    frac = (end - start) / piece.length
    if piece.v is None:
        return Piece(
            piece.block, end - start, piece.feed, piece.origin + start * piece.u, piece.u.copy()
        )
    theta = piece.sweep * start / piece.length
    cos, sin = math.cos(theta), math.sin(theta)
    n = _cross(piece.u, piece.v)
    return Piece(
        piece.block,
        end - start,
        piece.feed,
        piece.origin + (piece.rise * start / piece.length) * n,
        cos * piece.u + sin * piece.v,
        -sin * piece.u + cos * piece.v,
        piece.radius,
        piece.sweep * frac,
        piece.rise * frac,
    )
