"""Lines into words as LinuxCNC reads them: comments, block delete, % lines, O words."""

from __future__ import annotations

import pytest

from orthoglide_pin.program.words import NGC_LANGUAGE, read_line


def _words(text: str) -> list[str]:
    line = read_line(text, 1)
    assert not line.refusals, line.refusals
    return [w.text for w in line.words]


def test_comments_as_linuxcnc_reads_them() -> None:
    assert _words("G1 X1 (a; b) Y2 ; rest (c)") == ["G1", "X1", "Y2"]
    assert _words("(MSG, hello) G0 X1") == ["G0", "X1"]
    assert _words("g 0 x 1 0 . 5") == ["G0", "X10.5"]  # spaces anywhere, any case


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("G1 (a (b) c)", "inside a comment"),
        ("G1 X1 (open", "not closed"),
        ("G1 X1 )", "without its"),
        ("G1 X#1", NGC_LANGUAGE),
        ("G1 X[1+2]", NGC_LANGUAGE),
        ("O100 sub", "O word"),
        ("G1 A10", "3-axis"),
        ("G1 E5 H1 e", "unreadable"),
        ("G1 X", "unreadable"),
    ],
)
def test_what_is_refused(text: str, reason: str) -> None:
    line = read_line(text, 7)
    assert line.refusals and reason in line.refusals[0].reason
    assert line.refusals[0].line == 7


def test_percent_block_delete_and_program_numbers() -> None:
    assert read_line("% some text", 1).words == []
    line = read_line("/G0 X1", 1)
    assert line.block_delete and [w.text for w in line.words] == ["G0", "X1"]
    assert read_line("O1000", 1).program_number
    assert read_line("O1000 (PART)", 1).program_number
