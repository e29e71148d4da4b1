"""A line's words sorted: every class of word accepted, ignored or refused, all in one pass."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.program.block import read_block
from orthoglide_pin.program.modes import REFUSED_G, State
from orthoglide_pin.program.words import read_line

#: Every word a 3-axis CAM post writes that does not move the tool.
NON_MOVING = (
    "S12000 M3", "M4", "M5", "M7", "M8", "M9", "T1", "M6", "M0", "M1", "M60", "M62 P1",
    "M63 P2", "M64 P1", "M65 P1", "M66 P0 L0 Q1", "M67 E0 Q5", "M68 E1 Q2", "G40", "G94",
    "G96 S100", "G97", "M19", "M48", "M49", "M50 P1", "M51", "M52", "M53", "M100 P1 Q2", "D1",
)  # fmt: skip


def _state() -> State:
    return State(np.zeros(3), np.zeros((9, 3)), np.zeros(3), np.zeros(3), {})


def _block(text: str, state: State | None = None):
    seen: list[tuple[str, int]] = []
    block = read_block(read_line(text, 3), state or _state(), lambda w, n: seen.append((w, n)))
    return block, seen


@pytest.mark.parametrize("text", NON_MOVING)
def test_a_word_that_does_not_move_the_tool_is_read_and_listed(text: str) -> None:
    block, seen = _block(text)
    assert block.refusals == [] and block.motion is None
    assert seen and all(n == 3 for _, n in seen)


def test_modal_words_are_read_not_listed() -> None:
    block, seen = _block("G17 G21 G90 G91.1 G49 G80 G54 G61 G98")
    assert block.refusals == [] and seen == []
    assert {170, 210, 900, 911, 490, 800, 540, 610, 980} <= block.gs


@pytest.mark.parametrize("code", sorted(REFUSED_G))
def test_each_refused_g_word_has_its_reason(code: int) -> None:
    word = f"G{code // 10}" if code % 10 == 0 else f"G{code / 10:g}"
    block, _ = _block(f"{word} X1")
    assert [r.reason for r in block.refusals][:1] == [REFUSED_G[code]]


def test_every_problem_of_a_line_is_listed() -> None:
    block, _ = _block("G0 G1 X1 X2 M98 G41 M77 P3")
    reasons = " | ".join(r.reason for r in block.refusals)
    for words in ("given twice", "G41", "M98", "unsupported word M77", "two motion words"):
        assert words in reasons


def test_motion_is_modal_and_g80_cancels_it() -> None:
    state = _state()
    state.motion = 10
    block, _ = _block("X5", state)
    assert block.motion == 10 and block.axes == {0: 5.0}
    block, _ = _block("G80 X5", state)
    assert "G80" in block.refusals[0].reason
    block, _ = _block("G2 I5", state)  # no end point: a full circle, as LinuxCNC 2.9 cuts it
    assert block.motion == 20 and not block.refusals and block.centre == {0: 5.0}
    block, _ = _block("G0", state)  # a motion word alone: a move where the tool is
    assert block.motion == 0 and not block.refusals
    block, _ = _block("G0 G80 X3", state)  # G80 with another motion: the motion is made
    assert block.motion == 0 and not block.refusals
