"""Shared by the program layer's tests: the corpus, and the built-in reader.

The differential tests compare the built-in reader
(:func:`~orthoglide_pin.program.read_moves`) with LinuxCNC's ``rs274``, both
from the machine origin without offsets.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from orthoglide_pin.program import Move, ReadProgram, check_refusals, make_setup, read_moves

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

#: What the built-in reader refuses in LinuxCNC's language, read through rs274:
#: program -> the number of refusals (all listed in one pass, each naming LinuxCNC).
CORPUS_NEEDS_LINUXCNC = {
    "cncjs-helical-thread-milling.gcode": 1,
    "linuxcnc-comp-g1.ngc": 1,
    "linuxcnc-comp.ngc": 4,
    "linuxcnc-daisy.ngc": 113,  # and an A axis word (twice) and G93: DAISY_OTHERS
    "linuxcnc-flowsnake.ngc": 26,
    "linuxcnc-good-arc-big-imperial.ngc": 1,
    "linuxcnc-hole-circle.ngc": 1,
    "linuxcnc-offsets.ngc": 6,
    "linuxcnc-polar.ngc": 5,
    "linuxcnc-spiral.ngc": 3,
    "linuxcnc-tp-bezel.ngc": 156,
    "linuxcnc-useful-subroutines.ngc": 46,
}
#: The daisy's refusals that are not LinuxCNC's language.
DAISY_OTHERS = ("axis word A0: a 3-axis machine", "inverse-time feed G93")
#: What a refusal for LinuxCNC's language names.
NEEDS_LINUXCNC = ("LinuxCNC's interpreter", "read the program through LinuxCNC")


def read_builtin(text: str, tools: dict[int, tuple[float, float]] | None = None) -> ReadProgram:
    """The built-in reader's reading of ``text`` (machine origin, no offsets), refusals kept."""
    lengths = None if tools is None else {n: length for n, (length, _) in tools.items()}
    return read_moves(text, make_setup(tools=lengths))


def builtin_reader() -> Callable[..., Sequence[Move]]:
    """The built-in reader (text -> moves): :func:`read_moves` from the machine origin.

    It raises the :class:`~orthoglide_pin.exceptions.ProgramError` naming every
    refusal in one line (:func:`check_refusals`), as ``orthoglide plan`` does.
    """

    def read(text: str, tools: dict[int, tuple[float, float]] | None = None) -> Sequence[Move]:
        return list(check_refusals(read_builtin(text, tools)).moves)

    return read
