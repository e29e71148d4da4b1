"""G2 corner blends: quintic Bezier curves matching position, tangent and curvature.

Under ``G64`` a corner between two pieces (line or arc, either side) is cut
by trimming an arc length ``l_a`` off the end of the incoming piece and
``l_b`` off the start of the outgoing one, and joining the two trim points
``P0`` and ``P5`` by a quintic Bezier curve ``B(w)``, ``0 <= w <= 1``, that
matches each piece's point, unit tangent ``T`` and curvature vector ``K`` at
the trim points (G2: the curvature, hence the acceleration at a given speed,
is continuous). Its control points are::

    P1 = P0 + alpha_a T0                P4 = P5 - alpha_b T1
    P2 = P0 + 2 alpha_a T0 + 5/4 alpha_a^2 K0
    P3 = P5 - 2 alpha_b T1 + 5/4 alpha_b^2 K1

so that ``B'(0) = 5 alpha_a T0`` and ``B''(0) = 25 alpha_a^2 K0`` (the
curvature vector of ``B`` at ``w = 0`` is ``K0``), and the same at the other
end. The tangent lengths are ``alpha = a(theta) l`` with
``a = SHAPE c / (SHAPE + c)``, ``c = cos(theta / 2)``, ``theta`` the angle
between ``T0`` and ``T1``: between two lines this choice gives, within 1 %,
the lowest peak curvature of the family for a given tolerance (4 to 10 %
above a circular fillet's, which is not G2).

The tolerance rule: the Hausdorff distance between the blend and the path it
replaces is at most ``P`` (the ``G64 P`` tolerance): every point of each lies
within ``P`` of the other. Between two lines the farthest point of the path
from the blend is the corner, and the blend's closest point to it is its
midpoint, ``l (16 - 25 a) / 16 sin(theta / 2)`` away (:func:`line_miss`): the
trims are then set in closed form so that the corner is missed by ``P``
exactly. Around an arc the distance is measured (:func:`deviation`) and the
trims found by a secant search in ``log l``, within ``[(1 - 2 FIT_TOL) P,
(1 - FIT_TOL) P]``. Each trim is capped at :data:`TRIM_SHARE` of its piece's
length (a piece keeps its middle when both its ends are blended) and, on an
arc of radius ``r``, at ``ARC_TRIM_ANGLE r``; a capped side keeps its cap
while the other grows, and the tolerance may then not be used up. A corner
whose turn exceeds :data:`MAX_TURN` (a move that turns back on itself) is not
blended. The same blend smooths a tangent joint with a step of curvature.

The curve is handed to the path by its arc length
(:class:`~orthoglide_pin.planning.quintic.Quintic`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.quintic import (
    PROJECTION_STEPS,
    Quintic,
    distance,
    distances,
    polynomial,
    power_coefficients,
)

FloatArray = NDArray[np.float64]

#: The tangent-length rule's constant [-] (see the module).
SHAPE: Final[float] = 0.58
#: Largest share of a piece's length a blend trims off it [-].
TRIM_SHARE: Final[float] = 0.5
#: Largest angle a blend trims off an arc [rad].
ARC_TRIM_ANGLE: Final[float] = math.pi / 4
#: The blend's closest point lies within ``[(1 - FIT_TOL) P, P]`` of the corner [-].
FIT_TOL: Final[float] = 1e-3
#: Corners turning by more than this are not blended [rad].
MAX_TURN: Final[float] = math.pi - 1e-3
#: Trims shorter than this are not made [m].
MIN_TRIM: Final[float] = 1e-9
DEVIATION_SAMPLES: Final[int] = 33
#: Tries of the tolerance search.
MAX_FITS: Final[int] = 40


#: A corner's two ends: ``(P0, T0, K0, P5, T1, K1)``.
Ends = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]


@dataclass(frozen=True, kw_only=True)
class BlendPiece(Piece):
    """A corner blend: a :class:`Quintic` by arc length.

    Its ``origin`` is its start point and ``u`` its start tangent.

    Attributes:
        curve: The quintic curve.
    """

    curve: Quintic

    @property
    def is_blend(self) -> bool:
        """Whether it is a corner blend."""
        return True

    def evaluate(self, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``p``, ``p'`` and ``p''`` at arc lengths ``s`` [m], shape (n,): each (n, 3)."""
        return self.curve.evaluate(s)

    def third(self, s: FloatArray) -> FloatArray:
        """``p'''`` at arc lengths ``s`` [m], shape (n,): (n, 3) [1/m^2]."""
        return self.curve.third(s)


@dataclass(frozen=True)
class CornerBlend:
    """The blend of one corner.

    Attributes:
        trim_in: Arc length cut off the end of the incoming piece [m].
        trim_out: Arc length cut off the start of the outgoing piece [m].
        piece: The blend between the two trim points.
        miss: Distance from the corner to the blend's closest point [m].
    """

    trim_in: float
    trim_out: float
    piece: BlendPiece
    miss: float


def tangent_lengths(turn: float) -> float:
    """The tangent-length ratio ``alpha / l`` for a turn ``turn`` [rad] (see the module)."""
    c = math.cos(0.5 * turn)
    return SHAPE * c / (SHAPE + c)


def control_points(ends: Ends, trims: tuple[float, float]) -> FloatArray:
    """The quintic's control points, (6, 3), from ``(P0, T0, K0, P5, T1, K1)`` and the trims."""
    p0, t0, k0, p5, t1, k1 = ends
    turn = math.acos(float(np.clip(t0 @ t1, -1.0, 1.0)))
    ratio = tangent_lengths(turn)
    a0, a1 = ratio * trims[0], ratio * trims[1]
    return np.array(
        [
            p0,
            p0 + a0 * t0,
            p0 + 2.0 * a0 * t0 + 1.25 * a0 * a0 * k0,
            p5 - 2.0 * a1 * t1 + 1.25 * a1 * a1 * k1,
            p5 - a1 * t1,
            p5,
        ]
    )


def corner_distance(control: FloatArray, corner: FloatArray) -> float:
    """Distance from ``corner`` [m] to the closest point of the quintic ``control`` [m]."""
    coef = power_coefficients(control)
    return distance(coef, corner - control[0])


def _to_piece(piece: Piece, lo: float, hi: float, x: FloatArray) -> FloatArray:
    """Distances from points ``x`` (n, 3) to ``piece`` between arc lengths ``lo`` and ``hi``.

    In closed form on a line and on a plain arc (the angle of ``x`` about the
    centre, within half a turn of the part's middle, clipped to the part), by
    Newton's method from the closest of 17 samples on a helix.
    """
    if piece.v is None and not piece.is_blend:
        s = np.clip((x - piece.origin) @ piece.u, lo, hi)
        return np.asarray(np.linalg.norm(piece.origin + s[:, None] * piece.u - x, axis=1))
    if piece.v is not None and piece.rise == 0.0 and piece.spiral == 0.0:
        rel = x - piece.origin
        angle = np.arctan2(rel @ piece.v, rel @ piece.u)
        rate = piece.sweep / piece.length  # [rad/m]
        middle = 0.5 * (lo + hi) * rate
        angle = middle + np.remainder(angle - middle + math.pi, 2.0 * math.pi) - math.pi
        s = np.clip(angle / rate, lo, hi)
        return np.asarray(np.linalg.norm(piece.evaluate(s)[0] - x, axis=1))
    grid = np.linspace(lo, hi, 17)
    pts = piece.evaluate(grid)[0]
    dist = np.linalg.norm(x[:, None, :] - pts[None, :, :], axis=2)
    i = np.argmin(dist, axis=1)
    s = grid[i]
    for _ in range(PROJECTION_STEPS):  # Newton on (p - x) . p' = 0 (p' a unit vector)
        p, t, k = piece.evaluate(s)
        r = p - x
        slope = 1.0 + np.sum(r * k, axis=1)
        step = np.where(slope > 0.0, np.sum(r * t, axis=1) / np.where(slope > 0, slope, 1), 0.0)
        s = np.clip(s - step, lo, hi)
    best = np.linalg.norm(piece.evaluate(s)[0] - x, axis=1)
    return np.asarray(np.minimum(best, dist[np.arange(x.shape[0]), i]))


def _peak(values: FloatArray) -> float:
    """The largest of samples of a smooth function, refined by a parabola through its top."""
    i = int(np.argmax(values))
    top = float(values[i])
    if 0 < i < values.size - 1:
        left, right = float(values[i - 1]), float(values[i + 1])
        bend = 2.0 * top - left - right
        if bend > 0.0:
            top += (right - left) ** 2 / (8.0 * bend)
    return top


def deviation(a: Piece, b: Piece, trims: tuple[float, float], control: FloatArray) -> float:
    """Hausdorff distance [m] between a blend and the path it replaces (sampled).

    The largest of: the distance from each of :data:`DEVIATION_SAMPLES` points
    of the blend to the replaced ends of ``a`` and ``b``, and from as many
    points of each of those ends (the corner included) to the blend, each
    distance in closed form on a line or a plain arc, else by Newton's method
    from the closest sample, the largest of each set refined by a parabola
    through its three top samples.
    """
    coef = power_coefficients(control)
    w = np.linspace(0.0, 1.0, DEVIATION_SAMPLES)
    blend = polynomial(coef, w, 0) + control[0]
    lo_a = a.length - trims[0]
    to_path = np.minimum(_to_piece(a, lo_a, a.length, blend), _to_piece(b, 0.0, trims[1], blend))
    ends = np.concatenate(
        [
            a.evaluate(np.linspace(lo_a, a.length, DEVIATION_SAMPLES))[0],
            b.evaluate(np.linspace(0.0, trims[1], DEVIATION_SAMPLES))[0],
        ]
    )
    to_blend = distances(coef, ends - control[0])
    n = DEVIATION_SAMPLES
    return max(_peak(to_path), _peak(to_blend[:n]), _peak(to_blend[n:]))


def _ends(a: Piece, b: Piece, trims: tuple[float, float]) -> Ends:
    pa, ta, ka = a.evaluate(np.array([a.length - trims[0]]))
    pb, tb, kb = b.evaluate(np.array([trims[1]]))
    return pa[0], ta[0], ka[0], pb[0], tb[0], kb[0]


def _cap(piece: Piece) -> float:
    cap = TRIM_SHARE * piece.length
    return min(cap, ARC_TRIM_ANGLE * piece.radius) if piece.is_arc else cap


def corner_blend(a: Piece, b: Piece, tolerance: float) -> CornerBlend | None:
    """The G2 blend of the corner where ``a`` ends and ``b`` starts (see the module).

    Args:
        a: The incoming piece.
        b: The outgoing piece, starting where ``a`` ends.
        tolerance: The ``G64 P`` tolerance [m].

    Returns:
        The blend (the block of ``a``, the lower feed of the two), or ``None``
        when the corner turns back (:data:`MAX_TURN`) or its trims would be
        shorter than :data:`MIN_TRIM`.
    """
    lines = a.v is None and b.v is None and not (a.is_blend or b.is_blend)
    if lines:
        corner, t0, t1 = a.origin + a.length * a.u, a.u, b.u
    else:
        corner, t0, t1 = a.evaluate(np.array([a.length]))[0][0], a.end_tangent(), b.start_tangent()
    turn = math.acos(float(np.clip(t0 @ t1, -1.0, 1.0)))
    if turn > MAX_TURN or not tolerance > 0.0:
        return None
    caps = (_cap(a), _cap(b))
    # two lines: the corner distance, exact; otherwise the sampled Hausdorff distance
    ceiling = tolerance if lines else (1.0 - FIT_TOL) * tolerance
    floor = ceiling - FIT_TOL * tolerance

    def gap(length: float) -> tuple[float, FloatArray, tuple[float, float]]:
        trims = (min(length, caps[0]), min(length, caps[1]))
        ctrl = control_points(_ends(a, b, trims), trims)
        d = corner_distance(ctrl, corner) if lines else deviation(a, b, trims, ctrl)
        return d, ctrl, trims

    top, short = max(caps), min(caps)
    best: tuple[float, FloatArray, tuple[float, float]] | None = None
    if lines:  # equal trims l: the closest point is the midpoint, l line_miss(turn) away
        unit = line_miss(turn)
        length = tolerance / unit * (1.0 - 1e-12) if unit > 0.0 else math.inf
        if length <= short:
            ratio = tangent_lengths(turn)
            shape = np.array([-1.0, ratio - 1.0, 2.0 * ratio - 1.0])[:, None]
            ctrl = corner + length * np.concatenate([shape * t0, -shape[::-1] * t1])
            best = (length * unit, ctrl, (length, length))
    if best is None:
        best = gap(top)
        if best[0] > ceiling:
            best = _fit(gap, top, best[0], ceiling, floor, _first_guess(a, b, turn, ceiling))
    d, ctrl, trims = best
    if min(trims) < MIN_TRIM:
        return None
    curve = Quintic(ctrl)
    feeds = [f for f in (a.feed, b.feed) if f is not None]
    feed = min(feeds) if feeds else None
    piece = BlendPiece(a.block, curve.length, feed, ctrl[0].copy(), t0.copy(), curve=curve)
    return CornerBlend(trims[0], trims[1], piece, d)


def line_miss(turn: float) -> float:
    """Corner distance of two lines' blend per unit of equal trims, ``turn`` [rad] [-].

    By symmetry the closest point is the curve's midpoint,
    ``B(1/2) - corner = (16 - 25 ratio) / 32 (T1 - T0)``.
    """
    return (16.0 - 25.0 * tangent_lengths(turn)) / 16.0 * math.sin(0.5 * turn)


def _first_guess(a: Piece, b: Piece, turn: float, tolerance: float) -> tuple[float, float]:
    """A first trim and the power of the deviation in it: a corner, or a tangent joint."""
    if turn > 1e-3:
        return tolerance / line_miss(turn), 1.0
    _, _, k0, _, _, k1 = _ends(a, b, (0.0, 0.0))
    jump = float(np.linalg.norm(k0 - k1))
    return (math.sqrt(8.0 * tolerance / jump) if jump > 0.0 else math.inf), 2.0


def _fit(
    gap: Callable[[float], tuple[float, FloatArray, tuple[float, float]]],
    top: float,
    d_top: float,
    ceiling: float,
    floor: float,
    guess: tuple[float, float],
) -> tuple[float, FloatArray, tuple[float, float]]:
    """The longest trim found whose gap lies in ``[floor, ceiling]`` (secant on logs)."""
    length, power = guess
    lo, d_lo, hi, d_hi = 0.0, 0.0, top, d_top
    best: tuple[float, FloatArray, tuple[float, float]] = (0.0, np.zeros((6, 3)), (0.0, 0.0))
    for _ in range(MAX_FITS):
        length = min(max(length, 1e-6 * hi), hi)
        trial = gap(length)
        d = trial[0]
        if d <= ceiling:
            lo, d_lo, best = length, d, trial
            if d >= floor:
                break
        else:
            hi, d_hi = length, d
        target = 0.5 * (floor + ceiling)
        if lo > 0.0 and d_lo > 0.0 and d_hi > d_lo:
            power = math.log(d_hi / d_lo) / math.log(hi / lo)
            length = lo * (target / d_lo) ** (1.0 / power)
            if not lo < length < hi:
                length = math.sqrt(lo * hi)
        else:
            length = length * (target / max(d, 1e-300)) ** (1.0 / power)
    return best
