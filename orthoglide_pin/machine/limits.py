"""The slider limits and the prescribed cube: derived from it, checked against it.

The workspace rule (:mod:`orthoglide_pin.machine.params`): a slider limit not
given is the exact range of the slider values over the prescribed cube
(:func:`~orthoglide_pin.kinematics.closed_form.slider_range_over_cube`),
widened to include home (0) if the cube does not contain it; a limit given
explicitly must let the sliders reach the whole cube. Tool points given to the
functions of the API are checked against the limits as ``orthoglide ik``
checks its point (:func:`check_slider_limits`).
"""

from __future__ import annotations

from typing import Final, Protocol

import numpy as np
from numpy.typing import ArrayLike

from orthoglide_pin._validation import finite_rows
from orthoglide_pin.exceptions import InvalidParameterError, UnreachablePointError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, slider_range_over_cube
from orthoglide_pin.kinematics.slider_limits import SliderLimited
from orthoglide_pin.machine.cube import Cube


class Machine(SliderLimited, Protocol):
    """What the checks read of the parameters: the leg and slider limits, and the cube.

    :class:`~orthoglide_pin.machine.params.OrthoglideParams` has it; a protocol,
    so that this module does not import the parameters, which import it.
    """

    @property
    def workspace(self) -> Cube:
        """The prescribed cube."""

    @property
    def derived_limits(self) -> tuple[str, ...]:
        """Names of the slider limits derived from the cube."""


#: Slack on slider values against the limits [m]: absorbs rounding at the
#: cube's own corners, where the derived limits are reached exactly.
LIMIT_TOL: Final[float] = 1e-12


def cube_slider_range(p: Machine) -> tuple[float, float]:
    """The exact range of the slider values over the machine's prescribed cube.

    Args:
        p: The machine (leg length and cube).

    Returns:
        ``(lowest, highest)`` slider value over the cube [m].

    Raises:
        InvalidParameterError: A leg cannot reach the whole cube (naming the
            cube in mm, the leg length and the fix).
    """
    cube = p.workspace
    try:
        return slider_range_over_cube(p.leg_length, cube.corner, cube.side)
    except UnreachablePointError as exc:
        raise InvalidParameterError(
            "leg_length",
            p.leg_length,
            f"a leg that reaches the whole prescribed {cube.describe()} ({exc}); "
            "lengthen the leg, or move or shrink the cube (workspace_corner, workspace_side)",
        ) from None


def set_derived_limits(p: Machine) -> None:
    """Fill the slider limits not given: the slider range over the cube, home included.

    Called while the (frozen) parameters are built, which is why it sets them.

    Args:
        p: The machine; its limits named in ``derived_limits`` are set [m].

    Raises:
        InvalidParameterError: A leg cannot reach the whole cube.
    """
    if not p.derived_limits:
        return
    lower, upper = cube_slider_range(p)
    derived = {"slider_lower": min(lower, 0.0), "slider_upper": max(upper, 0.0)}
    for name in p.derived_limits:
        object.__setattr__(p, name, derived[name])


def check_given_limits(p: Machine) -> None:
    """Refuse given slider limits that keep the sliders from part of the cube.

    Args:
        p: The machine, its limits set.

    Raises:
        InvalidParameterError: Naming the limit, the cube (mm), the slider
            range it needs, the limits and the fix (widen them, or omit them).
    """
    if len(p.derived_limits) == 2:  # both derived: nothing given to check
        return
    lower, upper = cube_slider_range(p)
    short = [
        (name, value)
        for name, value, bad in (
            ("slider_lower", p.slider_lower, p.slider_lower > lower + LIMIT_TOL),
            ("slider_upper", p.slider_upper, p.slider_upper < upper - LIMIT_TOL),
        )
        if bad and name not in p.derived_limits
    ]
    if short:
        name, value = short[0]
        raise InvalidParameterError(
            name,
            value,
            f"slider limits that reach the whole prescribed {p.workspace.describe()}: "
            f"it needs slider values in [{1e3 * lower:.2f}, {1e3 * upper:.2f}] mm, the "
            f"limits are [{1e3 * p.slider_lower:.2f}, {1e3 * p.slider_upper:.2f}] mm; widen "
            "them, or omit slider_lower and slider_upper to derive them from the cube",
        )


def check_limits(p: Machine) -> None:
    """Derive the slider limits not given, then check them all (parameters being built).

    The limits must straddle home (``slider_lower <= 0 <= slider_upper``, with a
    positive stroke), given ones must reach the whole cube
    (:func:`check_given_limits`), and the leg must be longer than the largest
    slider excursion from home.

    Args:
        p: The machine; its limits named in ``derived_limits`` are set [m].

    Raises:
        InvalidParameterError: Naming the limit (or the leg length) at fault.
    """
    set_derived_limits(p)
    if not p.slider_lower <= 0.0:
        raise InvalidParameterError(
            "slider_lower", p.slider_lower, "<= 0 (the isotropic configuration is at 0)"
        )
    if not p.slider_upper >= 0.0:
        raise InvalidParameterError(
            "slider_upper", p.slider_upper, ">= 0 (the isotropic configuration is at 0)"
        )
    if not p.slider_upper > p.slider_lower:
        raise InvalidParameterError(
            "slider_upper", p.slider_upper, f"> slider_lower={p.slider_lower}"
        )
    check_given_limits(p)
    reach = max(p.slider_upper, -p.slider_lower)
    if not reach < p.leg_length:
        # A leg long enough for the stroke: at every slider value the leg's joint
        # point B_i = (q_i - L) e_i stays on its own side of the isotropic tool
        # point, so the leg never has to pass through the platform's position.
        raise InvalidParameterError(
            "leg_length",
            p.leg_length,
            f"longer than the largest slider excursion {reach:.6g} m from home "
            f"(slider limits [{p.slider_lower:.6g}, {p.slider_upper:.6g}] m); "
            "lengthen the leg or shorten the stroke",
        )


#: The way out named by :func:`check_slider_limits` by default.
CHECK_LIMITS_HINT: Final = "pass check_limits=False to compute there anyway"


def check_slider_limits(
    params: Machine,
    points: ArrayLike,
    *,
    hint: str | None = CHECK_LIMITS_HINT,
    tol: float = LIMIT_TOL,
) -> None:
    """Refuse tool points whose slider values leave the limits, as ``orthoglide ik`` does.

    Args:
        params: The machine (leg length, slider limits).
        points: Tool points [m], shape (N, 3) or (3,).
        hint: The way out the message names in brackets (``None``: none).
        tol: Slack on the slider values [m] (``LIMIT_TOL``: rounding only).

    Raises:
        UnreachablePointError: Naming the first such point, its slider, the value
            and the limits; also for a point no leg reaches.
        InvalidParameterError: Points that are not finite rows of three numbers.
    """
    p = finite_rows("points", points, 3, "[m]")
    lo, hi = params.slider_lower, params.slider_upper
    q = inverse_kinematics(p, params.leg_length)  # raises for a point out of reach
    bad = (q < lo - tol) | (q > hi + tol)
    if bad.any():
        row, col = (int(i[0]) for i in np.nonzero(bad))
        raise UnreachablePointError(
            p[row],
            col + 1,
            f"slider value {q[row, col]:.6g} m outside the limits [{lo:.6g}, {hi:.6g}] m"
            + (f" ({hint})" if hint else ""),
        )


def check_slider_values(
    params: Machine, q: ArrayLike, *, hint: str | None = CHECK_LIMITS_HINT
) -> None:
    """Refuse slider values beyond the limits, as ``orthoglide fk`` does.

    Args:
        params: The machine (slider limits).
        q: Slider values [m], shape (N, 3) or (3,).
        hint: As for :func:`check_slider_limits`.

    Raises:
        InvalidParameterError: Naming the first slider beyond its limits
            (``q1``, ``q2`` or ``q3``), its value and the limits; also for
            values that are not finite rows of three numbers (``q``).
    """
    values = finite_rows("q", q, 3, "[m]")
    lo, hi = params.slider_lower, params.slider_upper
    bad = (values < lo - LIMIT_TOL) | (values > hi + LIMIT_TOL)
    if bad.any():
        row, col = (int(i[0]) for i in np.nonzero(bad))
        raise InvalidParameterError(
            f"q{col + 1}",
            float(values[row, col]),
            f"within the slider limits [{lo:.6g}, {hi:.6g}] m" + (f" ({hint})" if hint else ""),
        )
