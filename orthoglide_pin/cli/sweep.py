"""Sweep command: ``sweep``, a grid of designs evaluated on local processes or Dask.

``orthoglide sweep --leg-length 0.25:0.45:21 --out DIR`` evaluates one design per
leg length (:mod:`orthoglide_pin.sweep.spec`): stroke, compactness, transmission
factors over the cube, moving mass, worst-case force and torque, footprint. It
writes ``DIR/results.csv``, ``DIR/results.parquet`` and ``DIR/sweep.png`` (each
metric against the first swept quantity, one line per value of the others, the
base design marked: the machine of ``--config`` and ``--param``, or the paper's
prototype; lengths in mm, stiffnesses in N/um, deflections in um), and every
finished design as ``DIR/parts/<key>.json``: run it again after an
interruption and it carries on where it stopped (the same sweep only: another
spec in ``DIR`` is refused, naming what differs; :mod:`orthoglide_pin.sweep.store`).
The terminal lists the designs, one column per swept quantity.

``--param NAME=START:STOP:N`` or ``--param NAME=A,B,C`` adds an axis (the
designs are the product of the axes); ``--param NAME=VALUE`` sets a machine
parameter of every design, as in the other commands. ``psi_min``, ``psi_max``,
``cube_side``, ``speed`` and ``acceleration`` may be axes too.
"""

from __future__ import annotations

import argparse
import math
from typing import Any, Final

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError, short_repr

#: Most design lines printed by the text output.
MAX_LINES = 30


def _split(texts: list[str]) -> tuple[list[str], list[str]]:
    """``--param`` texts: machine parameters of every design, and axes."""
    from orthoglide_pin.sweep.spec import FIXED_FIELDS, SETTINGS

    fixed, axes = [], []
    for text in texts:
        name, _, value = text.partition("=")
        name = name.strip()
        if name in ("slider_lower", "slider_upper"):
            raise InvalidParameterError(
                "--param",
                text,
                "a parameter other than the slider limits, "
                "which every design derives from its cube",
            )
        single = ":" not in value and "," not in value
        if name == "workspace_side" and not single:
            raise InvalidParameterError(
                "--param", text, "cube_side=START:STOP:N to sweep the side of the cube"
            )
        if name in SETTINGS or name == "leg_length":
            axes.append(text)
        elif name in FIXED_FIELDS or single:
            fixed.append(text)
        else:
            axes.append(text)
    return fixed, axes


def _spec(args: argparse.Namespace) -> Any:
    from orthoglide_pin.drives.motor import DriveTrain, load_drive
    from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

    fixed, texts = _split(args.param)
    base = common.build_params(argparse.Namespace(param=fixed, config=args.config))
    axes = [SweepAxis.parse(f"leg_length={args.leg_length}")] if args.leg_length else []
    axes += [SweepAxis.parse(t) for t in texts]
    base = common.with_criterion(args, base)  # the machine's criterion unless --psi
    corner, side = common.cube_arguments(args)
    return SweepSpec(
        axes=tuple(axes),
        mode=args.mode,
        base=base,
        cube_side=side,
        cube_corner=corner,
        psi_min=base.psi_min,
        psi_max=base.psi_max,
        speed=common.finite("--speed", args.speed),
        acceleration=common.finite("--acceleration", args.acceleration),
        grid=args.grid,
        requirement_grid=args.requirement_grid,
        drive=DriveTrain() if args.motor is None else load_drive(args.motor).train,
        program=None if args.program is None else common.read_program_text(args.program),
        cut=_cut_file(args),
    )


def _cut_file(args: argparse.Namespace) -> str | None:
    """``--cut``'s path (read by the spec), refused without ``--program``."""
    if args.cut is not None and args.program is None:
        raise InvalidParameterError("--cut", args.cut, "a cut file with --program PROGRAM.nc")
    return None if args.cut is None else str(args.cut)


#: Columns of the terminal table after the design's own: header, column, format;
#: lengths in mm (``"mm"``), factors as the interval reached.
_METRIC_CELLS: Final = (
    ("stroke [mm]", "stroke", "mm"),
    ("ratio", "ratio", ".3f"),
    ("factors reached", "", "factors"),
    ("holds", "bounds_hold", "holds"),
    ("cond max", "condition_max", ".3f"),
    ("mass [kg]", "moving_mass", ".3f"),
    ("force [N]", "max_slider_force", ".1f"),
    ("torque [N.m]", "max_motor_torque", ".3f"),
)


def _axis_header(name: str) -> str:
    """``"bar_radius [mm]"``: an axis in the report's units (none for a pure number)."""
    from orthoglide_pin.sweep.labels import display_unit

    unit = display_unit(name)[1]
    return name if unit == "-" else f"{name} [{unit}]"


def _value(name: str, value: Any) -> str:
    """A value of column ``name`` in the report's units, 4 significant digits."""
    from orthoglide_pin.sweep.labels import display_unit

    number = float(value)
    return "-" if not math.isfinite(number) else f"{display_unit(name)[0] * number:.4g}"


def _mm(value: Any) -> str:
    number = float(value)
    return "-" if not math.isfinite(number) else f"{1e3 * number:.2f}"


#: The program's cells (``sweep --program``): header, column.
_PROGRAM_CELLS: Final = (("cycle [s]", "cycle_time"), ("binding", "binding_limit"))


#: The cut's cells (``sweep --program --cut``): header, column.
_CUT_CELLS: Final = (("surface [um]", "surface_error_max"), ("margin", "stability_margin_min"))


def _cells(
    row: Any, axes: list[str], program: bool, cut: bool = False
) -> tuple[list[str], str | None]:
    """A design's cells: its own (leg, cube side, every other axis), then its metrics."""
    own = [_mm(row.leg_length), _mm(row.cube_side), *(_value(a, getattr(row, a)) for a in axes)]
    if row.status != "ok":
        return own, f"invalid: {row.error}"
    metrics = []
    for _, column, form in _METRIC_CELLS:
        if form == "factors":
            metrics.append(f"[{row.psi_min_reached:.3f}, {row.psi_max_reached:.3f}]")
        elif form == "holds":
            metrics.append("yes" if row.bounds_hold else "NO")
        elif form == "mm":
            metrics.append(_mm(getattr(row, column)))
        else:
            metrics.append(format(float(getattr(row, column)), form))
    if program:
        cycle = float(row.cycle_time)  # as plan and report print it
        metrics += ["-" if not math.isfinite(cycle) else f"{cycle:.4f}", str(row.binding_limit)]
    if cut:
        metrics += [_value(column, getattr(row, column)) for _, column in _CUT_CELLS]
    return own + metrics, None


def _design_lines(
    table: Any, axes: list[str], program: bool = False, cut: bool = False
) -> list[str]:
    """The terminal table: a header, then one line per design, columns aligned.

    Every swept quantity has its column after the leg length and the cube side
    (the leg and the side are always shown), in the report's units.
    """
    headers = ["L [mm]", "Lw [mm]", *(_axis_header(a) for a in axes)]
    headers += [h for h, _, _ in _METRIC_CELLS]
    headers += [h for h, _ in _PROGRAM_CELLS] if program else []
    headers += [h for h, _ in _CUT_CELLS] if cut else []
    rows = [_cells(row, axes, program, cut) for row in table.itertuples()]
    widths = [len(h) for h in headers]
    for cells, _ in rows:
        for k, cell in enumerate(cells):
            widths[k] = max(widths[k], len(cell))
    lines = ["  " + "  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))]
    for cells, note in rows:
        text = "  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=False))
        lines.append("  " + text + ("" if note is None else "  " + note))
    return lines


def _cmd_sweep(args: argparse.Namespace) -> int:
    from orthoglide_pin._lazy import optional_import
    from orthoglide_pin.sweep.plots import plot_sweep
    from orthoglide_pin.sweep.runner import require_tables, run_sweep
    from orthoglide_pin.sweep.scheduler import check_scheduler

    check_scheduler(args.scheduler)  # first: a silent peer is reported before any import
    require_tables()  # before anything is written: the table needs the [tables] extra
    if args.scheduler is not None:
        optional_import("distributed", "cluster", "--scheduler")
    spec = _spec(args)
    result = run_sweep(
        spec,
        args.out,
        force=args.force,
        workers=args.workers,
        scheduler=args.scheduler,
        chunk_size=args.chunk_size,
        progress=not (args.no_progress or args.json),
        force_workers=args.force_workers,
        force_designs=args.force_designs,
    )
    varying = [a.name for a in spec.axes if len(a.values) > 1]
    plot = None
    if varying and not args.no_plot and (result.table["status"] == "ok").any():
        plot = plot_sweep(
            result.table, result.out / "sweep.png", varying[0], group=varying[1:], spec=spec
        )
    criterion, criterion_text = common.criterion_info(args, spec.base)
    if any(a.name in ("psi_min", "psi_max") for a in spec.axes):
        criterion_text += " (psi axes: each design's own value)"
    payload = {
        **result.to_dict(),
        "criterion": criterion,
        "mode": spec.mode,
        "axes": {a.name: list(a.values) for a in spec.axes},
        "plot": None if plot is None else str(plot),
    }
    if spec.mode == "fixed-cube":
        payload["cube"] = spec.cube().to_dict()
    lines = [
        f"Sweep of {result.designs} designs ({spec.mode}): {result.computed} computed, "
        f"{result.skipped} already done, {result.invalid} invalid",
        f"  table  {result.csv}",
        f"         {result.parquet}",
    ]
    if plot is not None:
        lines.append(f"  plot   {plot}")
    if spec.mode == "fixed-cube":
        lines.append(f"  cube   {spec.cube().describe()} (every design)")
    lines.append(f"  criterion {criterion_text}")
    if spec.program is not None:  # the limits its cycle times are planned at
        lines.append(f"  program planned with {_program_limits(spec)}")
    if spec.cut is not None:  # the drive train its margins reflect
        lines.append(f"  cut    {_cut_drive(spec)}")
    axes = [a.name for a in spec.axes if a.name not in ("leg_length", "cube_side")]
    lines += _design_lines(
        result.table.head(MAX_LINES), axes, spec.program is not None, spec.cut is not None
    )
    if len(result.table) > MAX_LINES:
        lines.append(f"  ... {len(result.table) - MAX_LINES} more designs in the table")
    return common.emit(args, payload, "\n".join(lines))


def _program_limits(spec: Any) -> str:
    """The limits of the program's plans, as the summary states them."""
    from orthoglide_pin.report.units import quantity

    swept = {a.name for a in spec.axes}
    speed = "each design's speed" if "speed" in swept else quantity("speed", spec.speed)
    acc = (
        "each design's acceleration"
        if "acceleration" in swept
        else quantity("acceleration", spec.acceleration)
    )
    return f"the sliders within {speed} and {acc} (--speed, --acceleration), no motor limit"


def _cut_drive(spec: Any) -> str:
    """How the cut's columns are computed, as the summary states it."""
    from orthoglide_pin.drives.motor import DriveTrain

    train = "the default drive train" if spec.drive == DriveTrain() else "--motor's drive train"
    return (
        "surface error and stability margin as `orthoglide accuracy` computes them, "
        f"{train} reflected onto the carriages"
    )


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(
            f"invalid value {short_repr(text)}: expected a positive integer"
        )
    return value


def _grid(text: str) -> int:
    value = _positive_int(text)
    if value < 2:
        raise argparse.ArgumentTypeError(
            f"invalid value {short_repr(text)}: expected an integer >= 2"
        )
    return value


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add ``sweep`` to the command line."""
    from orthoglide_pin.sweep.runner import MAX_DESIGNS
    from orthoglide_pin.sweep.spec import (
        DEFAULT_ACCELERATION,
        DEFAULT_GRID,
        DEFAULT_REQUIREMENT_GRID,
        DEFAULT_SPEED,
        HARD_MAX_DESIGNS,
        MAX_GRID,
        MAX_REQUIREMENT_GRID,
        MODES,
    )

    p = common.add_command(
        sub,
        parent,
        "sweep",
        _cmd_sweep,
        "evaluate a grid of designs (leg length first) and write a tidy table; "
        "--param NAME=START:STOP:N adds an axis",
    )
    p.add_argument("--leg-length", metavar="START:STOP:N", help="leg lengths [m] (or A,B,C)")
    p.add_argument(
        "--mode",
        choices=MODES,
        default="fixed-cube",
        help="fixed-cube: the cube stays while the leg varies (default); "
        "redesign: each design is the paper's design for its bounds",
    )
    common.add_cube_options(p)
    common.add_psi_option(p)
    p.add_argument("--speed", metavar="V", default=str(DEFAULT_SPEED), help="tool speed [m/s]")
    p.add_argument(
        "--acceleration",
        metavar="A",
        default=str(DEFAULT_ACCELERATION),
        help="tool acceleration [m/s^2]",
    )
    p.add_argument("--motor", metavar="FILE.yaml", help="drive train (and motor) file")
    p.add_argument(
        "--program",
        metavar="PROGRAM.nc",
        help="a part program (G-code) planned on every design with the sliders within "
        "--speed and --acceleration: columns cycle_time [s] and binding_limit ([plan] extra)",
    )
    p.add_argument(
        "--cut",
        metavar="CUT.yaml",
        help="cut file (tool, material, engagement, spindle speed, modal damping) to cut "
        "--program with on every design: columns surface_error_max [m] and "
        "stability_margin_min [-] (part of the sweep's identity, like the program)",
    )
    p.add_argument(
        "--grid",
        metavar="N",
        type=_grid,
        default=DEFAULT_GRID,
        help=f"points per cube edge (at most {MAX_GRID})",
    )
    p.add_argument(
        "--requirement-grid",
        metavar="N",
        type=_grid,
        default=DEFAULT_REQUIREMENT_GRID,
        help="points per cube edge of the worst-case force and torque "
        f"(at most {MAX_REQUIREMENT_GRID})",
    )
    p.add_argument(
        "--workers",
        metavar="N",
        type=_positive_int,
        help="processes evaluating designs, this one included (default: this one, "
        "joined by one per other CPU when the sweep is large; at most the CPUs)",
    )
    p.add_argument("--force-workers", action="store_true", help="allow more --workers than CPUs")
    p.add_argument(
        "--force-designs",
        action="store_true",
        help=f"allow more than {MAX_DESIGNS} designs (up to {HARD_MAX_DESIGNS})",
    )
    p.add_argument("--scheduler", metavar="local|tcp://HOST:PORT", help="a Dask cluster")
    p.add_argument("--chunk-size", metavar="N", type=_positive_int, help="designs per task")
    p.add_argument("--no-plot", action="store_true", help="do not draw DIR/sweep.png")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output directory: new, empty, or an earlier sweep's of the same spec "
        "(which it carries on; another spec is refused)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="also write into a non-empty directory that holds no sweep (other files are kept)",
    )
