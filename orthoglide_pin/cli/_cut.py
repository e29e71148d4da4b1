"""The cut file of ``report --cut`` and ``sweep --cut``: reading it, and what the terminal shows.

The cut file is read (and refused, in one line) before any work; its spindle
speed is the file's, or the program's ``S`` when the file says ``program``
(:func:`~orthoglide_pin.machining.plan_samples.program_spindle_speed`).
"""

from __future__ import annotations

import argparse
import os
from typing import TYPE_CHECKING, Any

from orthoglide_pin.cli import _common as common

if TYPE_CHECKING:
    from orthoglide_pin.machining.cutting import CutConditions
    from orthoglide_pin.report.assemble import ReportData

#: The help of ``--cut``.
CUT_HELP = (
    "cut file (tool, material, engagement, spindle speed, modal damping; "
    "`orthoglide lobes --help`, formats reference)"
)


def add_cut_option(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--cut CUT.yaml`` to ``parser``; ``what`` says what it adds."""
    parser.add_argument("--cut", metavar="CUT.yaml", help=f"{CUT_HELP}: {what}")


def read_cut(args: argparse.Namespace) -> tuple[CutConditions | None, str, float | None]:
    """The cut file of ``args.cut`` (``None`` without one), its name and the program's speed.

    The program's spindle speed [rad/s] is read from ``args.program``'s ``S``
    words when the cut file says ``program`` (``None`` otherwise).

    Raises:
        CutConditionsError: A bad cut file, or ``S`` words that differ.
    """
    if args.cut is None:
        return None, "cut", None
    from orthoglide_pin.machining.cutting import read_cut_file
    from orthoglide_pin.machining.plan_samples import program_spindle_speed

    cut = read_cut_file(args.cut)
    speed = None
    if cut.spindle_speed is None and getattr(args, "program", None) is not None:
        speed = program_spindle_speed(common.read_program_text(args.program))
    return cut, os.path.basename(args.cut), speed


def accuracy_lines(data: ReportData) -> list[str]:
    """The report's accuracy section in a few lines of text."""
    from orthoglide_pin.report.accuracy import accuracy_dict

    if data.accuracy is None:
        return []
    d: dict[str, Any] = accuracy_dict(data.accuracy)
    speed = d["spindle_speed_rpm"]
    head = f"Part accuracy, cut {d['cut']} ({d['material']}" + (
        ")" if speed is None else f", {speed:.0f} rpm)"
    )
    if not d["program"]:
        return [
            head
            + ": lowest limiting depth "
            + ", ".join(
                f"{lb['point_name']} {1e3 * lb['minimum_depth']:.3g} mm" for lb in d["lobes"]
            )
            + (
                ""
                if speed is None
                else "; at the speed "
                + ", ".join(
                    f"{lb['point_name']} "
                    + ("stable" if lb["margin"] is None else f"margin {lb['margin']:.3g}")
                    for lb in d["lobes"]
                )
            )
        ]
    s, st = d["surface_error"], d["stability"]
    lines = [
        head
        + ": surface error static "
        + ", ".join(f"{k} {1e6 * s[k]['max']:+.2f} um" for k in ("static", "generated", "peak"))
        + (f" (peak on line {s['peak']['line']})" if s["peak"]["line"] is not None else ""),
    ]
    if st["min"] is not None:
        lines.append(
            f"  stability margin at least {st['min']:.3g} (line {st['line']}); "
            f"{st['unstable_blocks']} of {st['blocks']} cutting lines chatter"
        )
    return lines
