"""What a program runs against: work offsets, reference points, tools, start.

A :class:`Setup` holds, in machine coordinates of the program's axes [m]
(the coordinates ``G53`` names; home, the isotropic point, is their zero):

* the nine work offsets ``G54`` to ``G59.3`` (``G54`` is active at the start);
* the reference points of ``G28`` and ``G30`` (home by default);
* the tool table: each tool's length along program Z [m] (``G43 H``);
* the tool's start point, and whether block delete (``/``) is honoured.

Two files set them, both in LinuxCNC's own formats and in millimetres (see the
formats reference): an offsets file (LinuxCNC's parameter file, lines
``NUMBER VALUE``) and a tool table (lines ``T1 P1 Z50.0 D6 ;comment``).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import read_input_text
from orthoglide_pin._validation import finite_number, finite_vector, flag, mapping, path_argument
from orthoglide_pin.exceptions import Described, InvalidParameterError, path_repr, short_repr

FloatArray = NDArray[np.float64]

#: Millimetres in metres: the files' unit.
MM: Final[float] = 1e-3
#: The work offsets' names, in the order of LinuxCNC's ``P`` of ``G10 L2``.
SYSTEMS: Final = ("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3")
#: LinuxCNC's parameter numbers: X of G28, X of G30, X of G54 (then 20 apart).
G28_PARAMETER: Final[int] = 5161
G30_PARAMETER: Final[int] = 5181
G54_PARAMETER: Final[int] = 5221
#: Largest tool number read.
MAX_TOOL: Final[int] = 99_999
#: Largest offsets or tool-table file [bytes].
MAX_FILE_BYTES: Final[int] = 1_000_000
#: Characters of a bad word quoted in a message.
SHOWN_CHARS: Final[int] = 20
#: What a word of these files could be made of: the run an error quotes.
_WORD_RUN: Final = re.compile(r"[A-Za-z0-9.+-]*")


def _where(name: str, row: int, text: str | None = None) -> Described:
    """A file's line in a message: its name, then the word of the line at fault.

    The name is shown whole (cut in the middle past 255 characters). Of the
    line, only the run of characters a word could hold (letters, digits,
    ``.+-``) at its start is quoted, at most 20 of them: a file that is not
    an offsets file or a tool table (a password file...) shows no more of
    itself than that.
    """
    where = f"{path_repr(name)} line {row}"
    if text is None:
        return Described(where)
    word = _WORD_RUN.match(text.strip())
    shown = word.group(0) if word else ""
    return Described(f"{where}: {short_repr(shown[:SHOWN_CHARS])}")


def _zeros() -> FloatArray:
    return np.zeros(3)


@dataclass(frozen=True)
class Setup:
    """The machine's state when a program starts (see the module).

    Attributes:
        work_offsets: ``G54`` to ``G59.3`` [m], shape (9, 3), machine coordinates.
        g28: Reference point of ``G28`` [m], shape (3,).
        g30: Reference point of ``G30`` [m], shape (3,).
        tools: Tool number -> length along program Z [m].
        start: The spindle nose's start point [m], shape (3,), machine coordinates.
        block_delete: Skip the lines that start with ``/``.
        diameters: Tool number -> diameter [m] (LinuxCNC's interpreter only:
            cutter compensation).
    """

    work_offsets: FloatArray = field(default_factory=lambda: np.zeros((9, 3)))
    g28: FloatArray = field(default_factory=_zeros)
    g30: FloatArray = field(default_factory=_zeros)
    tools: Mapping[int, float] = field(default_factory=dict)
    start: FloatArray = field(default_factory=_zeros)
    block_delete: bool = False
    diameters: Mapping[int, float] = field(default_factory=dict)


def make_setup(
    *,
    origin: ArrayLike | None = None,
    offsets: Mapping[int, float] | None = None,
    tools: Mapping[int, float] | None = None,
    start: ArrayLike = (0.0, 0.0, 0.0),
    block_delete: bool = False,
    diameters: Mapping[int, float] | None = None,
) -> Setup:
    """A :class:`Setup` from an origin, an offsets file's parameters and a tool table.

    Args:
        origin: ``G54``'s offset [m], shape (3,), machine coordinates (the
            part zero); it overrides the offsets file's ``G54``; ``None``: the file's.
        offsets: LinuxCNC parameters [mm] (:func:`read_offsets`).
        tools: Tool lengths [m] (:func:`read_tool_table`).
        start: The spindle nose's start point [m], machine coordinates.
        block_delete: Skip the lines that start with ``/``.
        diameters: Tool diameters [m] (:func:`read_tool_diameters`).

    Raises:
        InvalidParameterError: A bad argument, named.
    """
    work = np.zeros((9, 3))
    g28, g30 = np.zeros(3), np.zeros(3)
    params = _numbers("offsets", offsets, "parameter numbers -> values [mm]")
    lengths = _numbers("tools", tools, "tool numbers -> lengths [m]")
    for number, value in params.items():
        for base, target in ((G28_PARAMETER, g28), (G30_PARAMETER, g30)):
            if base <= number < base + 3:
                target[number - base] = value * MM
        k, axis = divmod(number - G54_PARAMETER, 20)
        if 0 <= k < 9 and axis < 3:
            work[k, axis] = value * MM
    if origin is not None:
        work[0] = finite_vector("origin", origin, 3, "[m]")
    return Setup(
        work,
        g28,
        g30,
        lengths,
        finite_vector("start", start, 3, "[m]").copy(),
        flag("block_delete", block_delete),
        _numbers("diameters", diameters, "tool numbers -> diameters [m]"),
    )


def _numbers(name: str, value: Mapping[int, float] | None, allowed: str) -> dict[int, float]:
    """A mapping of whole numbers >= 0 to finite numbers (``None``: empty)."""
    out: dict[int, float] = {}
    given: Mapping[Any, Any] = mapping(name, {} if value is None else value, allowed)
    for key, number in given.items():
        whole = isinstance(key, (int, np.integer)) and not isinstance(key, (bool, np.bool_))
        if not whole or int(key) < 0:
            raise InvalidParameterError(name, key, allowed)
        out[int(key)] = finite_number(name, number)
    return out


def _number(path: str, what: str, row: int, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise InvalidParameterError(what, _where(os.fspath(path), row, text), "a finite number")
    return value


def read_offsets(path: str | os.PathLike[str]) -> dict[int, float]:
    """The parameters of a LinuxCNC parameter file (lines ``NUMBER VALUE`` [mm]).

    Blank lines and text after ``;`` or ``#`` are skipped; parameters other
    than those of :func:`make_setup` are read and left unused.

    Raises:
        InvalidParameterError: An unreadable file or line, naming it.
    """
    text = read_input_text(path_argument("path", path), "offsets file", MAX_FILE_BYTES)
    name = os.fspath(path)
    out: dict[int, float] = {}
    for row, raw in enumerate(text.splitlines(), start=1):
        body = raw.split(";", 1)[0].split("#", 1)[0].split()
        if not body:
            continue
        if len(body) != 2 or not body[0].isdigit():
            raise InvalidParameterError(
                "offsets file", _where(name, row, raw), "lines 'NUMBER VALUE'"
            )
        out[int(body[0])] = _number(name, "offsets file", row, body[1])
    return out


def read_tool_table(path: str | os.PathLike[str]) -> dict[int, float]:
    """Tool lengths [m] of a LinuxCNC tool table (``T1 P1 Z50.0 D6 ;comment``, mm).

    Each line names its tool by ``T``; ``Z`` is its length along program Z
    [mm] (0 when missing); the other words (``P``, ``D``, ``X`` ...) are read
    and left unused (:func:`read_tool_diameters` reads ``D``).

    Raises:
        InvalidParameterError: An unreadable line or a tool given twice, naming it.
    """
    return _tool_words(path, "Z")


def read_tool_diameters(path: str | os.PathLike[str]) -> dict[int, float]:
    """Tool diameters [m] of a LinuxCNC tool table (its ``D`` words, mm; 0 when missing).

    Only LinuxCNC's interpreter uses them (cutter compensation ``G41``/``G42``).

    Raises:
        InvalidParameterError: As :func:`read_tool_table`.
    """
    return _tool_words(path, "D")


def _tool_words(path: str | os.PathLike[str], letter: str) -> dict[int, float]:
    """Each tool's ``letter`` word [m] (from mm; 0 when missing) of a tool table."""
    text = read_input_text(path_argument("path", path), "tool table", MAX_FILE_BYTES)
    name = os.fspath(path)
    out: dict[int, float] = {}
    for row, raw in enumerate(text.splitlines(), start=1):
        words: dict[str, float] = {}
        for item in raw.split(";", 1)[0].split():
            first = item[:1].upper()
            if not first.isalpha() or len(item) < 2:
                raise InvalidParameterError(
                    "tool table", _where(name, row, item), "words like T1 Z50.0"
                )
            words[first] = _number(name, "tool table", row, item[1:])
        if not words:
            continue
        tool = words.get("T")
        if tool is None or tool != int(tool) or not 0 <= tool <= MAX_TOOL:
            raise InvalidParameterError(
                "tool table", _where(name, row), f"a tool number T0 to T{MAX_TOOL}"
            )
        if int(tool) in out:
            raise InvalidParameterError("tool table", _where(name, row), "each tool once")
        out[int(tool)] = words.get(letter, 0.0) * MM
    return out
