"""Simulation commands: the machine for MuJoCo, and a part program run in it.

``mjcf -o FILE.xml [--motor FILE.yaml]`` writes the machine as MJCF: the URDF's
bodies, joints and inertials, the loop closures as equality constraints, the
drives as armature, friction and damping of the sliders, and one force
actuator per slider (limited by the motor's peak torque through the screw when
the drive file gives it). MuJoCo compiles it before it is written
(``pip install 'orthoglide-pin[sim]'``).

``simulate PROGRAM.nc --motor F [--plan-motor G] [--wrench FX FY FZ [MX MY MZ]]
[--rate HZ] [--controller NAME] --out DIR`` plans the program under the limits
of ``G`` (by default ``F``) and the tool wrench (its inverse dynamics), then
runs it in MuJoCo with the motor of ``F`` under one position loop per slider,
the wrench applied to the platform, and writes ``DIR/simulation.csv`` (a chunk
of periods at a time, in memory that does not grow with the program;
``simulation.parquet`` with ``--trajectory-format parquet``),
``DIR/simulation.json`` and ``DIR/simulation.html`` atomically; ``--json``
prints the summary. Bad input (an unknown controller, a rate of 0, a bad
wrench, a program the plan refuses) gets one line, status 2, and nothing is
written.
"""

from __future__ import annotations

import argparse

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.program import add_setup_options


def _cmd_mjcf(args: argparse.Namespace) -> int:
    from orthoglide_pin.drives.motor import Drive, load_drive
    from orthoglide_pin.machine.description import load_loops
    from orthoglide_pin.simulation.engine import write_mjcf
    from orthoglide_pin.simulation.slider_drive import drive_terms

    params = common.build_params(args)
    drive = Drive() if args.motor is None else load_drive(args.motor)
    gravity = (
        None
        if args.gravity is None
        else common.numbers("--gravity", args.gravity, "GX GY GZ [m/s^2]", 3)
    )
    path = write_mjcf(args.output, params, drive, gravity=gravity).resolve()
    loops = load_loops()
    terms = drive_terms(drive)
    payload = {
        "path": str(path),
        "gravity": [float(g) for g in (gravity if gravity is not None else (0.0, 0.0, 9.81))],
        "sliders": list(loops.actuated_joints),
        "equalities": [
            {"name": c.name, "type": "connect" if c.kind == "point" else "weld"}
            for c in loops.closures
        ],
        **terms,
    }
    limit = terms["force_limit"]
    shown = "no force limit (no motor data)" if limit is None else f"force limit {limit:.6g} N"
    text = (
        f"{path}\n  sliders: armature {terms['armature']:.6g} kg, friction "
        f"{terms['frictionloss']:.6g} N, damping {terms['damping']:.6g} N.s/m, {shown}\n"
        f"  loops: {len(loops.closures)} equalities"
    )
    return common.emit(args, payload, text)


def _optional_number(name: str, text: str | None, default: float) -> float:
    from orthoglide_pin._validation import finite_number

    if text is None:
        return default
    try:
        value: float | str = float(text)
    except ValueError:
        value = text
    return finite_number(name, value)


def _cmd_simulate(args: argparse.Namespace) -> int:
    import os

    from orthoglide_pin._io import json_text
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.cli.plan import _float
    from orthoglide_pin.cli.program import program_setup
    from orthoglide_pin.drives.motor import load_drive
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.exceptions import InvalidParameterError
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.digest import design_comment, design_digest
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.limits import PlanLimits, torque_reserve
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.planning.shipped import example_program_text
    from orthoglide_pin.program.axes import design_axes
    from orthoglide_pin.report.simulation_page import simulation_html
    from orthoglide_pin.simulation.servo import ServoSettings
    from orthoglide_pin.simulation.stream import write_simulation

    if (args.program is None) == (args.example is None):
        raise InvalidParameterError("arguments", None, "PROGRAM.nc or --example NAME (one)")
    counts: int | str | None = None
    if args.encoder is not None:
        try:
            counts = int(args.encoder)
        except ValueError:
            counts = args.encoder
    rate = _optional_number("--rate", args.rate, 4000.0)
    settings = ServoSettings(
        controller=args.controller,
        rate=rate,
        encoder_counts=counts,  # type: ignore[arg-type]  # checked by ServoSettings
        mass_error=_optional_number("--mass-error", args.mass_error, 0.0),
        friction_error=_optional_number("--friction-error", args.friction_error, 0.0),
    )
    reserve = torque_reserve(_float(args.torque_reserve), "--torque-reserve")
    wrench = common.tool_wrench(args.wrench)
    params = common.build_params(args)
    output_directory(args.out, force=args.force)  # before any work
    if args.trajectory_format == "parquet":
        from orthoglide_pin._lazy import optional_import

        optional_import("pyarrow", "tables", "a Parquet simulation file")
    drive = load_drive(args.motor)
    plan_drive = drive if args.plan_motor is None else load_drive(args.plan_motor)
    text = (
        example_program_text(args.example)
        if args.example is not None
        else common.read_program_text(args.program)
    )
    name = args.example + ".nc" if args.example is not None else os.path.basename(args.program)
    axes = design_axes(params)
    program = read_program(
        text, setup=program_setup(args, axes), axes=axes, interpreter=args.interpreter
    )
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    limits = PlanLimits(drive=plan_drive, torque_reserve=reserve)
    with common.progress_bar(args, "planning", "blocks") as progress:
        plan = plan_program(program, dyn, limits, wrench=wrench, progress=progress)
    files = [f"simulation.{args.trajectory_format}", "simulation.json", "simulation.html"]
    with atomic_directory(args.out, force=args.force) as tmp:  # an error writes nothing
        with common.progress_bar(args, "simulating", "periods") as progress:
            streamed = write_simulation(
                tmp / files[0], plan, dyn, drive, settings,
                first_line=design_comment(params), file_format=args.trajectory_format,
                progress=progress,
            )  # fmt: skip
        payload = streamed.summary
        payload["plan_motor"] = None if plan_drive.motor is None else plan_drive.motor.name
        payload["torque_reserve"] = reserve
        payload["cycle_time"] = plan.cycle_time
        payload["wrench"] = None if plan.wrench is None else [float(v) for v in plan.wrench]
        payload["design"] = design_digest(params)  # the machine it belongs to
        common.check_finite(payload)
        (tmp / "simulation.json").write_text(json_text(payload, indent=1) + "\n", encoding="utf-8")
        html = simulation_html(streamed.plot, payload, name, files[:2])  # every peak kept
        (tmp / "simulation.html").write_text(html, encoding="utf-8")
    payload["directory"] = str(args.out)
    um = 1e6
    at = payload["max_contour_error_at"]
    where = "" if at is None else f" at t = {at['t']:.4f} s, line {at['line']}"
    lines = [
        f"Simulation of {name}: {streamed.samples} periods of {1e3 * settings.period:.4g} ms "
        f"({settings.controller}), MuJoCo step {streamed.timestep:.4g} s",
        f"  contour error while cutting ({100 * payload['cutting_share']:.1f} % of the time): "
        f"max {um * payload['max_contour_error']:.3f} um{where}, "
        f"RMS {um * payload['rms_contour_error']:.3f} um; rapid moves "
        f"{um * payload['max_rapid_deviation']:.3f} um",
        *(
            f"  slider {i + 1}: max tracking error "
            f"{um * payload['max_tracking_error'][i]:.3f} um, saturated "
            f"{payload['saturation_time_per_slider'][i]:.4f} s"
            for i in range(3)
        ),
        f"Written to {args.out}: " + ", ".join(files),
    ]
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``mjcf`` and ``simulate`` commands to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "mjcf",
        _cmd_mjcf,
        "the machine as MJCF for MuJoCo: loops as equalities, drives, force limits",
    )
    p.add_argument("-o", "--output", required=True, metavar="FILE.xml", help="MJCF file to write")
    p.add_argument(
        "--motor",
        metavar="FILE.yaml",
        help="drive file (`orthoglide drive --example` prints one; default: the default "
        "drive train, no motor data, so no force limit)",
    )
    p.add_argument(
        "--gravity",
        nargs=3,
        metavar=("GX", "GY", "GZ"),
        help="gravity [m/s^2] in the machine frame (default: 0 0 9.81, e3 down)",
    )

    from orthoglide_pin.cli.plan import add_torque_reserve
    from orthoglide_pin.planning.shipped import EXAMPLE_PROGRAMS

    q = common.add_command(
        sub,
        parent,
        "simulate",
        _cmd_simulate,
        "a part program planned, then run in MuJoCo under servo control: contour error",
    )
    q.add_argument("program", nargs="?", metavar="PROGRAM.nc", help="the G-code program")
    add_setup_options(q)
    q.add_argument(
        "--example", choices=tuple(EXAMPLE_PROGRAMS), help="simulate a shipped example program"
    )
    q.add_argument(
        "--motor",
        required=True,
        metavar="F.yaml",
        help="drive file of the simulated motor (`orthoglide drive --example` prints one)",
    )
    q.add_argument(
        "--plan-motor",
        metavar="G.yaml",
        help="drive file whose limits the plan respects (default: --motor)",
    )
    add_torque_reserve(q)
    q.add_argument(
        "--wrench",
        nargs="+",
        metavar=("FX", "FY", "FZ"),
        help="constant tool wrench FX FY FZ [MX MY MZ] [N, N.m] at the tool point, world axes: "
        "the plan balances it and MuJoCo applies it to the platform (default: none)",
    )
    q.add_argument(
        "--rate",
        metavar="HZ",
        help="servo rate [Hz], 500 to 100000 and at least 10 periods per block of the "
        "program (default: 4000)",
    )
    q.add_argument(
        "--controller",
        default="pid_ff",
        metavar="NAME",
        help="pid_ff (default: PID, velocity and torque feedforward), pd_ff (PD, both "
        "feedforwards) or pd (PD, velocity feedforward only)",
    )
    q.add_argument(
        "--encoder", metavar="COUNTS", help="encoder counts per motor revolution (default: exact)"
    )
    q.add_argument(
        "--mass-error",
        metavar="E",
        help="relative error of the controller's masses, e.g. 0.05 (default: 0)",
    )
    q.add_argument(
        "--friction-error",
        metavar="E",
        help="relative error of the controller's friction (default: 0)",
    )
    q.add_argument(
        "--trajectory-format",
        choices=("csv", "parquet"),
        default="csv",
        help="format of the run's file: simulation.csv (default) or simulation.parquet "
        "(about 40 %% smaller, [tables] extra); written a chunk at a time",
    )
    q.add_argument(
        "--out", required=True, metavar="DIR", help="output directory, written atomically"
    )
    q.add_argument("--force", action="store_true", help="also write into a non-empty directory")
