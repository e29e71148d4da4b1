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
memory does not grow with its length; the other sections are planned in runs
of about :data:`RUN_POINTS` grid points, and when there are several runs each
keeps only its sections' time laws (their verification summed,
:class:`~orthoglide_pin.planning.assemble.Verified`), so that memory does not
grow with the number of sections either. The arguments and the program are
checked before any grid is made (:mod:`~orthoglide_pin.planning.plan_inputs`);
the sections are then put together in the program's order
(:mod:`~orthoglide_pin.planning.assemble`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.machine.digest import design_digest
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.assemble import (
    BlockProgress,
    BlockTime,
    SectionResult,
    Verified,
    assemble,
)
from orthoglide_pin.planning.batch import (
    RunSummary,
    check_sections,
    coarse_forms,
    coarse_samples,
    section_forms,
)
from orthoglide_pin.planning.calibrated import CalibratedKinematics, calibrated_forms
from orthoglide_pin.planning.controller import rapid_caps
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
    build_path,
    collector_paused,
    grid_size,
)
from orthoglide_pin.planning.plan_inputs import check_before_grids, checked_inputs
from orthoglide_pin.planning.run_batch import check_run, run_feeds, run_lines
from orthoglide_pin.planning.sample_batch import sample_sections
from orthoglide_pin.planning.tighten import Fallback, smallest, tighten, whole_section
from orthoglide_pin.planning.verify import REFINE, USE_TOL, Motion
from orthoglide_pin.planning.windows import WindowedSection, plan_long_sections

__all__ = [
    "BATCH_SECTIONS",
    "MAX_GRID_POINTS",
    "MAX_ROUNDS",
    "RUN_POINTS",
    "BlockTime",
    "Plan",
    "plan_program",
]

FloatArray = NDArray[np.float64]

#: Plans of a section at most (the first, then tightened after verification).
MAX_ROUNDS: Final[int] = 8
#: Sections planned in one problem (then the progress is told) [-].
BATCH_SECTIONS: Final[int] = 64
#: Most points of the verification grid held at once (``REFINE`` per interval of
#: the planning grid, ``MIN_INTERVALS`` at least per piece): a section planned
#: whole, or the window around a long section's largest piece; counted before
#: any is made (the program's length is not capped).
MAX_GRID_POINTS: Final[int] = 5_000_000
#: Further plans at most, each slowing the section on the whole (tighten.whole_section).
FALLBACK_ROUNDS: Final[int] = 4
#: Sections planned whole are planned in runs of about this many planning-grid
#: points; when there are several runs, each keeps only its time laws (memory
#: independent of the number of sections).
RUN_POINTS: Final[int] = 16_384


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
            (``REFINE`` times finer) may hold at most :data:`MAX_GRID_POINTS` points
            at once.
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
            than :data:`MAX_GRID_POINTS` points at once (counted before any is made).
        ProgramError: A point outside the cube or the slider limits, a move
            without an acceleration limit, or a move no motion can make.
        DesignMismatchError: The calibration was made for another design.
        MissingExtraError: toppra is not installed (``[plan]``).
    """
    ins = checked_inputs(
        program, machine, limits, wrench=wrench, gravity=gravity, step=step,
        calibration=calibration, feed_override=feed_override, rapid_override=rapid_override,
        blend=blend, progress=progress,
    )  # fmt: skip
    program, limits, dyn, params, calibration = (
        ins.program, ins.limits, ins.dyn, ins.params, ins.calibration
    )  # fmt: skip
    step, g, w, rapid_override = ins.step, ins.g, ins.w, ins.rapid_override
    path = build_path(program)
    reference, stops = None, 0
    if limits.slider_jerk is not None:  # the second-order optimum, then stops at curvature steps
        reference = plan_program(
            ins.raw, dyn, replace(limits, slider_jerk=None), wrench=w, gravity=g, step=step,
            calibration=calibration, feed_override=feed_override,
            rapid_override=rapid_override, blend=blend,
        )  # fmt: skip
        path, stops = split_at_curvature_steps(path, limits.slider_jerk, limits.slider_speed)
    moving = [sec for sec in path.sections if sec.pieces]
    check_before_grids(path, params, moving, limits, step, MAX_GRID_POINTS)
    counter = BlockProgress(ins.progress, moving, len(program.blocks))

    def window_done(sec: Section, block: int) -> None:
        counter.planned(sec, block)
        counter.tell()

    windowed: dict[int, WindowedSection] = {}
    if reference is None:  # with a jerk limit, every section is planned whole
        windowed = plan_long_sections(
            path, moving, dyn, limits, g, w, step, calibration, MAX_ROUNDS,
            rapid_override=rapid_override, on_window=window_done,
        )  # fmt: skip
    moving = [sec for sec in moving if id(sec) not in windowed]
    whole: list[SectionResult] = []
    fallbacks: list[Fallback] = []
    summed: list[Verified] = []
    runs = _runs(moving, step) if reference is None else [moving]
    for run in runs:  # one run: kept whole; more: each summed, then freed
        with collector_paused():
            got, falls, verified = _plan_run(
                path, run, dyn, params, limits, g, w, step, calibration, rapid_override,
                counter, keep=len(runs) == 1,
            )  # fmt: skip
        whole += got
        fallbacks += falls
        summed += [] if verified is None else [verified]
    counter.finish()
    done = assemble(path, windowed, whole, summed)
    clock = done.cycle_time
    cost = None
    if reference is not None:
        ratio = clock / reference.cycle_time if reference.cycle_time > 0 else 1.0
        cost = {
            "second_order": reference.cycle_time,
            "with_jerk": clock,
            "ratio": ratio,
            "curvature_stops": float(stops),
        }
    return Plan(
        path, limits, done.results, clock, done.blocks, done.worst, done.binding,
        done.grid_points, w, g, calibration, cost, design=design_digest(params),
        fallbacks=tuple(fallbacks),
    )  # fmt: skip


def _runs(moving: list[Section], step: float) -> list[list[Section]]:
    """The sections in runs of about :data:`RUN_POINTS` planning-grid points, in order."""
    out: list[list[Section]] = [[]]
    points = 0.0
    for sec in moving:
        if out[-1] and points >= RUN_POINTS:
            out.append([])
            points = 0.0
        out[-1].append(sec)
        points += grid_size(sec, step)
    return out if out[0] else []


def _plan_run(
    path: Path,
    moving: list[Section],
    dyn: ClosedLoopDynamics,
    params: OrthoglideParams,
    limits: PlanLimits,
    g: FloatArray,
    w: FloatArray | None,
    step: float,
    calibration: CalibratedKinematics | None,
    rapid_override: float,
    counter: BlockProgress,
    *,
    keep: bool,
) -> tuple[list[SectionResult], list[Fallback], Verified | None]:
    """Plan, verify and tighten a run of sections (see the module).

    Returns:
        Each section's result, the fallbacks, and ``None`` when ``keep``; else the
        results without their grids and verifications, which are summed in a
        :class:`~orthoglide_pin.planning.assemble.Verified`.
    """
    jerk = limits.slider_jerk is not None
    # the fine grid holds the planning grid (every REFINE-th point): sampled once
    fines = sample_sections(moving, step, refine=REFINE)
    grids = [coarse_samples(fine) for fine in fines]
    check_run(params, calibration, fines, run_lines(path, moving, fines))
    fine_forms = section_forms(dyn, fines, g, w)
    forms = [coarse_forms(f) for f in fine_forms]
    if calibration is not None:  # the real tool follows the path: calibrated commands
        forms = [
            calibrated_forms(calibration, f, x.p, x.dp, x.ddp)
            for f, x in zip(forms, grids, strict=True)
        ]
    inputs = [
        SectionInput(grid.s, f, rapid_caps(feed, f, limits, rapid_override), Scales())
        for grid, f, feed in zip(grids, forms, run_feeds(moving, grids), strict=True)
    ]
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
            lambda secs, xs, fs: [
                rapid_caps(feed, f, limits, rapid_override)
                for feed, f in zip(run_feeds(secs, xs), fs, strict=True)
            ],
        )
        grids, fines = [x.grid for x in state], [x.fine for x in state]
        fine_forms = [x.fine_forms for x in state]
    fine_feeds = run_feeds(moving, fines)
    kins = fine_kinematics(fine_forms, fines, fine_feeds, calibration) if jerk else []
    laws: list[SectionPlan | None] = [None] * len(moving)
    checks: list[Motion | None] = [None] * len(moving)
    rounds = [0] * len(moving)
    falls: dict[int, tuple[int, str, float, float, dict[str, float]]] = {}
    summary = RunSummary(len(moving))
    todo = list(range(len(moving)))
    while todo:
        planned: list[SectionPlan | None] = []
        for lo in range(0, len(todo), BATCH_SECTIONS):
            part = todo[lo : lo + BATCH_SECTIONS]
            planned += (
                plan_sections([inputs[k] for k in part], limits)
                if limits.slider_jerk is None
                else jerk_plans([inputs[k] for k in part], [kins[k] for k in part], limits)
            )
            if rounds[part[-1]] == 0:  # the first plans
                for k in part:
                    counter.planned(moving[k], moving[k].pieces[-1].block)
                counter.tell()
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
        run = check_sections(f_forms, f_grids, f_laws, f_feeds, limits, calibration)  # type: ignore[arg-type]
        checked: Sequence[Motion] = run
        if limits.slider_jerk is not None:
            checked = [
                with_jerk(m, laws[k], kins[k], limits.slider_jerk)
                for k, m in zip(todo, checked, strict=True)
            ]
        if keep:
            for k, motion in zip(todo, checked, strict=True):
                checks[k] = motion
        else:
            summary.add(todo, run)
        again = []  # a section within every limit is not tightened (tighten does nothing)
        for j in range(len(todo)) if jerk else run.over(1.0 + USE_TOL):
            k, motion = todo[j], checked[j]
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
    fallbacks = [
        Fallback(line, name, use, min(applied.values()), laws[k].duration - before)  # type: ignore[union-attr]
        for k, (line, name, use, before, applied) in sorted(falls.items())
    ]
    if keep:
        whole = [
            SectionResult(sec, 0.0, grid, law, motion, n, smallest(inp.scales))
            for sec, grid, law, motion, n, inp in zip(
                moving, grids, laws, checks, rounds, inputs, strict=True
            )
        ]
        return whole, fallbacks, None
    summed = Verified(*summary.totals(), sum(grid.s.size for grid in grids))
    whole = [
        SectionResult(sec, 0.0, None, law, None, n, smallest(inp.scales))
        for sec, law, n, inp in zip(moving, laws, rounds, inputs, strict=True)
    ]
    return whole, fallbacks, summed
