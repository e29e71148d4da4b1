"""The motor-torque rows compiled with numba: one loop over the points and motors.

Each motor's torque rows (:func:`~orthoglide_pin.planning.limits.rows`) bound
``phi(x) = +-friction(w) - available(w)`` (``w`` the motor speed at the squared
path speed ``x``) by a line in ``x``, tight at the previous pass's speed: three
candidate lines (the tangent, two chords) are raised above ``phi``'s samples
and the lowest there is kept (:func:`~orthoglide_pin.planning.limits._majorant`).

Here the motor speeds, the friction and the available torque (the peak torque
and the speed-torque curve, read as ``numpy.interp`` reads it) are evaluated
in compiled loops, but for the friction's ``tanh`` (vectorised in numpy), at
the samples of ``[0, X]`` of every point and motor at once
(:func:`sample_values`); :func:`torque_rows`
then raises the lines of both signs and writes the four rows of each motor
point by point, without the dozens of (points, samples) arrays of the array
version, and with the same operations, so that the two agree to rounding
(``tests/planning/test_rows_compiled.py``). The samples of ``[0, X]`` depend on
the bound ``X`` alone, not on the previous pass's speeds: a window planned
again with the same bounds passes them back (``values``,
:class:`~orthoglide_pin.planning.row_cache.RowCache`) and only the four probes
around the previous speed are evaluated again. Without numba
(:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE` false) the array
version runs.
"""

from __future__ import annotations

import math
from typing import Final, NamedTuple

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import jit
from orthoglide_pin.drives.motor import RPM_PER_RAD_S, Drive
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.reach_compiled import AVAILABLE

FloatArray = NDArray[np.float64]
#: A row that never binds (padding) has this constant (as in the array version).
IDLE: Final[float] = -1e6


class Motors(NamedTuple):
    """What the torque rows read of the limits (:func:`~orthoglide_pin.planning.limits.motors`).

    Attributes:
        drive: The drive (its motor's torque limited).
        keep: The share of the available torque the plan may use [-].
        t_ref: The reference torque the rows are divided by [N.m].
    """

    drive: Drive
    keep: float
    t_ref: float


def curve_torque(x: float, curve_w: FloatArray, curve_t: FloatArray, peak: float,
                 keep: float) -> float:  # fmt: skip
    """``min(peak, curve(x)) keep`` at a speed ``x >= 0`` (the curve read as ``numpy.interp``)."""
    v, last = min(math.inf, peak), curve_w.size - 1
    if last >= 0:
        if x < curve_w[0]:
            t = curve_t[0]
        elif x > curve_w[last]:
            t = 0.0
        else:
            j = 0
            while j < last and curve_w[j + 1] <= x:
                j += 1
            if j == last or curve_w[j] == x:
                t = curve_t[j]
            else:
                slope = (curve_t[j + 1] - curve_t[j]) / (curve_w[j + 1] - curve_w[j])
                t = slope * (x - curve_w[j]) + curve_t[j]
        v = min(v, t)
    return v * keep


def _speeds(dq: FloatArray, x: FloatArray, k: float, w_eps: float, w: FloatArray,
            z: FloatArray) -> None:  # fmt: skip
    """The motor speeds ``w = k (dq sqrt(x))`` and ``z = w / w_eps``, (n, 3, K) each."""
    roots = np.empty(x.shape[1])
    for i in range(x.shape[0]):
        for j in range(x.shape[1]):
            roots[j] = math.sqrt(x[i, j])
        for mot in range(3):
            d = dq[i, mot]
            for j in range(x.shape[1]):
                speed = k * (d * roots[j])
                w[i, mot, j], z[i, mot, j] = speed, speed / w_eps


def _values(w: FloatArray, th: FloatArray, consts: FloatArray, curve_w: FloatArray,
            curve_t: FloatArray, h: FloatArray, av: FloatArray) -> None:  # fmt: skip
    """The friction ``(T_c th + b w) / T_ref`` and :func:`curve_torque` at every ``|w|``."""
    coulomb, viscous, t_ref, peak, keep = consts[0], consts[1], consts[2], consts[3], consts[4]
    flat_w, flat_th = w.reshape(-1), th.reshape(-1)
    flat_h, flat_av = h.reshape(-1), av.reshape(-1)
    for e in range(flat_w.size):
        flat_h[e] = (coulomb * flat_th[e] + viscous * flat_w[e]) / t_ref
        flat_av[e] = curve_torque(abs(flat_w[e]), curve_w, curve_t, peak, keep)


def _raise(vals: FloatArray, xs: FloatArray, i: int, slope: float, base: float) -> float:
    """The intercept of the line of ``slope`` raised from ``base`` above every sample."""
    high, other, m = -math.inf, -math.inf, vals.size
    for j in range(0, m - 1, 2):  # two running maxima: the same largest value, sooner
        high = max(high, vals[j] - slope * xs[i, j])
        other = max(other, vals[j + 1] - slope * xs[i, j + 1])
    if m % 2:
        high = max(high, vals[m - 1] - slope * xs[i, m - 1])
    return base + max(max(high, other) - base, 0.0)


def _kernel(
    dq: FloatArray, ddq: FloatArray, fa: FloatArray, fb: FloatArray, fc: FloatArray,
    xs: FloatArray, xt: FloatArray, step: FloatArray, h: FloatArray, av: FloatArray,
    hp: FloatArray, avp: FloatArray, scale: FloatArray, ends: NDArray[np.bool_],
    consts: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray,
) -> None:  # fmt: skip
    """The four rows of each motor at every point, into ``a``, ``b``, ``c`` (n, 12)."""
    r, inertia, eta, t_ref = consts[0], consts[1], consts[2], consts[3]
    n, m = xs.shape
    effs = (1.0 / eta, eta)
    vals, p, hv, avv = np.empty(m), np.empty(4), np.empty(m), np.empty(m)
    slopes, cuts = np.empty(2), np.empty(2)
    lin = np.empty((2, 3))
    for i in range(n):
        x_top, x_mid = xs[i, m - 1], min(4.0 * xt[i], xs[i, m - 1])
        for mot in range(3):
            d = dq[i, mot]
            for j in range(m):
                hv[j], avv[j] = h[i, mot, j], scale[i] * av[i, mot, j] / t_ref
            for col in range(2):
                sign = 1.0 if col == 0 else -1.0
                for j in range(m):
                    vals[j] = sign * hv[j] - avv[j]
                for j in range(4):
                    p[j] = sign * hp[i, mot, j] - scale[i] * avp[i, mot, j] / t_ref
                zero, top = vals[0], vals[m - 1]
                tangent = (p[2] - p[0]) / (2.0 * step[i])
                chord = (top - zero) / x_top if x_top > 0.0 else 0.0
                middle = (p[3] - zero) / x_mid if x_mid > 0.0 else 0.0
                best_slope, best_cut, best_at = 0.0, 0.0, math.inf
                for line in range(3):
                    raw = tangent if line == 0 else (chord if line == 1 else middle)
                    base = p[1] - tangent * xt[i] if line == 0 else zero
                    slope = raw if math.isfinite(raw) else 0.0
                    if base + slope * xt[i] >= best_at:  # raised, it cannot come lower
                        continue
                    cut = _raise(vals, xs, i, slope, base)
                    at = cut + slope * xt[i]
                    if at < best_at:
                        best_slope, best_cut, best_at = slope, cut, at
                slopes[col], cuts[col] = best_slope, best_cut
            for k in range(2):
                e = effs[k]
                lin[k, 0] = (r * e * fa[i, mot] + inertia * d) / t_ref
                lin[k, 1] = (r * e * fb[i, mot] + inertia * ddq[i, mot]) / t_ref
                lin[k, 2] = r * e * fc[i, mot] / t_ref
            positive, negative = d > 0.0, d < 0.0
            for row in range(4):  # (sign, back-driven where, applies where): see limits
                sign = 1.0 if row < 2 else -1.0
                if row == 0:
                    back, active = negative, True
                elif row == 1:
                    back, active = positive, positive or (negative and ends[i])
                elif row == 2:
                    back, active = positive, True
                else:
                    back, active = negative, negative or (positive and ends[i])
                k = 1 if back else 0
                col = 0 if row < 2 else 1
                out = 4 * mot + row
                if active:
                    a[i, out] = sign * lin[k, 0]
                    b[i, out] = sign * lin[k, 1] + slopes[col]
                    c[i, out] = sign * lin[k, 2] + cuts[col] + 1.0
                else:
                    a[i, out], b[i, out], c[i, out] = 0.0, 0.0, IDLE


if AVAILABLE:
    curve_torque = jit(curve_torque, inline=True)
    _speeds = jit(_speeds)
    _values = jit(_values)
    _raise = jit(_raise, inline=True)
    _kernel = jit(_kernel)


def _need() -> None:
    if not AVAILABLE:
        raise RuntimeError("the compiled rows need numba (pip install 'orthoglide-pin[plan]')")


def sample_values(motors: Motors, dq: FloatArray, x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Friction over ``T_ref`` and available torque [N.m] of each motor at ``x``, (n, 3, K) each.

    Args:
        motors: The drive and torque share.
        dq: The sliders' ``dq/ds`` at the ``n`` points, (n, 3).
        x: Squared path speeds at each point [(m/s)^2], (n, K).

    Raises:
        RuntimeError: numba is not installed.
    """
    _need()
    assert motors.drive.motor is not None
    train, motor = motors.drive.train, motors.drive.motor
    n, count = x.shape
    w, h, av = np.empty((n, 3, count)), np.empty((n, 3, count)), np.empty((n, 3, count))
    th = np.empty((n, 3, count))
    _speeds(np.asarray(dq, dtype=np.float64), np.ascontiguousarray(x, dtype=np.float64),
            float(train.motor_speed(1.0)), train.friction_speed, w, th)  # fmt: skip
    np.tanh(th, out=th)  # vectorised in numpy
    curve = np.zeros((0, 2))
    if motor.speed_torque_curve is not None:
        curve = np.asarray(motor.speed_torque_curve) * (1.0 / RPM_PER_RAD_S, 1.0)
    peak = math.inf if motor.peak_torque is None else float(motor.peak_torque)
    consts = np.array(
        [train.coulomb_torque, train.viscous_coefficient, motors.t_ref, peak, motors.keep]
    )
    _values(w, th, consts, np.ascontiguousarray(curve[:, 0]), np.ascontiguousarray(curve[:, 1]),
            h, av)  # fmt: skip
    return h, av


def torque_rows(
    motors: Motors,
    forms: PathForms,
    xs: FloatArray,
    probe: tuple[FloatArray, FloatArray, FloatArray],
    scale: float | FloatArray,
    ends: NDArray[np.bool_],
    values: tuple[FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The motor-torque rows of the ``n`` points, (n, 12) each: four per motor (see the module).

    Args:
        motors: The drive and torque share.
        forms: The path forms at the points.
        xs: The samples of ``[0, X]`` of each point [(m/s)^2], (n, S)
            (:func:`~orthoglide_pin.planning.limits.samples`).
        probe: The probes of ``phi`` (n, 4), the tangent points (n,) and the
            steps (n,) (:func:`~orthoglide_pin.planning.limits._probe`).
        scale: The motor-torque factor, a number, (n,) or (n, 1).
        ends: The points where a section starts or ends, (n,).
        values: :func:`sample_values` at ``xs`` when known, else ``None``.

    Raises:
        RuntimeError: numba is not installed.
    """
    _need()
    train = motors.drive.train
    r = train.lead / (2.0 * math.pi * train.gear_ratio)
    inertia = train.reflected_inertia * float(train.motor_speed(1.0))
    n = xs.shape[0]
    at, xt, step = probe
    h, av = sample_values(motors, forms.dq, xs) if values is None else values
    hp, avp = sample_values(motors, forms.dq, at)
    factor = np.broadcast_to(np.reshape(np.asarray(scale, dtype=np.float64), -1), (n,))
    consts = np.array([r, inertia, train.efficiency, motors.t_ref])
    a, b, c = np.empty((n, 12)), np.empty((n, 12)), np.empty((n, 12))
    # the path forms as they come (a planning grid's are every tenth fine sample's)
    dq, ddq, fa, fb, fc = (
        np.asarray(v, dtype=np.float64) for v in (forms.dq, forms.ddq, forms.a, forms.b, forms.c)
    )
    xs, xt, step, h, av = (
        np.ascontiguousarray(v, dtype=np.float64) for v in (xs, xt, step, h, av)
    )
    _kernel(
        dq, ddq, fa, fb, fc, xs, xt, step, h, av, hp, avp,
        np.ascontiguousarray(factor), np.ascontiguousarray(ends), consts, a, b, c,
    )  # fmt: skip
    return a, b, c
