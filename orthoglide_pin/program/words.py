"""The words of a part program's lines, as LinuxCNC's interpreter reads them.

A line is read into its words (a letter and a number) after:

* a leading ``/`` (block delete): the line is marked, the reader skips it when
  asked to honour block delete;
* comments: ``( ... )`` closes at the first ``)`` (a ``;`` inside it is part
  of the comment, so ``(a; b)`` is one comment); ``;`` outside parentheses
  starts a comment to the end of the line; a comment opened inside another is
  refused, as LinuxCNC refuses it;
* spaces and tabs, which may stand anywhere between a word's characters;
* lines that are ``%`` (with or without text after it) are skipped.

``O`` words with a number alone on their line (``O1000``, a program number of
a Fanuc-style header) are read as such; any other use of ``O`` and the NGC
language's parameters, expressions and polar coordinates (``#``, ``[``,
``@``, ``^``) are refused: they need
LinuxCNC's own interpreter. Every problem is collected as a :class:`Refusal`,
so a program's refusals are all listed in one pass.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Final

from orthoglide_pin.exceptions import short_repr

#: The letters of words read (LinuxCNC's, without the rotary and UVW axes).
LETTERS: Final = "DEFGHIJKLMNOPQRSTXYZ"
#: Letters of axes this 3-axis reader does not drive.
OTHER_AXES: Final = "ABCUVW"
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)")
_WORD = re.compile(r"([A-Za-z])([+-]?(?:\d+\.?\d*|\.\d+))")
_WORDS = re.compile(r"(?:[A-NP-Za-np-z][+-]?(?:\d+\.?\d*|\.\d+))*")
#: What an unreadable word is quoted up to: letters, digits, signs and points.
_RUN = re.compile(r"[A-Za-z0-9.+-]*")
#: Digits of a number quoted in a message (longer numbers are cut, their length named).
SHOWN_DIGITS: Final[int] = 20
#: What the NGC language needs, named in its refusal.
NGC_LANGUAGE: Final = (
    "needs LinuxCNC's interpreter (the NGC language: parameters, expressions, polar "
    "coordinates, O-word subroutines and control flow)"
)


@dataclass(frozen=True)
class Refusal:
    """Why one line of a program cannot be read.

    Attributes:
        line: Line number (1 for the first).
        reason: What is wrong, naming the word.
        brief: The reason without any of the line's text, shown for the
            refusals after the first when the line is not G-code at all (so
            an error quotes at most one word of a file that is not a
            program); ``None`` when ``reason`` quotes nothing but a word.
    """

    line: int
    reason: str
    brief: str | None = None


@dataclass(frozen=True)
class Word:
    """One word of a line.

    Attributes:
        letter: Its letter, upper case.
        value: Its number.
        text: The word as written (spaces removed), for messages.
    """

    letter: str
    value: float
    text: str


@dataclass
class Line:
    """The words of one line of a program.

    Attributes:
        number: Line number (1 for the first).
        words: The words, in order.
        block_delete: The line starts with ``/``.
        program_number: The line is an ``O`` program number alone (``O1000``).
        refusals: What could not be read on the line.
    """

    number: int
    words: list[Word] = field(default_factory=list)
    block_delete: bool = False
    program_number: bool = False
    refusals: list[Refusal] = field(default_factory=list)


def _strip_comments(text: str, line: Line) -> str:
    """The line's text without comments (LinuxCNC's rules, see the module)."""
    if "(" not in text and ")" not in text:
        return text.split(";", 1)[0]
    out: list[str] = []
    depth_start = -1
    for pos, char in enumerate(text):
        if depth_start >= 0:
            if char == ")":
                depth_start = -1
            elif char == "(":
                line.refusals.append(Refusal(line.number, "a comment opened inside a comment"))
                return ""
        elif char == "(":
            depth_start = pos
        elif char == ")":
            line.refusals.append(Refusal(line.number, "')' without its '(' (comment)"))
            return ""
        elif char == ";":
            break
        else:
            out.append(char)
    if depth_start >= 0:
        line.refusals.append(Refusal(line.number, "a comment '(' not closed on its line"))
        return ""
    return "".join(out)


def read_line(text: str, number: int) -> Line:
    """The words of one line (see the module); problems are in ``refusals``.

    Args:
        text: The line, without its end of line.
        number: Its line number (1 for the first).
    """
    line = Line(number)
    body = text.strip()
    if body.startswith("%"):
        return line
    if body.startswith("/"):
        line.block_delete = True
        body = body[1:]
    body = _strip_comments(body, line)
    body = "".join(body.split())
    if not body:
        return line
    if "#" in body or "[" in body or "@" in body or "^" in body:
        line.refusals.append(Refusal(number, f"{body[:40]!r} {NGC_LANGUAGE}"))
        return line
    if _WORDS.fullmatch(body):  # the common case: letters and numbers only, no O
        for letter, digits in _WORD.findall(body):
            _add(line, letter.upper(), digits)
        return line
    pos = 0
    while pos < len(body):
        letter = body[pos].upper()
        m = _NUMBER.match(body, pos + 1)
        if letter == "O":
            if pos == 0 and m is not None and m.end() == len(body):
                line.program_number = True
                line.words.append(Word("O", float(m.group()), body))
            else:
                line.refusals.append(Refusal(number, f"O word {body[:40]!r} {NGC_LANGUAGE}"))
            return line
        if m is None or not letter.isalpha():
            column = _columns(text)[pos] + 1
            if letter.isalpha():
                word = short_repr(_RUN.match(body, pos).group())  # type: ignore[union-attr]
                what = f"unreadable word {word} at column {column}"
                brief = f"unreadable word at column {column}"
                line.refusals.append(
                    Refusal(number, f"{what} (a word is a letter then a number)", brief)
                )
            else:
                what = f"unreadable character {short_repr(body[pos])} at column {column}"
                line.refusals.append(
                    Refusal(number, what, f"unreadable character at column {column}")
                )
            return line
        _add(line, letter, m.group())
        pos = m.end()
    return line


def _add(line: Line, letter: str, number: str) -> None:
    """Add the word ``letter number`` to ``line``, or its refusal."""
    shown = f"{letter}{number}"
    if len(number) > SHOWN_DIGITS:
        shown = f"{letter}{number[:SHOWN_DIGITS]}... ({len(number)} digits)"
    value = float(number)  # too many digits: inf, refused here
    if not math.isfinite(value):
        line.refusals.append(
            Refusal(line.number, f"unsupported word {shown}: expected a finite number")
        )
    elif letter in OTHER_AXES:
        line.refusals.append(Refusal(line.number, f"axis word {shown}: a 3-axis machine (X Y Z)"))
    elif letter not in LETTERS:
        line.refusals.append(Refusal(line.number, f"unknown word {shown}"))
    else:
        line.words.append(Word(letter, value, shown))


def _columns(text: str) -> list[int]:
    """The column (0 for the first) in ``text`` of each character :func:`read_line` reads.

    Computed only for a message: it follows :func:`read_line`'s steps (the
    leading ``/``, comments, spaces) keeping each character's place.
    """
    kept: list[int] = []
    start = len(text) - len(text.lstrip())
    if text[start : start + 1] == "/":
        start += 1
    in_comment = False
    for pos in range(start, len(text)):
        char = text[pos]
        if in_comment:
            in_comment = char != ")"
        elif char == "(":
            in_comment = True
        elif char == ";":
            break
        elif not char.isspace():
            kept.append(pos)
    return kept
