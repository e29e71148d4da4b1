"""The plan of a whole program: sections planned, verified, timed and sampled.

:func:`plan_program` reads nothing itself: it takes a
:class:`~orthoglide_pin.planning.gcode.Program`, builds its path
(:mod:`~orthoglide_pin.planning.path`), checks that every grid point lies in
the cube and the slider limits, and plans each section from rest to rest
(:mod:`~orthoglide_pin.planning.parametrize`) on the path forms of the
closed-loop dynamics (:func:`~orthoglide_pin.dynamics.path_forms.path_forms`).
Each section is then verified (:mod:`~orthoglide_pin.planning.verify`); a
section whose worst use of a limit exceeds ``1 + USE_TOL`` (the motion
between grid points overshoots) is planned again with that limit tightened by
the overshoot around where it is exceeded only
(:mod:`~orthoglide_pin.planning.tighten`), up to :data:`MAX_ROUNDS` plans;
a section still over a limit then falls back on a slower safe plan: the
limit lowered on the whole section by its overshoot
(:func:`~orthoglide_pin.planning.tighten.whole_section`), up to
:data:`FALLBACK_ROUNDS` more plans, reported in :attr:`Plan.fallbacks` (where,
and the time it cost); only a section over a limit after those is refused,
naming the line. A move that no
second-order limit bounds (no slider acceleration, no motor torque) is refused.
A long section (more than
:data:`~orthoglide_pin.planning.windows.WINDOWED_ABOVE` grid points) is planned
in windows with a look-ahead (:mod:`~orthoglide_pin.planning.windows`), so that
memory does not grow with its length.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    MAX_WRENCH,
    finite_vector,
    first_index,
    instance_of,
    optional_callable,
    positive_number,
    size_within,
)
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.motion_forms import as_dynamics
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.exceptions import InvalidParameterError, ProgramError
from orthoglide_pin.machine.digest import design_digest
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.batch import (
    check_sections,
    coarse_forms,
    coarse_samples,
    section_forms,
)
from orthoglide_pin.planning.calibrated import (
    CalibratedKinematics,
    calibrated_forms,
    check_sliders,
)
from orthoglide_pin.planning.controller import (
    RAPID_OVERRIDE_RANGE,
    check_override,
    rapid_caps,
    with_controller,
)
from orthoglide_pin.planning.gcode import Program
from orthoglide_pin.planning.grid import Grids, refine_grid
from orthoglide_pin.planning.jerk import jerk_plans, with_jerk
from orthoglide_pin.planning.jerk_kinematics import fine_kinematics
from orthoglide_pin.planning.jerk_stops import split_at_curvature_steps
from orthoglide_pin.planning.limits import PlanLimits, Scales
from orthoglide_pin.planning.parametrize import SectionInput, SectionPlan, plan_sections
from orthoglide_pin.planning.path import (
    GRID_STEP,
    Path,
    Samples,
    Section,
    block_ends,
    build_path,
    check_inside,
    grid_size,
)
from orthoglide_pin.planning.sample_batch import sample_batch
from orthoglide_pin.planning.tighten import Fallback, smallest, tighten, whole_section
from orthoglide_pin.planning.verify import (
    REFINE,
    USE_TOL,
    Motion,
    binding_time,
    worst_uses,
)
from orthoglide_pin.planning.windows import (
    WindowedSection,
    needs_windows,
    plan_in_windows,
)
from orthoglide_pin.planning.windows import section_feeds as _feeds

FloatArray = NDArray[np.float64]

#: Plans of a section at most (the first, then tightened after verification).
MAX_ROUNDS: Final[int] = 8
#: Sections planned in one problem (then the progress is told) [-].
BATCH_SECTIONS: Final[int] = 64
#: Most points of a plan's verification grid (``REFINE`` per interval of the
#: planning grid, ``MIN_INTERVALS`` at least per piece), counted before any is made.
MAX_GRID_POINTS: Final[int] = 5_000_000
#: Further plans at most, each slowing the section on the whole (tighten.whole_section).
FALLBACK_ROUNDS: Final[int] = 4


@dataclass(frozen=True)
class BlockTime:
    """When a block of the program runs.

    Attributes:
        line: Its line in the program.
        kind: ``"rapid"``, ``"line"``, ``"arc"`` or ``"dwell"``.
        start: Start time [s].
        end: End time [s].
    """

    line: int
    kind: str
    start: float
    end: float


@dataclass(frozen=True)
class SectionResult:
    """A section planned and verified.

    Attributes:
        section: The section.
        start: Its start time in the cycle [s].
        grid: The planning grid's samples (``None`` for a lone dwell or a
            section planned in windows, :mod:`~orthoglide_pin.planning.windows`).
        plan: Its time law (``None`` for a lone dwell).
        motion: Its verification on the fine grid (``None`` for a lone dwell or
            a section planned in windows: its worst uses and binding times are
            in the plan's ``worst`` and ``binding``).
        rounds: How many times it was planned.
        scales: The smallest tightening factor of each limit it needed
            (:mod:`~orthoglide_pin.planning.tighten`).
    """

    section: Section
    start: float
    grid: Samples | None
    plan: SectionPlan | None
    motion: Motion | None
    rounds: int
    scales: dict[str, float]

    @property
    def duration(self) -> float:
        """The motion's duration, without the dwell [s]."""
        return 0.0 if self.plan is None else self.plan.duration


@dataclass(frozen=True)
class Plan:
    """A program's time-optimal plan.

    Attributes:
        path: The tool path.
        limits: The limits it respects.
        sections: Each section planned, in order.
        cycle_time: The program's duration, dwells included [s].
        blocks: When each block runs.
        worst: The largest use of each given limit on the verification grid [-].
        binding: The share of the cycle time each limit binds [-].
        grid_points: Points of the planning grid.
        wrench: The tool wrench (6,), or ``None``. gravity: The gravity used (3,).
        calibration: The calibration whose kinematics command the sliders, or ``None``.
        jerk_time_cost: With a jerk limit: ``second_order`` (the cycle time without
            it [s]), ``with_jerk`` (the cycle time [s]), their ``ratio`` and the
            ``curvature_stops`` it adds (:mod:`~orthoglide_pin.planning.jerk_stops`);
            else ``None``.
        fallbacks: The sections planned slower on the whole because local
            tightening did not settle (:class:`~orthoglide_pin.planning.tighten.Fallback`).
        design: The design digest of the machine planned for
            (:func:`~orthoglide_pin.machine.digest.design_digest`): sampled or
            simulated on another, the plan is refused.
    """

    path: Path
    limits: PlanLimits
    sections: tuple[SectionResult, ...]
    cycle_time: float
    blocks: tuple[BlockTime, ...]
    worst: dict[str, float]
    binding: dict[str, float]
    grid_points: int
    wrench: FloatArray | None
    gravity: FloatArray
    calibration: CalibratedKinematics | None = None
    jerk_time_cost: dict[str, float] | None = None
    design: str | None = None
    fallbacks: tuple[Fallback, ...] = ()


def _lines(path: Path, section: Section, samples: Samples) -> NDArray[np.intp]:
    blocks = path.program.blocks
    lines = np.array([blocks[p.block].line for p in section.pieces], dtype=np.intp)
    return np.asarray(lines[samples.piece])


def plan_program(
    program: Program,
    machine: ClosedLoopDynamics | OrthoglideParams | None,
    limits: PlanLimits,
    *,
    wrench: ArrayLike | None = None,
    gravity: ArrayLike | None = None,
    step: float = GRID_STEP,
    calibration: CalibratedKinematics | None = None,
    feed_override: float = 1.0,
    rapid_override: float = 1.0,
    blend: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Plan:
    """Plan a program under the limits (see the module).

    Args:
        program: The program read (:func:`~orthoglide_pin.planning.gcode.read_program`).
        machine: The inverse dynamics, a machine's parameters, or ``None`` (the prototype).
        limits: The limits.
        wrench: Constant tool wrench (force [N], moment [N.m]), (3,) or (6,).
        gravity: Gravity [m/s^2], (3,); the dynamics' default when ``None``.
        step: Largest spacing of the planning grid [m]; the verification grid
            (``REFINE`` times finer) may have at most :data:`MAX_GRID_POINTS` points.
        calibration: A calibration (:func:`~orthoglide_pin.calibration.result.load_calibration`):
            the sliders are commanded so that the real tool follows the program, and
            the slider limits are checked on those commands
            (:mod:`~orthoglide_pin.planning.calibrated`). It must have been made
            for this machine's design.
        feed_override: Multiplies every programmed feed, in (0, 2] (as on a
            CNC panel, :mod:`~orthoglide_pin.planning.controller`).
        rapid_override: Caps the path speed of rapid moves at this share of
            what the speed limits allow, in (0, 1]; below 1 it needs a slider
            speed limit or a motor speed limit.
        blend: The tolerance of ``G64 P<blend>`` [m], the mode of the blocks
            before any ``G61``/``G64`` (0.01 mm when ``None``; 0 stops at
            every corner that is not tangent).
        progress: Called with (blocks planned, blocks) as the first plans are
            made, or ``None``.

    Returns:
        The plan, verified.

    Raises:
        InvalidParameterError: A bad argument, or a ``step`` that makes more
            than :data:`MAX_GRID_POINTS` points (counted before any is made).
        ProgramError: A point outside the cube or the slider limits, a move
            without an acceleration limit, or a move no motion can make.
        DesignMismatchError: The calibration was made for another design.
        MissingExtraError: toppra is not installed (``[plan]``).
    """
    program = instance_of("program", program, Program, "a Program (read_program)")
    limits = instance_of("limits", limits, PlanLimits, "a PlanLimits")
    raw = program
    program = with_controller(program, feed_override=feed_override, blend=blend)
    rapid_override = check_override("rapid_override", rapid_override, RAPID_OVERRIDE_RANGE[1])
    progress = optional_callable("progress", progress, "a function of (done, total), or None")
    if calibration is not None and not isinstance(calibration, CalibratedKinematics):
        raise InvalidParameterError("calibration", calibration, "a Calibration (load_calibration)")
    dyn = as_dynamics(machine)
    params = dyn.closed_loop.params
    if calibration is not None:
        calibration.check_design(params)  # made for this design, or refused
    step = positive_number("step", step, "a grid spacing > 0 [m]")
    g = dyn.gravity_vector(gravity)
    w = None if wrench is None else _wrench6(wrench)
    path = build_path(program)
    reference, stops = None, 0
    if limits.slider_jerk is not None:  # the second-order optimum, then stops at curvature steps
        reference = plan_program(
            raw, dyn, replace(limits, slider_jerk=None), wrench=w, gravity=g, step=step,
            calibration=calibration, feed_override=feed_override,
            rapid_override=rapid_override, blend=blend,
        )  # fmt: skip
        path, stops = split_at_curvature_steps(path, limits.slider_jerk, limits.slider_speed)
    moving = [sec for sec in path.sections if sec.pieces]
    ends, end_lines = block_ends(path.program)  # cheap: before the grids are made
    if ends.size:
        check_inside(params, ends, end_lines)
    points = sum(grid_size(sec, step, refine=REFINE) for sec in moving)
    size_within("step", step, points, MAX_GRID_POINTS, "points of the verification grid")
    if moving and not limits.second_order:
        _no_second_order(path, moving[0])
    windowed = (
        {}
        if reference is not None
        else _windowed(path, moving, dyn, limits, g, w, step, calibration)
    )
    moving = [sec for sec in moving if id(sec) not in windowed]
    # the fine grid holds the planning grid (every REFINE-th point): sampled once
    fines = [sample_batch(sec, step, refine=REFINE) for sec in moving]
    grids = [coarse_samples(fine) for fine in fines]
    for sec, fine in zip(moving, fines, strict=True):
        check_inside(params, fine.p, _lines(path, sec, fine))
        if calibration is not None:
            check_sliders(calibration, params, fine.p, _lines(path, sec, fine))
    fine_forms = section_forms(dyn, fines, g, w)
    forms = [coarse_forms(f) for f in fine_forms]
    if calibration is not None:  # the real tool follows the path: calibrated commands
        forms = [
            calibrated_forms(calibration, f, x.p, x.dp, x.ddp)
            for f, x in zip(forms, grids, strict=True)
        ]
    inputs = [
        SectionInput(grid.s, f, rapid_caps(_feeds(sec, grid), f, limits, rapid_override), Scales())
        for sec, grid, f in zip(moving, grids, forms, strict=True)
    ]
    jerk = limits.slider_jerk is not None
    if not jerk and limits.second_order:  # the grid follows the motion (planning.grid)

        def calibrate(f: PathForms, x: Samples) -> PathForms:
            return f if calibration is None else calibrated_forms(calibration, f, x.p, x.dp, x.ddp)

        state, inputs = refine_grid(
            moving,
            [Grids(*z) for z in zip(grids, forms, fines, fine_forms, strict=True)],
            inputs,
            limits,
            lambda xs: section_forms(dyn, xs, g, w),
            calibrate,
            _feeds,
        )
        grids, fines = [x.grid for x in state], [x.fine for x in state]
        fine_forms = [x.fine_forms for x in state]
    fine_feeds = [_feeds(sec, fine) for sec, fine in zip(moving, fines, strict=True)]
    kins = fine_kinematics(fine_forms, fines, fine_feeds, calibration) if jerk else []
    laws: list[SectionPlan | None] = [None] * len(moving)
    checks: list[Motion | None] = [None] * len(moving)
    rounds = [0] * len(moving)
    falls: dict[int, tuple[int, str, float, float, dict[str, float]]] = {}
    todo = list(range(len(moving)))
    total = len(program.blocks)
    while todo:
        planned: list[SectionPlan | None] = []
        for lo in range(0, len(todo), BATCH_SECTIONS):
            part = todo[lo : lo + BATCH_SECTIONS]
            planned += (
                plan_sections([inputs[k] for k in part], limits)
                if limits.slider_jerk is None
                else jerk_plans([inputs[k] for k in part], [kins[k] for k in part], limits)
            )
            if progress is not None and rounds[part[-1]] == 0:  # the first plans
                progress(moving[part[-1]].pieces[-1].block + 1, total)
        for k, law in zip(todo, planned, strict=True):
            if law is None:
                raise ProgramError(
                    int(_lines(path, moving[k], grids[k])[0]),
                    "no motion meets the limits on this move (the motors cannot hold or "
                    "move the machine here within their torque)",
                )
            laws[k] = law
            rounds[k] += 1
        f_forms, f_grids, f_laws, f_feeds = (
            [x[k] for k in todo] for x in (fine_forms, fines, laws, fine_feeds)
        )
        checked = check_sections(f_forms, f_grids, f_laws, f_feeds, limits, calibration)  # type: ignore[arg-type]
        if limits.slider_jerk is not None:
            checked = [
                with_jerk(m, laws[k], kins[k], limits.slider_jerk)
                for k, m in zip(todo, checked, strict=True)
            ]
        again = []
        for k, motion in zip(todo, checked, strict=True):
            checks[k] = motion
            over = tighten(
                inputs[k].scales, motion.uses, grids[k].s, fines[k].s, USE_TOL, rounds[k]
            )
            if over and rounds[k] >= MAX_ROUNDS:
                name, use = max(over.items(), key=lambda item: item[1])
                line = int(_lines(path, moving[k], fines[k])[int(np.argmax(motion.uses[name]))])
                if rounds[k] >= MAX_ROUNDS + FALLBACK_ROUNDS:
                    raise ProgramError(
                        line,
                        f"the plan still uses {use:.4f} of the limit {name} after "
                        f"{rounds[k]} plans, the last slowed on the whole section "
                        f"(at most {1.0 + USE_TOL:g})",
                    )
                start = falls.setdefault(k, (line, name, use, laws[k].duration, {}))  # type: ignore[union-attr]
                whole_section(inputs[k].scales, over, start[4])
            if over:
                inputs[k] = dataclasses.replace(inputs[k], previous=laws[k].x)  # type: ignore[union-attr]
                again.append(k)
        todo = again
    if progress is not None:
        progress(total, total)
    results: list[SectionResult] = []
    clock, index = 0.0, 0
    for section in path.sections:
        if not section.pieces:
            results.append(SectionResult(section, clock, None, None, None, 0, {}))
            clock += section.dwell
            continue
        if id(section) in windowed:
            done = windowed[id(section)]
            results.append(
                SectionResult(section, clock, None, done.plan, None, done.rounds, done.scales)
            )
            clock += done.plan.duration + section.dwell
            continue
        law = laws[index]
        assert law is not None
        results.append(
            SectionResult(
                section,
                clock,
                grids[index],
                law,
                checks[index],
                rounds[index],
                smallest(inputs[index].scales),
            )
        )
        clock += law.duration + section.dwell
        index += 1
    grid_points = sum(grid.s.size for grid in grids)
    grid_points += sum(done.grid_points for done in windowed.values())
    fallbacks = tuple(
        Fallback(line, name, use, min(applied.values()), laws[k].duration - before)  # type: ignore[union-attr]
        for k, (line, name, use, before, applied) in sorted(falls.items())
    )
    motions = [r.motion for r in results if r.motion is not None]
    worst, bound = worst_uses(motions), binding_time(motions)
    for done in windowed.values():
        for name, use in done.worst.items():
            worst[name] = max(worst.get(name, 0.0), use)
        for name, t in done.binding.items():
            bound[name] = bound.get(name, 0.0) + t
    shares = {k: v / clock if clock > 0 else 0.0 for k, v in bound.items()}
    return Plan(
        path,
        limits,
        tuple(results),
        clock,
        _block_times(path, results),
        worst,
        shares,
        grid_points,
        w,
        g,
        calibration,
        None
        if reference is None
        else {
            "second_order": reference.cycle_time,
            "with_jerk": clock,
            "ratio": clock / reference.cycle_time if reference.cycle_time > 0 else 1.0,
            "curvature_stops": float(stops),
        },
        design=design_digest(params),
        fallbacks=fallbacks,
    )


def _no_second_order(path: Path, section: Section) -> None:
    """Refuse a move that no second-order limit bounds, naming its line."""
    raise ProgramError(
        path.program.blocks[section.pieces[0].block].line,
        "no limit bounds this move's acceleration: give a slider acceleration "
        "(--max-slider-acceleration) or a motor with torque data (--motor)",
    )


def _windowed(
    path: Path,
    moving: list[Section],
    dyn: ClosedLoopDynamics,
    limits: PlanLimits,
    g: FloatArray,
    w: FloatArray | None,
    step: float,
    calibration: CalibratedKinematics | None,
) -> dict[int, WindowedSection]:
    """The long sections planned in windows (:mod:`~orthoglide_pin.planning.windows`), by id.

    A section whose windows cannot be settled is left out: it is planned whole.
    """
    out: dict[int, WindowedSection] = {}
    blocks = path.program.blocks
    for sec in moving:
        if not needs_windows(sec, step):
            continue
        lines = np.array([blocks[p.block].line for p in sec.pieces], dtype=np.intp)
        done = plan_in_windows(sec, lines, dyn, limits, g, w, step, calibration, MAX_ROUNDS)
        if done is not None:
            out[id(sec)] = done
    return out


def _wrench6(wrench: ArrayLike) -> FloatArray:
    """A constant tool wrench as six numbers (a force alone has no moment)."""
    arr = np.ravel(finite_vector("wrench", wrench, np.size(wrench), "[N, N.m]"))
    if arr.size not in (3, 6):
        raise InvalidParameterError(
            "wrench", wrench, "3 or 6 finite numbers: force [N], then moment [N.m]"
        )
    over = np.abs(arr) > MAX_WRENCH
    if over.any():
        bad = float(arr[first_index(over)])
        raise InvalidParameterError("wrench", bad, f"values within +-{MAX_WRENCH:g} [N, N.m]")
    out = np.zeros(6)
    out[: min(arr.size, 6)] = arr[:6]
    return out


def _block_times(path: Path, results: list[SectionResult]) -> tuple[BlockTime, ...]:
    """Start and end time of every block (zero-length moves take no time)."""
    blocks = path.program.blocks
    start = np.full(len(blocks), np.nan)
    end = np.full(len(blocks), np.nan)
    for r in results:
        sec = r.section
        if r.plan is not None:
            t_at = r.plan.at_lengths(sec.offsets)[0]
            for k, piece in enumerate(sec.pieces):
                b = piece.block
                t0, t1 = r.start + t_at[k], r.start + t_at[k + 1]
                start[b] = t0 if np.isnan(start[b]) else min(start[b], t0)
                end[b] = t1 if np.isnan(end[b]) else max(end[b], t1)
        if sec.dwell_block >= 0:
            t0 = r.start + r.duration
            start[sec.dwell_block], end[sec.dwell_block] = t0, t0 + sec.dwell
    out, last = [], 0.0
    for k, block in enumerate(blocks):
        t0 = last if np.isnan(start[k]) else float(start[k])
        t1 = t0 if np.isnan(end[k]) else float(end[k])
        out.append(BlockTime(block.line, block.kind, t0, t1))
        last = t1
    return tuple(out)
