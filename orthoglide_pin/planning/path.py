"""The tool path of a program: exact pieces, blended corners, stops, and its grid.

:func:`build_path` turns the blocks of :mod:`orthoglide_pin.planning.gcode`
into **sections**: runs of pieces (:mod:`orthoglide_pin.planning.geometry`)
along which the tool moves without stopping, each planned from rest to rest.
A section ends:

* at the end of every block under ``G61`` (exact stop);
* at a dwell (``G4``), and where a rapid move meets a feed move;
* at a corner that is not blended: under ``G64`` two lines (or two rapid
  moves) that meet at an angle are joined by a circular fillet tangent to
  both, whose midpoint lies within the tolerance ``P`` of the corner (and
  whose tangent points use at most half of each line); the tool stops at any
  other corner: where an arc meets a block at an angle, and where a line
  turns back on itself. Blocks that meet tangentially (within
  :data:`TANGENT_TOL`) are passed without a stop.

The fillet keeps the tangent continuous (G1); its curvature is a step, which
a second-order plan follows (the acceleration may jump) but which gives the
slider jerk a jump at speed (the planner is second order: it does not limit
the jerk).
Blocks shorter than :data:`MIN_LENGTH` (zero-length moves) take no time.

Every point of the path must lie in the machine's prescribed cube and within
its slider limits, up to :data:`INSIDE_TOL` (Q1 and Q2 are reached exactly):
:func:`check_inside` refuses the first point that does not, naming its line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.gcode import Block, Program
from orthoglide_pin.planning.geometry import Piece, arc_piece, fillet, fillet_trim, line_piece

FloatArray = NDArray[np.float64]

#: Points this far outside the cube or the slider limits are still inside [m].
INSIDE_TOL: Final[float] = 1e-9
#: Moves shorter than this take no time [m].
MIN_LENGTH: Final[float] = 1e-12
#: Blocks whose tangents differ by less than this angle meet without a stop [rad].
TANGENT_TOL: Final[float] = 1e-6
#: Fillets whose tangent points lie closer than this to the corner are not made [m].
MIN_TRIM: Final[float] = 1e-9
#: Default planning-grid spacing [m] and fewest intervals per piece.
GRID_STEP: Final[float] = 2e-3
MIN_INTERVALS: Final[int] = 8


@dataclass(frozen=True)
class Section:
    """Pieces travelled from rest to rest, then an optional dwell.

    Attributes:
        pieces: The pieces, tangent-continuous.
        offsets: Arc length at the start of each piece, and the total [m], (k + 1,).
        dwell: Dwell after the section [s].
        dwell_block: Index of the dwell's block, or -1.
    """

    pieces: tuple[Piece, ...]
    offsets: FloatArray
    dwell: float = 0.0
    dwell_block: int = -1

    @property
    def length(self) -> float:
        """Length of the section [m]."""
        return float(self.offsets[-1])


@dataclass(frozen=True)
class Path:
    """A program's tool path.

    Attributes:
        program: The program read.
        sections: The rest-to-rest sections (a section may be a lone dwell).
    """

    program: Program
    sections: tuple[Section, ...]

    @property
    def length(self) -> float:
        """Length of the whole path [m]."""
        return float(sum(s.length for s in self.sections))


@dataclass(frozen=True)
class Samples:
    """A section's path sampled at arc lengths ``s``.

    Attributes:
        s: Arc lengths from the section's start [m], increasing, (n,).
        p: Points [m], (n, 3). dp: Unit tangents [-], (n, 3).
        ddp: Curvature vectors [1/m], (n, 3).
        piece: Index of the piece each sample is evaluated on, (n,).
    """

    s: FloatArray
    p: FloatArray
    dp: FloatArray
    ddp: FloatArray
    piece: NDArray[np.intp]


def _piece_of(block: Block, index: int) -> Piece:
    feed = block.feed
    if block.kind == "arc":
        assert block.center is not None
        k = block.plane[2]
        return arc_piece(
            index,
            block.start,
            block.center,
            block.plane,
            block.sweep,
            float(block.end[k] - block.start[k]),
            feed,
        )
    return line_piece(index, block.start, block.end, feed)


def _turn(a: Piece, b: Piece) -> float:
    cosine = float(np.clip(a.end_tangent() @ b.start_tangent(), -1.0, 1.0))
    return math.acos(cosine)


def build_path(program: Program) -> Path:
    """Sections of the program's pieces, corners blended or stopped (see the module)."""
    program = instance_of("program", program, Program, "a Program (read_program)")
    sections: list[Section] = []
    moves: list[tuple[Block, Piece]] = []

    def close(dwell: float = 0.0, dwell_block: int = -1) -> None:
        pieces = _blend(moves)
        moves.clear()
        if pieces or dwell > 0.0:
            offsets = np.concatenate([[0.0], np.cumsum([p.length for p in pieces])])
            sections.append(Section(tuple(pieces), offsets, dwell, dwell_block))

    for index, block in enumerate(program.blocks):
        if block.kind == "dwell":
            close(block.dwell, index)
            continue
        if float(np.linalg.norm(block.end - block.start)) < MIN_LENGTH and block.kind != "arc":
            continue
        piece = _piece_of(block, index)
        if piece.length < MIN_LENGTH:
            continue
        if moves:
            last_block, last = moves[-1]
            same_kind = (last.feed is None) == (piece.feed is None)
            turn = _turn(last, piece)
            stop = last_block.exact_stop or not same_kind
            blendable = not (last.is_arc or piece.is_arc) and turn < math.pi - TANGENT_TOL
            if not stop and turn > TANGENT_TOL and not blendable:
                stop = True
            if stop:
                close()
        moves.append((block, piece))
    close()
    return Path(program, tuple(sections))


def _blend(moves: list[tuple[Block, Piece]]) -> list[Piece]:
    """The pieces of a run of moves, lines meeting at an angle joined by fillets."""
    if not moves:
        return []
    trims = [0.0] * (len(moves) + 1)  # trim at the start of move k (= end of move k - 1)
    for k in range(1, len(moves)):
        (block, a), (_, b) = moves[k - 1], moves[k]
        turn = _turn(a, b)
        if a.is_arc or b.is_arc or turn <= TANGENT_TOL:
            continue
        trim = min(fillet_trim(turn, block.tolerance), 0.5 * a.length, 0.5 * b.length)
        trims[k] = trim if trim >= MIN_TRIM else 0.0
    out: list[Piece] = []
    for k, (_, piece) in enumerate(moves):
        head, tail = trims[k], trims[k + 1]
        if head or tail:
            start = piece.origin + head * piece.u
            end = piece.origin + (piece.length - tail) * piece.u
            if float(np.linalg.norm(end - start)) >= MIN_LENGTH:
                out.append(line_piece(piece.block, start, end, piece.feed))
        else:
            out.append(piece)
        if tail:
            nxt = moves[k + 1][1]
            corner = piece.origin + piece.length * piece.u
            feeds = [f for f in (piece.feed, nxt.feed) if f is not None]
            out.append(
                fillet(piece.block, corner, piece.u, nxt.u, tail, min(feeds) if feeds else None)
            )
    return out


def sample_section(section: Section, step: float, *, refine: int = 1) -> Samples:
    """Sample a section at most ``step / refine`` apart, every piece's ends included.

    Each piece gets at least ``MIN_INTERVALS * refine`` intervals. A point at
    the junction of two pieces is evaluated on the later piece.

    Args:
        section: The section.
        step: Largest spacing of the planning grid [m].
        refine: Intervals of this sampling per interval of the planning grid.
    """
    s_parts, p_parts, d_parts, dd_parts, idx = [], [], [], [], []
    count = len(section.pieces)
    for k, piece in enumerate(section.pieces):
        n = max(MIN_INTERVALS, math.ceil(piece.length / step)) * refine
        last = k == count - 1
        local = np.linspace(0.0, piece.length, n + 1)[: None if last else -1]
        p, dp, ddp = piece.evaluate(local)
        s_parts.append(section.offsets[k] + local)
        p_parts.append(p)
        d_parts.append(dp)
        dd_parts.append(ddp)
        idx.append(np.full(local.shape, k, dtype=np.intp))
    return Samples(
        np.concatenate(s_parts),
        np.concatenate(p_parts),
        np.concatenate(d_parts),
        np.concatenate(dd_parts),
        np.concatenate(idx),
    )


def check_inside(params: OrthoglideParams, points: FloatArray, lines: NDArray[np.intp]) -> None:
    """Refuse the first point outside the cube or the slider limits (see the module).

    Args:
        params: The machine (cube, leg length, slider limits).
        points: Path points [m], (n, 3).
        lines: Program line of each point, (n,).

    Raises:
        ProgramError: Naming the line, the point in mm and the bound it breaks.
    """
    cube = params.workspace
    lo, hi = cube.q1 - INSIDE_TOL, cube.q2 + INSIDE_TOL
    out = ((points < lo) | (points > hi)).any(axis=1)
    if out.any():
        k = int(np.argmax(out))
        shown = ", ".join(f"{1e3 * x:.4f}" for x in points[k])
        raise ProgramError(
            int(lines[k]), f"the point ({shown}) mm lies outside the machine's {cube.describe()}"
        )
    q = inverse_kinematics(points, params.leg_length, check=False)
    bad = ~np.isfinite(q) | (q < params.slider_lower - INSIDE_TOL)
    bad |= q > params.slider_upper + INSIDE_TOL
    if bad.any():
        row, col = (int(i[0]) for i in np.nonzero(bad))
        shown = ", ".join(f"{1e3 * x:.4f}" for x in points[row])
        raise ProgramError(
            int(lines[row]),
            f"the point ({shown}) mm needs slider {col + 1} at {1e3 * q[row, col]:.4f} mm, "
            f"outside its limits [{1e3 * params.slider_lower:.4f}, "
            f"{1e3 * params.slider_upper:.4f}] mm",
        )
