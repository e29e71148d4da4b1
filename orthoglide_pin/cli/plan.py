"""Plan command: ``plan PROGRAM.nc --out DIR``, the time-optimal feed of a part program.

``orthoglide plan PROGRAM.nc [--motor DRIVE.yaml] [--torque-reserve R] [--max-slider-speed V]
[--max-slider-acceleration A] [--max-slider-jerk J] --out DIR`` reads the program, plans it from
rest to rest between stops under every limit given, verifies the plan on a
grid 10 times finer, and writes ``DIR/trajectory.csv`` (sampled every
``--dt``, or a step that follows the program; ``trajectory.parquet`` with
``--trajectory-format parquet``), ``DIR/plan.json`` and ``DIR/plan.html``
atomically; ``--json`` prints the summary. ``--feed-override``,
``--rapid-override`` and ``--blend`` are the controller's settings
(:mod:`~orthoglide_pin.planning.controller`); a progress bar shows the
blocks planned on a terminal. ``--linuxcnc DIR2`` also writes, atomically, the
plan as the joint stream LinuxCNC's HAL plays at the servo rate
(``plan.stream``, ``orthoglide_stream.hal``,
:mod:`orthoglide_pin.controller.stream`): the optimal route of ``orthoglide
linuxcnc``. ``orthoglide plan --example NAME`` prints a shipped program. A bad
program gets one line naming its line, status 2, nothing written.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from typing import Any

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.program import add_setup_options
from orthoglide_pin.exceptions import InvalidParameterError

#: Most samples written with a ``--dt`` given (about 15 GB of CSV) [-].
MAX_WRITTEN_SAMPLES = 100_000_000


def _limit(name: str, value: str | None) -> float | None:
    from orthoglide_pin._validation import bounded_number
    from orthoglide_pin.planning.limits import LIMIT_CAPS, LIMIT_UNITS

    key = name[len("--max-") :].replace("-", "_")
    if value is None:
        return None
    return bounded_number(name, _float(value), LIMIT_CAPS[key], LIMIT_UNITS[key])


def _fraction(name: str, text: str, top: float) -> float:
    from orthoglide_pin.planning.controller import check_override

    return check_override(name, _float(text), top)  # type: ignore[arg-type]


def _blend(text: str) -> float:
    from orthoglide_pin.planning.controller import MAX_BLEND

    value = _float(text)
    if not isinstance(value, float) or not 0.0 <= value <= 1e3 * MAX_BLEND:
        raise InvalidParameterError("--blend", text, f"a tolerance in [0, {1e3 * MAX_BLEND:g}] mm")
    return value * 1e-3


def _dt(text: str) -> float:
    from orthoglide_pin.planning.sampling import sampling_step

    return sampling_step("--dt", _float(text))  # before the plan: its count after


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
    from orthoglide_pin.cli.dynamics import _optional
    from orthoglide_pin.cli.program import program_setup
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.digest import design_comment, design_digest
    from orthoglide_pin.motion.cycle import CYCLE_A_MAX, CYCLE_V_MAX
    from orthoglide_pin.planning.controller import (
        FEED_OVERRIDE_RANGE,
        RAPID_OVERRIDE_RANGE,
        default_mode_text,
        stop_reasons,
    )
    from orthoglide_pin.planning.gcode import DEFAULT_TOLERANCE, read_program
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.planning.sampling import auto_dt, sample_chunks, sample_count
    from orthoglide_pin.planning.trajectory_file import write_trajectory
    from orthoglide_pin.program.axes import design_axes
    from orthoglide_pin.report.plan_page import limit_text, peaks_text, plan_html
    from orthoglide_pin.report.units import quantity

    params = common.build_params(args)
    output_directory(args.out, force=args.force)  # before any work
    if args.trajectory_format == "parquet":
        from orthoglide_pin._lazy import optional_import

        optional_import("pyarrow", "tables", "a Parquet trajectory")
    if args.linuxcnc is not None:
        _check_stream_directory(args)
    limits, calibration = plan_limits(args, params)
    wrench = common.tool_wrench(args.wrench)
    gravity = _optional("--gravity", args.gravity, "m/s^2")
    dt = None if args.dt is None else _dt(args.dt)
    axes = design_axes(params)
    program = read_program(
        common.read_program_text(args.program),
        setup=program_setup(args, axes),
        axes=axes,
        interpreter=args.interpreter,
    )
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    feed_override = _fraction("--feed-override", args.feed_override, FEED_OVERRIDE_RANGE[1])
    rapid_override = _fraction("--rapid-override", args.rapid_override, RAPID_OVERRIDE_RANGE[1])
    blend = None if args.blend is None else _blend(args.blend)
    with common.progress_bar(args, "planning", "blocks") as progress:
        plan = plan_program(
            program, dyn, limits, wrench=wrench, gravity=gravity, calibration=calibration,
            feed_override=feed_override, rapid_override=rapid_override, blend=blend,
            progress=progress,
        )  # fmt: skip
    step = auto_dt(plan.cycle_time) if dt is None else dt
    total = sample_count(plan, step)
    if total > MAX_WRITTEN_SAMPLES:  # only a step the user gave can ask for that many
        raise InvalidParameterError(
            "--dt", dt, f"a step giving at most {MAX_WRITTEN_SAMPLES} samples over "
            f"{plan.cycle_time:.6g} s (or no --dt: the step follows the program)",
        )  # fmt: skip
    payload = summary(plan)
    stops = stop_reasons(plan.path)
    payload["controller"] = {
        "feed_override": feed_override,
        "rapid_override": rapid_override,
        "default_mode": "G64",
        "blend": DEFAULT_TOLERANCE if blend is None else blend,
        "mode_line": program.mode_line,
    }
    payload["stops"] = {"total": sum(stops.values()), **stops}
    payload["calibration"] = args.calibration  # the sliders move the calibrated machine's tool
    payload["design"] = design_digest(params)  # the machine it belongs to
    common.check_finite(payload)
    name = os.path.basename(args.program)
    files = [f"trajectory.{args.trajectory_format}", "plan.json", "plan.html"]
    stream = {} if args.linuxcnc is None else _stream_files(plan, dyn)
    with contextlib.ExitStack() as stack:  # an error before the end writes neither
        if stream:
            streamed = stack.enter_context(atomic_directory(args.linuxcnc, force=args.force))
            for stream_name, stream_text in stream.items():
                (streamed / stream_name).write_text(stream_text, encoding="utf-8")
        tmp = stack.enter_context(atomic_directory(args.out, force=args.force))
        written = write_trajectory(
            tmp / files[0],
            sample_chunks(plan, dyn, step),
            total,
            first_line=design_comment(params),
            file_format=args.trajectory_format,
        )
        columns = written.plot  # every peak of the file, at most a few thousand rows
        payload["dt"], payload["samples"] = step, written.samples
        (tmp / "plan.json").write_text(json_text(payload, indent=1) + "\n", encoding="utf-8")
        html = plan_html(plan, columns, name, files[:2])
        (tmp / "plan.html").write_text(html, encoding="utf-8")
    payload["directory"] = str(args.out)
    payload["linuxcnc"] = None if args.linuxcnc is None else str(args.linuxcnc)
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
            "  limits: those given only; report --program and sweep --program plan at "
            f"{quantity('speed', CYCLE_V_MAX)} and {quantity('acceleration', CYCLE_A_MAX)} "
            "by default (give them here for the same cycle time)",
            f"  {peaks_text(columns)}",
            f"  path control: {default_mode_text(program, blend)}; overrides: feed "
            f"{100 * feed_override:g} %, rapid {100 * rapid_override:g} %",
            f"  the tool stops {sum(stops.values())} times: "
            + ", ".join(f"{why} {n}" for why, n in stops.items() if n),
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
                f"  line {f.line}: local tightening did not settle ({f.limit} at "
                f"{f.use:.4f}): its section planned with that limit x {f.factor:.4f}, "
                f"{1e3 * f.cost:.1f} ms slower"
                for f in plan.fallbacks
            ),
            *(
                []
                if calibration is None
                else [f"  sliders commanded through the calibration {args.calibration}"]
            ),
            f"  {files[0]}: {written.samples} samples every {1e3 * step:g} ms"
            + (" (the step follows the program: no --dt)" if dt is None else ""),
            *(
                [
                    "  words ignored (no effect on the path): "
                    + ", ".join(f"{i['word']} ({i['count']})" for i in payload["ignored"])
                ]
                if payload["ignored"]
                else []
            ),
            f"Written to {args.out}: " + ", ".join(files),
            *(
                [f"Joint stream for LinuxCNC written to {args.linuxcnc}: " + ", ".join(stream)]
                if stream
                else []
            ),
        ]
    )
    return common.emit(args, payload, text)


def plan_limits(args: argparse.Namespace, params: Any) -> tuple[Any, Any]:
    """The plan's limits and calibration from the options ``plan`` and ``accuracy`` share.

    Args:
        args: The parsed options (``--motor``, ``--calibration``, the slider limits,
            ``--torque-reserve``).
        params: The design, which a calibration must have been made for.

    Returns:
        The :class:`~orthoglide_pin.planning.limits.PlanLimits` and the calibration
        (``None`` without ``--calibration``).
    """
    from orthoglide_pin.cli.dynamics import _drive
    from orthoglide_pin.planning.limits import PlanLimits, torque_reserve

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
        torque_reserve=torque_reserve(_float(args.torque_reserve), "--torque-reserve"),
    )
    return limits, calibration


def _check_stream_directory(args: argparse.Namespace) -> None:
    """``--linuxcnc DIR2``: another directory than ``--out``, writable (before any work)."""
    from orthoglide_pin._paths import output_directory

    if os.path.realpath(args.linuxcnc) == os.path.realpath(args.out):
        raise InvalidParameterError("--linuxcnc", args.linuxcnc, "a directory other than --out")
    output_directory(args.linuxcnc, force=args.force)


def _stream_files(plan: Any, dyn: Any) -> dict[str, str]:
    """The plan as LinuxCNC's joint stream (``plan.stream``, ``orthoglide_stream.hal``)."""
    from orthoglide_pin.controller.stream import stream_files

    return stream_files(plan, dyn)


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
        "torque_reserve": lim.torque_reserve if lim.limits_torque else None,
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
        "fallbacks": [f.as_dict() for f in plan.fallbacks],
        "per_block": [
            {"line": b.line, "kind": b.kind, "start": b.start, "end": b.end} for b in plan.blocks
        ],
    }


def add_torque_reserve(p: argparse.ArgumentParser) -> None:
    """The ``--torque-reserve R`` option of the commands that plan under a motor's torque."""
    from orthoglide_pin.planning.limits import DEFAULT_TORQUE_RESERVE

    p.add_argument(
        "--torque-reserve",
        default=str(DEFAULT_TORQUE_RESERVE),
        metavar="R",
        help="share of the motor's peak torque (and speed-torque curve) the plan leaves "
        f"to the servo loop, in [0, 1) (default: {DEFAULT_TORQUE_RESERVE:g})",
    )


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
    p.add_argument(
        "--linuxcnc",
        metavar="DIR2",
        help="also write the plan as the joint stream LinuxCNC's HAL plays at the servo rate "
        "(plan.stream, orthoglide_stream.hal; halrun -f orthoglide_stream.hal), atomically",
    )
    p.add_argument("--force", action="store_true", help="also write into a non-empty directory")
    p.add_argument("--motor", metavar="FILE.yaml", help="drive file: torques and motor limits")
    add_torque_reserve(p)
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
        "--dt",
        metavar="DT",
        help="sampling step of the trajectory file [s], 1e-6 to 0.1 (default: 0.001, or for "
        "a cycle longer than 1000 s the smallest step of 1, 2, 5 x 10^k s giving at most "
        "1,000,000 samples)",
    )
    p.add_argument(
        "--feed-override",
        metavar="F",
        default="1",
        help="multiplies every programmed feed, as a CNC panel's feed override: a fraction "
        "in (0, 2] (default 1); the limits still bound the motion",
    )
    p.add_argument(
        "--rapid-override",
        metavar="R",
        default="1",
        help="caps the rapid moves (G0) at this share of the speed the slider and motor speed "
        "limits allow: a fraction in (0, 1] (default 1); below 1 it needs one of them",
    )
    p.add_argument(
        "--blend",
        metavar="TOL",
        help="[mm]: a program that says neither G61 nor G64 runs as after G64 P<TOL> "
        "(default 0.01, LinuxCNC's default continuous mode with our bounded deviation; "
        "0 stops at every corner); the program's own G61 or G64 rules the blocks after it",
    )
    p.add_argument(
        "--trajectory-format",
        choices=("csv", "parquet"),
        default="csv",
        help="the trajectory file: trajectory.csv (default; simulate and view read it) or "
        "trajectory.parquet (about 40 %% smaller, [tables] extra); written a chunk "
        "at a time either way",
    )
    p.add_argument(
        "--calibration",
        metavar="FILE.yaml",
        help="a calibration (orthoglide calibrate) made for this design: the sliders are "
        "commanded so that the real tool follows the program, and their limits are checked "
        "on those commands",
    )
