"""Trajectory segments: straight lines, circles, polygonal contours and dwells.

Each segment is a piece of tool path with its own time law, evaluated at local
times ``tau`` from 0 (vectorised) into tool positions [m], velocities [m/s],
accelerations [m/s^2] and jerks [m/s^3] in the world frame; before 0 and after
its duration it rests at its ends.
:func:`~orthoglide_pin.motion.trajectory.build_trajectory` chains and samples them.

* :func:`line_move`: a straight move ``p = p_0 + s(t) u`` between two points,
  ``u`` the unit direction, ``s`` a motion law of :mod:`orthoglide_pin.motion.profiles`
  over the distance; it starts and ends at rest.
* :func:`circle_move`: an arc of a circle (centre ``c``, unit normal ``n``,
  radius ``r``) run with a motion law on its length ``r |arc|``. The angle is
  measured from a unit vector ``u`` of the plane (``reference`` projected on
  the plane; by default the world axis least aligned with ``n``, the first one
  on a tie, so ``u = e_x`` for ``n = e_z``), towards ``w = n x u``; a positive
  ``arc`` turns counterclockwise about ``n``. With ``e_r`` the radial and
  ``t`` the unit tangent of motion: ``v = s' t``,
  ``a = s'' t - (s'^2 / r) e_r``,
  ``jerk = (s''' - s'^3 / r^2) t - 3 s' s'' / r e_r``. The bounds of the law
  apply along the path: the centripetal acceleration ``v^2 / r`` comes on top
  (choose the speed with it in mind, as :mod:`orthoglide_pin.motion.cycle` does).
* :func:`polygon_moves`: a polygonal contour through vertices. Corner handling:
  each edge is a separate straight move that **stops at every vertex** (exact
  corners, no blending; the velocity is zero at each vertex).
* :func:`dwell`: a rest at a point for a given time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_number, flag, float_array, positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.profiles import MotionLimits, MotionProfile

FloatArray = NDArray[np.float64]
#: Position [m], velocity [m/s], acceleration [m/s^2] and jerk [m/s^3], each (n, 3).
State = tuple[FloatArray, FloatArray, FloatArray, FloatArray]


class Segment(Protocol):
    """A piece of trajectory with its own time law (local time ``tau`` from 0)."""

    @property
    def label(self) -> str:
        """Name of the segment."""
        ...

    @property
    def duration(self) -> float:
        """Duration [s]."""
        ...

    @property
    def start(self) -> FloatArray:
        """First point [m], shape (3,)."""
        ...

    @property
    def end(self) -> FloatArray:
        """Last point [m], shape (3,)."""
        ...

    def evaluate(self, tau: FloatArray) -> State:
        """Position [m], velocity [m/s], acceleration [m/s^2], jerk [m/s^3], each (n, 3)."""
        ...


@dataclass(frozen=True, eq=False)
class LineMove:
    """A straight rest-to-rest move (see :func:`line_move`).

    Attributes:
        start: First point [m], shape (3,).
        end: Last point [m], shape (3,).
        profile: Motion law along the line.
        label: Name of the segment.
    """

    start: FloatArray
    end: FloatArray
    profile: MotionProfile
    label: str = "line"

    @property
    def duration(self) -> float:
        """Duration [s]."""
        return self.profile.duration

    def evaluate(self, tau: FloatArray) -> State:
        """State at local times ``tau`` [s], shape (n,); each result (n, 3)."""
        u = (self.end - self.start) / self.profile.distance
        s, v, a, j = self.profile.sample(_times(tau))
        return self.start + np.outer(s, u), np.outer(v, u), np.outer(a, u), np.outer(j, u)


@dataclass(frozen=True, eq=False)
class ArcMove:
    """An arc of circle run with a motion law on its length (see :func:`circle_move`).

    Attributes:
        center: Centre ``c`` [m], shape (3,).
        u: Unit vector of the plane at angle 0, shape (3,).
        w: Unit vector of the plane at angle ``pi / 2`` (``n x u``), shape (3,).
        radius: Radius ``r`` [m].
        start_angle: Angle of the first point [rad].
        arc: Angle swept [rad], positive counterclockwise about ``n``.
        profile: Motion law along the arc length.
        label: Name of the segment.
    """

    center: FloatArray
    u: FloatArray
    w: FloatArray
    radius: float
    start_angle: float
    arc: float
    profile: MotionProfile
    label: str = "circle"

    @property
    def normal(self) -> FloatArray:
        """Unit normal ``n = u x w``, shape (3,)."""
        return np.cross(self.u, self.w)

    @property
    def duration(self) -> float:
        """Duration [s]."""
        return self.profile.duration

    def point(self, angle: float) -> FloatArray:
        """Point of the circle at ``angle`` [rad], shape (3,)."""
        angle = finite_number("angle", angle, "[rad]")
        return self.center + self.radius * (math.cos(angle) * self.u + math.sin(angle) * self.w)

    @property
    def start(self) -> FloatArray:
        """First point [m], shape (3,)."""
        return self.point(self.start_angle)

    @property
    def end(self) -> FloatArray:
        """Last point [m], shape (3,)."""
        return self.point(self.start_angle + self.arc)

    def evaluate(self, tau: FloatArray) -> State:
        """State at local times ``tau`` [s], shape (n,); each result (n, 3)."""
        r, sign = self.radius, math.copysign(1.0, self.arc)
        s, v, a, j = self.profile.sample(_times(tau))
        theta = self.start_angle + sign * s / r
        cos, sin = np.cos(theta)[:, None], np.sin(theta)[:, None]
        e_r = cos * self.u + sin * self.w
        tangent = sign * (cos * self.w - sin * self.u)
        v_, a_, j_ = v[:, None], a[:, None], j[:, None]
        acc = a_ * tangent - (v_ * v_ / r) * e_r
        jerk = (j_ - v_**3 / (r * r)) * tangent - (3.0 * v_ * a_ / r) * e_r
        return self.center + r * e_r, v_ * tangent, acc, jerk


@dataclass(frozen=True, eq=False)
class Dwell:
    """A rest at a point (see :func:`dwell`).

    Attributes:
        point: Where [m], shape (3,).
        duration: How long [s].
        label: Name of the segment.
    """

    point: FloatArray
    duration: float
    label: str = "dwell"

    @property
    def start(self) -> FloatArray:
        """First point [m], shape (3,)."""
        return self.point

    @property
    def end(self) -> FloatArray:
        """Last point [m], shape (3,)."""
        return self.point

    def evaluate(self, tau: FloatArray) -> State:
        """State at local times ``tau`` [s], shape (n,); each result (n, 3)."""
        zeros = np.zeros((_times(tau).shape[0], 3))
        return np.broadcast_to(self.point, zeros.shape).copy(), zeros, zeros.copy(), zeros.copy()


def _times(tau: ArrayLike) -> FloatArray:
    """Local times ``tau`` [s] as a vector of finite floats, else an error naming ``tau``."""
    arr = float_array(tau)
    if arr.ndim != 1 or arr.size == 0 or not np.isfinite(arr).all():
        raise InvalidParameterError("tau", tau, "local times [s]: a vector of finite numbers")
    return arr


def _point(value: ArrayLike, name: str) -> FloatArray:
    """A finite point or vector of shape (3,) [m], else an error naming it."""
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "three finite numbers") from None
    if arr.shape != (3,) or not np.isfinite(arr).all():
        raise InvalidParameterError(name, value, "three finite numbers")
    arr.flags.writeable = False
    return arr


def _limits(limits: MotionLimits) -> MotionLimits:
    if not isinstance(limits, MotionLimits):
        raise InvalidParameterError("limits", limits, "a MotionLimits(v_max, a_max, jerk)")
    return limits


def line_move(
    start: ArrayLike, end: ArrayLike, limits: MotionLimits, *, label: str = "line"
) -> LineMove:
    """A straight rest-to-rest move from ``start`` to ``end``.

    Args:
        start: First point [m], shape (3,).
        end: Last point [m], shape (3,), distinct from ``start``.
        limits: Bounds of the motion law along the line.
        label: Name of the segment.

    Returns:
        The move.

    Raises:
        InvalidParameterError: Non-finite points, coincident points or bad limits.
    """
    p0, p1 = _point(start, "start"), _point(end, "end")
    length = float(np.linalg.norm(p1 - p0))
    if length == 0.0:
        raise InvalidParameterError("end", tuple(p1), f"a point distinct from start={tuple(p0)}")
    return LineMove(p0, p1, _limits(limits).profile(length), label)


def _plane_basis(
    normal: FloatArray, reference: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """Unit ``u`` (angle 0) and ``w = n x u`` of the plane of unit normal ``normal``."""
    if reference is None:
        reference = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = reference - np.dot(reference, normal) * normal
    norm = float(np.linalg.norm(u))
    if norm <= 1e-9 * float(np.linalg.norm(reference)):
        raise InvalidParameterError(
            "reference", tuple(reference), "a direction not parallel to the normal"
        )
    u = u / norm
    return u, np.cross(normal, u)


def circle_move(
    center: ArrayLike,
    normal: ArrayLike,
    radius: float,
    limits: MotionLimits,
    *,
    start_angle: float = 0.0,
    arc: float = 2.0 * math.pi,
    reference: ArrayLike | None = None,
    label: str = "circle",
) -> ArcMove:
    """A circle, or an arc of it, run rest to rest (see the module for the frame).

    Args:
        center: Centre ``c`` [m], shape (3,).
        normal: Normal ``n`` of the plane, shape (3,), non-zero (normalised here).
        radius: Radius ``r`` [m], positive.
        limits: Bounds of the motion law along the arc length.
        start_angle: Angle of the first point from ``u`` [rad].
        arc: Angle swept [rad], non-zero; ``2 pi`` is a full circle, a negative
            value turns clockwise about ``n``.
        reference: Direction of angle 0, projected on the plane (default: the
            world axis least aligned with ``n``).
        label: Name of the segment.

    Returns:
        The move.

    Raises:
        InvalidParameterError: A bad centre, normal, radius, angle, reference or limits.
    """
    c, n = _point(center, "center"), _point(normal, "normal")
    n_norm = float(np.linalg.norm(n))
    if n_norm == 0.0:
        raise InvalidParameterError("normal", tuple(n), "a non-zero vector")
    r = positive_number("radius", radius, "a positive finite radius [m]")
    theta0, sweep = (
        finite_number("start_angle", start_angle, "[rad]"),
        finite_number("arc", arc, "[rad]"),
    )
    if sweep == 0.0:
        raise InvalidParameterError("arc", arc, "a finite non-zero angle [rad]")
    ref = None if reference is None else _point(reference, "reference")
    u, w = _plane_basis(n / n_norm, ref)
    profile = _limits(limits).profile(r * abs(sweep))
    return ArcMove(c, u, w, r, theta0, sweep, profile, label)


def polygon_moves(
    vertices: ArrayLike, limits: MotionLimits, *, closed: bool = True, label: str = "polygon"
) -> tuple[LineMove, ...]:
    """A polygonal contour: one straight move per edge, stopping at each vertex.

    Args:
        vertices: Vertices [m], shape (m, 3), m >= 2 (>= 3 if closed), no two
            consecutive ones equal.
        limits: Bounds of the motion law on each edge.
        closed: Whether to come back from the last vertex to the first.
        label: Base name; edge ``k`` (from 1) is labelled ``f"{label} {k}"``.

    Returns:
        The edges, in order (``m`` if closed, else ``m - 1``).

    Raises:
        InvalidParameterError: Too few or non-finite vertices, a zero-length edge.
    """
    pts, closed = float_array(vertices), flag("closed", closed)
    need = 3 if closed else 2
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < need:
        allowed = f"an array of shape (m, 3) with m >= {need}"
        raise InvalidParameterError("vertices.shape", pts.shape, allowed)
    if not np.isfinite(pts).all():
        raise InvalidParameterError("vertices", "non-finite values", "finite numbers [m]")
    ring = np.vstack([pts, pts[:1]]) if closed else pts
    return tuple(
        line_move(ring[k], ring[k + 1], limits, label=f"{label} {k + 1}")
        for k in range(ring.shape[0] - 1)
    )


def dwell(point: ArrayLike, duration: float, *, label: str = "dwell") -> Dwell:
    """A rest at ``point`` [m] (shape (3,)) for ``duration`` [s] (positive).

    Raises:
        InvalidParameterError: A bad point or duration.
    """
    return Dwell(
        _point(point, "point"),
        positive_number("duration", duration, "a positive duration [s]"),
        label,
    )
