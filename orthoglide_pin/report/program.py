"""A part program in the torque-requirement report: what it needs of the motors.

:func:`program_section` plans a program (:func:`~orthoglide_pin.planning.plan.plan_program`)
with the report's figures as the **slider** limits: ``v_max`` bounds every
slider's speed [m/s] and ``a_max`` every slider's acceleration [m/s^2]; the
program's own feeds (``F``) cap the tool's path speed. The drive train of the
report computes the motor torques and speeds along the plan, but the motor's
data do **not** limit it: the plan is what the program asks at these slider
limits, and the verdict says whether the motor delivers it (with the motor as a
limit, ``orthoglide plan --motor`` gives the cycle time it allows instead).

The motor demand is taken on two samplings of the plan: every :data:`PROGRAM_DT`
in time (the RMS torque, a time average) and the plan's verification grid, ten
times finer than its planning grid (the peaks, which may fall between time
samples); the peaks and the speed-torque check are over both. The verdict
rows (:func:`program_rows`) are those of the standard cycle, for the program:
RMS torque against the rated torque, peak torque against the peak torque,
peak speed against the maximum speed and every sample against the speed-torque
curve, the torques multiplied by the report's safety factor.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of, text
from orthoglide_pin.drives.motor import Drive, MotorDemand, motor_demand
from orthoglide_pin.drives.sizing import CycleStatistics, MotorCheck, check_motor, cycle_statistics
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.planning.gcode import Program

if TYPE_CHECKING:
    from orthoglide_pin.planning.plan import Plan

FloatArray = NDArray[np.float64]

#: Time step of the program's samples [s] (the RMS torque).
PROGRAM_DT: Final[float] = 1e-3
#: Most time samples taken (longer programs are sampled more coarsely).
MAX_PROGRAM_SAMPLES: Final[int] = 200_000
#: The verdict rows of a program: criterion, key of the motor check, unit.
PROGRAM_CRITERIA: Final = (
    ("program: RMS torque vs rated torque", "rms_torque", "N.m"),
    ("program: peak torque vs peak torque", "peak_torque", "N.m"),
    ("program: peak speed vs maximum speed", "speed", "rpm"),
    ("program: torque vs speed-torque curve", "speed_torque_curve", "N.m"),
)


#: A verdict row: motor, criterion, required, available, unit, margin
#: (:class:`~orthoglide_pin.report.assemble.VerdictRow`'s fields, in order).
Row = tuple[int, str, float, float | None, str, float | None]


@dataclass(frozen=True)
class ProgramSection:
    """A program planned at the report's slider limits, and its motor demand.

    Attributes:
        name: The program's name (its file name).
        slider_speed: The slider speed limit of the plan [m/s] (the report's ``v_max``).
        slider_acceleration: The slider acceleration limit [m/s^2] (the report's ``a_max``).
        cycle_time: The program's duration [s].
        length: The tool path's length [m].
        blocks: Blocks of the program.
        binding: The share of the cycle time each limit binds [-].
        worst: The largest use of each limit of the plan [-].
        columns: The plan sampled in time (``trajectory.csv``'s columns, SI units).
        peak_force: Largest ``|F_i|`` of each slider [N], (3,).
        peak_slider_speed: Largest ``|q'_i|`` [m/s], (3,).
        statistics: Peak and RMS torque, peak speed and power of each motor.
        check: The motor check (margins, torques times the safety factor), or ``None``.
        curve: Each motor's sample nearest its speed-torque curve, ``(required,
            available)`` torques [N.m], each (3,)
            (:func:`~orthoglide_pin.report.verdict.curve_point`), or ``None``.
        plan: The plan itself (the accuracy section's), or ``None``.
    """

    name: str
    slider_speed: float
    slider_acceleration: float
    cycle_time: float
    length: float
    blocks: int
    binding: dict[str, float]
    worst: dict[str, float]
    columns: dict[str, FloatArray]
    peak_force: FloatArray
    peak_slider_speed: FloatArray
    statistics: CycleStatistics
    check: MotorCheck | None
    curve: tuple[FloatArray, FloatArray] | None = None
    plan: Plan | None = None


def _joined(a: MotorDemand, b: MotorDemand) -> MotorDemand:
    """Two demands as one (their samples one after the other)."""
    names = ("torque", "speed", "speed_rpm", "acceleration", "power", "load_torque")
    return MotorDemand(**{n: np.concatenate([getattr(a, n), getattr(b, n)]) for n in names})


def program_section(
    dyn: ClosedLoopDynamics,
    drive: Drive,
    program: Program,
    *,
    v_max: float,
    a_max: float,
    gravity: FloatArray,
    safety_factor: float = 1.0,
    name: str = "program",
    progress: Callable[[int, int], None] | None = None,
) -> ProgramSection:
    """Plan ``program`` at the slider limits ``v_max``, ``a_max`` and size the motors on it.

    Args:
        dyn: The closed-loop dynamics of the machine.
        drive: The report's drive (its train computes the torques; its motor is judged).
        program: The program (:func:`~orthoglide_pin.planning.gcode.read_program`).
        v_max: Slider speed limit [m/s].
        a_max: Slider acceleration limit [m/s^2].
        gravity: Gravity [m/s^2], (3,).
        safety_factor: Multiplies the required torques of the motor check (``>= 1``).
        name: The program's name, for the page.
        progress: Called with (blocks planned, blocks) as the plan is made, or ``None``.

    Raises:
        ProgramError: A point of the program outside the cube or the slider limits.
        MissingExtraError: toppra is not installed (``[plan]``).
    """
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.planning.sampling import MAX_DT, sample_plan
    from orthoglide_pin.report.verdict import curve_point

    limits = PlanLimits(
        slider_speed=v_max, slider_acceleration=a_max, drive=Drive(train=drive.train)
    )
    plan = plan_program(program, dyn, limits, gravity=gravity, progress=progress)
    dt = min(max(PROGRAM_DT, plan.cycle_time / MAX_PROGRAM_SAMPLES), MAX_DT)
    cols = sample_plan(plan, dyn, dt)
    timed = [np.column_stack([cols[f"{c}{i}"] for i in (1, 2, 3)]) for c in ("F", "qd", "qdd")]
    motions = [r.motion for r in plan.sections if r.motion is not None]
    fine = [
        np.concatenate([getattr(m, n) for m in motions] or [np.zeros((0, 3))])
        for n in ("forces", "qd", "qdd")
    ]
    demand = motor_demand(timed[0], timed[1], timed[2], drive.train)
    stats = cycle_statistics(demand, cols["t"]) if cols["t"].size > 1 else None
    both = _joined(demand, motor_demand(fine[0], fine[1], fine[2], drive.train))
    peaks = cycle_statistics(both)
    statistics = CycleStatistics(
        peak_torque=peaks.peak_torque,
        rms_torque=np.zeros(3) if stats is None else stats.rms_torque,
        peak_speed_rpm=peaks.peak_speed_rpm,
        peak_power=peaks.peak_power,
    )
    check = (
        None
        if drive.motor is None
        else check_motor(drive.motor, statistics, both, safety_factor=safety_factor)
    )
    forces, speeds = np.concatenate([timed[0], fine[0]]), np.concatenate([timed[1], fine[1]])
    return ProgramSection(
        name=name,
        slider_speed=v_max,
        slider_acceleration=a_max,
        cycle_time=plan.cycle_time,
        length=plan.path.length,
        blocks=len(plan.blocks),
        binding=dict(plan.binding),
        worst=dict(plan.worst),
        columns=cols,
        peak_force=np.abs(forces).max(axis=0),
        peak_slider_speed=np.abs(speeds).max(axis=0),
        statistics=statistics,
        check=check,
        curve=None if drive.motor is None else curve_point(drive.motor, both, safety_factor),
        plan=plan,
    )


def program_rows(
    section: ProgramSection, drive: Drive, safety_factor: float = 1.0
) -> tuple[Row, ...]:
    """The verdict rows of the program, per motor (see the module), as :class:`Row`."""
    motor, stats, k = drive.motor, section.statistics, safety_factor
    margins = {} if section.check is None else section.check.margins
    curve = section.curve
    available = {
        "rms_torque": None if motor is None else motor.rated_torque,
        "peak_torque": None if motor is None else motor.peak_torque,
        "speed": None if motor is None else motor.max_speed,
    }
    required = {
        "rms_torque": k * stats.rms_torque,
        "peak_torque": k * stats.peak_torque,
        "speed": stats.peak_speed_rpm,
        "speed_torque_curve": k * stats.peak_torque if curve is None else curve[0],
    }
    rows: list[Row] = []
    for i in range(3):
        for criterion, key, unit in PROGRAM_CRITERIA:
            if key == "speed_torque_curve" and key not in margins:
                continue
            margin = float(margins[key][i]) if key in margins else None
            given = (
                available.get(key)
                if key != "speed_torque_curve" or curve is None
                else float(curve[1][i])
            )
            rows.append((i + 1, criterion, float(required[key][i]), given, unit, margin))
    return tuple(rows)


def program_part(
    dyn: ClosedLoopDynamics,
    drive: Drive,
    program: Program | None,
    name: str,
    v_max: float,
    a_max: float,
    gravity: FloatArray,
    safety_factor: float,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[ProgramSection | None, tuple[Row, ...]]:
    """The program's section of the report and its verdict rows (``None, ()`` without one).

    ``progress`` is called with (blocks planned, blocks), or ``None``.
    """
    if program is None:
        return None, ()
    program = instance_of("program", program, Program, "a Program (read_program) or None")
    name = text("program_name", name)
    section = program_section(
        dyn,
        drive,
        program,
        v_max=v_max,
        a_max=a_max,
        gravity=gravity,
        safety_factor=safety_factor,
        name=name,
        progress=progress,
    )
    return section, program_rows(section, drive, safety_factor)


def program_dict(section: ProgramSection) -> dict[str, Any]:
    """The program's figures, JSON-ready (SI units, motor speeds in rpm)."""
    s = section.statistics
    return {
        "name": section.name,
        "limits": {
            "slider_speed": section.slider_speed,
            "slider_acceleration": section.slider_acceleration,
            "motor": "not a limit: judged by the verdict",
        },
        "cycle_time": section.cycle_time,
        "length": section.length,
        "blocks": section.blocks,
        "binding": section.binding,
        "peak_use": section.worst,
        "samples": int(section.columns["t"].size),
        "peak_force": section.peak_force.tolist(),
        "peak_slider_speed": section.peak_slider_speed.tolist(),
        "peak_torque": s.peak_torque.tolist(),
        "rms_torque": s.rms_torque.tolist(),
        "peak_speed_rpm": s.peak_speed_rpm.tolist(),
        "peak_power": s.peak_power.tolist(),
        "check": None if section.check is None else section.check.to_dict(),
    }


def program_html(section: ProgramSection) -> str:
    """The program's section of the report page: its limits, cycle time and motor figures."""
    import html

    from orthoglide_pin.report.units import quantity, shown

    s = section.statistics
    head = (
        f"<p>{html.escape(section.name)}: {section.blocks} blocks, "
        f"{1e3 * section.length:.1f} mm of path, cycle time <b>{section.cycle_time:.4f} s</b>, "
        "planned time-optimally with every slider within "
        f"{quantity('speed', section.slider_speed)} and "
        f"{quantity('acceleration', section.slider_acceleration)} and the program's feeds; "
        "the motors are not a "
        "limit of the plan, the verdict judges them on it.</p>"
    )
    rows = [
        ("peak slider force [N]", section.peak_force, ".1f"),
        ("peak slider speed [mm/s]", shown("speed", section.peak_slider_speed), ".1f"),
        ("peak motor torque [N.m]", s.peak_torque, ".3f"),
        ("RMS motor torque [N.m]", s.rms_torque, ".3f"),
        ("peak motor speed [rpm]", s.peak_speed_rpm, ".0f"),
        ("peak motor power [W]", s.peak_power, ".0f"),
    ]
    body = "".join(
        f"<tr><td>{label}</td>" + "".join(f"<td>{x:{spec}}</td>" for x in values) + "</tr>"
        for label, values, spec in rows
    )
    binding = ", ".join(
        f"{name} {100 * share:.1f} %" for name, share in section.binding.items() if share > 0
    )
    return (
        head
        + "<table><tr><th></th><th>motor 1</th><th>motor 2</th><th>motor 3</th></tr>"
        + body
        + "</table>"
        + f'<p class="note">Share of the cycle time each limit binds: {binding or "none"}.</p>'
    )
