"""The verification's arithmetic compiled with numba: one pass over the samples.

The verification (:func:`~orthoglide_pin.planning.verify.evaluate_forms`)
evaluates a time law at every sample of the fine grid: the slider forces
``F = a s_ddot + b s_dot^2 + c`` and motion ``q' = dq s_dot``,
``q'' = dq s_ddot + ddq s_dot^2`` from the path forms, the motor demand
(:func:`~orthoglide_pin.drives.motor.motor_demand`: the efficiency that divides
or multiplies, the inertia, the friction) and the use of every limit. In numpy
that is some forty passes over (samples, 3) arrays. :func:`forms_motion` makes
one compiled pass that writes each sample's forces, accelerations, torques and
uses at once, with the same operations in the same order, so that both agree
to rounding (``tests/planning/test_verify_compiled.py``). Only the friction's
``tanh`` stays in numpy (vectorised there). The few per-sample reads of the
time law and of the planning grid go through :func:`intervals`, a compiled
``searchsorted`` that walks sorted queries from its last answer.

Without numba (:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE`
false) the array versions run, with the same numbers.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import jit
from orthoglide_pin.drives.motor import RPM_PER_RAD_S, DriveTrain
from orthoglide_pin.planning.reach_compiled import AVAILABLE
from orthoglide_pin.planning.rows_compiled import curve_torque

FloatArray = NDArray[np.float64]


def _intervals(grid: FloatArray, s: FloatArray) -> NDArray[np.intp]:
    """``searchsorted(grid, s, side="right") - 1``, from the previous answer onwards."""
    n = grid.size
    out = np.empty(s.size, np.intp)
    j = 0  # grid[:j] <= the previous query
    for k in range(s.size):
        x = s[k]
        if math.isnan(x):  # after every point, as numpy sorts it
            out[k] = n - 1
            continue
        if j > 0 and not grid[j - 1] <= x:
            j = 0  # an unsorted query: search again from the start
        lo, hi = j, n
        while lo < hi and grid[lo] <= x and lo - j < 8:  # a few steps forwards first
            lo += 1
        if lo < hi and grid[lo] <= x:  # then bisect
            while lo < hi:
                mid = (lo + hi) // 2
                if grid[mid] <= x:
                    lo = mid + 1
                else:
                    hi = mid
        j = lo
        out[k] = j - 1
    return out


def _kernel(
    dq: FloatArray, ddq: FloatArray, fa: FloatArray, fb: FloatArray, fc: FloatArray,
    sd: FloatArray, sdd: FloatArray, qd: FloatArray, speed: FloatArray, th: FloatArray,
    consts: FloatArray, curve_w: FloatArray, curve_t: FloatArray,
    qdd: FloatArray, forces: FloatArray, torque: FloatArray, uses: FloatArray,
) -> bool:  # fmt: skip
    """Forces, accelerations, torques and the uses (4, m) of every sample; whether all finite."""
    (k_motor, screw, eta, inertia, coulomb, viscous, v_max, a_max, w_max, peak, keep) = (
        consts[0], consts[1], consts[2], consts[3], consts[4], consts[5], consts[6],
        consts[7], consts[8], consts[9], consts[10],
    )  # fmt: skip
    finite = True
    for i in range(sd.size):
        s2 = sd[i] * sd[i]
        v_use = a_use = t_use = w_use = 0.0
        for j in range(3):
            f = fa[i, j] * sdd[i] + fb[i, j] * s2 + fc[i, j]
            acc = dq[i, j] * sdd[i] + ddq[i, j] * s2
            forces[i, j], qdd[i, j] = f, acc
            finite = finite and math.isfinite(f) and math.isfinite(acc)
            v_use = max(v_use, abs(qd[i, j]))
            a_use = max(a_use, abs(acc))
            load = f * screw
            load = load / eta if f * qd[i, j] >= 0.0 else load * eta
            w = speed[i, j]
            t = load + inertia * (acc * k_motor) + (coulomb * th[i, j] + viscous * w)
            torque[i, j] = t
            aw = min(abs(w), w_max)
            avail = curve_torque(aw, curve_w, curve_t, peak, keep)
            t_use = max(t_use, abs(t) / avail if avail > 0.0 else math.inf)
            w_use = max(w_use, abs(w))
        uses[0, i], uses[1, i] = v_use / v_max, a_use / a_max
        uses[2, i], uses[3, i] = t_use, w_use / w_max
    return finite


if AVAILABLE:
    _intervals = jit(_intervals)
    _kernel = jit(_kernel)


def intervals(grid: FloatArray, s: FloatArray) -> NDArray[np.intp]:
    """``numpy.searchsorted(grid, s, side="right") - 1``, compiled (fast on sorted ``s``)."""
    if not AVAILABLE:
        return np.asarray(np.searchsorted(grid, s, side="right") - 1, dtype=np.intp)
    return _intervals(
        np.ascontiguousarray(grid, dtype=np.float64), np.ascontiguousarray(s, dtype=np.float64)
    )


def forms_motion(
    forms: tuple[FloatArray, ...],
    sd: FloatArray,
    sdd: FloatArray,
    train: DriveTrain,
    bounds: tuple[float | None, float | None, float | None],
    motor: tuple[float | None, FloatArray | None, float],
) -> tuple[FloatArray, ...] | None:
    """The motion and the uses of the sliders' and motor limits at ``m`` samples.

    Args:
        forms: The path forms ``dq, ddq, a, b, c`` at the samples, (m, 3) each.
        sd: Path speeds [m/s], (m,).
        sdd: Path accelerations [m/s^2], (m,).
        train: The drive train.
        bounds: The slider speed [m/s], slider acceleration [m/s^2] and motor
            speed [rad/s] limits (``None``: not given).
        motor: The peak torque [N.m] (or ``None``), the speed-torque curve
            ([rpm, N.m] rows, or ``None``) and the share of it the plan may use.

    Returns:
        ``(qd, qdd, forces, torque, speed, uses)``: (m, 3) each, then the uses
        (4, m) of the slider speed, slider acceleration, motor torque and
        motor speed (over 1 where the limit is not given); ``None`` when a value
        is not finite (the array version then names it).
    """
    dq, ddq, fa, fb, fc = (np.ascontiguousarray(v, dtype=np.float64) for v in forms)
    sd, sdd = np.ascontiguousarray(sd, dtype=np.float64), np.ascontiguousarray(sdd)
    qd = dq * sd[:, None]
    if not np.isfinite(qd).all():
        return None
    speed = qd * (2.0 * math.pi * train.gear_ratio / train.lead)
    th = np.tanh(speed / train.friction_speed)
    peak, curve, keep = motor
    table = np.zeros((0, 2)) if curve is None else np.asarray(curve) * (1.0 / RPM_PER_RAD_S, 1.0)
    v_max, a_max, w_max = (math.inf if b is None else float(b) for b in bounds)
    turn = 2.0 * math.pi * train.gear_ratio
    consts = np.array([
        turn / train.lead, train.lead / turn, train.efficiency, train.reflected_inertia,
        train.coulomb_torque, train.viscous_coefficient, v_max, a_max, w_max,
        math.inf if peak is None else float(peak), keep,
    ])  # fmt: skip
    m = sd.size
    qdd, forces, torque = np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3))
    uses = np.empty((4, m))
    ok = _kernel(
        dq, ddq, fa, fb, fc, sd, sdd, qd, speed, th, consts,
        np.ascontiguousarray(table[:, 0]), np.ascontiguousarray(table[:, 1]),
        qdd, forces, torque, uses,
    )  # fmt: skip
    if not ok:
        return None
    return qd, qdd, forces, torque, speed, uses
