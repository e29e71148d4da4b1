"""The checks of :func:`~orthoglide_pin.planning.plan.plan_program`, before anything is planned.

:func:`checked_inputs` converts and checks its arguments (each error names
the argument and what is allowed); :func:`check_before_grids` refuses a
program before any grid point is made: a block end outside the cube, a
verification grid of more points held at once than the cap (counted from the
path's pieces: a section planned whole, or the window around the largest
piece of a section planned in windows; the sections planned whole are planned
in runs, so the program's length is not capped), a move that no second-order
limit bounds. Both run for every
section, whether it is planned whole or in windows
(:mod:`~orthoglide_pin.planning.windows`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

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
from orthoglide_pin.exceptions import InvalidParameterError, ProgramError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.calibrated import CalibratedKinematics
from orthoglide_pin.planning.controller import (
    RAPID_OVERRIDE_RANGE,
    check_override,
    with_controller,
)
from orthoglide_pin.planning.gcode import Program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import (
    MIN_INTERVALS,
    Path,
    Section,
    block_ends,
    check_inside,
    grid_size,
)
from orthoglide_pin.planning.verify import REFINE
from orthoglide_pin.planning.windows import WINDOWED_ABOVE, needs_windows

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PlanInputs:
    """The arguments of :func:`~orthoglide_pin.planning.plan.plan_program`, checked.

    Attributes:
        raw: The program as read.
        program: The program as the controller runs it (feeds overridden,
            default mode set: :func:`~orthoglide_pin.planning.controller.with_controller`).
        limits: The limits.
        dyn: The inverse dynamics.
        params: The machine's parameters.
        step: Largest spacing of the planning grid [m].
        g: Gravity [m/s^2], (3,).
        w: The tool wrench (6,), or ``None``.
        calibration: A calibration made for this design, or ``None``.
        rapid_override: The rapid override, in (0, 1] [-].
        progress: The ``(done, total)`` callback, or ``None``.
    """

    raw: Program
    program: Program
    limits: PlanLimits
    dyn: ClosedLoopDynamics
    params: OrthoglideParams
    step: float
    g: FloatArray
    w: FloatArray | None
    calibration: CalibratedKinematics | None
    rapid_override: float
    progress: Callable[[int, int], None] | None


def checked_inputs(
    program: Program,
    machine: ClosedLoopDynamics | OrthoglideParams | None,
    limits: PlanLimits,
    *,
    wrench: ArrayLike | None,
    gravity: ArrayLike | None,
    step: float,
    calibration: CalibratedKinematics | None,
    feed_override: float,
    rapid_override: float,
    blend: float | None,
    progress: Callable[[int, int], None] | None,
) -> PlanInputs:
    """The arguments of :func:`~orthoglide_pin.planning.plan.plan_program`, checked.

    Raises:
        InvalidParameterError: A bad argument, naming it.
        DesignMismatchError: The calibration was made for another design.
    """
    program = instance_of("program", program, Program, "a Program (read_program)")
    limits = instance_of("limits", limits, PlanLimits, "a PlanLimits")
    run = with_controller(program, feed_override=feed_override, blend=blend)
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
    w = None if wrench is None else wrench6(wrench)
    return PlanInputs(
        program, run, limits, dyn, params, step, g, w, calibration, rapid_override, progress
    )


def check_before_grids(
    path: Path,
    params: OrthoglideParams,
    moving: list[Section],
    limits: PlanLimits,
    step: float,
    cap: int,
) -> None:
    """Refuse a path before any grid is made (see the module).

    Args:
        path: The path.
        params: The machine's parameters.
        moving: Its moving sections.
        limits: The limits.
        step: Largest spacing of the planning grid [m].
        cap: The most points of the verification grid held at once.

    Raises:
        InvalidParameterError: A ``step`` that makes more than ``cap`` points at once.
        ProgramError: A block end outside the cube, or a move without an
            acceleration limit.
    """
    ends, end_lines = block_ends(path.program)  # cheap: before the grids are made
    if ends.size:
        check_inside(params, ends, end_lines)
    points = max((_held(sec, step) for sec in moving), default=0.0)
    size_within("step", step, points, cap, "points of the verification grid")
    if moving and not limits.second_order:
        raise ProgramError(
            path.program.blocks[moving[0].pieces[0].block].line,
            "no limit bounds this move's acceleration: give a slider acceleration "
            "(--max-slider-acceleration) or a motor with torque data (--motor)",
        )


def _held(section: Section, step: float) -> float:
    """Points of the verification grid a section needs at once (see the module)."""
    if not needs_windows(section, step):
        return grid_size(section, step, refine=REFINE)
    lengths = np.array([p.length for p in section.pieces])
    largest = float(np.max(np.maximum(MIN_INTERVALS, np.ceil(lengths / step))))
    return REFINE * (WINDOWED_ABOVE + largest)


def wrench6(wrench: ArrayLike) -> FloatArray:
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
