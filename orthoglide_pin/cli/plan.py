"""Plan command: ``plan PROGRAM.nc --out DIR``, the time-optimal feed of a part program.

``orthoglide plan PROGRAM.nc [--motor DRIVE.yaml] [--max-slider-speed V]
[--max-slider-acceleration A] [--max-slider-jerk J] --out DIR`` reads the program, plans it from
rest to rest between stops under every limit given, verifies the plan on a
grid 10 times finer, and writes ``DIR/trajectory.csv`` (sampled every
``--dt``), ``DIR/plan.json`` and ``DIR/plan.html`` atomically; ``--json``
prints the summary. ``orthoglide plan --example NAME`` prints a shipped
program. A bad program gets one line naming its line, status 2, nothing written.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.program import add_setup_options
from orthoglide_pin.exceptions import InvalidParameterError

DEFAULT_DT = 0.001


def _limit(name: str, value: str | None) -> float | None:
    from orthoglide_pin._validation import bounded_number
    from orthoglide_pin.planning.limits import LIMIT_CAPS, LIMIT_UNITS

    key = name[len("--max-") :].replace("-", "_")
    if value is None:
        return None
    return bounded_number(name, _float(value), LIMIT_CAPS[key], LIMIT_UNITS[key])


def _float(text: str) -> float | str:
    try:
        return float(text)
    except ValueError:
        return text


def _cmd_plan(args: argparse.Namespace) -> int:
    if args.example is not None:
        from orthoglide_pin.planning.shipped import example_program_text

        sys.stdout.write(example_program_text(args.example))
        return 0
    if args.program is None or args.out is None:
        raise InvalidParameterError("arguments", None, "PROGRAM.nc and --out DIR (or --example)")
    from orthoglide_pin._io import json_text
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.cli.dynamics import _drive, _optional
    from orthoglide_pin.cli.program import program_setup
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.digest import design_comment, design_digest
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.planning.sampling import csv_text, sample_plan, sampling_step
    from orthoglide_pin.program.axes import design_axes
    from orthoglide_pin.report.plan_page import limit_text, peaks_text, plan_html

    params = common.build_params(args)
    output_directory(args.out, force=args.force)  # before any work
    drive = None if args.motor is None else _drive(args.motor)
    calibration = None
    if args.calibration is not None:
        from orthoglide_pin.calibration.result import load_calibration

        calibration = load_calibration(args.calibration)
        calibration.check_design(params, args.calibration)  # made for this design
    limits = PlanLimits(
        slider_speed=_limit("--max-slider-speed", args.max_slider_speed),
        slider_acceleration=_limit("--max-slider-acceleration", args.max_slider_acceleration),
        slider_jerk=_limit("--max-slider-jerk", args.max_slider_jerk),
        drive=drive,
    )
    wrench = common.tool_wrench(args.wrench)
    gravity = _optional("--gravity", args.gravity, "m/s^2")
    dt = sampling_step("--dt", _float(args.dt))  # before the plan: its count after
    axes = design_axes(params)
    program = read_program(
        common.read_program_text(args.program),
        setup=program_setup(args, axes),
        axes=axes,
        interpreter=args.interpreter,
    )
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    plan = plan_program(
        program, dyn, limits, wrench=wrench, gravity=gravity, calibration=calibration
    )
    columns = sample_plan(plan, dyn, dt)
    payload = summary(plan)
    payload["calibration"] = args.calibration  # the sliders move the calibrated machine's tool
    payload["design"] = design_digest(params)  # the machine it belongs to
    common.check_finite(payload)
    name = os.path.basename(args.program)
    files = ["trajectory.csv", "plan.json", "plan.html"]
    with atomic_directory(args.out, force=args.force) as tmp:
        trajectory = design_comment(params) + csv_text(columns)
        (tmp / "trajectory.csv").write_text(trajectory, encoding="utf-8")
        (tmp / "plan.json").write_text(json_text(payload, indent=1) + "\n", encoding="utf-8")
        html = plan_html(plan, columns, name, files[:2])
        (tmp / "plan.html").write_text(html, encoding="utf-8")
    payload["directory"] = str(args.out)
    text = "\n".join(
        [
            f"Plan of {name}: cycle time {plan.cycle_time:.4f} s, {len(plan.blocks)} blocks, "
            f"{1e3 * plan.path.length:.1f} mm",
            *(
                f"  {row['name']:<20} {limit_text(plan, row['name']):<20} peak use "
                f"{row['peak_use']:.4f}, binds "
                f"{100 * payload['binding'].get(row['name'], 0.0):.1f} % of the time"
                for row in payload["limits"]
            ),
            f"  {peaks_text(columns)}",
            *(
                []
                if plan.jerk_time_cost is None
                else [
                    f"  jerk limit: {plan.jerk_time_cost['with_jerk']:.4f} s against "
                    f"{plan.jerk_time_cost['second_order']:.4f} s without it (second order), "
                    f"{int(plan.jerk_time_cost['curvature_stops'])} stops at curvature steps"
                ]
            ),
            *(
                []
                if calibration is None
                else [f"  sliders commanded through the calibration {args.calibration}"]
            ),
            *(
                [
                    "  words ignored (no effect on the path): "
                    + ", ".join(f"{i['word']} ({i['count']})" for i in payload["ignored"])
                ]
                if payload["ignored"]
                else []
            ),
            f"Written to {args.out}: " + ", ".join(files),
        ]
    )
    return common.emit(args, payload, text)


def summary(plan: Any) -> dict[str, Any]:
    """The JSON summary of a plan (keys of ``plan --json`` and ``plan.json``)."""
    lim = plan.limits
    values = {
        "slider_speed": lim.slider_speed,
        "slider_acceleration": lim.slider_acceleration,
        "motor_speed": lim.motor_speed,
        "motor_torque": lim.reference_torque() if lim.limits_torque else None,
        "slider_jerk": lim.slider_jerk,
    }
    return {
        "cycle_time": plan.cycle_time,
        "blocks": len(plan.blocks),
        "length": plan.path.length,
        "grid_points": plan.grid_points,
        "limits": [
            {"name": name, "value": values.get(name), "peak_use": use}
            for name, use in plan.worst.items()
        ],
        "binding": dict(plan.binding),
        "jerk_time_cost": None if plan.jerk_time_cost is None else dict(plan.jerk_time_cost),
        "ignored": [
            {"word": i.word, "count": i.count, "line": i.line} for i in plan.path.program.ignored
        ],
        "per_block": [
            {"line": b.line, "kind": b.kind, "start": b.start, "end": b.end} for b in plan.blocks
        ],
    }


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``plan`` command to the ``orthoglide`` parser."""
    from orthoglide_pin.planning.shipped import EXAMPLE_PROGRAMS

    p = common.add_command(
        sub,
        parent,
        "plan",
        _cmd_plan,
        "time-optimal feed of a part program (G-code) under the machine's limits: cycle time",
    )
    p.add_argument("program", nargs="?", metavar="PROGRAM.nc", help="the G-code program")
    p.add_argument(
        "--example", choices=tuple(EXAMPLE_PROGRAMS), help="print a shipped example program"
    )
    p.add_argument("--out", metavar="DIR", help="output directory, written atomically")
    p.add_argument("--force", action="store_true", help="also write into a non-empty directory")
    p.add_argument("--motor", metavar="FILE.yaml", help="drive file: torques and motor limits")
    p.add_argument("--max-slider-speed", metavar="V", help="[m/s]")
    p.add_argument("--max-slider-acceleration", metavar="A", help="[m/s^2]")
    p.add_argument(
        "--max-slider-jerk",
        metavar="J",
        help="[m/s^3]: the second-order plan re-timed by a moving average (and stops where "
        "the curvature steps); the JSON gives the time it costs",
    )
    p.add_argument(
        "--wrench", nargs="+", metavar=("FX", "FY", "FZ"), help="tool wrench [N] (default: none)"
    )
    p.add_argument("--gravity", nargs="+", metavar=("GX", "GY", "GZ"), help="[m/s^2]")
    add_setup_options(p)
    p.add_argument(
        "--dt", default=str(DEFAULT_DT), metavar="DT", help="sampling step [s], 1e-6 to 0.1"
    )
    p.add_argument(
        "--calibration",
        metavar="FILE.yaml",
        help="a calibration (orthoglide calibrate) made for this design: the sliders are "
        "commanded so that the real tool follows the program, and their limits are checked "
        "on those commands",
    )
