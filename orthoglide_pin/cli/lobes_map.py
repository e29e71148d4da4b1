"""``lobes --map --cut CUT.yaml``: the limiting axial depth over the design's cube.

The limit at one spindle speed (the cut file's, or ``--speed``) at each point
of an N x N x N grid of the design's prescribed cube (its corner Q1 and side,
corners included, as the report and the sweep take it), by
:func:`~orthoglide_pin.machining.stability.limit_depth_map`; the machine's
lowest natural frequency at each point beside it. ``--out DIR`` writes
``lobes_map.json`` (the ``--json`` object) and ``lobes_map.csv`` (one row per
point). ``--json`` prints::

    {"design", "model", "grid", "q1": [3] [m], "side" [m], "spindle_speed_rpm",
     "feed_angle" [rad], "milling", "radial_width" [m], "axial_depth" [m],
     "lowest": {"point", "limit", "margin", "lowest_mode"},
     "highest": {...} (limit null: stable up to 50 mm), "unstable_points",
     "points": [n][3] [m], "limit": [n] [m], "margin": [n], "lowest_mode": [n] [Hz],
     "method", "files"}
"""

from __future__ import annotations

import argparse
import math
from typing import Any, Final

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError

#: Files written by ``--map --out``.
MAP_FILES: Final = ("lobes_map.json", "lobes_map.csv")
#: Default points per edge of the cube grid.
DEFAULT_GRID: Final[int] = 5
#: Most points per edge (1,331 points: about 8 s with the platform model).
MAX_GRID: Final[int] = 11
#: Highest spindle speed of ``--speed`` [rpm].
MAX_RPM: Final[float] = 1e6


def grid_size(text: str | None) -> int:
    """``--grid N``: points per edge of the cube, 2 to :data:`MAX_GRID` (default 5)."""
    if text is None:
        return DEFAULT_GRID
    try:
        n = int(text)
    except ValueError:
        n = 0
    if not 2 <= n <= MAX_GRID:
        raise InvalidParameterError("--grid", text, f"a whole number from 2 to {MAX_GRID}")
    return n


def spindle_rpm(text: str | None, cut_rpm: float | None) -> float:
    """``--speed RPM``, else the cut file's speed [rpm]; refused when neither is given."""
    if text is None:
        if cut_rpm is None:
            raise InvalidParameterError(
                "--speed", None, "a spindle speed [rpm]: the cut file's is the program's"
            )
        return cut_rpm
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0.0 < value < MAX_RPM):
        raise InvalidParameterError("--speed", text, f"a spindle speed in (0, {MAX_RPM:g}) [rpm]")
    return value


def degrees_option(text: str) -> float:
    """``--feed-angle DEG``: a finite number from -360 to 360 [deg]."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and -360.0 <= value <= 360.0):
        raise InvalidParameterError("--feed-angle", text, "a number from -360 to 360 [deg]")
    return value


def check_mixing(args: argparse.Namespace) -> None:
    """Refuse a point with ``--map``, map options without it, a missing point without it."""
    given = [n.upper() for n in ("x", "y", "z") if getattr(args, n) is not None]
    if args.map:
        if given:
            raise InvalidParameterError(
                " ".join(given), " ".join(getattr(args, n.lower()) for n in given),
                "no point with --map (it covers the cube)",
            )  # fmt: skip
        if args.speeds is not None:
            raise InvalidParameterError("--speeds", args.speeds, "--speed RPM with --map")
        return
    for option, value in (("--grid", args.grid), ("--speed", args.speed)):
        if value is not None:
            raise InvalidParameterError(option, value, f"{option} with --map only")
    if len(given) != 3:
        shown = " ".join(getattr(args, n.lower()) for n in given) or None
        raise InvalidParameterError("X Y Z", shown, "three numbers [m] (a tool point), or --map")


def _entry(points: Any, limit: Any, depth: float, lowest: Any, i: int) -> dict[str, Any]:
    value = float(limit[i])
    finite = math.isfinite(value)
    return {
        "point": points[i].tolist(),
        "limit": value if finite else None,
        "margin": value / depth if finite else None,
        "lowest_mode": float(lowest[i]),
    }


def _csv(points: Any, limit: Any, depth: float, lowest: Any) -> str:
    rows = ["x_m,y_m,z_m,limit_m,margin,lowest_mode_hz"]
    for p, d, f in zip(points, limit, lowest, strict=True):
        cells = [f"{v:.9g}" for v in p]
        cells += [f"{d:.9g}", f"{d / depth:.9g}"] if math.isfinite(d) else ["", ""]
        rows.append(",".join([*cells, f"{f:.6g}"]))
    return "\n".join(rows) + "\n"


def _lines(payload: dict[str, Any], depth: float, digest: str) -> list[str]:
    n, q1, side = payload["grid"], payload["q1"], payload["side"]
    out = [
        f"Limiting depth over the cube of design {digest} ({n}x{n}x{n} points, side "
        f"{side * 1e3:g} mm from Q1 = {common.fmt(q1, 1e3, '.1f')} mm; {payload['model']} model; "
        f"{payload['milling']} milling, {depth * 1e3:g} mm deep, "
        f"{payload['radial_width'] * 1e3:g} mm wide, {payload['spindle_speed_rpm']:.0f} rpm; "
        f"feed at {math.degrees(payload['feed_angle']):g} deg)"
    ]
    for word in ("lowest", "highest"):
        e = payload[word]
        limit = "> 50 mm" if e["limit"] is None else f"{e['limit'] * 1e3:.4g} mm"
        text = f"  {word + ' limit':14s} {limit} at p = {common.fmt(e['point'], 1e3, '.1f')} mm"
        text += f" (lowest mode {e['lowest_mode']:.1f} Hz)"
        if word == "lowest" and e["margin"] is not None:
            verdict = "stable" if e["margin"] > 1.0 else "chatter"
            text += f": margin of the {depth * 1e3:g} mm cut {e['margin']:.3g} ({verdict})"
        out.append(text)
    out.append(f"  unstable at {payload['unstable_points']} of {n**3} points (margin at most 1)")
    return out


def run_map(args: argparse.Namespace) -> int:
    """The ``lobes --map`` command (see the module)."""
    from orthoglide_pin._io import json_text
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.drives.motor import load_drive
    from orthoglide_pin.elasticity.modes import natural_frequencies
    from orthoglide_pin.kinetostatics.workspace import cube_grid
    from orthoglide_pin.machine.digest import design_digest
    from orthoglide_pin.machining.cutting import RPM_PER_RAD_S, read_cut_file
    from orthoglide_pin.machining.stability import limit_depth_map

    check_mixing(args)
    n = grid_size(args.grid)
    params = common.build_params(args)
    if args.out is not None:
        output_directory(args.out, force=args.force)  # before any work
    cut = read_cut_file(args.cut)
    drive = None if args.motor is None else load_drive(args.motor)
    cut_rpm = None if cut.spindle_speed is None else cut.spindle_speed * RPM_PER_RAD_S
    rpm = spindle_rpm(args.speed, cut_rpm)
    angle = math.radians(degrees_option(args.feed_angle))
    cube = params.workspace
    points = cube_grid(cube.q1, cube.side, n).points().reshape(-1, 3)
    limit = limit_depth_map(
        cut, points, speed=rpm / RPM_PER_RAD_S, feed_angle=angle, params=params,
        drive=drive, model=args.model,
    )  # fmt: skip
    lowest = natural_frequencies(params, points, drive, count=1, model=args.model).lowest
    eng = next((e for e in cut.engagements if e.lines is None), cut.engagements[0])
    depth = eng.axial_depth
    finite = np.isfinite(limit)
    low = int(np.argmin(limit))
    high = int(np.argmax(np.where(finite, limit, np.inf)))
    digest = design_digest(params)
    payload: dict[str, Any] = {
        "design": digest,
        "model": args.model,
        "grid": n,
        "q1": cube.q1.tolist(),
        "side": float(cube.side),
        "spindle_speed_rpm": rpm,
        "feed_angle": angle,
        "milling": eng.milling,
        "radial_width": eng.radial_width,
        "axial_depth": depth,
        "lowest": _entry(points, limit, depth, lowest, low),
        "highest": _entry(points, limit, depth, lowest, high),
        "unstable_points": int(np.count_nonzero(finite & (limit <= depth))),
        "points": points.tolist(),
        "limit": [float(v) if math.isfinite(v) else None for v in limit],
        "margin": [float(v) / depth if math.isfinite(v) else None for v in limit],
        "lowest_mode": lowest.tolist(),
        "method": "semi-discretization (first order) at one spindle speed, point by point",
        "files": list(MAP_FILES) if args.out is not None else [],
    }
    lines = _lines(payload, depth, digest)
    if args.out is not None:
        with atomic_directory(args.out, force=args.force) as tmp:
            (tmp / "lobes_map.json").write_text(json_text(payload, indent=1) + "\n", "utf-8")
            (tmp / "lobes_map.csv").write_text(_csv(points, limit, depth, lowest), "utf-8")
        lines.append(f"Written to {args.out}: " + ", ".join(MAP_FILES))
    return common.emit(args, payload, "\n".join(lines))


def add_map_options(p: argparse.ArgumentParser) -> None:
    """``--map``, ``--grid N`` and ``--speed RPM`` of the ``lobes`` command."""
    p.add_argument(
        "--map",
        action="store_true",
        help="instead of the lobes at a point (no X Y Z), the limiting depth at one spindle "
        "speed over an N x N x N grid of the design's cube; --out writes lobes_map.json "
        "and lobes_map.csv",
    )
    p.add_argument(
        "--grid",
        metavar="N",
        help=f"with --map: points per edge of the cube, 2 to {MAX_GRID} (default {DEFAULT_GRID})",
    )
    p.add_argument(
        "--speed",
        metavar="RPM",
        help="with --map: the spindle speed [rpm] (default: the cut file's)",
    )
