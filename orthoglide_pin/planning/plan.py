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
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_vector, instance_of, positive_number
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
    check_inside,
    sample_section,
)
from orthoglide_pin.planning.tighten import Fallback, smallest, tighten, whole_section
from orthoglide_pin.planning.verify import (
    REFINE,
    USE_TOL,
    Motion,
    binding_time,
    worst_uses,
)

FloatArray = NDArray[np.float64]

#: Plans of a section at most (the first, then tightened after verification).
MAX_ROUNDS: Final[int] = 8
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
        grid: The planning grid's samples (empty for a lone dwell).
        plan: Its time law (``None`` for a lone dwell).
        motion: Its verification on the fine grid (``None`` for a lone dwell).
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


def _feeds(section: Section, samples: Samples) -> FloatArray:
    """The path-speed cap at each sample [m/s] (``inf`` on rapid moves), junctions the lower."""
    caps = np.array([math.inf if p.feed is None else p.feed for p in section.pieces])
    feed = caps[samples.piece]
    first = np.flatnonzero(np.diff(samples.piece) != 0) + 1
    feed[first] = np.minimum(feed[first], caps[samples.piece[first] - 1])
    return np.asarray(feed)


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
) -> Plan:
    """Plan a program under the limits (see the module).

    Args:
        program: The program read (:func:`~orthoglide_pin.planning.gcode.read_program`).
        machine: The inverse dynamics, a machine's parameters, or ``None`` (the prototype).
        limits: The limits.
        wrench: Constant tool wrench (force [N], moment [N.m]), (3,) or (6,).
        gravity: Gravity [m/s^2], (3,); the dynamics' default when ``None``.
        step: Largest spacing of the planning grid [m].
        calibration: A calibration (:func:`~orthoglide_pin.calibration.result.load_calibration`):
            the sliders are commanded so that the real tool follows the program, and
            the slider limits are checked on those commands
            (:mod:`~orthoglide_pin.planning.calibrated`). It must have been made
            for this machine's design.

    Returns:
        The plan, verified.

    Raises:
        ProgramError: A point outside the cube or the slider limits, a move
            without an acceleration limit, or a move no motion can make.
        DesignMismatchError: The calibration was made for another design.
        MissingExtraError: toppra is not installed (``[plan]``).
    """
    program = instance_of("program", program, Program, "a Program (read_program)")
    limits = instance_of("limits", limits, PlanLimits, "a PlanLimits")
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
            program, dyn, replace(limits, slider_jerk=None), wrench=w, gravity=g, step=step,
            calibration=calibration,
        )  # fmt: skip
        path, stops = split_at_curvature_steps(path, limits.slider_jerk, limits.slider_speed)
    moving = [sec for sec in path.sections if sec.pieces]
    # the fine grid holds the planning grid (every REFINE-th point): sampled once
    fines = [sample_section(sec, step, refine=REFINE) for sec in moving]
    grids = [coarse_samples(fine) for fine in fines]
    for sec, grid, fine in zip(moving, grids, fines, strict=True):
        if not limits.second_order:
            raise ProgramError(
                int(_lines(path, sec, grid)[0]),
                "no limit bounds this move's acceleration: give a slider acceleration "
                "(--max-slider-acceleration) or a motor with torque data (--motor)",
            )
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
        SectionInput(grid.s, f, _feeds(sec, grid), Scales())
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
    while todo:
        planned = (
            plan_sections([inputs[k] for k in todo], limits)
            if limits.slider_jerk is None
            else jerk_plans([inputs[k] for k in todo], [kins[k] for k in todo], limits)
        )
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
    results: list[SectionResult] = []
    clock, index = 0.0, 0
    for section in path.sections:
        if not section.pieces:
            results.append(SectionResult(section, clock, None, None, None, 0, {}))
            clock += section.dwell
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
    fallbacks = tuple(
        Fallback(line, name, use, min(applied.values()), laws[k].duration - before)  # type: ignore[union-attr]
        for k, (line, name, use, before, applied) in sorted(falls.items())
    )
    motions = [r.motion for r in results if r.motion is not None]
    shares = {k: v / clock if clock > 0 else 0.0 for k, v in binding_time(motions).items()}
    return Plan(
        path,
        limits,
        tuple(results),
        clock,
        _block_times(path, results),
        worst_uses(motions),
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


def _wrench6(wrench: ArrayLike) -> FloatArray:
    """A constant tool wrench as six numbers (a force alone has no moment)."""
    arr = np.ravel(finite_vector("wrench", wrench, np.size(wrench), "[N, N.m]"))
    if arr.size not in (3, 6):
        raise InvalidParameterError(
            "wrench", wrench, "3 or 6 finite numbers: force [N], then moment [N.m]"
        )
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
