"""Sensitivity of the tool position to the geometric errors, over the cube.

At a tool point ``P`` the sliders command ``q = IK_nominal(P)``; an error
``d theta`` of the geometry then moves the tool by ``dP = (dP/dtheta) d theta``
(:meth:`~orthoglide_pin.calibration.model.GeometricModel.parameter_jacobian`).
The sensitivity of parameter ``k`` is the norm of column ``k``: the tool
displacement per unit of that error, [m/m] for a length (carriage position,
leg length) and [m/rad] for a rail tilt, as in the sensitivity indices of
Caro, Wenger, Bennis and Chablat (Orthoglide, ASME J. Mech. Design, 2006).
Grouped by kind, the index of a group is the root sum of squares of its
columns (the largest displacement a unit error of the group can cause, for
errors spread evenly over it).

The points are checked first, as the kinematics check them: out of reach,
(near) singular (:func:`~orthoglide_pin.kinematics.singularity.check_inverse_jacobian`),
and, given the machine's parameters, beyond its slider limits; one call takes
at most :data:`MAX_POINTS` points.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import capped_points
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel
from orthoglide_pin.kinematics.closed_form import inverse_jacobian
from orthoglide_pin.kinematics.singularity import check_inverse_jacobian
from orthoglide_pin.kinematics.slider_limits import SliderLimited, leg_and_limits

FloatArray = NDArray[np.float64]

#: Most points of one call (about 1 kB of work each).
MAX_POINTS: Final[int] = 1_000_000
#: Kinds of geometric errors and the parameters of each.
GROUPS: Final[dict[str, tuple[str, ...]]] = {
    "carriage position": tuple(n for n in PARAMETER_NAMES if n.startswith("a")),
    "rail orientation": tuple(n for n in PARAMETER_NAMES if n[:4] in ("alph", "beta")),
    "leg length": tuple(n for n in PARAMETER_NAMES if n.startswith("L")),
}
#: Unit of each group's index.
GROUP_UNITS: Final[dict[str, str]] = {
    "carriage position": "m/m",
    "rail orientation": "m/rad",
    "leg length": "m/m",
}


def sensitivity(leg_length: float | SliderLimited, points: ArrayLike) -> FloatArray:
    """``dP/dtheta`` at tool points of the drawing, shape (N, 3, 18) (or (3, 18)).

    Args:
        leg_length: The drawing's leg length ``L`` [m], or the machine's
            parameters (its leg length and slider limits, which are then checked).
        points: Tool points [m], shape (3,) or (N, 3), at most :data:`MAX_POINTS`.

    Raises:
        InvalidParameterError: Bad points, or more than :data:`MAX_POINTS`.
        UnreachablePointError: A point out of reach, or beyond the slider limits.
        SingularConfigurationError: A singular or near-singular point (serial or
            parallel), as :func:`~orthoglide_pin.kinematics.closed_form.jacobian` judges it.
    """
    p = capped_points(points, "points", MAX_POINTS)
    length, _ = leg_and_limits(leg_length)
    check_inverse_jacobian(inverse_jacobian(p, leg_length), p)
    model = GeometricModel.nominal(length)
    return model.parameter_jacobian(model.inverse_kinematics(p), p)


def sensitivity_indices(
    leg_length: float | SliderLimited, points: ArrayLike
) -> dict[str, FloatArray]:
    """Per parameter and per group, the tool displacement per unit error.

    Args:
        leg_length: The drawing's leg length ``L`` [m], or the machine's parameters.
        points: Tool points [m], shape (3,) or (N, 3), checked as :func:`sensitivity` does.

    Returns:
        A mapping of every parameter name and every group name
        (:data:`GROUPS`) to its index, shape ``(N,)`` (or ``()``).
    """
    jac = sensitivity(leg_length, points)
    columns = np.linalg.norm(jac, axis=-2)  # (..., 18)
    out: dict[str, FloatArray] = {name: columns[..., k] for k, name in enumerate(PARAMETER_NAMES)}
    for group, names in GROUPS.items():
        idx = [PARAMETER_NAMES.index(n) for n in names]
        out[group] = np.sqrt(np.sum(columns[..., idx] ** 2, axis=-1))
    return out
