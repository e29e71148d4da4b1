"""The G-code language: words, modes, offsets, tools, cycles, arcs and the program's axes.

This layer reads part programs into canonical
:class:`~orthoglide_pin.program.moves.Move` records, in machine coordinates of
the program's axes. It knows nothing of the machine's dynamics;
:mod:`orthoglide_pin.planning` uses it.

* :mod:`~orthoglide_pin.program.words`: lines into words (comments, block
  delete, ``%`` lines, program numbers);
* :mod:`~orthoglide_pin.program.block` and :mod:`~orthoglide_pin.program.modes`:
  the words accepted, ignored or refused, and the modal state;
* :mod:`~orthoglide_pin.program.settings`: modes and offsets set by a block;
* :mod:`~orthoglide_pin.program.offsets`: work offsets, reference points, tools;
* :mod:`~orthoglide_pin.program.arcs`: arcs as LinuxCNC cuts them;
* :mod:`~orthoglide_pin.program.cycles`: canned cycles expanded;
* :mod:`~orthoglide_pin.program.reader`: the built-in reader;
* :mod:`~orthoglide_pin.program.axes`: the program's axes on the machine.
"""

from orthoglide_pin.program.axes import PROTOTYPE_AXES, ProgramAxes, design_axes
from orthoglide_pin.program.compare import compare_moves
from orthoglide_pin.program.moves import KINDS, Move
from orthoglide_pin.program.offsets import Setup, make_setup, read_offsets, read_tool_table
from orthoglide_pin.program.reader import Ignored, ReadProgram, check_refusals, read_moves
from orthoglide_pin.program.rs274 import read_rs274, read_rs274_text
from orthoglide_pin.program.words import Refusal

#: The kinds of a :class:`Move`: rapid, line, arc, dwell (the package-wide name of ``KINDS``).
MOVE_KINDS = KINDS

__all__ = [
    "KINDS",
    "MOVE_KINDS",
    "PROTOTYPE_AXES",
    "Ignored",
    "Move",
    "ProgramAxes",
    "ReadProgram",
    "Refusal",
    "Setup",
    "check_refusals",
    "compare_moves",
    "design_axes",
    "make_setup",
    "read_moves",
    "read_offsets",
    "read_rs274",
    "read_rs274_text",
    "read_tool_table",
]
