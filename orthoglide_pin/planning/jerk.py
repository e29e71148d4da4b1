"""The slider jerk limit: a jerk-limited re-timing of the time-optimal plan.

TOPP-RA (:mod:`~orthoglide_pin.planning.parametrize`) is second order: its
path acceleration ``s_ddot`` is a step function, so the slider jerk of its
plan is unbounded. With a jerk limit ``J`` [m/s^3], each section's law
``s(t)`` is re-timed by a moving average over a window of ``T`` seconds, the
finite-impulse-response filter of CNC interpolators (Biagiotti and
Melchiorri, *Mechatronics* 2012):

    s_f(t) = (1 / T) int_{t-T}^{t} s(tau) dtau,   s_f''' = (s''(t) - s''(t - T)) / T.

The filtered law is exact and piecewise cubic in time (``s_f''`` is
continuous), starts and ends at rest with zero acceleration, and lasts
``T`` longer. The slider jerk along the path follows from it by the chain
rule (:mod:`~orthoglide_pin.planning.jerk_kinematics`).

* ``T`` starts at ``A / J`` (``A`` the largest slider acceleration of the
  second-order law: a rise from rest to ``A`` takes at least that) and grows
  by the jerk's overshoot until ``max |q'''| <= J`` on the verification grid
  and on both sides of the filtered law's knots. A straight move from rest to
  rest along which the sliders move in proportion becomes the 7-segment
  S-curve. Where the window alone cannot bring the jerk within the limit (its
  terms in ``s' s''`` and ``s'^3``), the speed is lowered there, as below.
* The filter averages speeds over positions at most ``v T`` apart (``v`` the
  peak speed), so the filtered speed may exceed a cap of the second-order plan
  (feed, slider and motor speeds, and ``(J / |dddq|)^(1/3)``, the jerk at
  constant speed) where the cap falls. Where it does, by a ratio ``r``, the
  caps within ``+-v T`` are divided by ``r``, and the section is planned and
  filtered again, up to :data:`CAP_ROUNDS` times.
* Where the curvature steps, or a tight blend would make the filter spread
  a crawl over the section, the tool stops instead
  (:mod:`~orthoglide_pin.planning.jerk_stops`).

The filtered law is verified like any plan (:mod:`~orthoglide_pin.planning.plan`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.jerk_kinematics import Kinematics, slider_jerk
from orthoglide_pin.planning.limits import PlanLimits, speed_bound
from orthoglide_pin.planning.parametrize import SectionInput, SectionPlan, plan_sections
from orthoglide_pin.planning.tighten import on_fine_grid
from orthoglide_pin.planning.verify import Motion

FloatArray = NDArray[np.float64]

#: Share of the jerk limit the speed cap ``(J / |dddq|)^(1/3)`` gives to constant speed.
CAP_SHARE: Final[float] = 0.95
#: Rounds of the window's growth, and of the speed caps' lowering.
WINDOW_ROUNDS, CAP_ROUNDS = 16, 8
#: Extra growth of the window, and lowering of the caps, beyond the measured overshoot [-].
MARGIN: Final[float] = 2e-4
#: Time table, then safeguarded Newton steps, when a filtered law is inverted.
_TABLE: Final[int] = 2048
_NEWTON: Final[int] = 5


@dataclass(frozen=True)
class SmoothedPlan(SectionPlan):
    """A second-order law (the inherited fields) filtered over ``window`` [s] (see the module)."""

    window: float = 0.0

    @cached_property
    def _integral(self) -> FloatArray:
        """``int_0^{t_i} s`` at the knots [m.s], (n,)."""
        dt = np.diff(self.t)
        v = np.sqrt(np.maximum(self.x[:-1], 0.0))
        part = self.s[:-1] * dt + 0.5 * v * dt**2 + self.u * dt**3 / 6.0
        return np.concatenate([[0.0], np.cumsum(part)])

    def _base(self, tau: FloatArray) -> tuple[FloatArray, ...]:
        """The second-order law at times ``tau``, at rest outside it: ``s, s', s'', int s``."""
        end = float(self.t[-1])
        tc = np.clip(tau, 0.0, end)
        i = np.clip(np.searchsorted(self.t, tc, side="right") - 1, 0, self.u.size - 1)
        h = tc - self.t[i]
        v0, a = np.sqrt(np.maximum(self.x[i], 0.0)), self.u[i]
        s = np.minimum(self.s[i] + v0 * h + 0.5 * a * h * h, self.s[-1])
        v = np.maximum(v0 + a * h, 0.0)
        big = self._integral[i] + self.s[i] * h + 0.5 * v0 * h * h + a * h**3 / 6.0
        out = (tau < 0.0) | (tau > end)
        big = np.where(tau < 0.0, self.s[0] * tau, big)
        big = np.where(tau > end, self._integral[-1] + self.s[-1] * (tau - end), big)
        return s, np.where(out, 0.0, v), np.where(out, 0.0, a), big

    @property
    def duration(self) -> float:
        """The section's duration [s]."""
        return float(self.t[-1]) + self.window

    def motion(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Arc length [m], speed [m/s], acceleration [m/s^2] and jerk [m/s^3] at times ``t``."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        w = self.window
        if w <= 0.0:
            s, v, a, _ = self._base(t)
            return s, v, a, np.zeros_like(t)
        now, then = self._base(t), self._base(t - w)
        s = np.clip((now[3] - then[3]) / w, self.s[0], self.s[-1])
        return s, (now[0] - then[0]) / w, (now[1] - then[1]) / w, (now[2] - then[2]) / w

    def at_times(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Arc length [m], speed [m/s] and acceleration [m/s^2] at times ``t`` [s]."""
        return self.motion(t)[:3]

    def time_at(self, s: FloatArray) -> FloatArray:
        """The time [s] at arc lengths ``s``: a table, then safeguarded Newton steps."""
        s = np.asarray(s, dtype=float)
        table = np.linspace(0.0, self.duration, _TABLE + 1)
        at = self.motion(table)[0]
        k = np.clip(np.searchsorted(at, s, side="left"), 1, _TABLE)
        lo, hi = table[k - 1], table[k]
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = np.clip((s - at[k - 1]) / (at[k] - at[k - 1]), 0.0, 1.0)
        t = lo + np.nan_to_num(frac, nan=0.5) * (hi - lo)
        for _ in range(_NEWTON):  # Newton's steps kept within the bracket, else bisection
            at, speed = self.motion(t)[:2]
            below = at < s
            lo, hi = np.where(below, t, lo), np.where(below, hi, t)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = t + (s - at) / speed
            inside = np.isfinite(step) & (step >= lo) & (step <= hi)
            t = np.where(inside, step, 0.5 * (lo + hi))
        return np.asarray(
            np.where(s <= self.s[0], 0.0, np.where(s >= self.s[-1], self.duration, t))
        )

    def at_lengths(
        self, s: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
        """Time [s], speed [m/s], acceleration [m/s^2] and grid interval at arc lengths ``s``."""
        t = self.time_at(s)
        _, v, a, _ = self.motion(t)
        i = np.clip(np.searchsorted(self.s, s, side="right") - 1, 0, self.u.size - 1)
        return t, v, a, i

    def jerk_at_lengths(self, s: FloatArray) -> tuple[FloatArray, ...]:
        """Time [s], speed, acceleration and path jerk ``s'''`` [m/s^3] at arc lengths ``s``."""
        t = self.time_at(s)
        return (t, *self.motion(t)[1:])


def jerk_use(law: SmoothedPlan, kin: Kinematics, jerk: float) -> tuple[FloatArray, FloatArray]:
    """The slider jerk [m/s^3], (m, 3), and its use ``max_i |q'''_i| / J``, (m,), on ``kin.s``."""
    _, sd, sdd, sddd = law.jerk_at_lengths(kin.s)
    qddd = slider_jerk(kin.dq, kin.ddq, kin.dddq, sd, sdd, sddd)
    return qddd, np.abs(qddd).max(axis=1) / jerk


def _knot_use(law: SmoothedPlan, kin: Kinematics, jerk: float) -> float:
    """The jerk's largest use on either side of the filtered law's knots (``s'''`` steps there).

    The path derivatives are interpolated linearly between the fine samples.
    """
    knots = np.concatenate([law.t, law.t + law.window])
    eps = 1e-9 * law.duration
    s, sd, sdd, sddd = law.motion(np.concatenate([knots - eps, knots + eps]))
    cols = [
        np.stack([np.interp(s, kin.s, arr[:, i]) for i in range(3)], axis=1)
        for arr in (kin.dq, kin.ddq, kin.dddq)
    ]
    return float(np.abs(slider_jerk(cols[0], cols[1], cols[2], sd, sdd, sddd)).max()) / jerk


def fit_window(
    law: SectionPlan, kin: Kinematics, jerk: float
) -> tuple[SmoothedPlan, FloatArray, FloatArray]:
    """The law filtered over the shortest window found keeping ``|q'''| <= J`` (see the module).

    Returns:
        The filtered law, its jerk's use on ``kin.s``, (m,) (above 1 where the
        window alone cannot bring the jerk within the limit), and its speed there [m/s].
    """
    _, sd, sdd, _ = law.at_lengths(kin.s)
    peak = float(np.abs(kin.dq * sdd[:, None] + kin.ddq * (sd * sd)[:, None]).max())
    window = max(peak / jerk, 1e-9)
    best: tuple[SmoothedPlan, FloatArray, FloatArray] | None = None
    best_worst = np.inf
    for _ in range(WINDOW_ROUNDS):
        cand = SmoothedPlan(law.s, law.x, law.u, law.t, window)
        _, sd, sdd, sddd = cand.jerk_at_lengths(kin.s)
        use = np.abs(slider_jerk(kin.dq, kin.ddq, kin.dddq, sd, sdd, sddd)).max(axis=1) / jerk
        worst = max(float(use.max()), _knot_use(cand, kin, jerk))
        if worst >= best_worst:
            break  # the window no longer helps
        best, best_worst = (cand, use, sd), worst
        if worst <= 1.0:
            break
        window *= worst * (1.0 + MARGIN)
    assert best is not None
    return best


def _speed_cap(item: SectionInput, kin: Kinematics, limits: PlanLimits) -> FloatArray:
    """The path-speed cap on the fine grid [m/s]: the second-order bounds and the jerk's."""
    assert limits.slider_jerk is not None
    scales = on_fine_grid(item.scales, item.s, kin.s)
    fine = scales.get("slider_jerk") * CAP_SHARE * limits.slider_jerk
    worst = np.abs(kin.dddq).max(axis=1)
    with np.errstate(divide="ignore"):
        jerk_cap = np.where(worst > 0.0, np.cbrt(fine / worst), np.inf)
    forms = _FineForms(kin.dq)
    x = speed_bound(limits, forms, kin.feed, scales)  # type: ignore[arg-type]
    return np.asarray(np.minimum(np.sqrt(x), jerk_cap))


@dataclass(frozen=True)
class _FineForms:
    """What :func:`~orthoglide_pin.planning.limits.speed_bound` reads of the path forms."""

    dq: FloatArray


def _spread(s: FloatArray, fine_s: FloatArray, ratio: FloatArray, width: float) -> FloatArray:
    """The largest ``ratio`` on the fine grid within ``+-width`` of each point ``s``."""
    lo = np.searchsorted(fine_s, s - width, side="left")
    hi = np.maximum(np.searchsorted(fine_s, s + width, side="right"), lo + 1)
    return np.array([ratio[a:b].max() for a, b in zip(lo, hi, strict=True)])


def jerk_plans(
    inputs: list[SectionInput], fine: list[Kinematics], limits: PlanLimits
) -> list[SmoothedPlan | None]:
    """The jerk-limited laws of sections, each from rest to rest (see the module).

    Args:
        inputs: The sections' second-order inputs (grid, forms, feed, scales).
        fine: Each section's :class:`Kinematics` on its verification grid.
        limits: The limits, ``slider_jerk`` given.

    Returns:
        Each section's law, ``None`` for a section no motion can make.
    """
    assert limits.slider_jerk is not None
    jerk = limits.slider_jerk
    caps = [_speed_cap(i, k, limits) for i, k in zip(inputs, fine, strict=True)]
    grid_caps = [c[np.searchsorted(k.s, i.s)] for i, k, c in zip(inputs, fine, caps, strict=True)]
    factor = [np.ones(i.s.size) for i in inputs]
    out: list[SmoothedPlan | None] = [None] * len(inputs)
    previous = [i.previous for i in inputs]  # the speed-dependent limits start from them
    todo = list(range(len(inputs)))
    for _ in range(CAP_ROUNDS):
        planned = plan_sections(
            [
                replace(inputs[k], feed=grid_caps[k] * factor[k], previous=previous[k])
                for k in todo
            ],
            limits,
        )
        again = []
        for k, law in zip(todo, planned, strict=True):
            if law is None:
                out[k] = None
                continue
            previous[k] = law.x
            smooth, use, sd = fit_window(law, fine[k], jerk)
            out[k] = smooth
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.where(caps[k] > 0.0, sd / caps[k], np.inf)
            # the jerk the window leaves: its terms in s' s'' and s'^3 need less speed
            ratio = np.maximum(ratio, np.cbrt(use))
            if float(ratio.max()) <= 1.0:
                continue
            reach = float(np.sqrt(law.x.max())) * smooth.window
            near = _spread(inputs[k].s, fine[k].s, ratio, reach)
            factor[k] = factor[k] / np.maximum(near * (1.0 + MARGIN), 1.0)
            again.append(k)
        todo = again
        if not todo:
            break
    return out


def with_jerk(motion: Motion, law: SectionPlan | None, kin: Kinematics, jerk: float) -> Motion:
    """The verified motion with the slider jerk and its use (``slider_jerk``) added."""
    assert isinstance(law, SmoothedPlan)
    qddd, use = jerk_use(law, kin, jerk)
    return replace(motion, qddd=qddd, uses={**motion.uses, "slider_jerk": use})
