"""Kinematics in closed form, vectorised over points: no Pinocchio.

* :mod:`~orthoglide_pin.kinematics.closed_form`: inverse kinematics, both
  assembly modes of the direct kinematics, ``J`` and ``J^-1`` (paper eq. 2),
  the fused IK + Jacobian kernel and the slider range over a cube;
* :mod:`~orthoglide_pin.kinematics.joint_motion`: every joint's position,
  velocity and acceleration from a tool motion (and back from the sliders),
  and their derivatives along a path;
* :mod:`~orthoglide_pin.kinematics.singularity`: serial, parallel and
  near-singular configurations judged from ``J^-1`` of any route.
"""

from __future__ import annotations

from orthoglide_pin.kinematics.closed_form import (
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_vectors,
    slider_range_over_cube,
)
from orthoglide_pin.kinematics.joint_motion import (
    LegMotion,
    PathMotion,
    leg_motion,
    path_motion,
    tool_motion_from_sliders,
)
from orthoglide_pin.kinematics.singularity import (
    MAX_CONDITION,
    check_inverse_jacobian,
    singularity_measures,
)

__all__ = [
    "MAX_CONDITION",
    "LegMotion",
    "PathMotion",
    "check_inverse_jacobian",
    "direct_kinematics",
    "ik_and_jacobian",
    "inverse_jacobian",
    "inverse_kinematics",
    "jacobian",
    "leg_motion",
    "leg_vectors",
    "path_motion",
    "singularity_measures",
    "slider_range_over_cube",
    "tool_motion_from_sliders",
]
