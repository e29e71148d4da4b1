"""Certified Cartesian limits for a controller that plans in Cartesian space (LinuxCNC).

LinuxCNC's planner (2.9) bounds the tool's path speed by ``[TRAJ]
MAX_LINEAR_VELOCITY`` and each axis's speed and acceleration by ``[AXIS_*]``;
it does not look at the joints' limits under a non-trivial kinematics
(LinuxCNC issue #97). This module chooses Cartesian limits under which no
motion anywhere in the cube can drive a slider beyond its own.

With ``M = J^-1`` (rows ``(P - B_i)^T / eta_i``, design notes section 2) and
``q_i = p_i + L - eta_i``:

* ``q_i' = M_i p'``, so ``|q_i'| <= ||M_i||_2 ||p'||_2`` and ``||M_i||_2 = L / eta_i``;
* ``q_i'' = M_i p'' + p'^T H_i p'`` with ``p'^T H_i p' = (p_j'^2 + p_k'^2) / eta_i
  + (p_j p_j' + p_k p_k')^2 / eta_i^3 <= ||p'||_2^2 L^2 / eta_i^3``, so
  ``|q_i''| <= ||M_i||_1 max_a |p_a''| + (L^2 / eta_i^3) ||p'||_2^2``.

The path speed bounds ``||p'||_2`` (``v``), the axes' accelerations bound
``|p_a''|`` (``a``). Over the cube, ``R2 = max L / eta_i``, ``R1 = max
||M_i||_1`` and ``K = max L^2 / eta_i^3`` are bounded from above with interval
arithmetic (arb balls over sub-boxes,
``inverse_jacobian_enclosure`` of ``kinetostatics.interval_jacobian``).
Then ``v = min(V_j / R2, sqrt(A_j / (2 K)))`` and ``a = (A_j - K v^2) / R1``
keep ``|q_i'| <= V_j`` and ``|q_i''| <= A_j`` (``V_j``, ``A_j``: the sliders'
limits). The design's program axes
(:func:`~orthoglide_pin.program.axes.design_axes`, a signed permutation, a
rotation) change none of these bounds: the path speed is the same in either
frame, and each axis's acceleration bound is the same number on every axis, so
only which program axis lies on which world axis differs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from flint import arb
from numpy.typing import NDArray

from orthoglide_pin._validation import bounded_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.interval_jacobian import (
    inverse_jacobian_enclosure,
    up,
)
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Sub-boxes per cube edge of the interval bounds (``8^3`` boxes).
SUBDIVISIONS: Final[int] = 8
#: The sliders' limits when neither a drive file nor options give them: the
#: prototype's sizing (1.2 m/s, 20 m/s^2, paper section 4) [m/s], [m/s^2].
DEFAULT_SLIDER_SPEED: Final[float] = 1.2
DEFAULT_SLIDER_ACCELERATION: Final[float] = 20.0
_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


@dataclass(frozen=True)
class CartesianLimits:
    """Joint limits and the Cartesian limits certified against them.

    Attributes:
        joint_speed: Largest slider speed ``V_j`` [m/s].
        joint_acceleration: Largest slider acceleration ``A_j`` [m/s^2].
        joint_jerk: Largest slider jerk [m/s^3], or ``None`` (LinuxCNC 2.9's
            planner has no jerk limit; recorded for the streamed plan).
        speed: Certified path speed ``v`` (and each axis's speed) [m/s].
        acceleration: Certified acceleration of each axis ``a`` [m/s^2].
        speed_gain: ``R2``, upper bound of ``L / eta_i`` over the cube [-].
        acceleration_gain: ``R1``, upper bound of ``||M_i||_1`` over the cube [-].
        curvature: ``K``, upper bound of ``L^2 / eta_i^3`` over the cube [1/m].
        sampled: The three maxima over a grid of the cube (lower bounds of the
            same quantities, to show how tight the bounds are).
    """

    joint_speed: float
    joint_acceleration: float
    joint_jerk: float | None
    speed: float
    acceleration: float
    speed_gain: float
    acceleration_gain: float
    curvature: float
    sampled: tuple[float, float, float]

    def worst_joint_speed(self) -> float:
        """The bound of any slider's speed under the Cartesian limits [m/s]."""
        return self.speed_gain * self.speed

    def worst_joint_acceleration(self) -> float:
        """The bound of any slider's acceleration under the Cartesian limits [m/s^2]."""
        return self.acceleration_gain * self.acceleration + self.curvature * self.speed**2


def _span(a: float, b: float) -> arb:
    return arb(a).union(arb(b))


def _abs_span(a: float, b: float) -> arb:
    """A ball holding ``{|t| : a <= t <= b}``."""
    lo = 0.0 if a <= 0.0 <= b else min(abs(a), abs(b))
    return _span(lo, max(abs(a), abs(b)))


def box_gains(lo: FloatArray, hi: FloatArray, leg_length: float) -> tuple[float, float, float]:
    """Upper bounds of ``(R2, R1, K)`` over one box of tool points.

    Args:
        lo: Lowest corner of the box [m], shape (3,).
        hi: Highest corner [m], shape (3,).
        leg_length: Leg length ``L`` [m].

    Returns:
        ``(max L / eta_i, max ||M_i||_1, max L^2 / eta_i^3)`` [-], [-], [1/m].

    Raises:
        InvalidParameterError: A leg may be orthogonal to its slider (or out of
            reach) in the box: no finite bound.
    """
    m = inverse_jacobian_enclosure(lo, hi, leg_length)
    if isinstance(m, int):
        raise InvalidParameterError(
            "workspace", f"leg {m}", "a cube free of serial singularities (eta_i > 0)"
        )
    L = arb(leg_length)
    r2 = r1 = k = 0.0
    for i, j, k_ in _CYCLIC:
        sq = [_abs_span(float(lo[n]), float(hi[n])) ** 2 for n in (j, k_)]
        inv_eta = (L * L - sq[0] - sq[1]).rsqrt()
        r2 = max(r2, up(L * inv_eta))
        k = max(k, up(L * L * inv_eta**3))
        row = arb(0)
        for c in range(3):
            row += abs(m[i, c])
        r1 = max(r1, up(row))
    return r2, r1, k


def cube_gains(params: OrthoglideParams, n: int = SUBDIVISIONS) -> tuple[float, float, float]:
    """Upper bounds of ``(R2, R1, K)`` over the design's cube (``n^3`` sub-boxes)."""
    corner = np.asarray(params.workspace_corner, dtype=float)
    h = params.workspace_side / n
    best = [0.0, 0.0, 0.0]
    for idx in np.ndindex(n, n, n):
        lo = corner + h * np.asarray(idx, dtype=float)
        hi = corner + h * (np.asarray(idx, dtype=float) + 1.0)
        for m, value in enumerate(box_gains(lo, hi, params.leg_length)):
            best[m] = max(best[m], value)
    return best[0], best[1], best[2]


def sampled_gains(params: OrthoglideParams, n: int = 41) -> tuple[float, float, float]:
    """The same three quantities, their maxima over an ``n^3`` grid of the cube."""
    axis = np.linspace(0.0, params.workspace_side, n)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    p = grid + np.asarray(params.workspace_corner, dtype=float)
    L = params.leg_length
    r2 = r1 = k = 0.0
    for _i, j, k_ in _CYCLIC:
        eta = np.sqrt(L * L - p[:, j] ** 2 - p[:, k_] ** 2)
        r2 = max(r2, float(np.max(L / eta)))
        r1 = max(r1, float(np.max(1.0 + (np.abs(p[:, j]) + np.abs(p[:, k_])) / eta)))
        k = max(k, float(np.max(L * L / eta**3)))
    return r2, r1, k


def _round_down(value: float) -> float:
    """``value`` rounded down to 6 significant digits (a certified limit stays one)."""
    if value <= 0.0:
        return value
    scale = 10.0 ** (math.floor(math.log10(value)) - 5)
    return math.floor(value / scale) * scale


def certify_limits(
    params: OrthoglideParams | None,
    joint_speed: float,
    joint_acceleration: float,
    joint_jerk: float | None = None,
) -> CartesianLimits:
    """Cartesian limits under which no slider exceeds its limits anywhere in the cube.

    Args:
        params: The design (leg length and cube); ``None``: the prototype.
        joint_speed: Largest slider speed [m/s].
        joint_acceleration: Largest slider acceleration [m/s^2].
        joint_jerk: Largest slider jerk [m/s^3], or ``None``.

    Returns:
        The certified limits (see the module for the proof).

    Raises:
        InvalidParameterError: Not a design, a limit not positive and finite, or
            a cube that meets a serial singularity.
    """
    params = as_params(params)
    vj = bounded_number("joint_speed", joint_speed, 1e3, "m/s")
    aj = bounded_number("joint_acceleration", joint_acceleration, 1e6, "m/s^2")
    jj = None if joint_jerk is None else bounded_number("joint_jerk", joint_jerk, 1e9, "m/s^3")
    r2, r1, k = cube_gains(params)
    v = _round_down(min(vj / r2, math.sqrt(aj / (2.0 * k))))
    a = _round_down((aj - k * v * v) / r1)
    return CartesianLimits(vj, aj, jj, v, a, r2, r1, k, sampled_gains(params))
