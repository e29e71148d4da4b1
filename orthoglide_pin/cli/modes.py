"""Vibration command: ``modes X Y Z [--motor F] [--count N] [--model full|platform]``.

Prints the natural frequencies [Hz] of the machine at a tool point and, for
each mode, the tool tip's direction of motion, the platform's rotation per
metre of tool motion [rad/m] and the shares of kinetic energy in the platform
(with spindle and tool), the carriages (with the drives) and the members (see
:mod:`orthoglide_pin.elasticity.modes`). ``--json`` prints::

    {"point": [3], "model": "full" or "platform", "frequencies": [count] [Hz],
     "shapes": [{"frequency", "tool_direction": [3], "platform_rotation": [3],
                 "energy": {"platform", "carriages", "members"}}, ...],
     "drive_mass": [kg] (0 without --motor), "segments": int or null,
     "assumptions": [...]}
"""

from __future__ import annotations

import argparse

from orthoglide_pin.cli import _common as common


def _cmd_modes(args: argparse.Namespace) -> int:
    from orthoglide_pin.drives.motor import load_drive
    from orthoglide_pin.elasticity.modes import natural_frequencies

    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    drive = None if args.motor is None else load_drive(args.motor)
    result = natural_frequencies(params, point, drive, count=args.count, model=args.model)
    payload = result.to_dict()
    lines = [
        f"Natural frequencies at p = {common.fmt(point)} m ({result.model} model"
        + (f", {payload['segments']} elements per member" if payload["segments"] else "")
        + ")",
        "mode  frequency [Hz]  tool direction           rotation [rad/m]         "
        "energy: platform carriages members",
    ]
    for k, shape in enumerate(payload["shapes"], start=1):
        e = shape["energy"]
        direction = common.fmt(shape["tool_direction"], 1.0, "+.3f")
        rotation = common.fmt(shape["platform_rotation"], 1.0, "+.3g")
        lines.append(
            f"{k:4d}  {shape['frequency']:14.2f}  {direction:24s} {rotation:24s} "
            f"{e['platform']:.2f} {e['carriages']:.2f} {e['members']:.2f}"
        )
    lines.extend("  " + line for line in result.assumptions())
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``modes`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "modes",
        _cmd_modes,
        "natural frequencies and mode shapes of the machine at a point",
    )
    common.add_point(p)
    p.add_argument(
        "--motor",
        metavar="FILE.yaml",
        help="drive file: its rotor and screw inertia are reflected onto each carriage "
        "(without it the carriages move alone)",
    )
    p.add_argument(
        "--count", type=int, default=6, metavar="N", help="number of modes (platform model: 1-6)"
    )
    p.add_argument(
        "--model",
        choices=("full", "platform"),
        default="full",
        help="full: members with their masses, point by point; platform: the platform, "
        "the carriages and the bars' first bending, vectorised (fast, for maps)",
    )
