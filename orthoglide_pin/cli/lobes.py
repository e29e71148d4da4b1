"""Chatter command: ``lobes X Y Z --cut CUT.yaml``, the stability lobes at a tool point.

Prints the limiting axial depth against spindle speed at the point (world
frame [m], as ``modes`` and ``stiffness`` take it): the machine's modes there
with the cut file's modal damping, the tool's own modes, the cut file's tool,
material and (default) engagement, by semi-discretization with the zero-order
solution beside it (see :mod:`orthoglide_pin.machining.stability`).
``--out DIR`` writes ``lobes.json`` and ``lobes.csv`` (one row per speed).
``--json`` prints::

    {"point": [3], "feed_angle": [rad], "milling": "up" or "down",
     "radial_width_mm", "axial_depth_mm", "speeds_rpm": [s],
     "limit_depth_mm": [s] (null: stable up to 50 mm), "zero_order_depth_mm": [s],
     "minimum_depth_mm", "modes": [{"frequency", "damping", "mass", "stiffness",
     "shape": [2], "source"}], "method", "spindle_speed_rpm" or null,
     "limit_at_speed_mm" or null, "margin" or null, "files": [...]}

``lobes --map`` gives the limiting depth at one speed over the design's cube
instead (:mod:`orthoglide_pin.cli.lobes_map`).
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli.lobes_map import add_map_options, check_mixing, degrees_option, run_map
from orthoglide_pin.exceptions import InvalidParameterError

#: Files written by ``--out``.
FILES = ("lobes.json", "lobes.csv")


def _speeds(text: str) -> np.ndarray[Any, Any]:
    parts = text.split(":")
    try:
        low, high, count = float(parts[0]), float(parts[1]), int(parts[2])
        ok = len(parts) == 3 and 0.0 < low < high < 1e6 and 2 <= count <= 5000
    except (ValueError, IndexError):
        ok = False
    if not ok:
        raise InvalidParameterError(
            "--speeds", text, "MIN:MAX:N in rpm, 0 < MIN < MAX, N from 2 to 5000"
        )
    return np.linspace(low, high, count) * (2.0 * math.pi / 60.0)


def _csv(payload: dict[str, Any]) -> str:
    rows = ["speed_rpm,limit_depth_mm,zero_order_depth_mm"]
    zoa = payload["zero_order_depth_mm"] or [None] * len(payload["speeds_rpm"])
    for rpm, sd, zo in zip(payload["speeds_rpm"], payload["limit_depth_mm"], zoa, strict=True):
        cells = [f"{rpm:.6g}"] + ["" if v is None else f"{v:.6g}" for v in (sd, zo)]
        rows.append(",".join(cells))
    return "\n".join(rows) + "\n"


def _cmd_lobes(args: argparse.Namespace) -> int:
    from orthoglide_pin._outdir import atomic_directory
    from orthoglide_pin._paths import output_directory
    from orthoglide_pin.drives.motor import load_drive
    from orthoglide_pin.machining.cutting import RPM_PER_RAD_S, read_cut_file
    from orthoglide_pin.machining.stability import LOBE_SPEEDS, stability_lobes

    if args.map:
        return run_map(args)
    check_mixing(args)
    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    if args.out is not None:
        output_directory(args.out, force=args.force)  # before any work
    cut = read_cut_file(args.cut)
    drive = None if args.motor is None else load_drive(args.motor)
    speeds = LOBE_SPEEDS if args.speeds is None else _speeds(args.speeds)
    degrees = degrees_option(args.feed_angle)
    angle = math.radians(degrees)
    lobes = stability_lobes(
        cut, point, params=params, speeds=speeds, feed_angle=angle, drive=drive, model=args.model
    )
    payload = lobes.to_dict()
    speed = cut.spindle_speed
    limit = None if speed is None else lobes.limit_at(speed)
    depth = lobes.engagement.axial_depth
    payload["spindle_speed_rpm"] = None if speed is None else speed * RPM_PER_RAD_S
    payload["limit_at_speed_mm"] = None if limit is None or math.isinf(limit) else limit * 1e3
    payload["margin"] = None if limit is None or math.isinf(limit) else limit / depth
    payload["files"] = list(FILES) if args.out is not None else []
    if args.out is not None:
        with atomic_directory(args.out, force=args.force) as tmp:
            (tmp / "lobes.json").write_text(json.dumps(payload, indent=1) + "\n", "utf-8")
            (tmp / "lobes.csv").write_text(_csv(payload), "utf-8")
    freq = ", ".join(f"{f:.1f}" for f in lobes.model.frequencies)
    low = int(np.argmin(lobes.depths))
    lines = [
        f"Stability lobes at p = {common.fmt(point)} m ({args.model} model; "
        f"{lobes.engagement.milling} milling, {depth * 1e3:g} mm deep, "
        f"{lobes.engagement.radial_width * 1e3:g} mm wide; feed at {degrees:g} deg)",
        f"  modes at the tool [Hz]: {freq}",
        f"  lowest limit {lobes.minimum * 1e3:.4g} mm at "
        f"{lobes.speeds[low] * RPM_PER_RAD_S:.0f} rpm",
    ]
    if payload["margin"] is not None:
        lines.append(
            f"  at {payload['spindle_speed_rpm']:.0f} rpm: limit "
            f"{payload['limit_at_speed_mm']:.4g} mm, margin {payload['margin']:.3g} "
            f"({'stable' if payload['margin'] > 1.0 else 'chatter'})"
        )
    lines.append("  speed [rpm]  limit [mm]  zero-order [mm]")
    every = max(1, lobes.speeds.size // 20)
    zoa = payload["zero_order_depth_mm"]
    for i in range(0, lobes.speeds.size, every):
        sd, zo = payload["limit_depth_mm"][i], zoa[i]
        lines.append(
            f"  {payload['speeds_rpm'][i]:11.0f}  "
            + ("      > 50" if sd is None else f"{sd:10.4g}")
            + ("       > 50" if zo is None else f"  {zo:15.4g}")
        )
    if args.out is not None:
        lines.append(f"Written to {args.out}: " + ", ".join(FILES))
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``lobes`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "lobes",
        _cmd_lobes,
        "chatter stability lobes at a tool point: the limiting axial depth against spindle "
        "speed, from the machine's modes there and the cut file",
    )
    for name in ("x", "y", "z"):
        p.add_argument(name, nargs="?", metavar=name.upper(), help=f"tool point {name} [m]")
    p.add_argument(
        "--cut",
        required=True,
        metavar="CUT.yaml",
        help="cut file: tool (and its modes), material, engagement, spindle speed, modal damping",
    )
    p.add_argument(
        "--motor",
        metavar="FILE.yaml",
        help="drive file: its rotor and screw inertia are reflected onto each carriage",
    )
    p.add_argument(
        "--model",
        choices=("platform", "full"),
        default="platform",
        help="the machine's vibration model (see modes): platform (fast) or full",
    )
    p.add_argument(
        "--feed-angle",
        default="0",
        metavar="DEG",
        help="the feed's direction in the program's X-Y plane, from +X towards +Y [deg]",
    )
    p.add_argument(
        "--speeds",
        metavar="MIN:MAX:N",
        help="spindle speeds [rpm] (default 2000:24000:200)",
    )
    add_map_options(p)
    p.add_argument(
        "--out",
        metavar="DIR",
        help="also write lobes.json and lobes.csv there (with --map: lobes_map.json and "
        "lobes_map.csv)",
    )
    p.add_argument("--force", action="store_true", help="also write into a non-empty directory")
