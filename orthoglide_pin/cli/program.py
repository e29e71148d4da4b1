"""Program command: ``program PROGRAM.nc``, what the planner will cut, without planning.

``orthoglide program PROGRAM.nc [--origin X Y Z] [--start X Y Z] [--offsets FILE]
[--tool-table FILE] [--block-delete] [--interpreter {builtin,linuxcnc,auto}]
[--json]`` reads the program with the built-in reader (or LinuxCNC's
``rs274``, see :func:`read_with`) and prints the number of moves by kind, the words read
without effect on the path (word, count, first line) and every refusal, one
per line; with ``--json`` one object with every move (program axes, machine
coordinates, and the world frame). A refused program exits with status 2 after
its listing, with one error line naming the first refusal.
"""

from __future__ import annotations

import argparse
import os
from collections import Counter
from typing import Any

from orthoglide_pin.cli import _common as common


def program_setup(args: argparse.Namespace, axes: Any) -> Any:
    """The :class:`~orthoglide_pin.program.offsets.Setup` of the offset and tool options.

    ``--origin`` and ``--start`` are world points [m] (the part zero, ``G54``'s
    default, and the tool's start), mapped to the program's axes.
    """
    from orthoglide_pin._validation import MAX_LENGTH, bounded_vector
    from orthoglide_pin.program.offsets import (
        make_setup,
        read_offsets,
        read_tool_diameters,
        read_tool_table,
    )

    what = "X Y Z or X,Y,Z [m]"
    origin = None if args.origin is None else common.numbers("--origin", args.origin, what, 3)
    start = None if args.start is None else common.numbers("--start", args.start, what, 3)
    if origin is not None:
        origin = bounded_vector("origin", origin, 3, MAX_LENGTH, "[m]")
    if start is not None:
        start = bounded_vector("start", start, 3, MAX_LENGTH, "[m]")
    return make_setup(
        origin=None if origin is None else axes.to_program(origin),
        offsets=None if args.offsets is None else read_offsets(args.offsets),
        tools=None if args.tool_table is None else read_tool_table(args.tool_table),
        diameters=None if args.tool_table is None else read_tool_diameters(args.tool_table),
        start=(0.0, 0.0, 0.0) if start is None else axes.to_program(start),
        block_delete=args.block_delete,
    )


def add_setup_options(p: argparse.ArgumentParser) -> None:
    """The offset and tool options of ``plan`` and ``program``."""
    p.add_argument(
        "--origin",
        nargs="+",
        metavar=("X", "Y", "Z"),
        help="part zero in the world frame [m]: G54's offset unless --offsets sets it",
    )
    p.add_argument(
        "--start", nargs="+", metavar=("X", "Y", "Z"), help="start point, world frame [m]"
    )
    p.add_argument(
        "--offsets",
        metavar="FILE",
        help="work offsets and G28/G30 points: LinuxCNC's parameter file (NUMBER VALUE, mm)",
    )
    p.add_argument(
        "--tool-table",
        metavar="FILE",
        help="tool lengths for G43 H: LinuxCNC's tool table (T1 P1 Z50.0, mm)",
    )
    p.add_argument(
        "--block-delete", action="store_true", help="skip the lines that start with '/'"
    )
    p.add_argument(
        "--interpreter",
        choices=("builtin", "linuxcnc", "auto"),
        default="builtin",
        help="who reads the program: the built-in reader (default), LinuxCNC's rs274 "
        "(the NGC language, G41/G42; Debian package linuxcnc-uspace), or auto (rs274 where "
        "the built-in reader refuses the program for LinuxCNC's language)",
    )


def _move(move: Any, axes: Any) -> dict[str, Any]:
    arc = move.kind == "arc"
    return {
        "line": move.line,
        "kind": move.kind,
        "start": move.start,
        "end": move.end,
        "center": move.center if arc else None,
        "normal": move.normal if arc else None,
        "turns": move.turns,
        "feed": move.feed,
        "dwell": move.dwell,
        "start_world": axes.to_world(move.start),
        "end_world": axes.to_world(move.end),
    }


def read_with(interpreter: str, text: str, setup: Any) -> Any:
    """The :class:`~orthoglide_pin.program.reader.ReadProgram` of ``--interpreter``.

    Through LinuxCNC's ``rs274`` (``linuxcnc``, or ``auto`` where the built-in
    reader refuses the program for LinuxCNC's language) the moves and their
    path control are ``rs274``'s, none ignored
    (:func:`~orthoglide_pin.program.rs274.read_rs274_program`).
    """
    from orthoglide_pin.planning.gcode import needs_linuxcnc
    from orthoglide_pin.program.reader import read_moves
    from orthoglide_pin.program.rs274 import read_rs274_program

    if interpreter != "linuxcnc":
        read = read_moves(text, setup)
        if interpreter == "builtin" or not any(needs_linuxcnc(r.reason) for r in read.refusals):
            return read
    return read_rs274_program(text, setup)


def _cmd_program(args: argparse.Namespace) -> int:
    from orthoglide_pin.program.axes import design_axes
    from orthoglide_pin.program.reader import check_refusals

    axes = design_axes(common.build_params(args))
    setup = program_setup(args, axes)
    read = read_with(args.interpreter, common.read_program_text(args.program), setup)
    kinds = Counter(m.kind for m in read.moves)
    payload = {
        "program": args.program,
        "interpreter": args.interpreter,
        "lines": read.lines,
        "axes": list(axes.mapping),
        "counts": {k: kinds.get(k, 0) for k in ("rapid", "line", "arc", "dwell")},
        "moves": [_move(m, axes) for m in read.moves],
        "ignored": [{"word": i.word, "count": i.count, "line": i.line} for i in read.ignored],
        "refusals": [{"line": r.line, "reason": r.reason} for r in read.refusals],
    }
    name = os.path.basename(args.program)
    counted = ", ".join(f"{n} {k}" for k, n in payload["counts"].items())
    text = [
        f"Program {name}: {len(read.moves)} moves ({counted}), {read.lines} lines read; "
        f"program axes {axes.describe()}",
        "Ignored: "
        + (", ".join(f"{i.word} ({i.count}, line {i.line})" for i in read.ignored) or "none"),
    ]
    text += [f"Refused: line {r.line}: {r.reason}" for r in read.refusals]
    if not read.refusals:
        text.append("Read as written.")
    status = common.emit(args, payload, "\n".join(text))
    if read.refusals:
        try:
            check_refusals(read)
        except Exception as exc:  # the one error line of the refused program
            return common.error(str(exc), "program")
    return status


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``program`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "program",
        _cmd_program,
        "read a part program (G-code) as the planner will cut it, without planning: its "
        "moves, the words ignored and every refusal",
    )
    p.add_argument("program", metavar="PROGRAM.nc", help="the G-code program")
    add_setup_options(p)
