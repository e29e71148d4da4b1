"""The built-in reader: a program's text into canonical moves, as LinuxCNC reads it.

:func:`read_moves` reads the program line by line (:mod:`~.words`) with its
modes (:mod:`~.modes`), offsets and tools (:mod:`~.offsets`), arcs
(:mod:`~.arcs`) and canned cycles (:mod:`~.cycles`) into
:class:`~orthoglide_pin.program.moves.Move` records in machine coordinates of
the program's axes. Within a line the words act in LinuxCNC's order: feed,
tool change, plane, units, tool length, work offset, path control, distance
modes, retract mode, ``G10``/``G28``/``G30``/``G92``, then the motion, then the
end of the program (``M2``, ``M30``: later lines are not read).

Words that do not change the path are listed in :attr:`ReadProgram.ignored`
(word, count, first line). Every refusal of a program is collected in one
pass (:attr:`ReadProgram.refusals`, every line and word); a refused line is
skipped and reading goes on. :func:`check_refusals` raises them all in one
:class:`~orthoglide_pin.exceptions.ProgramError`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import MAX_LENGTH, instance_of
from orthoglide_pin._validation import text as text_argument
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.program.arcs import centre_r, check_ijk
from orthoglide_pin.program.block import Block, read_block
from orthoglide_pin.program.cycles import RAPID_DELTA_INCH, expand_cycle
from orthoglide_pin.program.modes import CYCLES, INCH, MM, PLANE_AXES, State
from orthoglide_pin.program.moves import Move
from orthoglide_pin.program.offsets import Setup
from orthoglide_pin.program.settings import RefusedError, apply_settings
from orthoglide_pin.program.words import NGC_LANGUAGE, Refusal, read_line

FloatArray = NDArray[np.float64]

#: Longest program read [lines].
MAX_LINES: Final[int] = 1_000_000
#: Refusals named in full in the error's one line (the rest are counted).
SHOWN_REFUSALS: Final[int] = 12
_NORMALS: Final = {17: (0.0, 0.0, 1.0), 18: (0.0, 1.0, 0.0), 19: (1.0, 0.0, 0.0)}


@dataclass(frozen=True)
class Ignored:
    """A word read without effect on the path.

    Attributes:
        word: The word (``M3``, ``S``, ``T``, ``G40`` ...): letter and code,
            or the letter alone for ``S``, ``T``, ``D`` and the ``Q`` of ``G64``.
        count: How many times it was read.
        line: The first line it was read on.
    """

    word: str
    count: int
    line: int


@dataclass(frozen=True)
class ReadProgram:
    """A program read into canonical moves.

    Attributes:
        moves: The moves, in order.
        tolerances: The blending tolerance at the end of each move [m]
            (``G64 P``), ``None`` under exact stop (``G61``, the default).
        ignored: The words read without effect on the path, in order of first use.
        refusals: Every refusal, in line order (empty when the program is read).
        lines: Lines read (up to the end of the program).
        start: The spindle nose's start point [m], machine coordinates.
        mode_line: The first line that sets the path control (``G61``,
            ``G61.1`` or ``G64``), 0 when none does: a controller may run the
            moves before it in a default mode of its own.
    """

    moves: tuple[Move, ...]
    tolerances: tuple[float | None, ...]
    ignored: tuple[Ignored, ...]
    refusals: tuple[Refusal, ...]
    lines: int
    start: FloatArray
    mode_line: int = 0


class _Reader:
    def __init__(self, setup: Setup) -> None:
        self.state = State(
            pos=np.array(setup.start, dtype=float),
            work=np.array(setup.work_offsets, dtype=float),
            g28=np.array(setup.g28, dtype=float),
            g30=np.array(setup.g30, dtype=float),
            tools=dict(setup.tools),
        )
        self.block_delete = setup.block_delete
        self.moves: list[Move] = []
        self.tolerances: list[float | None] = []
        self.ignored: dict[str, list[int]] = {}
        self.refusals: list[Refusal] = []

    def ignore(self, word: str, line: int) -> None:
        seen = self.ignored.setdefault(word, [0, line])
        seen[0] += 1

    def emit(self, move: Move) -> None:
        if np.abs(move.end).max() > MAX_LENGTH:
            shown = ", ".join(f"{x:g}" for x in move.end)
            raise RefusedError(
                f"the move ends at ({shown}) m, beyond +-{MAX_LENGTH:g} m of the machine origin"
            )
        self.moves.append(move)
        self.tolerances.append(self.state.tolerance)
        self.state.pos = move.end.copy()

    def straight(self, line: int, kind: str, end: FloatArray) -> None:
        feed = None if kind == "rapid" else self.state.feed
        self.emit(Move(line, kind, self.state.pos.copy(), np.array(end, dtype=float), feed))

    # -- one line ---------------------------------------------------------------
    def read(self, number: int, raw: str) -> bool:
        """Read one line; whether the program ends there."""
        line = read_line(raw, number)
        if line.block_delete and self.block_delete:
            return False
        if line.program_number:
            self.ignore("O", number)
            return False
        block = read_block(line, self.state, self.ignore)
        if block.refusals:
            self.refusals.extend(block.refusals)
            return block.ends
        try:
            self.execute(block)
        except RefusedError as exc:
            self.refusals.append(Refusal(number, str(exc)))
        return block.ends

    def execute(self, b: Block) -> None:
        s = self.state
        previous = s.motion
        _check_lengths(b, (INCH if 200 in b.gs else MM) if b.gs & {200, 210} else s.unit)
        apply_settings(b, s, self)
        if b.motion not in CYCLES and (b.motion is not None or b.mode == 800):
            s.cycle_level = None  # a move of another kind ends the initial level
        if b.dwell is not None:
            self.emit(Move(b.line, "dwell", s.pos.copy(), s.pos.copy(), dwell=b.dwell))
        if b.motion is None:
            return
        if b.motion in (0, 10):
            end = self.target(b)
            if b.motion == 10:
                if s.feed is None:
                    s.pos = end  # the next lines are read from the programmed end
                    raise RefusedError("G1 without a feed (F)")
                self.straight(b.line, "line", end)
            else:
                self.straight(b.line, "rapid", end)
        elif b.motion in (20, 30):
            end = self.target(b)
            try:
                self.arc(b, end)
            except RefusedError:
                s.pos = end  # the next lines are read from the programmed end
                raise
        else:
            self.cycle(b, previous)

    def target(self, b: Block) -> FloatArray:
        s = self.state
        rotated = None if b.g53 else s.rotated()
        if rotated is not None:  # in the rotated frame of the work offset, then back
            r, base = rotated
            point = r.T @ (s.pos - base) - s.g92
            for axis, value in b.axes.items():
                point[axis] = value * s.unit + (0.0 if s.absolute else point[axis])
            return np.asarray(r @ (point + s.g92) + base, dtype=np.float64)
        end = s.pos.copy()
        zero = s.offset()
        for axis, value in b.axes.items():
            if b.g53:
                end[axis] = value * s.unit
            elif s.absolute:
                end[axis] = value * s.unit + zero[axis]
            else:
                end[axis] += value * s.unit
        return np.asarray(end, dtype=np.float64)

    def arc(self, b: Block, end: FloatArray) -> None:
        s = self.state
        if s.plane not in PLANE_AXES:
            raise RefusedError("an arc in a UVW plane (G17.1 to G19.1)")
        i, j, k = PLANE_AXES[s.plane]
        name = "G2" if b.motion == 20 else "G3"
        if s.feed is None:
            raise RefusedError(f"{name} without a feed (F)")
        rotated = s.rotated()
        start = s.pos
        unit = s.unit
        if rotated is not None:  # the arc in the rotated frame of the work offset
            rot, base = rotated
            start, end = rot.T @ (start - base), rot.T @ (end - base)
        a2 = (float(start[i] / unit), float(start[j] / unit))
        e2 = (float(end[i] / unit), float(end[j] / unit))
        turns = b.turns if b.motion == 30 else -b.turns
        if b.radius is not None:
            if b.centre:
                raise RefusedError(f"{name} takes its centre by I J K or by R, not both")
            c = centre_r(a2, e2, b.radius, b.motion == 20, s.inch)
            if isinstance(c, str):
                raise RefusedError(c)
            c2 = c
        else:
            if k in b.centre:
                raise RefusedError(f"{'IJK'[k]} is normal to the arc's plane (G{s.plane})")
            if s.arc_absolute:
                zero = (s.offset() if rotated is None else s.g92) / unit
                c2 = (b.centre.get(i, 0.0) + float(zero[i]), b.centre.get(j, 0.0) + float(zero[j]))
            else:
                c2 = (a2[0] + b.centre.get(i, 0.0), a2[1] + b.centre.get(j, 0.0))
            why = check_ijk(a2, e2, (c2[0], c2[1]), s.inch)
            if why is not None:
                raise RefusedError(why)
        centre = start.copy()
        centre[i], centre[j] = c2[0] * unit, c2[1] * unit
        normal = np.array(_NORMALS[s.plane])
        if rotated is not None:
            centre, normal, end = rot @ centre + base, rot @ normal, rot @ end + base
        self.emit(Move(b.line, "arc", s.pos.copy(), end, s.feed, centre, normal, turns))

    def cycle(self, b: Block, previous: int | None) -> None:
        s = self.state
        code = b.motion
        assert code is not None
        name = f"G{code // 10}"
        if s.plane not in PLANE_AXES:
            raise RefusedError(f"canned cycle {name} in a UVW plane (G17.1 to G19.1)")
        if s.rotated() is not None:
            raise RefusedError(f"canned cycle {name} under a rotated work offset (G10 L2 R)")
        # In the cycle's frame: the plane's two axes, then the drilling axis (its normal).
        order = list(PLANE_AXES[s.plane])
        first, second, normal = order
        if s.feed is None:
            raise RefusedError(f"{name} without a feed (F)")
        zero = s.offset()[order]
        pos = s.pos[order]
        c = s.cycle
        given = b.values
        depth = "XYZ"[normal]
        if previous != code and (normal not in b.axes or "cycle R" not in given):
            raise RefusedError(f"{name} needs R and {depth} where the cycle begins")
        if "R" not in c or "Z" not in c:
            raise RefusedError(f"{name} needs R and {depth}")
        peck = c.get("Q", 0.0) * s.unit
        if code in (730, 830) and not peck > 0.0:
            raise RefusedError(f"{name} needs Q > 0, the peck depth")
        if code in (820, 860, 890) and previous != code and "cycle P" not in given:
            raise RefusedError(f"{name} needs P, the dwell time [s]")
        dwell = c.get("P", 0.0)
        if s.cycle_level is None:
            s.cycle_level = float(pos[2])
        initial = s.cycle_level
        if b.g53:
            raise RefusedError("G53 with a canned cycle")
        if s.absolute:
            r = c["R"] * s.unit + zero[2]
            bottom = c["Z"] * s.unit + zero[2]
            x = b.axes[first] * s.unit + zero[0] if first in b.axes else pos[0]
            y = b.axes[second] * s.unit + zero[1] if second in b.axes else pos[1]
            holes = [(float(x), float(y))] * b.repeats
        else:
            r = initial + c["R"] * s.unit
            bottom = r + c["Z"] * s.unit
            dx, dy = (b.axes.get(axis, 0.0) * s.unit for axis in (first, second))
            holes = [
                (float(pos[0] + n * dx), float(pos[1] + n * dy)) for n in range(1, b.repeats + 1)
            ]
        if r < bottom:
            raise RefusedError(f"canned cycle with R below Z ({name})")
        delta = RAPID_DELTA_INCH * INCH
        try:
            steps = expand_cycle(
                code, pos, holes, float(r), float(bottom), initial=initial,
                retract_r=s.retract_r, peck=peck, dwell=dwell, rapid_delta=delta,
            )  # fmt: skip
        except ValueError as exc:
            raise RefusedError(f"canned cycle of {exc}") from None
        for step in steps:
            if step.kind == "dwell":
                self.emit(Move(b.line, "dwell", s.pos.copy(), s.pos.copy(), dwell=step.dwell))
            else:
                end = np.empty(3)
                end[order] = step.end
                self.straight(b.line, step.kind, end)


def _check_lengths(b: Block, unit: float) -> None:
    """Refuse a length word of ``b`` (in ``unit`` [m]) beyond +-:data:`MAX_LENGTH`."""
    words = [("XYZ"[a], v) for a, v in b.axes.items()]
    words += [("IJK"[a], v) for a, v in b.centre.items()]
    words += [] if b.radius is None else [("R", b.radius)]
    words += [(k[-1], v) for k, v in b.values.items() if k in ("cycle R", "cycle Q")]
    for letter, value in words:
        if abs(value * unit) > MAX_LENGTH:
            raise RefusedError(f"word {letter}{value:.12g}: beyond +-{MAX_LENGTH:g} m")


def read_moves(text: str, setup: Setup | None = None) -> ReadProgram:
    """Read a program into canonical moves, collecting every refusal (see the module).

    Args:
        text: The program.
        setup: Work offsets, tools, start point and block delete (all zero,
            none, home and not honoured by default).

    Returns:
        The moves, the words ignored and the refusals (empty when the program
        is read as written).

    Raises:
        InvalidParameterError: ``text`` is not a string, or ``setup`` not a Setup.
        ProgramError: The program has more than :data:`MAX_LINES` lines.
    """
    lines = text_argument("text", text, "the text of a program (str)").splitlines()
    setup = Setup() if setup is None else instance_of("setup", setup, Setup, "a Setup")
    if len(lines) > MAX_LINES:
        raise ProgramError(MAX_LINES + 1, f"a program of at most {MAX_LINES} lines")
    reader = _Reader(setup)
    start = reader.state.pos.copy()
    count = 0
    for count, raw in enumerate(lines, start=1):
        if reader.read(count, raw):
            break
    ignored = tuple(Ignored(word, n, first) for word, (n, first) in reader.ignored.items())
    return ReadProgram(
        tuple(reader.moves),
        tuple(reader.tolerances),
        ignored,
        tuple(reader.refusals),
        count,
        start,
        reader.state.mode_line,
    )


def check_refusals(read: ReadProgram) -> ReadProgram:
    """The program read, or a :class:`ProgramError` naming all its refusals in one line.

    The error's line is the first refusal's; its reason lists the first
    :data:`SHOWN_REFUSALS` refusals (``line N: reason``) and counts the rest.
    Of a line that is not G-code at all (an unreadable word), only the first
    refusal quotes the word: the others name its column (``brief``).
    """
    read = instance_of("read", read, ReadProgram, "a ReadProgram (read_moves)")
    if not read.refusals:
        return read
    first, *rest = read.refusals
    parts = [first.reason] + [
        f"line {r.line}: {r.reason if r.brief is None else r.brief}"
        for r in rest[: SHOWN_REFUSALS - 1]
    ]
    # the NGC language's reason in full once, then by its name
    named = [i for i, part in enumerate(parts) if NGC_LANGUAGE in part]
    for i in named[1:]:
        parts[i] = parts[i].replace(NGC_LANGUAGE, "(NGC language)")
    more = len(read.refusals) - SHOWN_REFUSALS
    if more > 0:
        parts.append(f"and {more} more refusals")
    if len(read.refusals) > 1:
        parts[0] = f"{len(read.refusals)} refusals: {parts[0]}"
    if any(NGC_LANGUAGE in r.reason for r in read.refusals):
        parts.append("read it with --interpreter linuxcnc (or auto)")
    raise ProgramError(first.line, "; ".join(parts))
