"""A strict reader of the G-code subset of a 3-axis mill, into blocks in the world frame.

The subset, and nothing else (any other word is refused, naming its line):

* motion: ``G0`` (rapid, at the machine's limits), ``G1`` (line at feed),
  ``G2``/``G3`` (clockwise / counter-clockwise arc, or helix when the axis
  normal to the plane moves) with the centre by ``I J K`` (offsets from the
  start point) or by ``R`` (radius; negative for an arc of more than half a
  turn); the motion mode is modal;
* ``G17``/``G18``/``G19``: the arc plane XY / ZX / YZ (normal +Z / +Y / +X;
  clockwise as seen from the normal's positive side);
* ``G20``/``G21``: inches / millimetres (default millimetres); ``G90``/``G91``:
  absolute / incremental coordinates (default absolute; arc centres are
  always offsets from the start point);
* ``F``: feed [program units per minute], modal; a G1/G2/G3 move needs one > 0;
* ``G4 P<seconds>``: dwell; ``G61``: exact stop (the tool stops at the end of
  every block; the blocks read before any ``G61``/``G64`` are marked so, and
  the planner gives them the controller's default mode,
  :mod:`~orthoglide_pin.planning.controller`); ``G64 [P<tol>]``: blending within ``tol``
  [program units] (:data:`DEFAULT_TOLERANCE` without ``P``);
* ``( ... )`` and ``;`` comments, ``N`` numbers, ``%`` lines, ``M2``/``M30``
  (end of program: later lines are not read).

Coordinates are those of the world frame (origin at the isotropic point)
shifted by ``origin`` [m] (the part zero); the tool starts at ``start`` [m].
An arc whose radius to the end differs from its radius to the start by more
than :data:`ARC_RADIUS_TOL` (absolute, or relative to the radius, whichever is
larger) is refused; within it the centre is moved onto the perpendicular
bisector of the chord (by at most that tolerance), so the arc is exact.
:mod:`orthoglide_pin.planning.path` turns the blocks into geometry.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import check_text, read_input_text
from orthoglide_pin._validation import finite_vector
from orthoglide_pin._validation import text as text_argument
from orthoglide_pin.exceptions import MAX_VALUE_CHARS, ProgramError, short_repr

FloatArray = NDArray[np.float64]

#: Millimetres and inches in metres.
MM: Final[float] = 1e-3
INCH: Final[float] = 25.4e-3
#: Blending tolerance of ``G64`` without ``P`` [m].
DEFAULT_TOLERANCE: Final[float] = 0.01e-3
#: Largest mismatch of an arc's start and end radii: absolute [m] and relative.
ARC_RADIUS_TOL: Final[float] = 5e-6
ARC_RADIUS_RTOL: Final[float] = 1e-3
#: Longest program read [lines].
MAX_LINES: Final[int] = 1_000_000
#: Largest program file read [bytes] (its size is checked before it is read).
MAX_PROGRAM_BYTES: Final[int] = 64_000_000
#: The plane of G17, G18, G19: its two in-plane axes and its normal axis.
PLANES: Final = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}
_LETTERS: Final = "GMNFXYZIJKRP"
_WORD = re.compile(r"\s*([A-Za-z])\s*([+-]?(?:\d+\.?\d*|\.\d+))")
_COMMENT = re.compile(r"\([^()]*\)")
#: What a word could be made of: the run quoted by an error.
_RUN = re.compile(r"[A-Za-z0-9.+-]+")
_MOTION: Final = frozenset({0, 1, 2, 3})
_SUPPORTED_G: Final = frozenset({0, 1, 2, 3, 4, 17, 18, 19, 20, 21, 61, 64, 90, 91})


@dataclass(frozen=True)
class Block:
    """One move or dwell of a program, in the world frame (SI units).

    Attributes:
        line: Line of the program (1 for the first).
        kind: ``"rapid"``, ``"line"``, ``"arc"`` or ``"dwell"``.
        start: Start point [m], shape (3,).
        end: End point [m], shape (3,).
        feed: Programmed path speed [m/s] (``None`` for a rapid or a dwell).
        center: Arc centre [m], in the plane of the start point (arcs only).
        plane: Indices of the plane's two axes and of its normal, e.g. ``(0, 1, 2)``.
        sweep: Signed angle swept about the plane's normal [rad] (arcs only;
            positive counter-clockwise, G3).
        dwell: Dwell time [s] (dwells only).
        exact_stop: The tool stops at the end of the block (G61).
        tolerance: Blending tolerance at the end of the block [m] (G64).
    """

    line: int
    kind: str
    start: FloatArray
    end: FloatArray
    feed: float | None = None
    center: FloatArray | None = None
    plane: tuple[int, int, int] = (0, 1, 2)
    sweep: float = 0.0
    dwell: float = 0.0
    exact_stop: bool = True
    tolerance: float = 0.0


@dataclass(frozen=True)
class Program:
    """A program read into blocks.

    Attributes:
        blocks: The moves and dwells, in order.
        start: The tool's start point [m], shape (3,).
        lines: Number of lines read.
        mode_line: The first line that says ``G61`` or ``G64``, 0 when none
            does (the blocks before it run in the controller's default mode,
            :mod:`~orthoglide_pin.planning.controller`).
    """

    blocks: tuple[Block, ...]
    start: FloatArray
    lines: int
    mode_line: int = 0


def _word_text(letter: str, number: str) -> str:
    """A word as shown in a message: ``G41``, or its first digits and its length."""
    if len(number) < MAX_VALUE_CHARS:
        return f"{letter}{number}"
    return f"{letter}{number[: MAX_VALUE_CHARS - 8]}... ({len(number)} digits)"


def _unreadable(stripped: str, pos: int, line: int) -> ProgramError:
    """The error of text at ``pos`` that is not a word: its first characters quoted, escaped.

    Only the run of characters a word could hold (letters, digits, ``.+-``)
    is quoted, at most :data:`~orthoglide_pin.exceptions.MAX_VALUE_CHARS` of
    it, so no more of a file than that is ever shown.
    """
    column = pos + len(stripped[pos:]) - len(stripped[pos:].lstrip()) + 1
    run = _RUN.match(stripped, column - 1)
    bad = "character" if run is None else "word"
    shown = stripped[column - 1] if run is None else run.group(0)
    return ProgramError(
        line,
        f"unreadable {bad} {short_repr(shown)} at column {column} "
        "(a word is a letter then a number)",
    )


def _words(text: str, line: int) -> list[tuple[str, float, str]]:
    """The ``(letter, value, text)`` words of one line, comments removed."""
    body = _COMMENT.sub(lambda m: " " * len(m.group(0)), text.split(";", 1)[0])
    if "(" in body or ")" in body:
        raise ProgramError(line, "unbalanced parenthesis comment")
    words, pos = [], 0
    stripped = body.rstrip()
    while pos < len(stripped):
        m = _WORD.match(stripped, pos)
        if m is None:
            raise _unreadable(stripped, pos, line)
        letter = m.group(1).upper()
        shown = _word_text(letter, m.group(2))
        if letter not in _LETTERS:
            raise ProgramError(line, f"unsupported word {shown}")
        words.append((letter, float(m.group(2)), shown))
        pos = m.end()
    return words


def _arc_center(
    line: int,
    a: FloatArray,
    b: FloatArray,
    plane: tuple[int, int, int],
    words: dict[str, float],
    clockwise: bool,
    unit: float,
) -> tuple[FloatArray, float]:
    """Centre [m] (in the start's plane) and signed sweep [rad] of an arc from ``a`` to ``b``."""
    i, j, k = plane
    u, v = np.zeros(3), np.zeros(3)
    u[i], v[j] = 1.0, 1.0
    chord = np.array([b[i] - a[i], b[j] - a[j]])
    offsets = {"I": 0, "J": 1, "K": 2}
    given = [w for w in "IJK" if w in words]
    if "R" in words:
        if given:
            raise ProgramError(line, "an arc takes its centre by I J K or by R, not both")
        r = words["R"] * unit
        d = float(np.hypot(*chord))
        if d == 0.0:
            raise ProgramError(line, "a full circle needs its centre by I J K, not R")
        if abs(r) < 0.5 * d * (1.0 - 1e-12):
            raise ProgramError(
                line, f"arc radius {abs(r) / MM:g} mm is less than half the chord {d / MM:g} mm"
            )
        h = math.sqrt(max(r * r - 0.25 * d * d, 0.0))
        perp = np.array([-chord[1], chord[0]]) / d
        side = 1.0 if (r > 0.0) != clockwise else -1.0  # the centre left of the chord for G3 R>0
        c2 = 0.5 * chord + side * h * perp
    else:
        if not given:
            raise ProgramError(line, "an arc needs its centre (I J K) or its radius (R)")
        off = np.zeros(3)
        for w in given:
            if offsets[w] == k:
                raise ProgramError(line, f"{w} is normal to the arc plane (G{_plane_code(plane)})")
            off[offsets[w]] = words[w] * unit
        c2 = np.array([off[i], off[j]])
        r0, r1 = float(np.hypot(*c2)), float(np.hypot(*(c2 - chord)))
        if r0 == 0.0:
            raise ProgramError(line, "arc of radius 0 (its centre is its start point)")
        if abs(r1 - r0) > max(ARC_RADIUS_TOL, ARC_RADIUS_RTOL * r0):
            raise ProgramError(
                line,
                f"arc radius to the end point {r1 / MM:.6g} mm differs from the radius to the "
                f"start {r0 / MM:.6g} mm by more than "
                f"{max(ARC_RADIUS_TOL, ARC_RADIUS_RTOL * r0) / MM:.3g} mm",
            )
        d2 = float(chord @ chord)
        if d2 > 0.0:  # onto the perpendicular bisector: both radii equal
            c2 = c2 - ((c2 - 0.5 * chord) @ chord / d2) * chord
    start_angle = math.atan2(-c2[1], -c2[0])
    end_angle = math.atan2(chord[1] - c2[1], chord[0] - c2[0])
    sweep = end_angle - start_angle
    if clockwise:
        sweep = -((-sweep) % (2.0 * math.pi))
    else:
        sweep %= 2.0 * math.pi
    if abs(sweep) < 1e-12 or np.allclose(chord, 0.0, atol=1e-15):
        sweep = -2.0 * math.pi if clockwise else 2.0 * math.pi  # a full circle
    centre = a + c2[0] * u + c2[1] * v
    return centre, sweep


def _plane_code(plane: tuple[int, int, int]) -> int:
    return next(code for code, axes in PLANES.items() if axes == plane)


def read_program(
    text: str, *, origin: ArrayLike = (0.0, 0.0, 0.0), start: ArrayLike = (0.0, 0.0, 0.0)
) -> Program:
    """Read a program of the subset (see the module) into blocks.

    Args:
        text: The program.
        origin: The part zero in the world frame [m], shape (3,).
        start: The tool's start point in the world frame [m], shape (3,).

    Returns:
        The program's blocks, in the world frame [m].

    Raises:
        ProgramError: The first bad line, named by its number.
        InvalidParameterError: A bad origin or start, or a text no text file
            could hold (a NUL character, named by its offset).
    """
    zero = finite_vector("origin", origin, 3, "[m]")
    pos = finite_vector("start", start, 3, "[m]").copy()
    first = pos.copy()
    text = check_text(text_argument("text", text, "the text of a program (str)"), "text")
    lines = text.splitlines()
    if len(lines) > MAX_LINES:
        raise ProgramError(MAX_LINES + 1, f"a program of at most {MAX_LINES} lines")
    unit, absolute, plane, motion = MM, True, PLANES[17], None
    feed: float | None = None
    exact, tol = True, 0.0
    mode_line = 0
    blocks: list[Block] = []
    count = 0
    for count, raw in enumerate(lines, start=1):
        if raw.strip() == "%":
            continue
        words = _words(raw, count)
        seen: dict[str, float] = {}
        gs, ms = [], []
        for letter, value, shown in words:
            if letter == "G":
                if value != int(value) or int(value) not in _SUPPORTED_G:
                    raise ProgramError(count, f"unsupported word {shown}")
                gs.append(int(value))
            elif letter == "M":
                if value not in (2.0, 30.0):
                    raise ProgramError(count, f"unsupported word {shown}")
                ms.append(int(value))
            elif letter == "N":
                continue
            elif letter in seen:
                raise ProgramError(count, f"word {letter} given twice")
            else:
                seen[letter] = value
        moves = [g for g in gs if g in _MOTION]
        if len(moves) > 1 or len(set(gs)) != len(gs):
            raise ProgramError(count, "two G words of one group in one line")
        for g in gs:
            if g in (20, 21):
                unit = INCH if g == 20 else MM
            elif g in (90, 91):
                absolute = g == 90
            elif g in PLANES:
                plane = PLANES[g]
        if 64 in gs and 61 in gs:
            raise ProgramError(count, "G61 and G64 in one line")
        if 4 in gs and 64 in gs:
            raise ProgramError(count, "G4 and G64 in one line (both read P)")
        if (61 in gs or 64 in gs) and not mode_line:
            mode_line = count
        if 61 in gs:
            exact, tol = True, 0.0
        if 64 in gs:
            p = seen.pop("P", None)
            if p is not None and p < 0.0:
                raise ProgramError(count, f"G64 P{p:g}: the tolerance must be >= 0")
            exact, tol = False, DEFAULT_TOLERANCE if p is None else p * unit
        if "F" in seen:
            f = seen.pop("F")
            if f <= 0.0:
                raise ProgramError(count, f"feed F{f:g}: it must be > 0")
            feed = f * unit / 60.0
        if 4 in gs:
            if moves:
                raise ProgramError(count, "G4 and a move in one line")
            p = seen.pop("P", None)
            if p is None or p < 0.0:
                raise ProgramError(count, "G4 needs P, the dwell time [s] >= 0")
            if seen:
                raise ProgramError(count, f"unexpected word {next(iter(seen))} with G4")
            blocks.append(Block(count, "dwell", pos.copy(), pos.copy(), dwell=p))
            continue
        if moves:
            motion = moves[0]
        if "P" in seen:
            raise ProgramError(count, "P belongs to G4 or G64 only")
        axes = [w for w in "XYZ" if w in seen]
        arc_words = [w for w in "IJKR" if w in seen]
        if axes or arc_words:
            if motion is None:
                raise ProgramError(count, "coordinates before any G0, G1, G2 or G3")
            if arc_words and motion not in (2, 3):
                raise ProgramError(count, f"{arc_words[0]} belongs to an arc (G2, G3)")
            target = pos.copy()
            for axis, w in enumerate("XYZ"):
                if w in seen:
                    value = seen[w] * unit
                    target[axis] = zero[axis] + value if absolute else target[axis] + value
            if motion != 0 and feed is None:
                raise ProgramError(count, f"G{motion} without a feed (F)")
            if motion == 0:
                blocks.append(
                    Block(count, "rapid", pos.copy(), target, exact_stop=exact, tolerance=tol)
                )
            elif motion == 1:
                blocks.append(
                    Block(count, "line", pos.copy(), target, feed, exact_stop=exact, tolerance=tol)
                )
            else:
                centre, sweep = _arc_center(count, pos, target, plane, seen, motion == 2, unit)
                blocks.append(
                    Block(
                        count,
                        "arc",
                        pos.copy(),
                        target,
                        feed,
                        centre,
                        plane,
                        sweep,
                        exact_stop=exact,
                        tolerance=tol,
                    )
                )
            pos = target
        elif moves and motion in (2, 3):
            raise ProgramError(count, f"G{motion} without an end point or centre")
        if ms:
            break
    return Program(tuple(blocks), first, count, mode_line)


def read_program_file(
    path: str | os.PathLike[str],
    *,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    start: ArrayLike = (0.0, 0.0, 0.0),
) -> Program:
    """Read a program file as ``orthoglide plan`` does, then :func:`read_program`.

    The file is read safely (:func:`~orthoglide_pin._io.read_input_text`): a
    regular file (a link to one is followed; a FIFO, a device or a directory
    is refused before any read), its size checked against
    :data:`MAX_PROGRAM_BYTES` before it is read, and text (UTF-8 without a NUL
    byte) before it is parsed. No error quotes more than 80 characters of it.

    Args:
        path: The file, named in the errors as given.
        origin: The part zero in the world frame [m], shape (3,).
        start: The tool's start point in the world frame [m], shape (3,).

    Raises:
        InvalidParameterError: Not a readable regular text file of at most
            :data:`MAX_PROGRAM_BYTES`.
        ProgramError: The first bad line, named by its number.
    """
    text = read_input_text(path, "program", MAX_PROGRAM_BYTES)
    return read_program(text, origin=origin, start=start)
