"""Long sections planned in windows: memory independent of the program's length.

A section of many pieces (a 3D relief of 100,000 short blended blocks is one
section) is planned window after window. A window is a run of pieces of about
:data:`WINDOW_POINTS` planning-grid points, followed by a look-ahead of about
:data:`LOOK_AHEAD_POINTS` more. Each window is sampled, its path forms
computed, planned (TOPP-RA, :mod:`~orthoglide_pin.planning.reachability`),
verified on the fine grid and tightened like a whole section
(:func:`~orthoglide_pin.planning.plan.plan_program`), then only its pieces
before the look-ahead are kept:

* the window starts at the squared speed its predecessor ended with;
* the window is planned to rest at the look-ahead's end. Its speed where the
  look-ahead begins is therefore one from which the rest of the path can still
  brake (it lies in TOPP-RA's controllable set of the look-ahead), so the next
  window, which reaches further, can always start from it: no window needs a
  later one to be planned again.

The look-ahead changes the plan only where braking takes longer than the
look-ahead is long (a fast move ending after a long run of short blocks): the
plan is then a little slower than the whole section's optimum, never faster
or over a limit. A window is kept as its planning grid's squared speeds only
(no fine-grid samples): the verification's worst uses and binding times are
summed as the windows go. A window that cannot start where its predecessor
ended (its verification tightened a limit right at its start, or the two
windows' bounds of the speed-dependent limits differ there) makes the
predecessor end at rest there instead, and starts from rest; only if that
fails too is the section handed back to be planned whole.

A window gets everything a section planned whole gets: the feed override (in
the program's feeds), the rapid override's caps
(:func:`~orthoglide_pin.planning.controller.rapid_caps`), the calibrated
commands, the limits (torque reserve included); the progress callback is told
after each window. The next window is sampled and its path forms computed on a
second thread while one is planned (one worker; the same plans, in order),
the samples it shares with the window before taken from it
(:mod:`~orthoglide_pin.planning.window_prep`).
:func:`plan_long_sections` is the hook of
:func:`~orthoglide_pin.planning.plan.plan_program`, called after the size cap
and the cube check of the block ends, before any grid is made.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import math
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.batch import (
    _cut,
    changed_samples,
    check_again,
    check_sections,
)
from orthoglide_pin.planning.calibrated import CalibratedKinematics
from orthoglide_pin.planning.limits import PlanLimits, rows
from orthoglide_pin.planning.parametrize import (
    SectionInput,
    SectionPlan,
    first_bounds,
    narrowed,
    time_law,
)
from orthoglide_pin.planning.path import (
    MIN_INTERVALS,
    Path,
    Section,
    grid_size,
)
from orthoglide_pin.planning.reachability import reach
from orthoglide_pin.planning.row_cache import RowCache
from orthoglide_pin.planning.tighten import smallest, tighten
from orthoglide_pin.planning.verify import USE_TOL, binding_time, worst_uses
from orthoglide_pin.planning.window_prep import Prepared, WindowSetting
from orthoglide_pin.planning.window_prep import prepare as _prepare

FloatArray = NDArray[np.float64]

#: Planning-grid points kept per window (about: windows hold whole pieces).
WINDOW_POINTS: Final[int] = 8192
#: Planning-grid points of the look-ahead planned after each window.
LOOK_AHEAD_POINTS: Final[int] = 1024
#: Sections of more planning-grid points than this are planned in windows.
WINDOWED_ABOVE: Final[int] = WINDOW_POINTS + 2 * LOOK_AHEAD_POINTS


@dataclass
class WindowedSection:
    """A section planned in windows.

    Attributes:
        plan: Its time law on the planning grid.
        rounds: The most plans a window needed.
        scales: The smallest tightening factor of each limit over its windows.
        worst: The largest use of each limit on the verification grid [-].
        binding: The time each limit binds [s].
        grid_points: Points of its planning grid.
    """

    plan: SectionPlan
    rounds: int
    scales: dict[str, float] = field(default_factory=dict)
    worst: dict[str, float] = field(default_factory=dict)
    binding: dict[str, float] = field(default_factory=dict)
    grid_points: int = 0


def needs_windows(section: Section, step: float) -> bool:
    """Whether a section is long enough to be planned in windows."""
    return grid_size(section, step) > WINDOWED_ABOVE


def _cuts(section: Section, step: float) -> list[int]:
    """First piece of each window, then the piece count."""
    sizes = [max(MIN_INTERVALS, math.ceil(p.length / step)) for p in section.pieces]
    out, run = [0], 0
    for k, n in enumerate(sizes):
        run += n
        if run >= WINDOW_POINTS and k + 1 < len(sizes):
            out.append(k + 1)
            run = 0
    if len(out) > 1 and run < LOOK_AHEAD_POINTS:  # a short tail joins the last window
        out.pop()
    return [*out, len(sizes)]


def _ahead(section: Section, step: float, first: int) -> int:
    """The piece after the look-ahead that starts at piece ``first``."""
    run, k = 0, first
    while k < len(section.pieces) and run < LOOK_AHEAD_POINTS:
        run += max(MIN_INTERVALS, math.ceil(section.pieces[k].length / step))
        k += 1
    return k


def plan_window(
    inp: SectionInput, limits: PlanLimits, start: float, cache: RowCache | None = None
) -> SectionPlan | None:
    """A window's law from the squared speed ``start`` to rest, or ``None``.

    The passes of :func:`~orthoglide_pin.planning.parametrize.plan_sections`
    (speed-dependent bounds taken around the previous pass), one section.
    ``cache``: the window's rows kept from its earlier plans (the same numbers).
    """
    bound, x_high, x0, passes = first_bounds(inp, limits, limits.limits_torque)
    x = None
    for _ in range(passes):
        if cache is None:
            a, b, c = rows(limits, inp.forms, x_high, x0, inp.scales)
        else:
            a, b, c = cache.rows(x_high, x0, inp.scales)
        xb = np.maximum(x_high, 0.0)
        xb[0], xb[-1] = max(xb[0], start), 0.0
        if cache is not None and cache.passes is not None:
            x = cache.passes.reach(inp.s, a, b, c, xb, start)
        else:
            x = reach(inp.s, a, b, c, xb, start=start)
        if x is None:
            return None
        x[-1] = 0.0
        if limits.limits_torque:
            x0 = x.copy()
            x_high = narrowed(bound, x)
            x_high[0] = max(x_high[0], start)
    assert x is not None
    return time_law(inp.s, x)


@dataclass(frozen=True)
class _Kept:
    """The part of a window that is kept: its grid and squared speeds, its verification."""

    s: FloatArray
    x: FloatArray
    end: float
    rounds: int
    scales: dict[str, float]
    worst: dict[str, float]
    binding: dict[str, float]


def _window(
    st: WindowSetting, lo: int, keep: int, hi: int, start: float, ready: Prepared | None = None
) -> _Kept | None:
    """Plan pieces ``lo:hi`` from ``start`` to rest, verified; keep ``lo:keep``.

    ``ready``: the pieces ``lo:hi`` prepared
    (:func:`~orthoglide_pin.planning.window_prep.prepare`), or ``None``.
    Returns ``None`` when the window cannot start at ``start`` (> 0).
    """
    section, lines, limits, calibration = st.section, st.lines, st.limits, st.calibration
    r = _prepare(st, lo, hi) if ready is None else ready
    sub, fine, grid, fine_lines, fine_forms = r.sub, r.fine, r.grid, r.fine_lines, r.fine_forms
    fine_feed, inp = r.fine_feed, r.inp
    rounds, cache = 0, RowCache(limits, inp.forms)
    while True:
        law = plan_window(inp, limits, start, cache)
        if law is None:
            if start > 0.0:
                return None
            raise ProgramError(
                int(lines[lo]),
                "no motion meets the limits on this move (the motors cannot hold or "
                "move the machine here within their torque)",
            )
        rounds += 1
        if inp.previous is None:
            checked = check_sections([fine_forms], [fine], [law], [fine_feed], limits, calibration)
            motion = checked[0]
        else:  # only the samples the re-plan changed are verified again
            changed = changed_samples(inp.previous, law.x, fine.s.size)
            motion = check_again(
                fine_forms, fine, law, fine_feed, limits, calibration, motion, changed
            )
        over = tighten(inp.scales, motion.uses, grid.s, fine.s, USE_TOL, rounds)
        if not over:
            break
        if rounds >= st.max_rounds:
            name, use = max(over.items(), key=lambda item: item[1])
            at = int(np.argmax(motion.uses[name]))
            raise ProgramError(
                int(fine_lines[at]),
                f"the plan still uses {use:.4f} of the limit {name} after "
                f"{st.max_rounds} plans tightened around it (at most {1.0 + USE_TOL:g})",
            )
        inp = dataclasses.replace(inp, previous=law.x)
    last = keep == hi
    end = float(sub.offsets[keep - lo])  # where the look-ahead begins
    n_keep = grid.s.size if last else int(np.searchsorted(grid.s, end, side="right"))
    m_keep = fine.s.size if last else int(np.searchsorted(fine.s, end, side="right"))
    kept = _cut(motion, slice(0, m_keep))
    # the boundary point starts the next window, unless the section ends there
    stop = n_keep if keep == len(section.pieces) else n_keep - 1
    return _Kept(
        float(section.offsets[lo]) + grid.s[:stop],
        law.x[:stop].copy(),
        float(law.x[n_keep - 1]),
        rounds,
        smallest(inp.scales),
        worst_uses([kept]),
        binding_time([kept]),
    )


def plan_in_windows(
    section: Section,
    lines: NDArray[np.intp],
    dyn: ClosedLoopDynamics,
    limits: PlanLimits,
    g: FloatArray,
    w: FloatArray | None,
    step: float,
    calibration: CalibratedKinematics | None,
    max_rounds: int,
    *,
    rapid_override: float = 1.0,
    on_window: Callable[[int], None] | None = None,
) -> WindowedSection | None:
    """Plan a long section window after window (see the module).

    A window that cannot start where its predecessor ended (its verification
    tightened a limit right at its start) makes the predecessor end at rest
    there instead, and starts from rest.

    Args:
        section: The section.
        lines: The program line of each of its pieces.
        dyn: The inverse dynamics.
        limits: The limits.
        g: Gravity [m/s^2].
        w: The tool wrench (6,), or ``None``.
        step: Largest spacing of the planning grid [m].
        calibration: A calibration, or ``None``.
        max_rounds: Plans of a window at most.
        rapid_override: The rapid override, in (0, 1]
            (:func:`~orthoglide_pin.planning.controller.rapid_caps`).
        on_window: Called with the program index of the last block of each
            window kept, or ``None``.

    Returns:
        The section's plan, or ``None`` when a window's start cannot be settled.

    Raises:
        ProgramError: As :func:`~orthoglide_pin.planning.plan.plan_program`.
    """
    st = WindowSetting(
        section, lines, dyn, limits, g, w, step, calibration, max_rounds, rapid_override
    )
    pairs = list(itertools.pairwise(_cuts(section, step)))
    kept: list[_Kept] = []
    starts: list[float] = []
    start, i = 0.0, 0

    def ahead(k: int) -> tuple[int, int]:
        return pairs[k][0], _ahead(section, step, pairs[k][1])

    # the next window is prepared on a second thread while this one is planned
    with ThreadPoolExecutor(max_workers=1) as pool:
        nxt: Future[Prepared] | None = pool.submit(_prepare, st, *ahead(0))
        try:
            while i < len(pairs):
                lo, keep = pairs[i]
                ready = None if nxt is None else nxt.result()
                nxt = (
                    pool.submit(_prepare, st, *ahead(i + 1), ready) if i + 1 < len(pairs) else None
                )  # the pieces the two windows share are taken from this one
                got = _window(st, lo, keep, _ahead(section, step, keep), start, ready)
                if got is None:  # the previous window stops here instead
                    plo, pkeep = pairs[i - 1]
                    redo = _window(st, plo, pkeep, pkeep, starts[-1])
                    if redo is None:
                        return None
                    kept[-1], start = redo, 0.0
                    if nxt is not None:
                        nxt.cancel()
                    nxt = None  # window i again, prepared afresh
                    continue
                kept.append(got)
                starts.append(start)
                if on_window is not None:
                    on_window(section.pieces[keep - 1].block)
                start, i = got.end, i + 1
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
    out = WindowedSection(time_law(np.array([0.0, 1.0]), np.zeros(2)), 0)
    for part in kept:
        for name, use in part.worst.items():
            out.worst[name] = max(out.worst.get(name, 0.0), use)
        for name, t in part.binding.items():
            out.binding[name] = out.binding.get(name, 0.0) + t
        for name, f in part.scales.items():
            out.scales[name] = min(out.scales.get(name, 1.0), f)
        out.rounds = max(out.rounds, part.rounds)
    s_all = np.concatenate([part.s for part in kept])
    out.plan = time_law(s_all, np.concatenate([part.x for part in kept]))
    out.grid_points = s_all.size
    return out


def plan_long_sections(
    path: Path,
    moving: list[Section],
    dyn: ClosedLoopDynamics,
    limits: PlanLimits,
    g: FloatArray,
    w: FloatArray | None,
    step: float,
    calibration: CalibratedKinematics | None,
    max_rounds: int,
    *,
    rapid_override: float = 1.0,
    on_window: Callable[[Section, int], None] | None = None,
) -> dict[int, WindowedSection]:
    """The long sections of ``moving`` planned in windows, by ``id`` (see the module).

    A section whose windows cannot be settled is left out: it is planned whole.
    The arguments are :func:`plan_in_windows`'s; ``on_window`` is called with
    the section and the program index of the last block of each window kept.
    """
    out: dict[int, WindowedSection] = {}
    blocks = path.program.blocks
    for sec in moving:
        if not needs_windows(sec, step):
            continue
        lines = np.array([blocks[p.block].line for p in sec.pieces], dtype=np.intp)
        tell = None if on_window is None else functools.partial(on_window, sec)
        done = plan_in_windows(
            sec, lines, dyn, limits, g, w, step, calibration, max_rounds,
            rapid_override=rapid_override, on_window=tell,
        )  # fmt: skip
        if done is not None:
            out[id(sec)] = done
    return out
