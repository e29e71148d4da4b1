"""Simulation command: ``mjcf -o FILE.xml [--motor FILE.yaml]``, the machine for MuJoCo.

The file has the URDF's bodies, joints and inertials, the loop closures as
equality constraints, the drives as armature, friction and damping of the
sliders, and one force actuator per slider (limited by the motor's peak
torque through the screw when the drive file gives it). MuJoCo compiles it
before it is written (``pip install 'orthoglide-pin[sim]'``).
"""

from __future__ import annotations

import argparse

from orthoglide_pin.cli import _common as common


def _cmd_mjcf(args: argparse.Namespace) -> int:
    from orthoglide_pin.drives.motor import Drive, load_drive
    from orthoglide_pin.machine.description import load_loops
    from orthoglide_pin.simulation.mjcf import drive_terms, write_mjcf

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


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``mjcf`` command to the ``orthoglide`` parser."""
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
