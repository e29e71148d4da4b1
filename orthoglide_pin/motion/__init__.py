"""Tool motion: time profiles, path segments, sampled trajectories and the standard cycle.

* :mod:`~orthoglide_pin.motion.profiles`: trapezoidal and 7-phase S-curve
  profiles under speed, acceleration and jerk limits;
* :mod:`~orthoglide_pin.motion.segments`: lines, arcs, circles, polygons, dwells;
* :mod:`~orthoglide_pin.motion.trajectory`: segments sampled into one trajectory;
* :mod:`~orthoglide_pin.motion.cycle`: the documented standard test cycle and
  the paper's tool speed and acceleration.
"""

from __future__ import annotations

from orthoglide_pin.motion.cycle import (
    circle_limits,
    standard_cycle,
    standard_cycle_segments,
    standard_limits,
)
from orthoglide_pin.motion.profiles import (
    MotionLimits,
    MotionProfile,
    ProfileSample,
    s_curve_profile,
    trapezoidal_profile,
)
from orthoglide_pin.motion.segments import (
    ArcMove,
    Dwell,
    LineMove,
    Segment,
    circle_move,
    dwell,
    line_move,
    polygon_moves,
)
from orthoglide_pin.motion.trajectory import Trajectory, build_trajectory

__all__ = [
    "ArcMove",
    "Dwell",
    "LineMove",
    "MotionLimits",
    "MotionProfile",
    "ProfileSample",
    "Segment",
    "Trajectory",
    "build_trajectory",
    "circle_limits",
    "circle_move",
    "dwell",
    "line_move",
    "polygon_moves",
    "s_curve_profile",
    "standard_cycle",
    "standard_cycle_segments",
    "standard_limits",
    "trapezoidal_profile",
]
