"""The torque-requirement report: what the motors must deliver, and whether they do.

:func:`assemble_report` computes every number of the report for a machine and
an optional drive (:func:`~orthoglide_pin.drives.motor.load_drive`):

* the worst case over every direction of the tool motion
  (:mod:`orthoglide_pin.dynamics.requirements`) on a grid of the whole cube (maxima and
  where they occur, with the worst motion checked by a direct inverse-dynamics
  call) and on plane slices of it (maps): by default ``z`` at the cube's lower
  face, centre and upper face;
* the standard cycle (:func:`~orthoglide_pin.motion.cycle.standard_cycle`) at the
  same speed and acceleration: tool and slider motion, slider forces, motor
  torques and speeds, and the cycle statistics
  (:func:`~orthoglide_pin.drives.sizing.size_drives`);
* with motor data, the verdict: margins ``1 - required / available`` of each
  motor, for the cycle (RMS, peak torque, speed, speed-torque curve) and for
  the worst case over the cube (torque against the torque available at the
  motor's speed there, speed), and what the motors guarantee in the worst
  direction (:class:`~orthoglide_pin.dynamics.requirements.Guarantees`).
  A safety factor ``k >= 1`` (default 1) multiplies every required **torque** of
  the verdict (RMS, peak, samples against the speed-torque curve, worst case
  over the cube) before it is compared; speeds are compared as computed, and
  the maxima, maps and cycle figures are shown as computed.
* the tool's stiffness over the cube and its deflection under a cutting force
  (:mod:`orthoglide_pin.report.stiffness`), and its transmission factors there,
  judged by the machine's criterion
  (:func:`~orthoglide_pin.kinetostatics.factor_range.factor_range`);
* the lowest natural frequency over the cube (:mod:`orthoglide_pin.report.vibration`),
  a verdict row when a minimum frequency is given;
* with a cut file, the part's accuracy (:mod:`orthoglide_pin.report.accuracy`):
  along the program, the surface error, the error budget and the chatter
  stability margin of every program line that cuts (as ``orthoglide accuracy``,
  with the report's drive train); without a program, the stability
  lobes at the cube's home, Q1 and Q2.

:func:`~orthoglide_pin.report.files.write_report` writes it out
(``report.html``, ``report.json`` and CSV files, atomically) and
:mod:`orthoglide_pin.report.html` draws it.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import integer, optional_callable
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.drives.sizing import DriveSizing, safety_factor_value, size_drives
from orthoglide_pin.dynamics.inertia import assumptions as inertia_assumptions
from orthoglide_pin.dynamics.inverse import (
    DEFAULT_GRAVITY,
    GRAVITY_ASSUMPTION,
    ClosedLoopDynamics,
    DynamicsResult,
)
from orthoglide_pin.dynamics.motion_forms import requirement_forms
from orthoglide_pin.dynamics.requirements import (
    DEFAULT_A_MAX,
    DEFAULT_V_MAX,
    WorstCase,
    worst_case_on_grid,
)
from orthoglide_pin.kinetostatics.factor_range import FactorRange, factor_range
from orthoglide_pin.kinetostatics.workspace import Grid, cube_grid, slice_grid
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import CutConditions
from orthoglide_pin.motion.cycle import CYCLE_JERK, standard_cycle
from orthoglide_pin.motion.profiles import MotionLimits
from orthoglide_pin.motion.trajectory import Trajectory
from orthoglide_pin.planning.gcode import Program
from orthoglide_pin.report.accuracy import AccuracySection, accuracy_section, check_cut
from orthoglide_pin.report.program import ProgramSection, program_part
from orthoglide_pin.report.stiffness import (
    DEFAULT_CUTTING_FORCE,
    StiffnessSection,
    stiffness_section,
)
from orthoglide_pin.report.units import quantity
from orthoglide_pin.report.verdict import VerdictRow as VerdictRow
from orthoglide_pin.report.verdict import motor_rows
from orthoglide_pin.report.vibration import VibrationSection, vibration_rows, vibration_section

FloatArray = NDArray[np.float64]

#: Default points per axis of each map slice.
DEFAULT_RESOLUTION: Final[int] = 41
#: Default points per edge of the cube grid of the maxima (corners included).
DEFAULT_CUBE_RESOLUTION: Final[int] = 21
#: Largest resolutions accepted (memory and time).
MAX_RESOLUTION: Final[int] = 401
MAX_CUBE_RESOLUTION: Final[int] = 101
#: How to get a verdict without motor data, for the terminal and the page.
NO_MOTOR_HINT: Final = (
    "no motor data, so no verdict on the motors' limits: give the drive with "
    "--motor FILE.yaml (sections drive_train and motor); "
    "`orthoglide drive --example > drive.yaml` writes the shipped example to edit"
)
#: The default slices: ``z`` at these fractions of the cube side from its corner.
SLICE_FRACTIONS: Final = ((0.0, "lower face"), (0.5, "centre"), (1.0, "upper face"))


class Bar(Protocol):
    """What a progress bar offers (a ``tqdm`` instance does)."""

    def update(self, n: int = 1) -> object:
        """Advance by ``n`` units."""

    def close(self) -> None:
        """Finish the bar."""


#: Makes a bar from a description and a total number of units.
Progress = Callable[[str, int], Bar]


@dataclass(frozen=True)
class MapSlice:
    """The worst case on one plane slice of the cube.

    Attributes:
        label: Human-readable name (e.g. ``"z = centre"``).
        axis: The fixed axis, ``"x"``, ``"y"`` or ``"z"``.
        value: Its value [m].
        worst: The worst case on the slice grid.
    """

    label: str
    axis: str
    value: float
    worst: WorstCase


@dataclass(frozen=True)
class ReportData:
    """Every number of the report (see the module).

    Attributes:
        params: The machine.
        drive: The drive (the default drive train when no motor file is given).
        motor_given: Whether motor data came with the drive.
        v_max: Tool speed of the worst case and of the cycle [m/s].
        a_max: Tool acceleration of the worst case and of the cycle [m/s^2].
        jerk: Jerk of the cycle's moves [m/s^3].
        gravity: Gravity [m/s^2], shape (3,).
        corner: Lowest corner of the cube [m], shape (3,): the machine's
            prescribed cube (``params.workspace``).
        side: Side of the cube [m].
        assumptions: Sentences per topic (``inertia``, ``drive``, ``method``).
        cube: The worst case on the cube grid.
        worst_motions: Per slider, the point, velocity and acceleration giving
            its largest ``|F_i|``, and the force from a direct dynamics call.
        slices: The map slices.
        cycle: The standard cycle.
        cycle_dynamics: Inverse dynamics along it.
        sizing: Motor demand, statistics and (with motor data) check on the cycle.
        verdict: Criteria per motor (required torques multiplied by the
            safety factor).
        safety_factor: Multiplies the required torques of the verdict, ``>= 1``.
        stiffness: The tool's stiffness over the cube and the deflection under
            the cutting force, or ``None`` when not computed.
        transmission: The factors on the cube grid and the machine's criterion
            (``params.psi_min``, ``psi_max``) there, or ``None``.
        program: A part program's demand (:mod:`~orthoglide_pin.report.program`), or ``None``.
        vibration: The natural frequencies over the cube, or ``None`` when not computed.
        accuracy: The part's accuracy under a cut file, or ``None`` without one.
    """

    params: OrthoglideParams
    drive: Drive
    motor_given: bool
    v_max: float
    a_max: float
    jerk: float
    gravity: FloatArray
    corner: FloatArray
    side: float
    assumptions: dict[str, list[str]]
    cube: WorstCase
    worst_motions: list[dict[str, Any]]
    slices: tuple[MapSlice, ...]
    cycle: Trajectory
    cycle_dynamics: DynamicsResult
    sizing: DriveSizing
    verdict: tuple[VerdictRow, ...]
    safety_factor: float = 1.0
    stiffness: StiffnessSection | None = None
    transmission: FactorRange | None = None
    program: ProgramSection | None = None
    vibration: VibrationSection | None = None
    accuracy: AccuracySection | None = None

    @property
    def passed(self) -> bool | None:
        """Every criterion passes; ``None`` when none is judged (no motor data, no minimum)."""
        judged = [row.passed for row in self.verdict if row.margin is not None]
        return all(judged) if judged or self.motor_given else None


def method_assumptions(v_max: float, a_max: float) -> list[str]:
    """How the worst case is computed and what is exact, for reports."""
    return [
        f"Worst case over every direction of the tool velocity and acceleration, "
        f"|v| <= {quantity('speed', v_max)} and |a| <= {quantity('acceleration', a_max)} "
        "independently.",
        "Slider forces are affine in a and quadratic in v at each point; their extremes are "
        "in closed form (eigenvalues) and exact.",
        "Motor torques: the load part is exact when the motor drives (the usual case, flagged "
        "per point); with the ball-screw efficiency multiplying when back-driven, the larger "
        "of the two cases is taken. Friction is bounded by its value at the largest slider "
        "speed at the point: the torque is a safe-side bound.",
        "Guaranteed speed and acceleration in the worst direction follow from the same "
        "bounds (safe side); the torque available at a speed is the peak torque capped by "
        "the speed-torque curve.",
    ]


def _slices(corner: FloatArray, side: float, n: int) -> list[tuple[str, Grid]]:
    lo, hi = corner[:2].tolist(), (corner[:2] + side).tolist()
    return [
        (f"z = {name}", slice_grid("z", float(corner[2] + f * side), lo, hi, n))
        for f, name in SLICE_FRACTIONS
    ]


def _worst_motions(
    dyn: ClosedLoopDynamics, wc: WorstCase, gravity: FloatArray
) -> list[dict[str, Any]]:
    """The motion of the largest ``|F_i|`` of each slider, checked by a direct call."""
    where = wc.max_force_at
    forms = requirement_forms(dyn, where, gravity=gravity)
    vel, acc = forms.forces.worst_motion(wc.v_max, wc.a_max)
    rows = np.arange(3)
    v, a = vel[rows, rows], acc[rows, rows]
    direct = dyn.inverse_dynamics(where, v, a, gravity=gravity).forces[rows, rows]
    return [
        {
            "slider": i + 1,
            "point": where[i].tolist(),
            "velocity": v[i].tolist(),
            "acceleration": a[i].tolist(),
            "force": float(direct[i]),
        }
        for i in range(3)
    ]


def _gravity_line(g: FloatArray) -> str:
    if tuple(g.tolist()) == DEFAULT_GRAVITY:
        return GRAVITY_ASSUMPTION[0].upper() + GRAVITY_ASSUMPTION[1:] + "."
    return "Gravity (" + ", ".join(f"{x:g}" for x in g) + ") m/s^2 in the machine frame (given)."


def assemble_report(
    params: OrthoglideParams | None = None,
    drive: Drive | None = None,
    *,
    v_max: float = DEFAULT_V_MAX,
    a_max: float = DEFAULT_A_MAX,
    resolution: int = DEFAULT_RESOLUTION,
    cube_resolution: int = DEFAULT_CUBE_RESOLUTION,
    gravity: ArrayLike | None = None,
    progress: Progress | None = None,
    safety_factor: float = 1.0,
    cutting_force: float = DEFAULT_CUTTING_FORCE,
    program: Program | None = None,
    program_name: str = "program",
    min_frequency: float | None = None,
    cut: CutConditions | None = None,
    cut_name: str = "cut",
    spindle_speed: float | None = None,
) -> ReportData:
    """Compute every number of the report (see the module).

    Args:
        params: The machine (default: the prototype).
        drive: Drive train and optional motor data (default: the default drive
            train, no motor data).
        v_max: Tool speed [m/s] of the worst case and of the cycle.
        a_max: Tool acceleration [m/s^2] of the worst case and of the cycle.
        resolution: Points per axis of each map slice (2 to ``MAX_RESOLUTION``).
        cube_resolution: Points per edge of the cube grid (2 to ``MAX_CUBE_RESOLUTION``).
        gravity: Gravity [m/s^2], shape (3,) (default: the package's).
        progress: Makes a progress bar (see :func:`progress_bar`), or ``None``.
        safety_factor: Multiplies the required torques of the verdict (``>= 1``;
            see the module).
        cutting_force: Magnitude of the cutting force of the stiffness section [N],
            applied in the tool's softest direction.
        program: A part program planned with ``v_max``, ``a_max`` as slider limits (its rows
            join the verdict: :mod:`~orthoglide_pin.report.program`).
        program_name: Its name, for the page.
        min_frequency: The lowest natural frequency the machine must have over the cube
            [Hz] (a verdict row), or ``None``. The drive's inertia counts when ``drive`` is given.
        cut: Cutting conditions (:func:`~orthoglide_pin.machining.cutting.read_cut_file`)
            for the accuracy section, or ``None``.
        cut_name: The cut file's name, for the page.
        spindle_speed: The program's spindle speed [rad/s] (its ``S``), when the
            cut file says ``program``.

    Returns:
        The report's data.

    Raises:
        InvalidParameterError: Bad bounds, resolutions, gravity or safety factor.
        CutConditionsError: A program and a cut file but no spindle speed.
    """
    params = as_params(params)
    n = integer("resolution", resolution, 2, MAX_RESOLUTION)
    n_cube = integer("cube_resolution", cube_resolution, 2, MAX_CUBE_RESOLUTION)
    progress = optional_callable("progress", progress, "a progress-bar factory or None")
    k = safety_factor_value(safety_factor)
    limits = MotionLimits(v_max, a_max, CYCLE_JERK)  # validates the bounds
    if cut is not None:
        check_cut(cut, spindle_speed, program is not None)  # before any work
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    g = dyn.gravity_vector(gravity)
    vib = vibration_section(
        params, params.workspace.q1, params.workspace.side, drive, n_cube, min_frequency
    )
    drive = Drive() if drive is None else drive
    planned, finished = _plan_progress(progress)
    try:
        part = program_part(
            dyn, drive, program, program_name, limits.v_max, limits.a_max, g, k, planned
        )
    finally:
        finished()
    corner, side = params.workspace.q1, params.workspace.side  # the machine's own cube
    grids = [("cube", cube_grid(corner, side, n_cube)), *_slices(corner, side, n)]
    bar = None if progress is None else progress("worst case", sum(gr.size for _, gr in grids))
    step = None if bar is None else bar.update
    common: dict[str, Any] = {"v_max": limits.v_max, "a_max": limits.a_max, "drive": drive}
    maps = [worst_case_on_grid(dyn, gr, gravity=g, progress=step, **common) for _, gr in grids]
    if bar is not None:
        bar.close()
    cube = maps[0]
    slices = tuple(
        MapSlice(label, "z", float(gr.z[0]), wc)
        for (label, gr), wc in zip(grids[1:], maps[1:], strict=True)
    )
    cycle = standard_cycle(params, limits=limits)
    res = dyn.inverse_dynamics(cycle.p, cycle.v, cycle.a, gravity=g)
    sizing = size_drives(res, drive, cycle.t, safety_factor=k)
    assumptions = {
        "inertia": [*inertia_assumptions(params), _gravity_line(g)],
        "drive": drive.train.assumptions(),
        "method": method_assumptions(limits.v_max, limits.a_max),
    }
    return ReportData(
        params=params,
        drive=drive,
        motor_given=drive.motor is not None,
        v_max=limits.v_max,
        a_max=limits.a_max,
        jerk=CYCLE_JERK,
        gravity=g,
        corner=corner,
        side=side,
        assumptions=assumptions,
        cube=cube,
        worst_motions=_worst_motions(dyn, cube, g),
        slices=slices,
        cycle=cycle,
        cycle_dynamics=res,
        sizing=sizing,
        verdict=motor_rows(drive, cube, sizing, k)
        + tuple(VerdictRow(*r) for r in (*part[1], *vibration_rows(vib))),
        safety_factor=k,
        stiffness=stiffness_section(params, corner, side, cutting_force, n, n_cube),
        transmission=factor_range(params, grid_points=n_cube),
        program=part[0],
        vibration=vib,
        accuracy=None
        if cut is None
        else accuracy_section(
            params,
            cut,
            None if part[0] is None else part[0].plan,
            cut_name=cut_name,
            spindle_speed=spindle_speed,
            drive=drive,
        ),
    )


def _plan_progress(
    progress: Progress | None,
) -> tuple[Callable[[int, int], None] | None, Callable[[], None]]:
    """A ``(done, total)`` callback drawing a ``program`` bar of ``progress``, and its closer."""
    if progress is None:
        return None, lambda: None
    bars: list[Bar] = []
    done_before = [0]

    def update(done: int, total: int) -> None:
        if not bars:
            bars.append(progress("program", total))
        bars[0].update(max(0, done - done_before[0]))
        done_before[0] = max(done, done_before[0])

    def close() -> None:
        for bar in bars:
            bar.close()

    return update, close


def progress_bar(*, quiet: bool = False) -> Progress:
    """Progress bars (tqdm) on stderr, off with ``quiet`` or when stderr is not a terminal."""
    from tqdm import tqdm

    def make(description: str, total: int) -> Bar:
        return tqdm(
            total=total,
            desc=description,
            file=sys.stderr,
            disable=True if quiet else None,
            leave=False,
        )

    return make
