"""The G-code language: words, modes, offsets, tools, cycles and LinuxCNC's interpreter.

This layer reads part programs into canonical :class:`~orthoglide_pin.program.moves.Move`
records. It knows nothing of the machine's dynamics; :mod:`orthoglide_pin.planning`
uses it.
"""

from orthoglide_pin.program.moves import KINDS, Move

__all__ = ["KINDS", "Move"]
