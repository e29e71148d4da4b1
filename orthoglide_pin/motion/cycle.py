"""The standard test cycle of the prototype: the whole cube at the paper's speed.

The motors of the prototype were sized for 1.2 m/s and 20 m/s^2 at the
isotropic configuration (paper, section 4). The standard cycle drives the tool
through the prescribed cube (lower corner ``c``, side ``h``, centre
``m = c + h / 2``) with these bounds and a jerk of 1000 m/s^3 (S-curve moves),
every move from rest to rest, with a rest of ``CYCLE_DWELL`` between moves:

1. ``approach``: from the centre ``m`` to the corner Q1 = ``c`` (the slider
   side of the main diagonal, where a transmission factor reaches 2 on the
   prototype);
2. ``diagonal Q1-Q2`` and ``diagonal Q2-Q1``: the whole main diagonal to the
   opposite corner Q2 = ``c + h (1, 1, 1)`` and back;
3. ``edge 1 (+x)`` .. ``edge 8 (-z)``: a tour of the eight corners along the
   edges, from Q1 back to Q1: +x, +y, -x, +z, +x, -y, -x, -z (each axis alone,
   both ways, on four different edges);
4. ``to square``, ``square 1`` .. ``square 4``: the square of side ``h / 2``
   centred on ``m`` in the horizontal mid-plane ``z = m_z``, counterclockwise
   from its ``(-, -)`` vertex, stopping at each vertex;
5. ``to circle xy``, ``circle xy``, ``to circle yz``, ``circle yz``,
   ``to circle zx``, ``circle zx``: a full circle of radius ``h / 4`` centred
   on ``m`` in each mid-plane (normals +z, +x, +y; starting at ``m + r e_x``,
   ``m + r e_y``, ``m + r e_z``). On a circle the speed is lowered so that the
   acceleration stays within ``a_max``: the tangential law gets
   ``CIRCLE_TANGENTIAL_SHARE a_max`` and the speed ``v`` keeps the centripetal
   ``v^2 / r <= CIRCLE_NORMAL_SHARE a_max`` (0.6 and 0.8: ``0.6^2 + 0.8^2 = 1``);
6. ``return``: back to the centre ``m``.

The jerk bound holds on the straight moves; on the circles the law's jerk
gains the centripetal terms (:mod:`orthoglide_pin.motion.segments`), about 1.36 times
the bound on the prototype.

Every point lies in the cube (convex; the moves join corners, mid-plane
points and inscribed circles). By default the cube is the machine's prescribed
cube (:attr:`~orthoglide_pin.machine.params.OrthoglideParams.workspace`); any
other cube may be given, and it is checked to fit the machine's slider limits.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import instance_of, positive_length
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import slider_range_over_cube
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.motion.profiles import MotionLimits
from orthoglide_pin.motion.segments import Segment, circle_move, line_move, polygon_moves
from orthoglide_pin.motion.trajectory import DEFAULT_DT, Trajectory, build_trajectory

FloatArray = NDArray[np.float64]

#: Tool speed the prototype's motors were sized for [m/s] (paper, section 4).
CYCLE_V_MAX: Final[float] = 1.2
#: Tool acceleration the prototype's motors were sized for [m/s^2] (paper, section 4).
CYCLE_A_MAX: Final[float] = 20.0
#: Jerk of the cycle's S-curve moves [m/s^3] (a choice: ``a_max`` is reached in 20 ms).
CYCLE_JERK: Final[float] = 1000.0
#: Rest between consecutive moves [s].
CYCLE_DWELL: Final[float] = 0.05
#: Share of ``a_max`` given to the tangential law on a circle.
CIRCLE_TANGENTIAL_SHARE: Final[float] = 0.6
#: Share of ``a_max`` allowed to the centripetal acceleration on a circle.
CIRCLE_NORMAL_SHARE: Final[float] = 0.8
#: Slack when checking the cube against the slider limits [m].
LIMIT_TOL: Final[float] = 1e-12

#: Tour of the cube's corners along its edges, in units of the side (from Q1).
_TOUR: Final = (
    (1, 0, 0),
    (1, 1, 0),
    (0, 1, 0),
    (0, 1, 1),
    (1, 1, 1),
    (1, 0, 1),
    (0, 0, 1),
    (0, 0, 0),
)
_AXES: Final = "xyz"


def standard_limits() -> MotionLimits:
    """The cycle's bounds: 1.2 m/s, 20 m/s^2, 1000 m/s^3."""
    return MotionLimits(CYCLE_V_MAX, CYCLE_A_MAX, CYCLE_JERK)


def circle_limits(limits: MotionLimits, radius: float) -> MotionLimits:
    """Bounds of the tangential law on a circle of ``radius`` [m] (see the module).

    ``a_max`` becomes ``CIRCLE_TANGENTIAL_SHARE a_max`` and ``v_max`` becomes
    ``min(v_max, sqrt(CIRCLE_NORMAL_SHARE a_max r))``, so that
    ``|a| <= a_max`` along the circle.
    """
    instance_of("limits", limits, MotionLimits, "MotionLimits")
    radius = positive_length("radius", radius)
    v_circle = min(limits.v_max, math.sqrt(CIRCLE_NORMAL_SHARE * limits.a_max * radius))
    return limits.scaled(v_max=v_circle, a_max=CIRCLE_TANGENTIAL_SHARE * limits.a_max)


def _cube(
    params: OrthoglideParams, corner: ArrayLike | None, side: float | None
) -> tuple[FloatArray, float]:
    """The cube of the cycle, checked against the slider limits."""
    default_corner, default_side = params.workspace.q1, params.workspace.side
    try:
        c = np.array(default_corner if corner is None else corner, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidParameterError("corner", corner, "three finite numbers [m]") from None
    if c.shape != (3,) or not np.isfinite(c).all():
        raise InvalidParameterError("corner", corner, "three finite numbers [m]")
    try:
        h = math.nan if isinstance(side, bool) else float(default_side if side is None else side)
    except (TypeError, ValueError):
        h = math.nan
    if not (math.isfinite(h) and h > 0.0):
        raise InvalidParameterError("side", side, "a positive finite cube side [m]")
    lo, hi = slider_range_over_cube(params.leg_length, c, h)
    if lo < params.slider_lower - LIMIT_TOL or hi > params.slider_upper + LIMIT_TOL:
        allowed = (
            f"a cube whose slider range [{lo:.6g}, {hi:.6g}] m fits the slider limits "
            f"[{params.slider_lower:.6g}, {params.slider_upper:.6g}] m"
        )
        raise InvalidParameterError("side", h, allowed)
    return c, h


def standard_cycle_segments(
    params: OrthoglideParams | None = None,
    *,
    corner: ArrayLike | None = None,
    side: float | None = None,
    limits: MotionLimits | None = None,
) -> tuple[Segment, ...]:
    """The moves of the standard cycle, in order (see the module).

    Args:
        params: The machine (default: the prototype).
        corner: Lowest corner of the cube [m], shape (3,) (default: the
            machine's prescribed cube, ``params.workspace``).
        side: Side of the cube [m] (default: likewise).
        limits: Bounds of the moves (default: :func:`standard_limits`).

    Returns:
        The segments; consecutive ones join, the first starts and the last
        ends at the cube centre.

    Raises:
        UnreachablePointError: Some point of the cube is out of reach of a leg.
        InvalidParameterError: A bad cube, or a cube beyond the slider limits.
    """
    params = as_params(params)
    c, h = _cube(params, corner, side)
    lim = (
        standard_limits()
        if limits is None
        else instance_of("limits", limits, MotionLimits, "MotionLimits or None")
    )
    m = c + h / 2.0
    q1, q2 = c, c + h
    moves: list[Segment] = [
        line_move(m, q1, lim, label="approach"),
        line_move(q1, q2, lim, label="diagonal Q1-Q2"),
        line_move(q2, q1, lim, label="diagonal Q2-Q1"),
    ]
    here = q1
    for k, unit in enumerate(_TOUR):
        there = c + h * np.asarray(unit, dtype=np.float64)
        axis = int(np.argmax(np.abs(there - here)))
        sign = "+" if there[axis] > here[axis] else "-"
        moves.append(line_move(here, there, lim, label=f"edge {k + 1} ({sign}{_AXES[axis]})"))
        here = there
    quarter = h / 4.0
    square = m + quarter * np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    moves.append(line_move(here, square[0], lim, label="to square"))
    moves.extend(polygon_moves(square, lim, closed=True, label="square"))
    here = square[0]
    round_lim = circle_limits(lim, quarter)
    eye = np.eye(3)
    for name, normal, start in (("xy", 2, 0), ("yz", 0, 1), ("zx", 1, 2)):
        first = m + quarter * eye[start]
        moves.append(line_move(here, first, lim, label=f"to circle {name}"))
        moves.append(
            circle_move(
                m, eye[normal], quarter, round_lim, reference=eye[start], label=f"circle {name}"
            )
        )
        here = first
    moves.append(line_move(here, m, lim, label="return"))
    return tuple(moves)


def standard_cycle(
    params: OrthoglideParams | None = None,
    *,
    corner: ArrayLike | None = None,
    side: float | None = None,
    limits: MotionLimits | None = None,
    dt: float = DEFAULT_DT,
    dwell_time: float = CYCLE_DWELL,
) -> Trajectory:
    """The standard test cycle, sampled (see the module and :func:`standard_cycle_segments`).

    Args:
        params: The machine (default: the prototype).
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        limits: Bounds of the moves (default: 1.2 m/s, 20 m/s^2, 1000 m/s^3).
        dt: Sampling period [s].
        dwell_time: Rest between consecutive moves [s].

    Returns:
        The sampled trajectory.

    Raises:
        UnreachablePointError: Some point of the cube is out of reach of a leg.
        InvalidParameterError: A bad cube, limits, ``dt`` or ``dwell_time``.
    """
    segments = standard_cycle_segments(params, corner=corner, side=side, limits=limits)
    return build_trajectory(segments, dt=dt, dwell_time=dwell_time)
