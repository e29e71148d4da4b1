"""The built-in reader of the program layer, where it exists, as moves.

The differential tests compare it with LinuxCNC's ``rs274``. Until the
program layer's own reader (``orthoglide_pin.program.read_program_text``,
returning :class:`~orthoglide_pin.program.Move` records, or an object with
``moves``) is there, they are skipped with that reason.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import pytest

import orthoglide_pin.program as program_layer
from orthoglide_pin.program import Move

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
