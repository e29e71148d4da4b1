"""Accuracy command: ``accuracy PROGRAM.nc --cut CUT.yaml --out DIR``, the program on the part.

``orthoglide accuracy PROGRAM.nc --cut CUT.yaml [--motor F] [--calibration F]
[--temperature-rise K] [--simulate] --out DIR`` (or ``--example NAME`` for a
shipped program) plans the program as ``plan`` does (the same limit, set-up
and interpreter options), then along the plan: the milling forces from the
planned feed, the surface error they leave, the error budget
(:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`), and the
chatter stability margin of every line that cuts, with the machine's modes
where the tool is (:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`),
and the stability lobes at the point of smallest margin. The drive train of
``--motor`` (the default drive train without it) is reflected onto the
carriages, as ``report --cut`` and ``sweep --cut`` do; ``accuracy.json``
names it and the plan's limits. ``--simulate`` also
runs the plan in MuJoCo under servo control (it needs ``--motor``) and puts
its contour error in the budget. It writes ``DIR/accuracy.json``,
``DIR/accuracy.csv`` (one row per sample, written a chunk at a time) and
``DIR/accuracy.html`` atomically; ``--json`` prints the summary. A bad
program, cut file or option gets one line, status 2, nothing written.
"""

from __future__ import annotations

import argparse
import hashlib
import io
import json
import os
import re
from dataclasses import asdict
from pathlib import Path
from typing import Any, Final

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.program import add_setup_options
from orthoglide_pin.exceptions import InvalidParameterError

#: Files written in ``--out``.
FILES: Final = ("accuracy.csv", "accuracy.json", "accuracy.html")
#: Rows of ``accuracy.csv`` formatted at a time.
CSV_CHUNK: Final[int] = 20_000
#: A cell without a value (``nan``, or an infinite margin: beyond the depths searched).
_EMPTY_CELL: Final = re.compile(r"(?<![^,\n])-?(?:nan|inf)(?![^,\n])")


def _number(name: str, text: str | None, low: float, high: float, unit: str) -> float | None:
    """An option's number in ``[low, high]``, or ``None`` when not given."""
    from orthoglide_pin._validation import number_in

    if text is None:
        return None
    try:
        value: float | str = float(text)
    except ValueError:
        value = text
    return number_in(name, value, low, high, unit)


def cut_summary(cut: Any) -> dict[str, Any]:
    """The cut conditions as strict JSON, with a digest of them (16 hexadecimal digits)."""
    from orthoglide_pin._io import json_text, strict_json

    data = dict(strict_json(asdict(cut)))
    digest = hashlib.sha256(json_text(data, sort_keys=True).encode()).hexdigest()[:16]
    return {"digest": digest, **data}


def csv_columns(result: Any, stability: Any, servo: Any) -> dict[str, Any]:
    """The per-sample columns of ``accuracy.csv`` (SI units; ``nan``: no value)."""
    columns = dict(result.columns())
    n = result.samples.t.size
    columns["stability_margin"] = stability.sample_margin
    worst, rss = np.zeros(n), np.zeros(n)
    cut = np.flatnonzero(result.samples.cutting)
    worst[cut], rss[cut] = result.budget.worst_case, result.budget.rss
    columns["budget_worst_case"], columns["budget_rss"] = worst, rss
    if servo is not None:
        columns["servo_error"] = np.interp(result.samples.t, servo[0], servo[1])
    return columns


def write_csv(path: Path, columns: dict[str, Any], first_line: str) -> int:
    """Write the columns a chunk at a time (empty cells for ``nan``); return the rows."""
    names = list(columns)
    n = int(columns["t"].size)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(first_line + ",".join(names) + "\n")
        for lo in range(0, n, CSV_CHUNK):
            table = np.column_stack([np.asarray(columns[c])[lo : lo + CSV_CHUNK] for c in names])
            buffer = io.StringIO()
            np.savetxt(buffer, table, fmt="%.10g", delimiter=",")
            handle.write(_EMPTY_CELL.sub("", buffer.getvalue()))
    return n


def _where(result: Any, values: Any) -> dict[str, Any] | None:
    s = result.samples
    if not s.cutting.any():
        return None
    k = int(np.argmax(np.abs(values)))
    return {"t": float(s.t[k]), "point": s.points[k].tolist(), "line": int(s.line[k])}


def stability_summary(stability: Any, lobes: Any) -> dict[str, Any]:
    """The ``stability`` entry of ``accuracy.json``."""
    w = stability.worst
    blocks = [
        {"line": int(ln), "point": p.tolist(), "feed_angle": float(a), "depth": float(d),
         "limit": float(lim), "margin": float(m)}
        for ln, p, a, d, lim, m in zip(
            stability.lines, stability.points, stability.angles, stability.depths,
            stability.limits, stability.margin, strict=True,
        )
    ]  # fmt: skip
    return {
        "margin_min": None if w < 0 else float(stability.margin[w]),
        "cutting_blocks": int(stability.lines.size),
        "unstable_blocks": stability.unstable,
        "points_per_block": stability.points_per_block,
        "worst": None if w < 0 else blocks[w],
        "blocks": blocks,
        "unconditional_limit": None if lobes is None else lobes.minimum,
    }


def _lobes_at_worst(cut: Any, stability: Any, params: Any, options: dict[str, Any]) -> Any:
    from orthoglide_pin.machining.cutting import RPM_PER_RAD_S
    from orthoglide_pin.machining.stability import LOBE_SPEEDS, stability_lobes

    w = stability.worst
    if w < 0:
        return None
    rpm = stability.speed * RPM_PER_RAD_S
    low, high = LOBE_SPEEDS[0] * RPM_PER_RAD_S, LOBE_SPEEDS[-1] * RPM_PER_RAD_S
    speeds = LOBE_SPEEDS
    if not low <= rpm <= high:  # the cut's speed within the lobes drawn
        speeds = np.linspace(min(low, 0.5 * rpm), max(high, 1.5 * rpm), LOBE_SPEEDS.size)
        speeds = speeds / RPM_PER_RAD_S
    return stability_lobes(
        cut, stability.points[w], params=params, speeds=speeds,
        feed_angle=float(stability.angles[w]),
        engagement=cut.engagement_at(int(stability.lines[w])), **options,
    )  # fmt: skip


def _simulate(args: argparse.Namespace, plan: Any, dyn: Any, drive: Any) -> Any:
    """``--simulate``: the plan run in MuJoCo; ``(times, contour errors)`` and its summary."""
    from orthoglide_pin.simulation.outputs import run_contour_error, simulation_summary
    from orthoglide_pin.simulation.run import simulate
    from orthoglide_pin.simulation.servo import ServoSettings

    with common.progress_bar(args, "simulating", "periods") as progress:
        run = simulate(plan, dyn, drive, ServoSettings(), progress=progress)
    contour = run_contour_error(plan, run)
    info = simulation_summary(run, contour, plan)
    keep = ("controller", "rate", "max_contour_error", "rms_contour_error", "saturation_time")
    return (run.t, contour.distance), {k: info[k] for k in keep if k in info}


def _cmd_accuracy(args: argparse.Namespace) -> int:
    from orthoglide_pin._io import json_text
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.cli.plan import plan_limits
    from orthoglide_pin.cli.program import program_setup
    from orthoglide_pin.drives.motor import Drive
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.digest import design_comment, design_digest
    from orthoglide_pin.machining.accuracy import accuracy_along_plan
    from orthoglide_pin.machining.budget import MAX_TEMPERATURE_RISE
    from orthoglide_pin.machining.cutting import RPM_PER_RAD_S, read_cut_file
    from orthoglide_pin.machining.plan_samples import MAX_DT, MIN_DT, program_spindle_speed
    from orthoglide_pin.machining.plan_stability import stability_along_plan
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.planning.shipped import example_program_text
    from orthoglide_pin.program.axes import design_axes
    from orthoglide_pin.report.accuracy_page import accuracy_html

    if (args.program is None) == (args.example is None):
        raise InvalidParameterError("arguments", None, "PROGRAM.nc or --example NAME (one)")
    if args.simulate and args.motor is None:
        raise InvalidParameterError("--simulate", None, "--motor F.yaml too (the motor simulated)")
    if args.simulate:  # the extra is there before any work
        from orthoglide_pin._lazy import optional_import

        optional_import("mujoco", "sim", "orthoglide accuracy --simulate")
    params = common.build_params(args)
    output_directory(args.out, force=args.force)  # before any work
    cut = read_cut_file(args.cut)
    top = MAX_TEMPERATURE_RISE
    rise = _number("--temperature-rise", args.temperature_rise, -top, top, "[K]")
    dt = _number("--dt", args.dt, MIN_DT, MAX_DT, "[s]")
    limits, calibration = plan_limits(args, params)
    drive = limits.drive
    text = (
        example_program_text(args.example)
        if args.example is not None
        else common.read_program_text(args.program)
    )
    name = args.example + ".nc" if args.example is not None else os.path.basename(args.program)
    speed = cut.spindle_speed
    source = "cut file"
    if speed is None:
        speed, source = program_spindle_speed(text), "program"
        if speed is None:
            raise InvalidParameterError(
                "spindle_speed", "program", "an S word in the program, or a speed in the cut file"
            )
    axes = design_axes(params)
    program = read_program(
        text, setup=program_setup(args, axes), axes=axes, interpreter=args.interpreter
    )
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    with common.progress_bar(args, "planning", "blocks") as progress:
        plan = plan_program(program, dyn, limits, calibration=calibration, progress=progress)
    servo, servo_info = (None, None) if not args.simulate else _simulate(args, plan, dyn, drive)
    result = accuracy_along_plan(
        plan, cut, params, dt=dt, spindle_speed=speed, calibration=calibration, servo=servo,
        temperature_rise=rise,
    )  # fmt: skip
    train = (Drive() if drive is None else drive).train  # reflected, as report and sweep do
    options = {"drive": train, "model": args.model}
    with common.progress_bar(args, "stability", "points") as progress:
        stability = stability_along_plan(plan, result, params, progress=progress, **options)
    lobes = _lobes_at_worst(cut, stability, params, {**options, "axes": axes})
    payload: dict[str, Any] = {"program": name, "design": design_digest(params)}
    payload["cut"] = {"file": os.path.basename(args.cut), **cut_summary(cut)}
    payload["spindle_speed_from"] = source
    payload["limits"] = {
        "slider_speed": limits.slider_speed,
        "slider_acceleration": limits.slider_acceleration,
        "slider_jerk": limits.slider_jerk,
        "motor": drive is not None and drive.motor is not None,
    }
    payload["drive_train"] = asdict(train)
    payload["cycle_time"] = plan.cycle_time
    summary = result.summary()
    payload.update(summary)
    payload["surface_error_at"] = {
        "static": _where(result, result.surface_static),
        "generated": _where(result, result.surface_generated),
        "peak": _where(result, result.surface_peak),
    }
    payload["stability"] = stability_summary(stability, lobes)
    payload["lobes"] = None if lobes is None else lobes.to_dict()
    payload["calibration"] = args.calibration
    payload["temperature_rise"] = rise
    payload["servo"] = servo_info
    payload["model"] = args.model
    payload = json.loads(json_text(payload))  # strict: an infinite limit or a nan as null
    columns = csv_columns(result, stability, servo)
    with atomic_directory(args.out, force=args.force) as tmp:
        rows = write_csv(tmp / FILES[0], columns, design_comment(params))
        (tmp / FILES[1]).write_text(json_text(payload, indent=1) + "\n", encoding="utf-8")
        html = accuracy_html(columns, payload, axes, name, list(FILES[:2]))
        (tmp / FILES[2]).write_text(html, encoding="utf-8")
    payload["directory"] = str(args.out)
    um = 1e6
    st = payload["stability"]
    worst = st["worst"]
    reflected = "the default drive train reflected" if drive is None else "--motor's drive train"
    margin = (
        "nothing cuts"
        if worst is None
        else f"smallest margin {_margin(worst['margin'])} at line {worst['line']}, "
        f"{st['unstable_blocks']} of {st['cutting_blocks']} cutting lines unstable ({reflected})"
    )
    budget = payload["budget"]
    lines = [
        f"Accuracy of {name}: {payload['cutting_samples']} of {payload['samples']} samples cut, "
        f"{payload['material']['name']} at {speed * RPM_PER_RAD_S:.0f} rpm ({source})",
        f"  forces: mean up to {payload['force_mean_max']:.1f} N, "
        f"peak {payload['force_peak_max']:.1f} N",
        f"  surface error: static {um * payload['surface_error_static_max']:.2f} um, generated "
        f"{um * payload['surface_error_generated_max']:.2f} um, peak "
        f"{um * payload['surface_error_peak_max']:.2f} um",
        f"  stability: {margin}",
        "  budget (largest): "
        + (", ".join(f"{k} {um * v:.2f} um" for k, v in budget["max"].items()) or "no term")
        + f"; RSS {um * budget['rss_max']:.2f} um",
        f"Written to {args.out}: " + ", ".join(FILES) + f" ({rows} rows)",
    ]
    return common.emit(args, payload, "\n".join(lines))


def _margin(value: float | None) -> str:
    return "beyond the depths searched" if value is None else f"{value:.3f}"


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``accuracy`` command to the ``orthoglide`` parser."""
    from orthoglide_pin.cli.plan import add_torque_reserve
    from orthoglide_pin.planning.shipped import EXAMPLE_PROGRAMS

    p = common.add_command(
        sub,
        parent,
        "accuracy",
        _cmd_accuracy,
        "what a part program does to the part: cutting forces, surface error, chatter "
        "stability of every line, error budget",
    )
    p.add_argument("program", nargs="?", metavar="PROGRAM.nc", help="the G-code program")
    p.add_argument(
        "--example", choices=tuple(EXAMPLE_PROGRAMS), help="a shipped example program instead"
    )
    p.add_argument(
        "--cut",
        required=True,
        metavar="CUT.yaml",
        help="cut file: tool, material, engagement, spindle speed (formats reference)",
    )
    p.add_argument(
        "--out", required=True, metavar="DIR", help="output directory, written atomically"
    )
    p.add_argument("--force", action="store_true", help="also write into a non-empty directory")
    p.add_argument(
        "--motor",
        metavar="FILE.yaml",
        help="drive file: torques and motor limits of the plan, the rotor and screw inertia "
        "reflected onto the carriages for the stability (default: the default drive train, "
        "no motor limit), the motor simulated",
    )
    add_torque_reserve(p)
    p.add_argument("--max-slider-speed", metavar="V", help="[m/s]")
    p.add_argument("--max-slider-acceleration", metavar="A", help="[m/s^2]")
    p.add_argument("--max-slider-jerk", metavar="J", help="[m/s^3]")
    add_setup_options(p)
    p.add_argument(
        "--calibration",
        metavar="FILE.yaml",
        help="a calibration of this design: the plan commands the calibrated sliders, and "
        "the budget's geometric term is the error its parameters' uncertainty leaves",
    )
    p.add_argument(
        "--temperature-rise",
        metavar="K",
        help="uniform temperature rise [K], -100 to 100: the budget's thermal term "
        "(default: none)",
    )
    p.add_argument(
        "--simulate",
        action="store_true",
        help="also run the plan in MuJoCo under servo control (needs --motor, "
        "[sim] extra): its contour error is the budget's servo term",
    )
    p.add_argument(
        "--dt",
        metavar="DT",
        help="sampling step [s], 1e-4 to 1 (default: 0.005, coarser on a long program: at "
        "most 50,000 samples)",
    )
    p.add_argument(
        "--model",
        choices=("platform", "full"),
        default="platform",
        help="the machine's vibration model for the stability (see modes): platform (the "
        "platform, the carriages and the bars' first bending; fast) or full (the members "
        "point by point)",
    )
