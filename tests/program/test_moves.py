"""The canonical move record shared by both readers."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from orthoglide_pin.program import KINDS, Move


def test_move_is_frozen_and_defaults_to_no_arc() -> None:
    move = Move(line=3, kind="line", start=np.zeros(3), end=np.array([0.01, 0.0, 0.0]), feed=0.01)
    assert move.center is None and move.normal is None and move.turns == 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        move.line = 4  # type: ignore[misc]


def test_kinds_are_the_documented_four() -> None:
    assert KINDS == ("rapid", "line", "arc", "dwell")
