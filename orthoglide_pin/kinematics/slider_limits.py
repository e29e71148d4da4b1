"""The machine of a kinematic call: a bare leg length, or parameters with slider limits.

The closed-form functions (:func:`~orthoglide_pin.kinematics.closed_form.jacobian`,
:func:`~orthoglide_pin.kinematics.closed_form.inverse_jacobian`,
:func:`~orthoglide_pin.kinematics.closed_form.inverse_kinematics`,
:func:`~orthoglide_pin.kinematics.closed_form.direct_kinematics`) take as
``leg_length`` either a leg length [m] or the machine's parameters
(:class:`~orthoglide_pin.machine.params.OrthoglideParams`, or anything with
``leg_length``, ``slider_lower`` and ``slider_upper``). A bare length names no
machine, hence no slider limits: nothing is checked beyond reach and
singularities. Parameters name the machine, and a tool point whose slider
values leave its limits is refused (``check_limits=False`` computes there
anyway), naming the point, the slider and the limits.

Boundary rule: a slider value within :data:`BOUNDARY_TOL` (1e-9 m) beyond a
limit counts as inside, so that the corners Q1 and Q2 of the prescribed cube,
where the derived limits are reached exactly, and points rounded onto them are
accepted (the rule of the part programs' points, see
:mod:`orthoglide_pin.planning.path`).
"""

from __future__ import annotations

from typing import Any, Final, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import first_index, positive_length
from orthoglide_pin.exceptions import InvalidParameterError, UnreachablePointError

FloatArray = NDArray[np.float64]

#: Slack on slider values against the limits [m]: within it a value counts as
#: inside (points on the limits, such as Q1 and Q2, rounded).
BOUNDARY_TOL: Final[float] = 1e-9
#: The way out named in the messages.
HINT: Final = "pass check_limits=False to compute there anyway"


@runtime_checkable
class SliderLimited(Protocol):
    """What the kinematic functions read of a machine: its leg and slider limits."""

    @property
    def leg_length(self) -> float:
        """Leg length [m]."""

    @property
    def slider_lower(self) -> float:
        """Lower slider limit [m]."""

    @property
    def slider_upper(self) -> float:
        """Upper slider limit [m]."""


def leg_and_limits(value: Any) -> tuple[float, tuple[float, float] | None]:
    """The leg length [m] of ``value`` and its slider limits [m] (``None``: a bare length).

    Raises:
        InvalidParameterError: ``value`` is neither a valid leg length nor a
            machine (naming ``leg_length``).
    """
    if isinstance(value, SliderLimited) and not isinstance(value, (int, float, np.generic)):
        length = positive_length("leg_length", value.leg_length)
        return length, (float(value.slider_lower), float(value.slider_upper))
    return positive_length("leg_length", value), None


def refuse_points_beyond(
    points: FloatArray, q: FloatArray, limits: tuple[float, float], tol: float = BOUNDARY_TOL
) -> None:
    """Refuse the first tool point whose slider values ``q`` leave ``limits``.

    Args:
        points: Tool points [m], shape (..., 3).
        q: Their slider values [m], same shape.
        limits: ``(slider_lower, slider_upper)`` [m].
        tol: Slack [m] (values within it beyond a limit count as inside).

    Raises:
        UnreachablePointError: Naming the point, its slider, the value and the limits.
    """
    lo, hi = limits
    bad = ((q < lo - tol) | (q > hi + tol)).reshape(-1, 3)
    if bad.any():
        row = first_index(bad.any(axis=1))
        col = first_index(bad[row])
        value = float(q.reshape(-1, 3)[row, col])
        raise UnreachablePointError(
            points.reshape(-1, 3)[row],
            col + 1,
            f"slider value {value:.6g} m outside the slider limits [{lo:.6g}, {hi:.6g}] m "
            f"(within {tol:g} m counts as inside; {HINT})",
        )


def refuse_values_beyond(
    q: FloatArray, limits: tuple[float, float], tol: float = BOUNDARY_TOL
) -> None:
    """Refuse the first slider value beyond ``limits``, naming it ``q1``, ``q2`` or ``q3``.

    Raises:
        InvalidParameterError: Naming the slider, its value and the limits.
    """
    lo, hi = limits
    bad = ((q < lo - tol) | (q > hi + tol)).reshape(-1, 3)
    if bad.any():
        row = first_index(bad.any(axis=1))
        col = first_index(bad[row])
        raise InvalidParameterError(
            f"q{col + 1}",
            float(q.reshape(-1, 3)[row, col]),
            f"within the slider limits [{lo:.6g}, {hi:.6g}] m "
            f"(within {tol:g} m counts as inside; {HINT})",
        )
