"""Drive command: ``drive --example`` prints a shipped drive file, ``--check FILE`` reads one.

``orthoglide drive --example > drive.yaml`` gives a complete drive file to edit
(the prototype's ball screws and an illustrative motor, every value commented),
for ``report --motor drive.yaml`` and ``dynamics --motor drive.yaml``.
``orthoglide drive --check drive.yaml`` reads it as those commands do and
prints what it holds, or the one-line error that they would give.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from orthoglide_pin.cli import _common as common


def _cmd_drive(args: argparse.Namespace) -> int:
    from orthoglide_pin.drives.motor import load_drive
    from orthoglide_pin.drives.shipped import example_drive_file, example_drive_text

    if args.check is None:
        text = example_drive_text(args.example)
        if args.json:
            payload = {"example": args.example, "path": str(example_drive_file(args.example))}
            return common.emit(args, {**payload, "text": text}, text)
        sys.stdout.write(text)  # the file as shipped, comments included
        return 0
    drive = load_drive(args.check)
    train, motor = drive.train, drive.motor
    payload = {
        "drive_train": dataclasses.asdict(train),
        "reflected_inertia": train.reflected_inertia,
        "motor": None if motor is None else dataclasses.asdict(motor),
    }
    lines = [f"Drive read from {args.check}:", *(f"  {s}" for s in train.assumptions()[1:])]
    if motor is None:
        lines.append("  no motor data: `report` gives the requirements but no verdict")
    else:
        figures = (
            ("rated torque", motor.rated_torque, "N.m"),
            ("peak torque", motor.peak_torque, "N.m"),
            ("maximum speed", motor.max_speed, "rpm"),
        )
        shown = ", ".join(f"{name} {value:g} {unit}" for name, value, unit in figures if value)
        curve = "" if motor.speed_torque_curve is None else ", a speed-torque curve"
        lines.append(f"  motor {motor.name}: {shown or 'no figures'}{curve}")
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``drive`` command to the ``orthoglide`` parser."""
    from orthoglide_pin.drives.shipped import DEFAULT_EXAMPLE, EXAMPLE_DRIVES

    p = common.add_command(
        sub,
        parent,
        "drive",
        _cmd_drive,
        "drive files for --motor: print the shipped example, or check a file",
    )
    group = p.add_mutually_exclusive_group(required=True)
    group.add_argument(
        "--example",
        nargs="?",
        const=DEFAULT_EXAMPLE,
        choices=tuple(EXAMPLE_DRIVES),
        help=f"print a shipped example drive file (default example: {DEFAULT_EXAMPLE}), "
        "e.g. `orthoglide drive --example > drive.yaml`",
    )
    group.add_argument(
        "--check",
        metavar="FILE.yaml",
        help="read a drive file as `report --motor` does and print what it holds",
    )
