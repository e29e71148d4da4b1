"""One line's words sorted into what they do: a block, its refusals collected.

:func:`read_block` checks a line's words against the accepted ones
(:mod:`~.modes`), lists those without effect on the path through ``ignore``,
and gathers the others into a :class:`Block` that
:mod:`~orthoglide_pin.program.reader` executes. Every problem of the line is
collected, none stops the others from being found.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from orthoglide_pin.program.modes import (
    CYCLES,
    END_M,
    IGNORED_G,
    IGNORED_M,
    M_ARGUMENTS,
    MAX_DWELL,
    MOTION,
    NGC_M,
    REFUSED_G,
    SYSTEM_CODES,
    State,
)
from orthoglide_pin.program.words import NGC_LANGUAGE, Line, Refusal

#: G codes of the non-modal group that take a line's axis words.
_AXIS_USERS = frozenset({100, 280, 300, 920, 431})
#: Every other G code read.
_MODAL = frozenset(
    {40, 170, 180, 190, 200, 210, 430, 490, 530, 610, 611, 640, 800, 900, 910, 901, 911}
    | {980, 990, 281, 301, 921, 922, 923}
    | set(SYSTEM_CODES)
)
_GROUP0 = frozenset({40, 100, 280, 281, 300, 301, 530, 920, 921, 922, 923})


@dataclass
class Block:
    """What one line asks for (values in the program's units).

    Attributes:
        line: Line number.
        gs: Its G codes (ten times their number).
        motion: The motion it makes (ten times the G code), ``None`` for none.
        axes: X Y Z words by axis index.
        centre: I J K words by axis index.
        radius: The ``R`` of an arc, or ``None``.
        turns: The arc's turns (``P``, 1 by default).
        dwell: ``G4``'s ``P`` [s], or ``None``.
        repeats: A cycle's ``L`` (1 by default).
        g53: Machine coordinates (``G53``).
        mode: The motion mode the line sets (800 for ``G80``), or ``None``.
        values: The other words read (F, T, H, P, L, Q of G10 and G64 ...).
        ends: ``M2`` or ``M30``: the program ends.
        refusals: The line's refusals.
    """

    line: int
    gs: set[int] = field(default_factory=set)
    motion: int | None = None
    axes: dict[int, float] = field(default_factory=dict)
    centre: dict[int, float] = field(default_factory=dict)
    radius: float | None = None
    turns: int = 1
    dwell: float | None = None
    repeats: int = 1
    g53: bool = False
    mode: int | None = None
    values: dict[str, float] = field(default_factory=dict)
    ends: bool = False
    refusals: list[Refusal] = field(default_factory=list)

    def refuse(self, reason: str) -> None:
        """Collect a refusal of this line."""
        self.refusals.append(Refusal(self.line, reason))


def _g(code: int) -> str:
    return f"G{code // 10}" if code % 10 == 0 else f"G{code / 10:g}"


def _sort_g(b: Block, code: int, ignore: Callable[[str, int], None]) -> None:
    if code in IGNORED_G:
        ignore(_g(code), b.line)
    elif code in REFUSED_G:
        b.refuse(REFUSED_G[code])
    elif code in MOTION or code in CYCLES or code in _MODAL or code in _AXIS_USERS:
        b.gs.add(code)
    else:
        b.refuse(f"unsupported word {_g(code)}")


def read_block(line: Line, state: State, ignore: Callable[[str, int], None]) -> Block:
    """The block of one line (see the module); its problems are in ``refusals``.

    Args:
        line: The line's words (:func:`~orthoglide_pin.program.words.read_line`).
        state: The modes before the line (read, not changed).
        ignore: Called with each ignored word and the line number.
    """
    b = Block(line.number, refusals=list(line.refusals))
    words: dict[str, float] = {}
    ms: list[int] = []
    for word in line.words:
        if word.letter == "G":
            code = round(word.value * 10)
            if abs(word.value * 10 - code) > 1e-6:
                b.refuse(f"unsupported word {word.text}")
            elif code in b.gs:
                b.refuse(f"{word.text} twice on one line")
            else:
                _sort_g(b, code, ignore)
        elif word.letter == "M":
            if word.value != int(word.value):
                b.refuse(f"unsupported word {word.text}")
            ms.append(int(word.value))
        elif word.letter == "N":
            continue
        elif word.letter in words:
            b.refuse(f"word {word.letter} given twice on one line")
        else:
            words[word.letter] = word.value
    for m in ms:
        if m in IGNORED_M:
            ignore(f"M{m}", b.line)
            for letter in M_ARGUMENTS.get(m, "PQ" if m >= 100 else ""):
                words.pop(letter, None)
        elif m in END_M:
            b.ends = True
        elif m == 6:
            ignore("M6", b.line)
            b.values["M6"] = 1.0
        elif m in NGC_M:
            b.refuse(f"M{m} (subprogram) {NGC_LANGUAGE}")
            words.pop("P", None)
            words.pop("L", None)
        else:
            b.refuse(f"unsupported word M{m}")
    _sort_words(b, words, state, ignore)
    return b


def _sort_words(
    b: Block, words: dict[str, float], state: State, ignore: Callable[[str, int], None]
) -> None:
    for letter in ("S", "D"):
        if words.pop(letter, None) is not None:
            ignore(letter, b.line)
    if "T" in words:
        ignore("T", b.line)
        b.values["T"] = words.pop("T")
    if "F" in words:
        b.values["F"] = words.pop("F")
    motions = sorted(b.gs & (MOTION | CYCLES | {800}))
    if len(motions) > 1 and 800 in motions:
        motions.remove(800)  # G80 with another motion word: the motion is made (LinuxCNC)
    group0 = sorted(b.gs & _GROUP0)
    if len(motions) > 1:
        b.refuse(f"two motion words on one line ({_g(motions[0])}, {_g(motions[1])})")
    if len([g for g in group0 if g != 530]) > 1:
        b.refuse(f"two non-modal words on one line ({', '.join(_g(g) for g in group0)})")
    axes = {i: words.pop(a) for i, a in enumerate("XYZ") if a in words}
    users = sorted(b.gs & _AXIS_USERS)
    b.g53 = 530 in b.gs
    if 40 in b.gs:
        p = words.pop("P", None)
        if p is None or not 0.0 <= p <= MAX_DWELL:
            b.refuse(f"G4 needs P, the dwell time [s] in [0, {MAX_DWELL:g}]")
        else:
            b.dwell = p
    if 640 in b.gs:
        if "Q" in words:
            words.pop("Q")
            ignore("G64 Q", b.line)
        if "P" in words:
            b.values["G64 P"] = words.pop("P")
    if 100 in b.gs:
        for letter in "LPR":
            if letter in words:
                b.values[f"G10 {letter}"] = words.pop(letter)
    if 430 in b.gs and "H" in words:
        b.values["H"] = words.pop("H")
    word = motions[0] if motions else None
    if word is not None:
        b.mode = word
    if users:
        if word is not None and word != 800 and axes:
            b.refuse(f"{_g(users[0])} and {_g(word)} both use the axis words")
        b.axes = axes
        return _leftover(b, words)
    if word == 800:
        if axes:
            b.refuse("axis words with G80 (no motion to use them)")
        return _leftover(b, words)
    motion = word if word is not None else state.motion
    b.axes = axes
    if motion is None:
        if axes:
            b.refuse("coordinates before any motion mode (G0, G1, G2, G3 or a cycle)")
        return _leftover(b, words)
    if motion in (20, 30) and (axes or word is not None):
        _arc_or_cycle_words(b, words, motion)
        b.motion = motion  # without axis words: a full circle from the current point
    elif motion in CYCLES and (axes or word is not None):
        _arc_or_cycle_words(b, words, motion)
        b.motion = motion
    elif motion in (0, 10) and (axes or word is not None):
        b.motion = motion  # G0 or G1 alone: a move where the tool is, as LinuxCNC makes it
    _leftover(b, words)


def _arc_or_cycle_words(b: Block, words: dict[str, float], motion: int) -> None:
    if motion in (20, 30):
        b.centre = {i: words.pop(a) for i, a in enumerate("IJK") if a in words}
        b.radius = words.pop("R", None)
        p = words.pop("P", None)
        if p is not None:
            if p != int(p) or p < 1:
                b.refuse(f"arc turns P{p:g}: a whole number >= 1")
            else:
                b.turns = int(p)
        return
    for letter in "RPQ":
        if letter in words:
            b.values[f"cycle {letter}"] = words.pop(letter)
    dwell = b.values.get("cycle P", 0.0)
    if not 0.0 <= dwell <= MAX_DWELL:
        b.refuse(f"cycle dwell P{dwell:g}: the dwell time [s] must be in [0, {MAX_DWELL:g}]")
    if "L" in words:
        repeats = words.pop("L")
        if repeats != int(repeats) or repeats < 1:
            b.refuse(f"cycle repeats L{repeats:g}: a whole number >= 1")
        else:
            b.repeats = int(repeats)


def _leftover(b: Block, words: dict[str, float]) -> None:
    for letter, value in words.items():
        b.refuse(f"word {letter}{value:g} with nothing to use it")
