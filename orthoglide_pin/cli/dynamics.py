"""Dynamics commands: ``dynamics`` (one state) and ``report`` (the torque-requirement report).

``report`` ends with a status a script can use: 0 when the verdict is PASS or
there is no motor data (then it says how to give it), 1 when it is FAIL (the
report is written all the same), 2 on an error (nothing is written).
``--safety-factor K`` multiplies the required torques of the verdict by ``K``.
``--program PROGRAM.nc`` adds a part program planned at the report's limits
(:mod:`orthoglide_pin.report.program`) and its rows to the verdict.
``--min-frequency HZ`` adds the machine's lowest natural frequency over the
cube (:mod:`orthoglide_pin.report.vibration`) to the verdict.
"""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli._cut import accuracy_lines, add_cut_option, read_cut
from orthoglide_pin.cli.program import add_setup_options
from orthoglide_pin.elasticity.maps import DEFAULT_CUTTING_FORCE
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.cycle import CYCLE_A_MAX, CYCLE_V_MAX
from orthoglide_pin.report.units import quantity, shown

if TYPE_CHECKING:
    from orthoglide_pin.drives.motor import Drive
    from orthoglide_pin.machine.params import OrthoglideParams
    from orthoglide_pin.planning.gcode import Program
    from orthoglide_pin.report.assemble import ReportData, VerdictRow

#: Exit status of ``orthoglide report`` when the verdict is FAIL (the report is written).
EXIT_FAIL = 1
#: Default directory of ``orthoglide report``, in the current directory.
DEFAULT_REPORT_DIR = "orthoglide_report"
#: The report's default resolutions, as in :mod:`orthoglide_pin.report.assemble` (which
#: imports Pinocchio, so it is not imported to build the parser).
DEFAULT_RESOLUTION = 41
DEFAULT_CUBE_RESOLUTION = 21


def _vector(
    name: str, values: Sequence[str], unit: str, size: int | None = None
) -> np.ndarray[Any, Any]:
    """Three numbers ``X Y Z`` (or ``X,Y,Z``) of an option (:func:`common.numbers`)."""
    return common.numbers(name, values, f"X Y Z or X,Y,Z [{unit}]", size)


def _scalar(name: str, text: str, unit: str) -> float:
    """One finite number of an option [unit]: a list (``1,2``) is refused, not cut."""
    values = common.numbers(name, [text], f"[{unit}]")
    if values.size != 1:
        raise InvalidParameterError(name, text, f"one number [{unit}]")
    return float(values[0])


def _optional(name: str, values: Sequence[str] | None, unit: str) -> np.ndarray[Any, Any] | None:
    """As :func:`_vector`, or ``None`` when the option is absent."""
    return None if values is None else _vector(name, values, unit, 3)


def _drive(path: str | None) -> Drive:
    from orthoglide_pin.drives.motor import Drive, load_drive

    return Drive() if path is None else load_drive(path)


def _cmd_dynamics(args: argparse.Namespace) -> int:
    from orthoglide_pin.drives.motor import motor_demand
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    params = common.build_params(args)
    drive = _drive(args.motor)
    point = _vector("--point", args.point, "m", 3)
    zero = ["0", "0", "0"]
    velocity = _vector("--velocity", args.velocity or zero, "m/s", 3)
    acceleration = _vector("--acceleration", args.acceleration or zero, "m/s^2", 3)
    wrench = _optional("--wrench", args.wrench, "N")
    gravity = _optional("--gravity", args.gravity, "m/s^2")
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    res = dyn.inverse_dynamics(point, velocity, acceleration, wrench=wrench, gravity=gravity)
    demand = motor_demand(res.forces, res.slider_velocities, res.slider_accelerations, drive.train)
    payload = {
        "forces": res.forces[0].tolist(),
        "motor_torques": demand.torque[0].tolist(),
        "motor_speeds_rpm": demand.speed_rpm[0].tolist(),
    }
    g = dyn.gravity_vector(gravity)
    text = "\n".join(
        [
            f"Inverse dynamics at p = {common.fmt(point)} m, v = {common.fmt(velocity)} m/s, "
            f"a = {common.fmt(acceleration)} m/s^2",
            f"  gravity {common.fmt(g)} m/s^2, wrench on the tool "
            + ("none" if wrench is None else f"{common.fmt(wrench)} N"),
            f"  slider forces     {common.fmt(res.forces[0], spec='.6g')} N",
            f"  slider speeds     "
            f"{common.fmt(shown('speed', res.slider_velocities[0]), spec='.6g')} mm/s",
            f"  motor torques     {common.fmt(demand.torque[0], spec='.6g')} N.m",
            f"  motor speeds      {common.fmt(demand.speed_rpm[0], spec='.6g')} rpm",
        ]
    )
    return common.emit(args, payload, text)


def _stiffness_lines(data: ReportData) -> list[str]:
    """The stiffness section in two lines of text."""
    from orthoglide_pin.report.stiffness import stiffness_dict

    if data.stiffness is None:
        return []
    s = stiffness_dict(data.stiffness)
    return [
        f"Stiffness over the cube: at least {s['min_stiffness'] / 1e6:.4g} N/um at "
        f"{common.fmt(s['worst_point'])} m; up to {s['max_deflection'] * 1e6:.4g} um under "
        f"{s['cutting_force']:g} N",
        f"  (E = {data.params.youngs_modulus / 1e9:.4g} GPa, "
        f"k_a = {data.params.actuator_stiffness / 1e6:.4g} N/um, ideal revolutes)",
    ]


def _vibration_lines(data: ReportData) -> list[str]:
    """The vibration section in two lines of text."""
    from orthoglide_pin.report.vibration import vibration_dict

    if data.vibration is None:
        return []
    v = vibration_dict(data.vibration)
    full, diff = v["check"]["frequencies"][0], v["check"]["difference"][0]
    return [
        f"Lowest natural frequency over the cube: {v['lowest_frequency']:.4g} Hz at "
        f"{common.fmt(v['worst_point'])} m (platform model; full model there {full:.4g} Hz, "
        f"difference {100 * diff:+.1f} %)",
        f"  ({v['drive']})",
    ]


def _row_dict(row: VerdictRow) -> dict[str, Any]:
    """One criterion of the verdict, strict JSON (an infinite margin is ``None``)."""
    margin = row.margin if row.margin is not None and math.isfinite(row.margin) else None
    return {
        "motor": row.motor,
        "criterion": row.criterion,
        "required": row.required,
        "available": row.available,
        "unit": row.unit,
        "margin": margin,
    }


def _row_text(row: VerdictRow) -> str:
    """``motor 2, worst case: speed vs maximum speed: required ..., margin -17.8 %``."""
    unit = row.unit
    available = "no motor datum" if row.available is None else f"{row.available:.4g} {unit}"
    margin = "none" if row.margin is None else f"{100 * row.margin:+.1f} %"
    who = "machine" if row.motor is None else f"motor {row.motor}"
    return (
        f"{who}, {row.criterion}: required {row.required:.4g} {unit}, "
        f"available {available}, margin {margin}"
    )


def _verdict_rows(data: ReportData) -> tuple[list[VerdictRow], VerdictRow | None]:
    """The failing criteria, and the one of least margin (``None`` without motor data)."""
    rows = [r for r in data.verdict if r.margin is not None]
    least = min(rows, key=lambda r: r.margin if r.margin is not None else 0.0, default=None)
    return [r for r in rows if r.passed is False], least


def _transmission_line(data: ReportData, criterion: str) -> list[str]:
    """The factors over the cube and the criterion's verdict (the prototype's note too)."""
    from orthoglide_pin.kinetostatics.design import prototype_note

    fr, note = data.transmission, prototype_note(data.params)
    if fr is None:
        return []
    return [
        f"Transmission factors {fr.describe()}; criterion {criterion}: {fr.verdict} "
        "(not part of the motors' verdict)",
        *([] if note is None else [f"  note: {note}"]),
    ]


def _program(args: argparse.Namespace, params: OrthoglideParams) -> Program:
    from orthoglide_pin.cli.program import program_setup
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.program.axes import design_axes

    axes = design_axes(params)
    return read_program(
        common.read_program_text(args.program),
        setup=program_setup(args, axes),
        axes=axes,
        interpreter=args.interpreter,
    )


def _program_lines(data: ReportData) -> list[str]:
    sec = data.program
    if sec is None:
        return []
    return [
        f"Program {sec.name}: cycle time {sec.cycle_time:.4f} s with the sliders within "
        f"{quantity('speed', sec.slider_speed)} and "
        f"{quantity('acceleration', sec.slider_acceleration)} (motors judged, "
        "not limiting)",
        f"  peak |T|  {common.fmt(sec.statistics.peak_torque, spec='.3f')} N.m, "
        f"RMS {common.fmt(sec.statistics.rms_torque, spec='.3f')} N.m, "
        f"peak speed {common.fmt(sec.statistics.peak_speed_rpm, spec='.0f')} rpm",
    ]


def _cmd_report(args: argparse.Namespace) -> int:
    from orthoglide_pin.report.accuracy import accuracy_dict
    from orthoglide_pin.report.assemble import NO_MOTOR_HINT, assemble_report, progress_bar
    from orthoglide_pin.report.files import check_report_directory, write_report
    from orthoglide_pin.report.stiffness import stiffness_dict
    from orthoglide_pin.report.vibration import vibration_dict

    params = common.with_criterion(args, common.with_cube(args, common.build_params(args)))
    drive = None if args.motor is None else _drive(args.motor)
    v_max = _scalar("--v-max", args.v_max, "m/s")
    a_max = _scalar("--a-max", args.a_max, "m/s^2")
    gravity = _optional("--gravity", args.gravity, "m/s^2")
    floor = None
    if args.min_frequency is not None:
        floor = _scalar("--min-frequency", args.min_frequency, "Hz")
    safety = _scalar("--safety-factor", args.safety_factor, "-")
    cutting = _scalar("--cutting-force", args.cutting_force, "N")
    program = None if args.program is None else _program(args, params)
    cut, cut_name, spindle_speed = read_cut(args)
    bar = progress_bar(quiet=args.quiet or args.json)
    check_report_directory(args.out, force=args.force)  # before minutes of work
    data = assemble_report(
        params,
        drive,
        v_max=v_max,
        a_max=a_max,
        resolution=args.resolution,
        cube_resolution=args.cube_resolution,
        gravity=gravity,
        progress=bar,
        safety_factor=safety,
        cutting_force=cutting,
        program=program,
        program_name="program" if args.program is None else os.path.basename(args.program),
        min_frequency=floor,
        cut=cut,
        cut_name=cut_name,
        spindle_speed=spindle_speed,
    )
    files = write_report(args.out, data, progress=bar, force=args.force)
    wc = data.cube
    criterion, criterion_text = common.criterion_info(args, params)
    failing, least = _verdict_rows(data)
    payload = {
        "report": str(files.html),
        "directory": str(files.directory),
        "json": str(files.json),
        "csv": {name: str(path) for name, path in files.csv.items()},
        "passed": files.passed,
        "note": None if data.motor_given else NO_MOTOR_HINT,
        "safety_factor": data.safety_factor,
        "stiffness": None if data.stiffness is None else stiffness_dict(data.stiffness),
        "vibration": None if data.vibration is None else vibration_dict(data.vibration),
        "accuracy": None if data.accuracy is None else accuracy_dict(data.accuracy),
        "max_force": wc.max_force.tolist(),
        "max_force_at": wc.max_force_at.tolist(),
        "max_torque": wc.max_torque.tolist(),
        "max_torque_at": wc.max_torque_at.tolist(),
        "cube": params.workspace.to_dict(),
        "criterion": criterion,
        "transmission": None if data.transmission is None else data.transmission.to_dict(),
        "failing": [_row_dict(r) for r in failing],
        "least_margin": None if least is None else _row_dict(least),
    }
    if files.passed is False:
        verdict_lines = ["  failing criteria:", *(f"    {_row_text(r)}" for r in failing)]
    elif files.passed and least is not None:
        verdict_lines = [f"  least margin: {_row_text(least)}"]
    else:
        verdict_lines = []
    verdict = {None: "no motor data: no verdict on limits", True: "PASS", False: "FAIL"}
    text = "\n".join(
        [
            f"Workspace: {params.workspace.describe()}",
            f"Worst case over the cube at {quantity('speed', data.v_max)} and "
            f"{quantity('acceleration', data.a_max)}, "
            "every direction:",
            f"  max |F|  {common.fmt(wc.max_force, spec='.1f')} N",
            f"  max |T|  {common.fmt(wc.max_torque, spec='.3f')} N.m",
            f"Verdict: {verdict[files.passed]}"
            + (
                f" (required torques x {data.safety_factor:g}, the safety factor)"
                if data.safety_factor != 1.0 and data.motor_given
                else ""
            ),
            *verdict_lines,
            *([] if data.motor_given else [f"  {NO_MOTOR_HINT}"]),
            *_transmission_line(data, criterion_text),
            *_stiffness_lines(data),
            *_vibration_lines(data),
            *_program_lines(data),
            *accuracy_lines(data),
            f"Report written to {files.html}",
        ]
    )
    code = common.emit(args, payload, text)
    return EXIT_FAIL if code == 0 and files.passed is False else code


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``dynamics`` and ``report`` commands to the ``orthoglide`` parser."""
    motor_help = (
        "drive file (YAML: drive_train and motor sections; `orthoglide drive --example` "
        "prints one; default: the default drive train, no motor data)"
    )
    gravity_help = "gravity [m/s^2] in the machine frame (default: 0 0 9.81, e3 down)"
    p = common.add_command(
        sub,
        parent,
        "dynamics",
        _cmd_dynamics,
        "slider forces, motor torques and speeds for one tool state (inverse dynamics)",
    )
    p.add_argument("--point", nargs="+", required=True, metavar=("X", "Y", "Z"), help="[m]")
    p.add_argument("--velocity", nargs="+", metavar=("VX", "VY", "VZ"), help="[m/s] (default: 0)")
    p.add_argument(
        "--acceleration", nargs="+", metavar=("AX", "AY", "AZ"), help="[m/s^2] (default: 0)"
    )
    p.add_argument(
        "--wrench",
        nargs="+",
        metavar=("FX", "FY", "FZ"),
        help="force of the environment on the tool [N] (default: none)",
    )
    p.add_argument("--gravity", nargs="+", metavar=("GX", "GY", "GZ"), help=gravity_help)
    p.add_argument("--motor", metavar="FILE.yaml", help=motor_help)
    p = common.add_command(
        sub,
        parent,
        "report",
        _cmd_report,
        "torque-requirement report: worst case over the cube, standard cycle, verdict",
    )
    p.add_argument("--motor", metavar="FILE.yaml", help=motor_help)
    common.add_cube_options(p)
    common.add_psi_option(p)
    p.add_argument(
        "--out",
        default=DEFAULT_REPORT_DIR,
        metavar="DIR",
        help="report directory, written atomically; an existing directory must be empty "
        f"or hold an earlier report (default: ./{DEFAULT_REPORT_DIR})",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="also write into a non-empty directory that holds no report: the report's "
        "files are added or replaced, every other file is kept",
    )
    p.add_argument(
        "--v-max",
        default=str(CYCLE_V_MAX),
        metavar="V",
        help=f"tool speed [m/s] (default {CYCLE_V_MAX:g})",
    )
    p.add_argument(
        "--a-max",
        default=str(CYCLE_A_MAX),
        metavar="A",
        help=f"tool acceleration [m/s^2] (default {CYCLE_A_MAX:g})",
    )
    p.add_argument(
        "--resolution",
        type=int,
        default=DEFAULT_RESOLUTION,
        metavar="N",
        help=f"N x N points per map slice (default {DEFAULT_RESOLUTION})",
    )
    p.add_argument(
        "--cube-resolution",
        type=int,
        default=DEFAULT_CUBE_RESOLUTION,
        metavar="N",
        help=f"N^3 points of the cube grid for the maxima (default {DEFAULT_CUBE_RESOLUTION})",
    )
    p.add_argument("--gravity", nargs="+", metavar=("GX", "GY", "GZ"), help=gravity_help)
    p.add_argument(
        "--safety-factor",
        default="1",
        metavar="K",
        help="multiply every required motor torque of the verdict by K >= 1 before it is "
        "compared with the motor (speeds are not multiplied; default 1)",
    )
    p.add_argument(
        "--cutting-force",
        default=str(DEFAULT_CUTTING_FORCE),
        metavar="F",
        help="cutting force [N] of the stiffness section, applied in the tool's softest "
        f"direction (default {DEFAULT_CUTTING_FORCE:g})",
    )
    p.add_argument(
        "--program",
        metavar="PROGRAM.nc",
        help="a part program (G-code) planned with the sliders within --v-max and --a-max: "
        "its motor torques and speeds join the verdict (needs the [plan] extra)",
    )
    add_setup_options(p)
    add_cut_option(
        p,
        "an accuracy section (with --program: surface error, error budget, "
        "stability margin of every block; without: lobes at home, Q1, Q2)",
    )
    p.add_argument(
        "--min-frequency",
        metavar="HZ",
        help="lowest natural frequency [Hz] the machine must have over the cube (platform "
        "model, checked by the full model at the worst point): a verdict row, PASS or FAIL "
        "with its margin (default: none; the frequencies are reported all the same)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.epilog = (
        "Exit status: 0 when the verdict is PASS or without motor data, 1 when it is "
        "FAIL (the report is written all the same; the terminal lists each failing "
        "criterion), 2 on an error (nothing written). "
        "Without --motor there is no verdict: `orthoglide drive --example > drive.yaml` "
        "writes an example drive file to edit."
    )
