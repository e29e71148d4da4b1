"""A planning grid that follows the motion: points added where the speed changes fast.

The planner holds the path acceleration ``u`` constant between grid points,
so a grid interval in which the optimal motion switches (from a ramp at the
largest acceleration to a speed cap, from a cap to the largest deceleration,
from one ramp to the other) is crossed at a single, lower ``u``: on a grid of
2 mm, a move at F6000 whose ramp from rest lasts 0.33 mm loses about 17 ms
at each end. After each plan, :func:`switch_points` looks at every interval
``[s_i, s_i+1]`` and builds the motion the limits of its end points allow:

* from ``(s_i, x_i)`` the largest acceleration ``u_acc`` (the rows at ``s_i``),
  ``x = x_i + 2 u_acc (s - s_i)``;
* into ``(s_i+1, x_i+1)`` the largest deceleration ``u_dec``,
  ``x = x_i+1 + 2 u_dec (s_i+1 - s)``;
* the cap: the larger of the two points' squared speeds that can be held
  (``u = 0``: the speed bounds, the feed, and every row's ``b x + c <= 1``).

The lower envelope of these three lines is the local optimum; where it is
faster than the plan's straight ``x`` by more than :data:`GAIN_TOL` of the
interval's time (and all the section's intervals together save more than
:data:`SECTION_TOL` of its time), its break points (where a ramp meets the cap, or the two
ramps meet) join the grid; an interval without such a point inside (the
limits themselves change along it, as the torque with the motor's speed) is
halved. :func:`refine_grid` then plans again, at most
:data:`ROUNDS` times: the grid gains a few points at each rest, feed step and
curvature change, and the plan comes within a fraction of a per cent of the
phase-plane optimum (the planning guide gives the figures). Each round's plan
also linearises the speed-dependent motor limits around the last speeds
(:mod:`~orthoglide_pin.planning.limits`), so the majorants tighten with it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.grid_merge import merge_added
from orthoglide_pin.planning.limits import (
    TRUST,
    PlanLimits,
    Scales,
    joined_rows,
)
from orthoglide_pin.planning.parametrize import SectionInput, plan_sections, speed_bounds
from orthoglide_pin.planning.path import Samples, Section

FloatArray = NDArray[np.float64]

#: Re-plans at most while the grid gains points [-].
ROUNDS: Final[int] = 4
#: An interval is refined when the local optimum saves this share of its time [-].
GAIN_TOL: Final[float] = 1e-3
#: A section is refined when the local optima save this share of its time in all [-].
SECTION_TOL: Final[float] = 3e-4
#: Halvings of a section's first and last intervals under torque limits [-].
REST_HALVINGS: Final[int] = 4
#: A point added lies at least this share of its interval from the interval's ends [-].
MIN_SPLIT: Final[float] = 1e-6
#: A point whose squared speed is below this share of its cap is still ramping [-].
BELOW_CAP: Final[float] = 0.995


def _caps(a: FloatArray, b: FloatArray, c: FloatArray, bound: FloatArray) -> FloatArray:
    """The largest squared speed each point can hold (``u = 0``), (n,)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        hold = np.where(b > 0.0, (1.0 - c) / b, np.inf).min(axis=1, initial=np.inf)
    return np.asarray(np.minimum(bound, np.maximum(hold, 0.0)))


def _extreme_u(
    a: FloatArray, b: FloatArray, c: FloatArray, x: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The largest and smallest path acceleration at each point at speed ``x``, (n,) each."""
    with np.errstate(divide="ignore", invalid="ignore"):
        lim = (1.0 - c - b * x[:, None]) / a
        hi = np.where(a > 0.0, lim, np.inf).min(axis=1, initial=np.inf)
        lo = np.where(a < 0.0, lim, -np.inf).max(axis=1, initial=-np.inf)
    return hi, lo


def _time(s: FloatArray, x: FloatArray) -> FloatArray:
    """Time along straight pieces of ``x(s)`` between columns, summed per row."""
    sd = np.sqrt(np.maximum(x, 0.0))
    ds = np.diff(s, axis=1)
    return np.asarray(
        np.sum(2.0 * ds / np.maximum(sd[:, :-1] + sd[:, 1:], 1e-300), axis=1), dtype=np.float64
    )


def switch_points(
    s: FloatArray, x: FloatArray, abc: tuple[FloatArray, FloatArray, FloatArray], bound: FloatArray
) -> FloatArray:
    """The arc lengths to add to a section's grid (see the module), sorted.

    Args:
        s: The grid [m], (n,).
        x: The plan's squared speeds there [(m/s)^2], (n,).
        abc: The rows ``a u + b x + c <= 1`` at the grid points, each (n, m).
        bound: The bounds on ``x`` at the points (speeds, feed) [(m/s)^2], (n,).
    """
    return _chosen(*_candidates(s, x, abc, bound))


def switch_points_of(
    items: list[
        tuple[FloatArray, FloatArray, tuple[FloatArray, FloatArray, FloatArray], FloatArray]
    ],
) -> list[FloatArray]:
    """:func:`switch_points` of several sections ``(s, x, abc, bound)``, in one batch.

    Their grids are laid end to end; every quantity is one per interval, so the
    intervals between two sections are computed and dropped.
    """
    if len(items) <= 1:
        return [switch_points(*item) for item in items]
    s, x, bound = (np.concatenate([item[j] for item in items]) for j in (0, 1, 3))
    a, b, c = (np.concatenate([item[2][j] for item in items]) for j in range(3))
    cands, keep, gain, t_plan = _candidates(s, x, (a, b, c), bound)
    out, start = [], 0
    for item in items:
        part = slice(start, start + item[0].size - 1)
        out.append(_chosen(cands[part], keep[part], gain[part], t_plan[part]))
        start += item[0].size
    return out


def _chosen(
    cands: FloatArray, keep: NDArray[np.bool_], gain: FloatArray, t_plan: FloatArray
) -> FloatArray:
    """The points a section gains by, sorted (none when the section would hardly gain)."""
    if np.sum(gain[keep]) <= SECTION_TOL * np.sum(t_plan):
        return np.zeros(0)  # the whole section would hardly gain
    out = cands[keep].ravel()
    return np.unique(out[np.isfinite(out)])


def _candidates(
    s: FloatArray, x: FloatArray, abc: tuple[FloatArray, FloatArray, FloatArray], bound: FloatArray
) -> tuple[FloatArray, NDArray[np.bool_], FloatArray, FloatArray]:
    """Per interval: its candidate points (2), whether kept, the time gained and planned."""
    a, b, c = abc
    cap = _caps(a, b, c, bound)
    u_acc, _ = _extreme_u(a, b, c, x)
    _, u_dec = _extreme_u(a, b, c, x)
    x0, x1, s0, s1 = x[:-1], x[1:], s[:-1], s[1:]
    h = s1 - s0
    top = np.maximum(np.maximum(cap[:-1], cap[1:]), np.maximum(x0, x1))
    ua = np.clip(u_acc[:-1], 0.0, 1e12)
    ud = np.clip(-u_dec[1:], 0.0, 1e12)
    ramping = (x0 < BELOW_CAP * cap[:-1]) | (x1 < BELOW_CAP * cap[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        up = np.where(ua > 0.0, (top - x0) / (2.0 * ua), np.inf)  # ramp meets the cap
        down = np.where(ud > 0.0, (top - x1) / (2.0 * ud), np.inf)  # cap meets the braking
        meet = np.where(ua + ud > 0.0, (x1 - x0 + 2.0 * ud * h) / (2.0 * (ua + ud)), np.nan)
    t_up, t_down = s0 + up, s1 - down
    cross = t_up >= t_down  # the ramps meet below the cap
    cands = np.stack([np.where(cross, s0 + meet, t_up), np.where(cross, np.nan, t_down)], axis=1)
    margin = MIN_SPLIT * h[:, None]
    inside = (cands > s0[:, None]) & (cands < s1[:, None])
    cands = np.where(inside, np.clip(cands, s0[:, None] + margin, s1[:, None] - margin), np.nan)
    # the local optimum's time against the plan's straight x (a missing point: s_i+1)
    inner = np.where(np.isnan(cands), s1[:, None], cands)
    pts = np.sort(np.concatenate([s0[:, None], inner, s1[:, None]], axis=1), axis=1)
    rel = pts - s0[:, None]
    env = np.minimum(
        np.minimum(top[:, None], x0[:, None] + 2.0 * ua[:, None] * rel),
        x1[:, None] + 2.0 * ud[:, None] * (h[:, None] - rel),
    )
    env = np.maximum(env, 0.0)
    t_plan = 2.0 * h / np.maximum(np.sqrt(x0) + np.sqrt(x1), 1e-300)
    gain = t_plan - _time(pts, env)
    keep = ramping & (gain > GAIN_TOL * t_plan)
    # no break point inside: the limits change along the interval, which is halved
    halve = keep & np.all(np.isnan(cands), axis=1)
    cands[halve, 0] = 0.5 * (s0[halve] + s1[halve])
    return cands, keep, gain, t_plan


def rest_points(s: FloatArray) -> FloatArray:
    """Points closing geometrically on both ends of a grid (see :data:`REST_HALVINGS`)."""
    k = 0.5 ** np.arange(1, REST_HALVINGS + 1)
    return np.concatenate([s[0] + (s[1] - s[0]) * k, s[-1] - (s[-1] - s[-2]) * k])


def section_rows(
    limits: PlanLimits, inputs: list[SectionInput], xs: list[FloatArray]
) -> list[tuple[tuple[FloatArray, FloatArray, FloatArray], FloatArray]]:
    """The rows and speed bounds plans of squared speeds ``xs`` were made under (approximately).

    The rows of all the sections are computed in one batch
    (:func:`~orthoglide_pin.planning.limits.joined_rows`).
    """
    bounds, highs = speed_bounds(inputs, limits), []
    for bound, x in zip(bounds, xs, strict=True):
        high = bound
        if limits.limits_torque:
            high = np.minimum(bound, TRUST * max(float(np.max(x)), 1e-12))
        highs.append(np.maximum(high, x))
    forms, scales = [i.forms for i in inputs], [i.scales for i in inputs]
    abc = joined_rows(limits, forms, highs, xs, scales)
    return list(zip(abc, bounds, strict=True))


@dataclass
class Grids:
    """A section's planning grid and verification grid, with their path forms.

    Attributes:
        grid: The planning grid. forms: The path forms there (calibrated commands
            when the plan has a calibration).
        fine: The verification grid (holds the planning grid). fine_forms: Its
            path forms (of the nominal machine).
    """

    grid: Samples
    forms: PathForms
    fine: Samples
    fine_forms: PathForms


def refine_grid(
    sections: list[Section],
    grids: list[Grids],
    inputs: list[SectionInput],
    limits: PlanLimits,
    forms_of: Callable[[list[Samples]], list[PathForms]],
    calibrate: Callable[[PathForms, Samples], PathForms],
    feeds_of: Callable[[Section, Samples, PathForms], FloatArray],
) -> tuple[list[Grids], list[SectionInput]]:
    """Plan, add the :func:`switch_points`, and plan again, :data:`ROUNDS` times at most.

    Args:
        sections: The sections planned.
        grids: Their grids (replaced where points are added).
        inputs: Their planning inputs (replaced likewise).
        limits: The limits.
        forms_of: The path forms (nominal machine) at samples of each section, in one batch.
        calibrate: The planning forms from nominal forms at samples (identity without
            a calibration).
        feeds_of: The path-speed caps at samples of a section, given their path
            forms [m/s] (the feeds, and the rapid override's caps).

    Returns:
        The grids and inputs, each input starting from the last plan's speeds (a
        section whose grid gained no point is not planned again).
    """
    grids, inputs = list(grids), list(inputs)
    active = list(range(len(inputs)))  # the sections whose grid changed
    for round_ in range(ROUNDS):
        laws = plan_sections([inputs[k] for k in active], limits)
        if any(law is None for law in laws):
            break  # the plan itself will name the move
        xs = [law.x for law in laws if law is not None]
        made = section_rows(limits, [inputs[k] for k in active], xs)
        switches = switch_points_of(
            [
                (inputs[k].s, x, abc, bound)
                for k, x, (abc, bound) in zip(active, xs, made, strict=True)
            ]
        )
        gains = []
        for k, law, added in zip(active, laws, switches, strict=True):
            assert law is not None
            inputs[k] = replace(inputs[k], previous=law.x)
            gains.append(added)
            if round_ == 0 and limits.limits_torque:
                gains[-1] = np.concatenate([added, rest_points(law.s)])
        merged_all = merge_added(
            [sections[k] for k in active],
            [(grids[k].grid, grids[k].forms, grids[k].fine, grids[k].fine_forms) for k in active],
            gains,
            forms_of,
            calibrate,
        )
        if not merged_all:
            break
        active = [active[i] for i in sorted(merged_all)]
        for i, k in zip(sorted(merged_all), active, strict=True):
            old_s = grids[k].grid.s
            grids[k] = Grids(*merged_all[i])
            grid, forms = grids[k].grid, grids[k].forms
            previous = np.interp(grid.s, old_s, np.asarray(inputs[k].previous))
            inputs[k] = replace(
                inputs[k], s=grid.s, forms=forms, feed=feeds_of(sections[k], grid, forms),
                scales=Scales(), previous=previous,
            )  # fmt: skip
    return grids, inputs
