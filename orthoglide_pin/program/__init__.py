"""The G-code language: words, modes, offsets, tools, cycles and LinuxCNC's interpreter.

This layer reads part programs into canonical :class:`~orthoglide_pin.program.moves.Move`
records. It knows nothing of the machine's dynamics; :mod:`orthoglide_pin.planning`
uses it.
"""

from orthoglide_pin.program.compare import compare_moves
from orthoglide_pin.program.moves import KINDS, Move
from orthoglide_pin.program.rs274 import read_rs274, read_rs274_text

__all__ = ["KINDS", "Move", "compare_moves", "read_rs274", "read_rs274_text"]
