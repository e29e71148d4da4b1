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
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.grid_merge import merge_added
from orthoglide_pin.planning.limits import (
    TRUST,
    X_CAP,
    PlanLimits,
    Scales,
    flat_rows,
    joined_scales,
    speed_bound_dq,
)
from orthoglide_pin.planning.parametrize import SectionInput, plan_sections
from orthoglide_pin.planning.path import Samples, Section
from orthoglide_pin.planning.run_batch import cut

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
    sizes = [item[0].size for item in items]
    ids, values = _chosen_all(*_candidates(s, x, (a, b, c), bound), sizes)
    counts = np.bincount(ids, minlength=len(items)).tolist()
    return cut(values, counts)


def run_switch_points(
    limits: PlanLimits, inputs: list[SectionInput], xs: list[FloatArray]
) -> tuple[NDArray[np.intp], FloatArray]:
    """The :func:`switch_points` of sections planned with squared speeds ``xs``, laid end to end.

    The rows and speed bounds the plans were made under (approximately, as
    :func:`section_rows`), computed for all the sections at once.

    Returns:
        The section of each point and the points, by section then arc length.
    """
    sizes = [i.s.size for i in inputs]
    names = ("q", "dq", "ddq", "a", "b", "c")
    forms = PathForms(*(np.concatenate([getattr(i.forms, n) for i in inputs]) for n in names))
    s, feed = (np.concatenate([getattr(i, n) for i in inputs]) for n in ("s", "feed"))
    x = np.concatenate(xs)
    scales = joined_scales([i.scales for i in inputs], sizes)
    bound = np.minimum(speed_bound_dq(limits, forms.dq, feed, scales), X_CAP)
    high = bound
    if limits.limits_torque:
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
        peak = TRUST * np.maximum(np.maximum.reduceat(x, starts), 1e-12)
        high = np.minimum(bound, np.repeat(peak, sizes))
    abc = flat_rows(limits, forms, np.maximum(high, x), x, scales, sizes)
    return _chosen_all(*_candidates(s, x, abc, bound), sizes)


def _chosen_all(
    cands: FloatArray,
    keep: NDArray[np.bool_],
    gain: FloatArray,
    t_plan: FloatArray,
    sizes: list[int],
) -> tuple[NDArray[np.intp], FloatArray]:
    """:func:`_chosen` of sections laid end to end: each point's section, and the points.

    The intervals from one section's last point to the next one's first are
    dropped. A section's sums are taken as :func:`_chosen` takes them wherever
    the batch's sums leave its choice within rounding.
    """
    ends = np.cumsum(sizes)
    inner = np.ones(gain.size, dtype=bool)
    inner[ends[:-1] - 1] = False
    cands, keep, gain, t_plan = cands[inner], keep[inner], gain[inner], t_plan[inner]
    count = len(sizes)
    firsts = np.concatenate([[0], np.cumsum([n - 1 for n in sizes])[:-1]]).astype(np.intp)
    sec = np.repeat(np.arange(count, dtype=np.intp), [n - 1 for n in sizes])
    with np.errstate(invalid="ignore"):
        kept = np.add.reduceat(np.where(keep, gain, 0.0), firsts)
        total = SECTION_TOL * np.add.reduceat(t_plan, firsts)
        gains = kept > total
        clear = np.abs(kept - total) > 1e-9 * np.maximum(np.abs(kept), np.abs(total))
    for k in np.flatnonzero(~clear).tolist():  # close: summed as section by section
        part = slice(int(firsts[k]), int(firsts[k]) + sizes[k] - 1)
        gains[k] = not np.sum(gain[part][keep[part]]) <= SECTION_TOL * np.sum(t_plan[part])
    rows = keep & gains[sec]
    values = cands[rows].ravel()
    ids = np.repeat(sec[rows], cands.shape[1])
    finite = np.isfinite(values)
    values, ids = values[finite], ids[finite]
    order = np.lexsort((values, ids))
    values, ids = values[order], ids[order]
    new = np.ones(values.size, dtype=bool)
    new[1:] = (values[1:] != values[:-1]) | (ids[1:] != ids[:-1])
    return ids[new], values[new]


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


def _rest_points_all(grids: list[FloatArray]) -> tuple[NDArray[np.intp], FloatArray]:
    """:func:`rest_points` of each grid: each point's grid, and the points."""
    k = 0.5 ** np.arange(1, REST_HALVINGS + 1)
    first, second, last, before = (np.array([g[j] for g in grids]) for j in (0, 1, -1, -2))
    pts = np.concatenate(
        [
            first[:, None] + (second - first)[:, None] * k,
            last[:, None] - (last - before)[:, None] * k,
        ],
        axis=1,
    )
    ids = np.repeat(np.arange(len(grids), dtype=np.intp), pts.shape[1])
    return ids, pts.ravel()


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
    feeds_of: Callable[[list[Section], list[Samples], list[PathForms]], list[FloatArray]],
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
        feeds_of: The path-speed caps at samples of sections, given their path
            forms [m/s] (the feeds, and the rapid override's caps), in one batch.

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
        ids, values = run_switch_points(limits, [inputs[k] for k in active], xs)
        for k, x in zip(active, xs, strict=True):
            inp = inputs[k]
            inputs[k] = SectionInput(inp.s, inp.forms, inp.feed, inp.scales, x)
        if round_ == 0 and limits.limits_torque:
            rest_ids, rest = _rest_points_all([inputs[k].s for k in active])
            ids, values = np.concatenate([ids, rest_ids]), np.concatenate([values, rest])
        gaining = np.unique(ids)  # only the sections with points to add are merged
        active = [active[i] for i in gaining.tolist()]
        if not active:
            break
        merged_all = merge_added(
            [sections[k] for k in active],
            [(grids[k].grid, grids[k].forms, grids[k].fine, grids[k].fine_forms) for k in active],
            (np.searchsorted(gaining, ids), values),
            forms_of,
            calibrate,
        )
        if not merged_all:
            break
        active = [active[i] for i in sorted(merged_all)]
        for i, k in zip(sorted(merged_all), active, strict=True):
            grids[k] = Grids(*merged_all[i])
        feeds = feeds_of(
            [sections[k] for k in active], [grids[k].grid for k in active],
            [grids[k].forms for k in active],
        )  # fmt: skip
        for k, feed in zip(active, feeds, strict=True):
            grid, old = grids[k].grid, inputs[k]
            previous = np.interp(grid.s, old.s, np.asarray(old.previous))
            inputs[k] = SectionInput(grid.s, grids[k].forms, feed, Scales(), previous)
    return grids, inputs
