"""LinuxCNC command: ``linuxcnc --out DIR``, a LinuxCNC 2.9 configuration of the design.

``orthoglide linuxcnc --out DIR [--config F] [--motor DRIVE.yaml]
[--max-slider-speed V] [--max-slider-acceleration A] [--max-slider-jerk J]``
writes ``orthoglide_kins.comp``, ``orthoglide.ini``, ``orthoglide_sim.hal``,
``orthoglide_play.py``, ``tool.tbl`` and ``README.md`` atomically
(:mod:`orthoglide_pin.controller.configuration`). The sliders' speed is the
least of ``--max-slider-speed`` and the drive's motor speed through its screw
(``--motor``), else 1.2 m/s; their acceleration ``--max-slider-acceleration``,
else 20 m/s^2 (the prototype's sizing). The INI's Cartesian limits are
certified against them over the whole cube
(:func:`~orthoglide_pin.controller.limits.certify_limits`). ``--program
PROGRAM.nc`` adds the optimal route, its time-optimal plan under the sliders'
limits as a joint stream; ``orthoglide plan PROGRAM.nc --out DIR --linuxcnc
DIR2`` writes the stream of a plan made with every option of ``plan``
(motor, torque reserve, offsets, calibration).
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.plan import _limit


def _slider_speed(args: argparse.Namespace) -> float:
    from orthoglide_pin.controller.limits import DEFAULT_SLIDER_SPEED

    given = _limit("--max-slider-speed", args.max_slider_speed)
    speeds = [] if given is None else [given]
    if args.motor is not None:
        from orthoglide_pin.cli.dynamics import _drive
        from orthoglide_pin.planning.limits import PlanLimits

        drive = _drive(args.motor)
        motor = PlanLimits(drive=drive).motor_speed  # [rad/s]
        if motor is not None:
            train = drive.train
            speeds.append(motor * train.lead / (2.0 * math.pi * train.gear_ratio))
    return min(speeds) if speeds else DEFAULT_SLIDER_SPEED


def _stream(
    args: argparse.Namespace, params: Any, limits: Any, files: dict[str, str]
) -> list[str]:
    """Plan ``--program`` under the sliders' limits and add its stream to ``files``.

    The program is read as ``orthoglide plan`` reads it: in the design's
    program axes, the axes of the exported kinematics component.
    """
    from orthoglide_pin.controller.stream import STREAM_FILES, stream_files
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.program.axes import design_axes

    program = read_program(common.read_program_text(args.program), axes=design_axes(params))
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    plan_limits = PlanLimits(
        slider_speed=limits.joint_speed,
        slider_acceleration=limits.joint_acceleration,
        slider_jerk=limits.joint_jerk,
    )
    files.update(stream_files(plan_program(program, dyn, plan_limits), dyn))
    return list(STREAM_FILES)


def _cmd_linuxcnc(args: argparse.Namespace) -> int:
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.controller.configuration import FILES, configuration_files
    from orthoglide_pin.controller.limits import DEFAULT_SLIDER_ACCELERATION, certify_limits
    from orthoglide_pin.machine.digest import design_digest

    params = common.build_params(args)
    output_directory(args.out, force=args.force)  # before any work
    speed = _slider_speed(args)
    accel = _limit("--max-slider-acceleration", args.max_slider_acceleration)
    jerk = _limit("--max-slider-jerk", args.max_slider_jerk)
    limits = certify_limits(
        params, speed, DEFAULT_SLIDER_ACCELERATION if accel is None else accel, jerk
    )
    digest = design_digest(params)
    source = "" if args.config is None else " from its parameters file"
    files = configuration_files(params, limits, digest, source)
    names = list(FILES)
    if args.program is not None:
        names += _stream(args, params, limits, files)
    with atomic_directory(args.out, force=args.force) as tmp:
        for name in names:
            (tmp / name).write_text(files[name], encoding="utf-8")
    payload = {
        "directory": str(args.out),
        "files": names,
        "design": digest,
        "slider_speed": limits.joint_speed,
        "slider_acceleration": limits.joint_acceleration,
        "slider_jerk": limits.joint_jerk,
        "path_speed": limits.speed,
        "axis_acceleration": limits.acceleration,
        "speed_gain": limits.speed_gain,
        "acceleration_gain": limits.acceleration_gain,
        "curvature": limits.curvature,
    }
    text = "\n".join(
        [
            f"LinuxCNC configuration of design {digest}: sliders "
            f"{1e3 * limits.joint_speed:.6g} mm/s, {1e3 * limits.joint_acceleration:.6g} mm/s^2",
            f"  certified Cartesian limits: path speed {1e3 * limits.speed:.6g} mm/s, "
            f"axis acceleration {1e3 * limits.acceleration:.6g} mm/s^2",
            f"  over the cube: slider speed <= {limits.speed_gain:.6f} x path speed; slider "
            f"acceleration <= {limits.acceleration_gain:.6f} x axis acceleration + "
            f"{limits.curvature:.6f} /m x path speed^2",
            f"Written to {args.out}: " + ", ".join(names),
        ]
    )
    return common.emit(args, payload, text)


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``linuxcnc`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "linuxcnc",
        _cmd_linuxcnc,
        "a LinuxCNC 2.9 configuration of the design (kinematics component, INI with "
        "certified Cartesian limits, simulation HAL file)",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory, atomic")
    p.add_argument("--force", action="store_true", help="also write into a non-empty directory")
    p.add_argument("--motor", metavar="FILE.yaml", help="drive file: the motor's speed limit")
    p.add_argument("--max-slider-speed", metavar="V", help="[m/s] (default 1.2)")
    p.add_argument("--max-slider-acceleration", metavar="A", help="[m/s^2] (default 20)")
    p.add_argument(
        "--program",
        metavar="PROGRAM.nc",
        help="also write its time-optimal plan under the sliders' limits as a joint stream "
        "(plan.stream, orthoglide_stream.hal), read as orthoglide plan reads it (the "
        "design's program axes); orthoglide plan --linuxcnc DIR streams a plan with every "
        "option of plan",
    )
    p.add_argument(
        "--max-slider-jerk", metavar="J", help="[m/s^3], recorded (LinuxCNC 2.9 has no jerk limit)"
    )
