"""Shared by the program layer's tests: the corpus, and the built-in reader where it exists.

The differential tests compare it with LinuxCNC's ``rs274``. Until the
program layer's own reader (``orthoglide_pin.program.read_program_text``,
returning :class:`~orthoglide_pin.program.Move` records, or an object with
``moves``) is there, they are skipped with that reason.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import orthoglide_pin.program as program_layer
from orthoglide_pin.program import Move

#: The program corpus (public programs with their sources, SOURCES.md).
CORPUS = Path(__file__).parent / "corpus"
#: The tool table the corpus is read with: number -> (length [m], diameter [m]).
CORPUS_TOOLS = {n: (1e-3 * n, 0.5e-3) for n in range(1, 100)}
#: The corpus's programs (file names), every file but its SOURCES.md.
CORPUS_PROGRAMS = sorted(p.name for p in CORPUS.iterdir() if p.name != "SOURCES.md")
#: Programs of the corpus that LinuxCNC refuses as written: name -> (line, message part).
CORPUS_REFUSED = {
    "cncjs-full-circle-without-xyz.gcode": (11, "R i j k words all missing for arc"),
}
#: Name of the built-in reader of a program's text in :mod:`orthoglide_pin.program`.
READER = "read_program_text"


def builtin_reader() -> Callable[..., Sequence[Move]]:
    """The built-in reader (text -> moves), or skip the test."""
    reader: Any = getattr(program_layer, READER, None)
    if reader is None:
        pytest.skip(f"the built-in reader orthoglide_pin.program.{READER} is not there yet")

    def read(text: str, **options: Any) -> Sequence[Move]:
        result = reader(text, **options)
        return list(getattr(result, "moves", result))

    return read


def planning_reader(text: str) -> list[Move]:
    """The planning layer's present reader (``og.read_program``) as moves.

    It reads the subset in world coordinates with the part zero at the world
    origin, which on a program without offsets are the machine coordinates of
    ``rs274``; it knows neither ``G94`` (the default, dropped here) nor ``P``
    turns, and projects arc centres. To be replaced by :func:`builtin_reader`.
    """
    from orthoglide_pin.planning.gcode import read_program

    out = []
    for b in read_program(text.replace(" G94", "")).blocks:
        if b.kind != "arc":
            out.append(Move(b.line, b.kind, b.start, b.end, feed=b.feed, dwell=b.dwell))
            continue
        normal = np.zeros(3)
        normal[b.plane[2]] = 1.0
        turns = int(math.copysign(math.ceil(abs(b.sweep) / (2 * math.pi) - 1e-9), b.sweep))
        out.append(
            Move(
                b.line, "arc", b.start, b.end, b.feed, center=b.center, normal=normal, turns=turns
            )
        )
    return out
