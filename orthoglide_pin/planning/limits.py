"""The limits of a plan, and their constraints along a path as rows in ``(s_ddot, s_dot^2)``.

With ``u = s_ddot`` and ``x = s_dot^2`` along a path, the slider motion is
``q' = dq sqrt(x)`` and ``q'' = dq u + ddq x``, and the slider forces are
``F = a u + b x + c`` (:mod:`orthoglide_pin.dynamics.path_forms`). Each limit
becomes rows ``A u + B x + C <= 1`` at every grid point, or a bound on ``x``:

* slider speed ``|q'_i| <= v``: ``x <= (v / |dq_i|)^2``; the feed ``F``: ``x <= F^2``;
  the motor speed ``|w_i| <= w_max`` (and the last speed of the speed-torque
  curve): ``x <= (w_max / (k |dq_i|))^2`` with ``k = 2 pi n / l``;
* slider acceleration ``|q''_i| <= A``: two rows per slider;
* motor torque (:mod:`orthoglide_pin.drives.motor`)
  ``T = r e F + J k q'' + h(q')``, ``r = l / (2 pi n)``, ``e = 1 / eta`` when
  the motor drives (``F q' >= 0``) and ``eta`` when back-driven, within
  ``+-T_av(|w|)``, the smaller of the peak torque and the speed-torque curve.
  The load torque is ``max(rF/eta, rF eta)`` where ``dq > 0`` (convex in F:
  its upper bound is exactly two rows, its lower bound is taken on the
  back-driven row) and ``min(...)`` where ``dq < 0`` (the mirror); at rest
  (a section's ends) the driving row bounds both sides.

The friction ``h`` and the available torque ``T_av`` depend on the speed
``sqrt(x)``, which is not linear in ``x``. Their part ``phi(x)`` of each row is
replaced by an affine **majorant** on ``[0, X]``: the tangent at ``x0`` (the
previous pass's speed profile) raised by the largest excess of ``phi`` over it
on a sampling of ``[0, X]``, where ``X`` bounds ``x`` (the speed bounds above,
or a trust region around the previous pass, enforced as a bound on ``x``). A
concave ``phi`` (friction while driving at constant available torque) keeps
its tangent, exact at ``x0``; the plan is then iterated on the new profile, and
the verification (:mod:`orthoglide_pin.planning.verify`) checks the exact
nonlinear limits on a finer grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import MAX_ACCELERATION, MAX_JERK, MAX_SPEED, bounded_number
from orthoglide_pin.drives.motor import RPM_PER_RAD_S, Drive
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.reach_compiled import AVAILABLE
from orthoglide_pin.planning.rows_compiled import IDLE, Motors, torque_rows

FloatArray = NDArray[np.float64]

#: Whether the torque rows run compiled (:mod:`~orthoglide_pin.planning.rows_compiled`).
COMPILED: bool = AVAILABLE

#: Samples of ``[0, X]`` for the majorants (quadratically spaced).
MAJORANT_SAMPLES: Final[int] = 24
#: The trust region: ``X`` is at most this times the previous pass's largest ``x``.
TRUST: Final[float] = 4.0
#: Largest squared path speed considered when nothing bounds it [(m/s)^2].
X_CAP: Final[float] = 1e4
#: Largest value of each slider limit (the package's input caps).
LIMIT_CAPS: Final = {
    "slider_speed": MAX_SPEED,
    "slider_acceleration": MAX_ACCELERATION,
    "slider_jerk": MAX_JERK,
}
#: The units of the slider limits, as the errors name them.
LIMIT_UNITS: Final = {
    "slider_speed": "[m/s]",
    "slider_acceleration": "[m/s^2]",
    "slider_jerk": "[m/s^3]",
}
#: A row that never binds (padding) has this constant.
_IDLE: Final[float] = IDLE
#: Share of the motor's torque a plan leaves to the servo loop by default [-]: the
#: position loop needs some to correct its errors, and a plan that uses the whole
#: peak torque saturates the motor it was planned for (measured in simulation on
#: the shipped programs: 2.25 ms saturated on ``contour`` without a reserve, none
#: from a reserve of 1 %; 10 % costs 0.5 % of the cycle time; see the guide).
DEFAULT_TORQUE_RESERVE: Final[float] = 0.1


@dataclass(frozen=True)
class PlanLimits:
    """The limits a plan respects; each applies when it is given.

    Attributes:
        slider_speed: Largest slider speed [m/s], in ``(0, 1000]``.
        slider_acceleration: Largest slider acceleration [m/s^2], in ``(0, 1e5]``.
        slider_jerk: Largest slider jerk [m/s^3], in ``(0, 1e9]``, applied by a jerk-limited
            re-timing of the second-order plan (:mod:`~orthoglide_pin.planning.jerk`).
        drive: The drive of each slider: the torques are computed with it, and
            its motor data (peak torque, speed-torque curve, maximum speed) limit them.
        torque_reserve: Share of the motor's available torque (the peak torque
            and the speed-torque curve) kept free for the servo loop, in
            ``[0, 1)`` [-]: the plan uses at most ``1 - torque_reserve`` of it.
    """

    slider_speed: float | None = None
    slider_acceleration: float | None = None
    slider_jerk: float | None = None
    drive: Drive | None = None
    torque_reserve: float = DEFAULT_TORQUE_RESERVE

    def __post_init__(self) -> None:
        for name in ("slider_speed", "slider_acceleration", "slider_jerk"):
            value = getattr(self, name)
            if value is not None:
                cap, unit = LIMIT_CAPS[name], LIMIT_UNITS[name]
                object.__setattr__(self, name, bounded_number(name, value, cap, unit))
        if self.drive is not None and not isinstance(self.drive, Drive):
            raise InvalidParameterError("drive", self.drive, "a Drive (load_drive)")
        object.__setattr__(self, "torque_reserve", torque_reserve(self.torque_reserve))

    @property
    def motor_speed(self) -> float | None:
        """Largest motor speed [rad/s]: the motor's maximum, or its curve's last speed."""
        motor = None if self.drive is None else self.drive.motor
        if motor is None:
            return None
        speeds = [] if motor.max_speed is None else [motor.max_speed]
        if motor.speed_torque_curve is not None:
            speeds.append(motor.speed_torque_curve[-1][0])
        return min(speeds) / RPM_PER_RAD_S if speeds else None

    @property
    def limits_torque(self) -> bool:
        """Whether the motor's torque is limited (a peak torque or a curve)."""
        motor = None if self.drive is None else self.drive.motor
        return motor is not None and (
            motor.peak_torque is not None or motor.speed_torque_curve is not None
        )

    @property
    def second_order(self) -> bool:
        """Whether some limit bounds the accelerations (needed by every move)."""
        return self.slider_acceleration is not None or self.limits_torque

    def available_torque(self, speed: FloatArray) -> FloatArray:
        """Torque the plan may use at motor speeds ``|w|`` [rad/s] [N.m] (``inf`` without a limit).

        The smaller of the peak torque and the speed-torque curve, times
        ``1 - torque_reserve``.
        """
        w = np.abs(np.asarray(speed, dtype=float))
        out = np.full(w.shape, np.inf)
        motor = None if self.drive is None else self.drive.motor
        if motor is None:
            return out
        if motor.peak_torque is not None:
            out = np.minimum(out, motor.peak_torque)
        if motor.speed_torque_curve is not None:
            curve = np.asarray(motor.speed_torque_curve) * (1.0 / RPM_PER_RAD_S, 1.0)
            out = np.minimum(out, np.interp(w, curve[:, 0], curve[:, 1], right=0.0))
        return out * (1.0 - self.torque_reserve)

    def reference_torque(self) -> float:
        """The largest torque the plan may use [N.m] (scales the torque rows)."""
        return float(self.available_torque(np.zeros(1))[0])


def torque_reserve(value: object, name: str = "torque_reserve") -> float:
    """``value`` as a torque reserve: a finite fraction in ``[0, 1)``.

    Raises:
        InvalidParameterError: Naming ``name``, the value and the range.
    """
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
    number = float(value) if ok else math.nan  # type: ignore[arg-type]
    if not (math.isfinite(number) and 0.0 <= number < 1.0):
        raise InvalidParameterError(
            name, value, "a fraction of the peak torque from 0 to below 1 (0.1: 10 %)"
        )
    return number


@dataclass
class Scales:
    """Factors (<= 1) that tighten the limits of a section after a failed verification.

    A factor is one number for the whole section, or one per planning-grid point
    ((n,), :mod:`~orthoglide_pin.planning.tighten`: only the points around a
    violation are tightened).
    """

    factors: dict[str, float | FloatArray] = field(default_factory=dict)

    def get(self, name: str) -> float | FloatArray:
        """The factor of limit ``name``: a number or (n,) (1 when untouched)."""
        return self.factors.get(name, 1.0)

    def column(self, name: str) -> float | FloatArray:
        """The factor of ``name`` as a column, (n, 1), to scale rows of (n, m) (or a number)."""
        f = self.get(name)
        return f if isinstance(f, float) else np.reshape(f, (-1, 1))


def speed_bound(
    limits: PlanLimits, forms: PathForms, feed: FloatArray, scales: Scales
) -> FloatArray:
    """The bound on ``x = s_dot^2`` at each point [(m/s)^2], ``inf`` where none, (n,)."""
    return speed_bound_dq(limits, forms.dq, feed, scales)


def speed_bound_dq(
    limits: PlanLimits, dq_path: FloatArray, feed: FloatArray, scales: Scales
) -> FloatArray:
    """:func:`speed_bound` from the sliders' ``dq/ds`` alone, (n, 3) (point by point)."""
    dq = np.abs(dq_path).max(axis=1)
    x = np.full(dq.shape, np.inf)
    with np.errstate(divide="ignore"):
        if limits.slider_speed is not None:
            x = np.minimum(x, (scales.get("slider_speed") * limits.slider_speed / dq) ** 2)
        w = limits.motor_speed
        if w is not None:
            assert limits.drive is not None
            k = float(limits.drive.train.motor_speed(1.0))
            x = np.minimum(x, (scales.get("motor_speed") * w / (k * dq)) ** 2)
    return np.asarray(np.minimum(x, (scales.get("feed") * feed) ** 2))


def _probe(xs: FloatArray, xt: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The points where :func:`_majorant` reads ``phi`` besides ``xs``, (n, 4), and its step."""
    step = 1e-4 * xt
    return np.stack([xt - step, xt, xt + step, np.minimum(4.0 * xt, xs[:, -1])], axis=1), step


def _majorant(
    probe: FloatArray, vals: FloatArray, xs: FloatArray, xt: FloatArray, step: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Slope and intercept of an affine majorant of ``phi`` on the samples ``xs``, tight at ``xt``.

    Three lines are raised until they lie above every sample: the tangent at
    ``xt``, the chord over ``[0, X]`` and the chord over ``[0, min(4 xt, X)]``
    (a chord is a majorant of a convex part, a tangent of a concave one); the
    lowest at ``xt`` is kept.

    Args:
        probe: ``phi`` at the :func:`_probe` points, (n, 4).
        vals: ``phi`` at ``xs``, (n, S).
        xs: Samples of ``[0, X]`` per point, (n, S), from 0 to ``X``.
        xt: The point where the line should be tight, (n,).
        step: The step of the tangent's central difference, (n,).
    """
    zero, top = vals[:, 0], vals[:, -1]
    x_top, x_mid = xs[:, -1], np.minimum(4.0 * xt, xs[:, -1])
    with np.errstate(divide="ignore", invalid="ignore"):
        slopes = (
            (probe[:, 2] - probe[:, 0]) / (2.0 * step),
            np.where(x_top > 0.0, (top - zero) / x_top, 0.0),
            np.where(x_mid > 0.0, (probe[:, 3] - zero) / x_mid, 0.0),
        )
    bases = (probe[:, 1] - slopes[0] * xt, zero, zero)
    best_slope, best_cut, best_at = np.zeros_like(xt), np.zeros_like(xt), np.full(xt.shape, np.inf)
    for raw, base in zip(slopes, bases, strict=True):
        slope = np.nan_to_num(raw, nan=0.0, posinf=0.0, neginf=0.0)
        lift = np.maximum((vals - slope[:, None] * xs).max(axis=1) - base, 0.0)
        cut = base + lift
        at = cut + slope * xt
        better = at < best_at
        best_slope = np.where(better, slope, best_slope)
        best_cut = np.where(better, cut, best_cut)
        best_at = np.where(better, at, best_at)
    return best_slope, best_cut


def rows(
    limits: PlanLimits,
    forms: PathForms,
    x_high: FloatArray,
    x0: FloatArray,
    scales: Scales,
    ends: NDArray[np.bool_] | None = None,
    values: tuple[FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The rows ``A u + B x + C <= 1`` of the second-order limits at each point.

    Args:
        limits: The limits.
        forms: The path forms at the ``n`` grid points of a section.
        x_high: The bound ``X`` on ``x`` at each point [(m/s)^2], finite, (n,).
        x0: The squared speeds of the previous pass [(m/s)^2], (n,).
        scales: Tightening factors per limit.
        ends: The points where a section starts or ends, (n,) (``None``: the
            first and the last; several sections laid end to end, :func:`joined_rows`).
        values: The friction and available torque at :func:`samples` of ``x_high``
            (:func:`~orthoglide_pin.planning.rows_compiled.sample_values`), when
            known (compiled rows only), else ``None``.

    Returns:
        ``(A, B, C)``, each (n, m).
    """
    n = forms.q.shape[0]
    parts: list[tuple[FloatArray, FloatArray, FloatArray]] = []
    if limits.slider_acceleration is not None:
        acc = scales.column("slider_acceleration") * limits.slider_acceleration
        for sign in (1.0, -1.0):
            parts.append((sign * forms.dq / acc, sign * forms.ddq / acc, np.zeros((n, 3))))
    if limits.limits_torque:
        scale = scales.column("motor_torque")
        parts.extend(_torque_rows(limits, forms, x_high, x0, scale, ends, values))
    if not parts:
        return np.zeros((n, 0)), np.zeros((n, 0)), np.zeros((n, 0))
    a, b, c = (np.concatenate(col, axis=1) for col in zip(*parts, strict=True))
    return a, b, c


def joined_scales(scales: list[Scales], sizes: list[int]) -> Scales:
    """The factors of sections of ``sizes`` points laid end to end, one per point."""
    return Scales(
        {
            name: np.concatenate(
                [
                    np.broadcast_to(np.asarray(s.get(name), dtype=float), (k,))
                    for s, k in zip(scales, sizes, strict=True)
                ]
            )
            for name in sorted({n for s in scales for n in s.factors})
        }
    )


def joined_rows(
    limits: PlanLimits,
    forms: list[PathForms],
    x_high: list[FloatArray],
    x0: list[FloatArray],
    scales: list[Scales],
) -> list[tuple[FloatArray, FloatArray, FloatArray]]:
    """:func:`rows` of several sections, computed in one batch (the same numbers).

    A program of many short sections (a stop at every block) would otherwise
    pay the rows' set-up once per section.
    """
    if len(forms) == 1:
        return [rows(limits, forms[0], x_high[0], x0[0], scales[0])]
    sizes = [f.q.shape[0] for f in forms]
    names = ("q", "dq", "ddq", "a", "b", "c")
    cat = PathForms(*(np.concatenate([getattr(f, n) for f in forms]) for n in names))
    joined = joined_scales(scales, sizes)
    a, b, c = flat_rows(limits, cat, np.concatenate(x_high), np.concatenate(x0), joined, sizes)
    cuts = np.cumsum(sizes)[:-1]
    return list(zip(*(np.split(m, cuts) for m in (a, b, c)), strict=True))


def flat_rows(
    limits: PlanLimits,
    forms: PathForms,
    x_high: FloatArray,
    x0: FloatArray,
    scales: Scales,
    sizes: list[int],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`rows` of sections of ``sizes`` points laid end to end (their ends marked)."""
    cuts = np.cumsum(sizes)
    ends = np.zeros(int(cuts[-1]), dtype=bool)
    ends[cuts - 1] = True
    ends[np.concatenate([[0], cuts[:-1]])] = True
    return rows(limits, forms, x_high, x0, scales, ends)


def motors(limits: PlanLimits) -> Motors:
    """What the compiled torque rows read of ``limits`` (the motor's torque limited)."""
    assert limits.drive is not None
    return Motors(limits.drive, 1.0 - limits.torque_reserve, limits.reference_torque())


def samples(x_high: FloatArray) -> FloatArray:
    """The samples of ``[0, X]`` of each point for its majorants (quadratically spaced), (n, S)."""
    frac = (np.arange(MAJORANT_SAMPLES + 1) / MAJORANT_SAMPLES) ** 2
    return np.asarray(x_high[:, None] * frac[None, :])


def _torque_rows(
    limits: PlanLimits,
    forms: PathForms,
    x_high: FloatArray,
    x0: FloatArray,
    scale: float | FloatArray,
    ends: NDArray[np.bool_] | None = None,
    values: tuple[FloatArray, FloatArray] | None = None,
) -> list[tuple[FloatArray, FloatArray, FloatArray]]:
    """Four rows per motor (see the module), each ``/ T_ref``, as ``... <= 1``."""
    assert limits.drive is not None
    train = limits.drive.train
    r = train.lead / (2.0 * math.pi * train.gear_ratio)
    k = float(train.motor_speed(1.0))
    inertia = train.reflected_inertia * k
    eta = train.efficiency
    t_ref = limits.reference_torque()
    n = forms.q.shape[0]
    # the samples of [0, X] and the tangent points, per grid point
    xs = samples(x_high)  # (n, S)
    xt = np.clip(x0, 1e-6 * x_high, x_high)
    probe, step = _probe(xs, xt)
    out = []
    dq, ddq = forms.dq, forms.ddq
    if ends is None:
        ends = np.zeros(n, dtype=bool)
        ends[[0, -1]] = True
    if COMPILED:  # the same rows, one loop (rows_compiled)
        return [torque_rows(motors(limits), forms, xs, (probe, xt, step), scale, ends, values)]
    for i in range(3):
        d = dq[:, i]

        def parts(x: FloatArray, d: FloatArray = d) -> tuple[FloatArray, FloatArray]:
            """Friction and available torque at ``x`` over ``T_ref`` (phi for both signs)."""
            w = k * (d[:, None] * np.sqrt(x))  # motor speed [rad/s]
            return train.friction(w) / t_ref, scale * limits.available_torque(w) / t_ref

        linear = {}
        for e in (1.0 / eta, eta):
            lin_u = (r * e * forms.a[:, i] + inertia * d) / t_ref
            lin_x = (r * e * forms.b[:, i] + inertia * ddq[:, i]) / t_ref
            lin_c = r * e * forms.c[:, i] / t_ref
            linear[e] = (lin_u, lin_x, lin_c)
        (h_probe, av_probe), (h_xs, av_xs) = parts(probe), parts(xs)
        maj = {
            sign: _majorant(sign * h_probe - av_probe, sign * h_xs - av_xs, xs, xt, step)
            for sign in (1.0, -1.0)
        }
        positive, negative = d > 0.0, d < 0.0
        drive_e, back_e = 1.0 / eta, eta
        every = np.ones(n, dtype=bool)
        # (sign, back-driven efficiency where, row applies where): see the module
        plan = (
            (1.0, negative, every),
            (1.0, positive, positive | (negative & ends)),
            (-1.0, positive, every),
            (-1.0, negative, negative | (positive & ends)),
        )
        for sign, back, active in plan:
            lu = np.where(back, linear[back_e][0], linear[drive_e][0])
            lx = np.where(back, linear[back_e][1], linear[drive_e][1])
            lc = np.where(back, linear[back_e][2], linear[drive_e][2])
            slope, intercept = maj[sign]
            a = np.where(active, sign * lu, 0.0)
            b = np.where(active, sign * lx + slope, 0.0)
            c = np.where(active, sign * lc + intercept + 1.0, _IDLE)
            out.append((a[:, None], b[:, None], c[:, None]))
    return out
