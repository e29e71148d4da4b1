"""The tool path of a program: exact pieces, blended corners, stops, and its grid.

:func:`build_path` turns the blocks of :mod:`orthoglide_pin.planning.gcode`
into **sections**: runs of pieces (:mod:`orthoglide_pin.planning.geometry`)
along which the tool moves without stopping, each planned from rest to rest.
A section ends:

* at the end of every block under ``G61`` (exact stop);
* at a dwell (``G4``), and where a rapid move meets a feed move;
* at a corner that is not blended: under ``G64`` two pieces (lines or arcs,
  either side, or two rapid moves) that meet at an angle are joined by a G2
  blend (:mod:`~orthoglide_pin.planning.blend`: a quintic that matches the
  point, the tangent and the curvature of both pieces and passes within the
  tolerance ``P`` of the corner, trimming at most half of each piece); the
  tool stops at a corner that cannot be blended: where a move turns back on
  itself (beyond :data:`~orthoglide_pin.planning.blend.MAX_TURN`) or where the
  trims would be shorter than :data:`~orthoglide_pin.planning.blend.MIN_TRIM`.

Blocks that meet tangentially (within :data:`TANGENT_TOL`) are passed without
a stop. Under ``G64``, where their curvature vectors differ (a line tangent to
an arc, arcs of two radii) the joint is blended the same way, so that the
path's curvature, hence the acceleration at a given speed, is continuous along
every section under ``G64``; a tangent joint whose blend cannot be made is
passed with its curvature step. Blocks shorter than :data:`MIN_LENGTH`
(zero-length moves) take no time.

Every point of the path must lie in the machine's prescribed cube and within
its slider limits, up to :data:`INSIDE_TOL` (Q1 and Q2 are reached exactly):
:func:`check_inside` refuses the first point that does not, naming its line.
"""

from __future__ import annotations

import contextlib
import gc
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.blend import CornerBlend
from orthoglide_pin.planning.blend_batch import Corner, corner_blends
from orthoglide_pin.planning.gcode import Block, Program
from orthoglide_pin.planning.geometry import Piece, arc_piece, line_piece, sub_piece

FloatArray = NDArray[np.float64]

#: Points this far outside the cube or the slider limits are still inside [m].
INSIDE_TOL: Final[float] = 1e-9
#: Moves shorter than this take no time [m].
MIN_LENGTH: Final[float] = 1e-12
#: Blocks whose tangents differ by less than this angle meet without a stop [rad].
TANGENT_TOL: Final[float] = 1e-6
#: Tangent joints whose curvature vectors differ by less than this share are not blended [-].
CURVATURE_RTOL: Final[float] = 1e-6
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
        i, j, k = block.plane
        end_radius = math.hypot(block.end[i] - block.center[i], block.end[j] - block.center[j])
        return arc_piece(
            index,
            block.start,
            block.center,
            block.plane,
            block.sweep,
            float(block.end[k] - block.start[k]),
            feed,
            end_radius,
        )
    return line_piece(index, block.start, block.end, feed)


def _is_line(piece: Piece) -> bool:
    return piece.v is None and not piece.is_blend


def _turn(a: Piece, b: Piece) -> float:
    if _is_line(a) and _is_line(b):
        cosine = float(a.u @ b.u)
    else:
        cosine = float(a.end_tangent() @ b.start_tangent())
    return math.acos(min(max(cosine, -1.0), 1.0))


def _curvature_jump(a: Piece, b: Piece) -> bool:
    """Whether the curvature vectors differ where ``a`` ends and ``b`` starts."""
    if _is_line(a) and _is_line(b):
        return False
    ka = a.evaluate(np.array([a.length]))[2][0]
    kb = b.evaluate(np.array([0.0]))[2][0]
    jump = float(np.linalg.norm(ka - kb))
    return jump > CURVATURE_RTOL * max(float(np.linalg.norm(ka)), float(np.linalg.norm(kb)))


def build_path(program: Program) -> Path:
    """Sections of the program's pieces, corners blended or stopped (see the module).

    Raises:
        ProgramError: The program has no block (no move, no dwell), naming its last line.
    """
    program = instance_of("program", program, Program, "a Program (read_program)")
    if not program.blocks:
        raise ProgramError(max(program.lines, 1), "the program has no move and no dwell")
    with collector_paused():
        return _build(program)


@contextlib.contextmanager
def collector_paused() -> Iterator[None]:
    """Pause Python's cyclic garbage collector, if it runs, for the block.

    A path holds a few small objects per block and no reference cycle; while a
    long program's are made, the collector would traverse the growing heap
    again and again (about a quarter of the time of building the path of a
    100,000-block program). A run of short sections is planned under it too
    (:func:`~orthoglide_pin.planning.plan.plan_program`: about a tenth of its time).
    """
    running = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if running:
            gc.enable()


def _build(program: Program) -> Path:
    """:func:`build_path` of a program checked to have blocks."""
    steps = _steps(program)
    wanted = _corners(steps)
    blends = dict(zip(wanted, corner_blends(list(wanted.values())), strict=True))
    sections: list[Section] = []
    moves: list[Piece] = []
    joints: list[CornerBlend | None] = []  # joints[k]: the blend before moves[k]

    def close(dwell: float = 0.0, dwell_block: int = -1) -> None:
        pieces = _blend(moves, joints)
        moves.clear()
        joints.clear()
        if pieces or dwell > 0.0:
            offsets = np.concatenate([[0.0], np.cumsum([p.length for p in pieces])])
            sections.append(Section(tuple(pieces), offsets, dwell, dwell_block))

    last_block: Block | None = None
    for k, (index, block, piece) in enumerate(steps):
        if piece is None:
            close(block.dwell, index)
            continue
        joint = None
        if moves:
            assert last_block is not None
            stop = last_block.exact_stop or (moves[-1].feed is None) != (piece.feed is None)
            if k in blends:
                joint = blends[k]
                stop = joint is None and _turn(moves[-1], piece) > TANGENT_TOL
            if stop:
                close()
        moves.append(piece)
        joints.append(joint)
        last_block = block
    close()
    return Path(program, tuple(sections))


def _steps(program: Program) -> list[tuple[int, Block, Piece | None]]:
    """The program's dwells (piece ``None``) and moves long enough to keep, with their index.

    The lines' lengths and directions are computed in arrays, once for all.
    """
    blocks = program.blocks
    straight = [i for i, b in enumerate(blocks) if b.kind not in ("dwell", "arc")]
    line_of: dict[int, int] = {}
    if straight:
        start = np.array([blocks[i].start for i in straight], dtype=float)
        d = np.array([blocks[i].end for i in straight], dtype=float) - start
        length = np.linalg.norm(d, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            u = d / length[:, None]
        lengths = length.tolist()
        line_of = {i: k for k, i in enumerate(straight)}
    out: list[tuple[int, Block, Piece | None]] = []
    for index, block in enumerate(blocks):
        if block.kind == "dwell":
            out.append((index, block, None))
            continue
        k = line_of.get(index, -1)
        if k >= 0:
            if lengths[k] < MIN_LENGTH:
                continue
            piece = Piece(index, lengths[k], block.feed, start[k], u[k])  # line_piece's, once
        else:
            piece = _piece_of(block, index)
        if piece.length >= MIN_LENGTH:
            out.append((index, block, piece))
    return out


def _corners(steps: list[tuple[int, Block, Piece | None]]) -> dict[int, Corner]:
    """The corners to blend, by the step that follows them: not a stop, not tangent.

    The turns between two lines are computed in arrays, once for all.
    """
    out: dict[int, Corner] = {}
    n = len(steps)
    lined = np.zeros(n, dtype=bool)
    u = np.zeros((n, 3))
    for k, (_, _, piece) in enumerate(steps):
        if piece is not None and _is_line(piece):
            lined[k], u[k] = True, piece.u
    both = (lined[:-1] & lined[1:]).tolist()
    turns = np.arccos(np.clip(np.sum(u[:-1] * u[1:], axis=1), -1.0, 1.0)).tolist()
    for k in range(1, n):
        _, last_block, last = steps[k - 1]
        piece = steps[k][2]
        if last is None or piece is None or last_block.exact_stop:
            continue
        if (last.feed is None) != (piece.feed is None):
            continue
        if both[k - 1]:
            if turns[k - 1] > TANGENT_TOL:
                out[k] = (last, piece, last_block.tolerance)
        elif _turn(last, piece) > TANGENT_TOL or _curvature_jump(last, piece):
            out[k] = (last, piece, last_block.tolerance)
    return out


def _blend(moves: list[Piece], joints: list[CornerBlend | None]) -> list[Piece]:
    """The pieces of a run of moves: each trimmed by its blends, the blends between."""
    out: list[Piece] = []
    for k, piece in enumerate(moves):
        before = joints[k]
        after = joints[k + 1] if k + 1 < len(moves) else None
        head = 0.0 if before is None else before.trim_out
        tail = 0.0 if after is None else after.trim_in
        if before is not None:
            out.append(before.piece)
        if not (head or tail):
            out.append(piece)
        elif piece.length - tail - head >= MIN_LENGTH:
            out.append(sub_piece(piece, head, piece.length - tail))
    return out


def _intervals(length: float, step: float) -> float:
    """Intervals of a piece of ``length`` at spacing ``step`` (a float: it may be huge)."""
    ratio = length / step
    return float(max(MIN_INTERVALS, math.ceil(ratio))) if ratio < 1e15 else ratio


def grid_size(section: Section, step: float, *, refine: int = 1) -> float:
    """Points :func:`sample_section` would make, counted without making them."""
    return 1.0 + refine * sum(_intervals(piece.length, step) for piece in section.pieces)


def block_ends(program: Program) -> tuple[FloatArray, NDArray[np.intp]]:
    """Start and end of every move, and its line: ``(points (2k, 3) [m], lines (2k,))``."""
    moves = [b for b in program.blocks if b.kind != "dwell"]
    if not moves:
        return np.zeros((0, 3)), np.zeros(0, dtype=np.intp)
    points = np.array([p for b in moves for p in (b.start, b.end)], dtype=float)
    lines = np.array([b.line for b in moves for _ in (0, 1)], dtype=np.intp)
    return points, lines


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
        n = int(_intervals(piece.length, step)) * refine
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
