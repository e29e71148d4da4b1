"""One-dimensional motion laws: trapezoidal and jerk-limited (S-curve) velocity profiles.

A motion law moves a scalar path coordinate ``s`` [m] from rest at 0 to rest at
a distance ``D`` [m] under bounds on the velocity ``v_max`` [m/s], the
acceleration ``a_max`` [m/s^2] and, for the S-curve, the jerk ``jerk``
[m/s^3]. Both laws are symmetric (the deceleration mirrors the acceleration)
and time-optimal under their bounds.

Every law is stored as seven phases of constant jerk ``j_k`` with durations
``T_1 .. T_7`` [s]; inside phase ``k`` the state is the exact cubic
``s = s_k + v_k tau + a_k tau^2 / 2 + j_k tau^3 / 6`` (``tau`` the time since the
phase start), so sampling is closed form at any time:

* S-curve (``j_k = J, 0, -J, 0, -J, 0, J``): ``T_1 = T_3 = T_5 = T_7 = T_j``
  (jerk phases), ``T_2 = T_6`` (constant acceleration), ``T_4`` (cruise).
  ``T_j = a_max / J`` and ``T_2 = v_max / a_max - a_max / J`` when both bounds
  are reached, so ``T = D / v_max + v_max / a_max + a_max / J``. Degenerate
  cases: ``a_max`` not reached (``v_max J < a_max^2`` or
  ``D < 2 a_max^3 / J^2``): ``T_2 = 0``; ``v_max`` not reached
  (``D < v_max (T_j + T_2 + T_j)``): ``T_4 = 0`` and a lower peak velocity.
* Trapezoid: the S-curve with an infinite jerk, i.e. the jerk phases last 0
  and the acceleration jumps. ``T = D / v_max + v_max / a_max`` when
  ``v_max^2 / a_max < D``, else (triangle) ``T = 2 sqrt(D / a_max)``. Its jerk
  is reported as 0 (the Dirac impulses at the switches are left out).

Samples are right-continuous (at a switch, the value of the phase that starts);
before 0 the axis rests at ``s = 0``, from the end on at ``s = D``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import MAX_ACCELERATION, MAX_JERK, MAX_SPEED
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]

#: Names of the two laws, as reported by :attr:`MotionProfile.kind`.
KINDS: Final = ("trapezoidal", "s-curve")


class ProfileSample(NamedTuple):
    """A motion law sampled at given times; every array has the shape of the times.

    Attributes:
        s: Path coordinate [m].
        v: Velocity [m/s].
        a: Acceleration [m/s^2].
        j: Jerk [m/s^3].
    """

    s: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray


def _number(
    name: str, value: float, allowed: str, *, positive: bool, high: float = math.inf
) -> float:
    """``value`` as a finite float (positive, or non-negative) up to ``high``, else an error."""
    try:
        out = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not math.isfinite(out) or out < 0.0 or (positive and out == 0.0) or out > high:
        raise InvalidParameterError(name, value, allowed)
    return out


#: Bounds of a law and their ranges: up to ``MAX_SPEED``, ``MAX_ACCELERATION``
#: and ``MAX_JERK`` (:mod:`orthoglide_pin._validation`), so that every time,
#: distance and power of the law stays finite.
_BOUNDS: Final = {
    "v_max": (MAX_SPEED, "m/s"),
    "a_max": (MAX_ACCELERATION, "m/s^2"),
    "jerk": (MAX_JERK, "m/s^3"),
}


def _bound(name: str, value: float) -> float:
    high, unit = _BOUNDS[name]
    return _number(
        name, value, f"a positive bound up to {high:g} {unit}", positive=True, high=high
    )


@dataclass(frozen=True)
class MotionProfile:
    """A rest-to-rest motion law over a distance, in seven constant-jerk phases.

    Build one with :func:`trapezoidal_profile`, :func:`s_curve_profile` or
    :meth:`MotionLimits.profile`.

    Attributes:
        distance: Distance ``D`` travelled [m].
        v_max: Velocity bound [m/s].
        a_max: Acceleration bound [m/s^2].
        jerk: Jerk bound [m/s^3] (``inf`` for the trapezoid).
        durations: Durations of the seven phases [s].
        peak_velocity: Velocity reached (``v_max`` unless ``D`` is too short) [m/s].
        peak_acceleration: Acceleration reached (``a_max`` unless limited) [m/s^2].
    """

    distance: float
    v_max: float
    a_max: float
    jerk: float
    durations: tuple[float, float, float, float, float, float, float]
    peak_velocity: float
    peak_acceleration: float

    @property
    def kind(self) -> str:
        """``"trapezoidal"`` or ``"s-curve"``."""
        return KINDS[0] if math.isinf(self.jerk) else KINDS[1]

    @property
    def duration(self) -> float:
        """Total duration ``T`` [s]."""
        return math.fsum(self.durations)

    @property
    def phase_starts(self) -> FloatArray:
        """Start time of each phase [s], shape (7,)."""
        return np.concatenate(([0.0], np.cumsum(self.durations[:-1])))

    def _phases(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """Start time, position, velocity, acceleration and the jerk of each phase, (7,)."""
        ap = self.peak_acceleration
        jk = 0.0 if math.isinf(self.jerk) else self.jerk
        acc = np.array([0.0, ap, ap, 0.0, 0.0, -ap, -ap])
        jerk = np.array([jk, 0.0, -jk, 0.0, -jk, 0.0, jk])
        pos, vel = np.zeros(7), np.zeros(7)
        for k in range(6):  # exact cubic of phase k up to its end
            d = self.durations[k]
            vel[k + 1] = vel[k] + acc[k] * d + jerk[k] * d * d / 2.0
            pos[k + 1] = pos[k] + vel[k] * d + acc[k] * d * d / 2.0 + jerk[k] * d**3 / 6.0
        return self.phase_starts, pos, vel, acc, jerk

    def sample(self, t: ArrayLike) -> ProfileSample:
        """Position, velocity, acceleration and jerk at the given times.

        Args:
            t: Times [s], any shape; values outside ``[0, T]`` give the rest
                states at the ends.

        Returns:
            The samples, each of the shape of ``t``.

        Raises:
            InvalidParameterError: ``t`` is not an array of finite numbers.
        """
        try:
            tt = np.asarray(t, dtype=np.float64)
        except (TypeError, ValueError):
            raise InvalidParameterError("t", t, "an array of finite times [s]") from None
        if not np.isfinite(tt).all():
            raise InvalidParameterError("t", t, "an array of finite times [s]")
        starts, pos, vel, acc, jerk = self._phases()
        k = np.searchsorted(starts[1:], tt, side="right")  # right-continuous
        tau = tt - starts[k]
        a0, j0 = acc[k], jerk[k]
        s = pos[k] + tau * (vel[k] + tau * (a0 / 2.0 + tau * j0 / 6.0))
        v = vel[k] + tau * (a0 + tau * j0 / 2.0)
        a = a0 + tau * j0
        moving = (tt >= 0.0) & (tt < self.duration)
        return ProfileSample(
            s=np.where(moving, s, np.where(tt < 0.0, 0.0, self.distance)),
            v=np.where(moving, v, 0.0),
            a=np.where(moving, a, 0.0),
            j=np.where(moving, j0, 0.0),
        )


@dataclass(frozen=True)
class MotionLimits:
    """Bounds of a motion law, validated on construction.

    Attributes:
        v_max: Velocity bound [m/s], positive.
        a_max: Acceleration bound [m/s^2], positive.
        jerk: Jerk bound [m/s^3], positive, or ``None`` for the trapezoid.
    """

    v_max: float
    a_max: float
    jerk: float | None = None

    def __post_init__(self) -> None:
        for name in ("v_max", "a_max"):
            object.__setattr__(self, name, _bound(name, getattr(self, name)))
        if self.jerk is not None:
            allowed = f"a positive jerk bound up to {MAX_JERK:g} m/s^3, or None for a trapezoid"
            jerk = _number("jerk", self.jerk, allowed, positive=True, high=MAX_JERK)
            object.__setattr__(self, "jerk", jerk)

    def profile(self, distance: float) -> MotionProfile:
        """The time-optimal law over ``distance`` [m] under these bounds."""
        if self.jerk is None:
            return trapezoidal_profile(distance, self.v_max, self.a_max)
        return s_curve_profile(distance, self.v_max, self.a_max, self.jerk)

    def scaled(self, v_max: float | None = None, a_max: float | None = None) -> MotionLimits:
        """A copy with other velocity or acceleration bounds (same jerk)."""
        return MotionLimits(
            self.v_max if v_max is None else v_max,
            self.a_max if a_max is None else a_max,
            self.jerk,
        )


def _check_law(distance: float, v_max: float, a_max: float) -> tuple[float, float, float]:
    D = _number("distance", distance, "a non-negative finite distance [m]", positive=False)
    V, A = _bound("v_max", v_max), _bound("a_max", a_max)
    return D, V, A


def trapezoidal_profile(distance: float, v_max: float, a_max: float) -> MotionProfile:
    """Trapezoidal velocity law: constant acceleration, cruise, constant deceleration.

    Args:
        distance: Distance ``D`` [m], non-negative.
        v_max: Velocity bound [m/s], positive.
        a_max: Acceleration bound [m/s^2], positive.

    Returns:
        The law; a triangle (``v_max`` not reached) when ``v_max^2 / a_max >= D``.

    Raises:
        InvalidParameterError: A negative or non-finite distance, a non-positive bound.
    """
    D, V, A = _check_law(distance, v_max, a_max)
    if D >= V * V / A:
        vp, ta, tv = V, V / A, D / V - V / A
    else:
        vp = math.sqrt(A * D)
        ta, tv = vp / A, 0.0
    ap = A if D > 0.0 else 0.0
    return MotionProfile(D, V, A, math.inf, (0.0, ta, 0.0, tv, 0.0, ta, 0.0), vp, ap)


def s_curve_profile(distance: float, v_max: float, a_max: float, jerk: float) -> MotionProfile:
    """Jerk-limited (S-curve, seven-phase) velocity law.

    Args:
        distance: Distance ``D`` [m], non-negative.
        v_max: Velocity bound [m/s], positive.
        a_max: Acceleration bound [m/s^2], positive.
        jerk: Jerk bound ``J`` [m/s^3], positive.

    Returns:
        The law, with the degenerate cases of the module docstring.

    Raises:
        InvalidParameterError: A negative or non-finite distance, a non-positive bound.
    """
    D, V, A = _check_law(distance, v_max, a_max)
    J = _bound("jerk", jerk)
    # Reaching v_max: jerk phases of A / J if a_max is reachable, else of sqrt(V / J).
    if V * J >= A * A:
        tj, t2 = A / J, V / A - A / J
    else:
        tj, t2 = math.sqrt(V / J), 0.0
    if V * (2.0 * tj + t2) <= D:  # v_max reached: cruise for the rest
        vp, tv = V, D / V - (2.0 * tj + t2)
    elif D >= 2.0 * A**3 / J**2:  # a_max reached, v_max not: D = vp (A / J + vp / A)
        tv, tj = 0.0, A / J
        vp = 2.0 * A * D / (A * A / J + math.sqrt((A * A / J) ** 2 + 4.0 * A * D))
        t2 = max(vp / A - A / J, 0.0)
    else:  # neither: D = 2 J tj^3
        tv, t2 = 0.0, 0.0
        tj = (D / (2.0 * J)) ** (1.0 / 3.0)
        vp = J * tj * tj
    ap = J * tj if D > 0.0 else 0.0
    return MotionProfile(D, V, A, J, (tj, t2, tj, tv, tj, t2, tj), vp, min(ap, A))
