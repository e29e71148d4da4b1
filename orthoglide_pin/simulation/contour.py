"""Contour error: the distance from the tool to the programmed path.

The path is the plan's (:class:`~orthoglide_pin.planning.path.Path`): the
program's lines, arcs and helices, with the corners blended as planned. Each
tool point is matched to the path's points sampled every
:data:`DENSE_STEP` (a k-d tree, :class:`scipy.spatial.cKDTree`), then
projected from its :data:`SEEDS` nearest samples on their pieces (a junction,
both ends of a full circle) by Newton's method on the arc
length (``(p(s) - x) . p'(s) = 0``, clamped to the piece): the distance is
exact up to :data:`PROJECTION_TOL`, whatever the sampling. The tracking error
along the path does not count: only how far the tool is from the path.

With ``cut_only=True`` the path is its cutting moves alone (the pieces of the
feed moves ``G1``, ``G2``, ``G3`` and the blends between them, not the rapid
moves ``G0``): a tool that lags on a rapid line while the plan plunges is
measured against the plunge, not against the rapid it has not left.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, float_array, instance_of, size_within
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.path import Path

FloatArray = NDArray[np.float64]

#: Spacing of the path's samples that seed the projection [m].
DENSE_STEP: Final[float] = 2e-4
#: Nearest samples each point is projected from (a closed circle's two ends, a junction's pieces).
SEEDS: Final[int] = 6
#: Newton iterations of the projection, and its tolerance on the arc length [m].
NEWTON_STEPS: Final[int] = 8
PROJECTION_TOL: Final[float] = 1e-12
#: Most tool points of one call (a run's longest, in servo periods).
MAX_POINTS: Final[int] = 1_000_000
#: Most path samples (1 km of path every ``DENSE_STEP``), counted before any is made.
MAX_SAMPLES: Final[int] = 5_000_000


@dataclass(frozen=True)
class ContourError:
    """The contour error of ``N`` tool points.

    Attributes:
        distance: Distance to the path [m], (N,).
        nearest: Nearest point of the path [m], (N, 3).
        line: Program line of the block the nearest point lies on, (N,).
    """

    distance: FloatArray
    nearest: FloatArray
    line: NDArray[np.intp]

    @property
    def maximum(self) -> float:
        """Largest distance [m]."""
        return float(self.distance.max()) if self.distance.size else 0.0

    @property
    def rms(self) -> float:
        """Root mean square of the distances [m]."""
        return float(np.sqrt(np.mean(self.distance**2))) if self.distance.size else 0.0

    @property
    def worst(self) -> int:
        """Index of the largest distance."""
        return int(np.argmax(self.distance))


def _pieces(path: Path, cut_only: bool) -> tuple[list[Piece], list[int]]:
    pieces, lines = [], []
    blocks = path.program.blocks
    for section in path.sections:
        for piece in section.pieces:
            if cut_only and piece.feed is None:  # a rapid move
                continue
            pieces.append(piece)
            lines.append(blocks[piece.block].line)
    return pieces, lines


def _project(piece: Piece, x: FloatArray, s0: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Arc lengths and points of ``piece`` nearest to ``x`` (n, 3), from ``s0`` (n,)."""
    s = np.clip(s0, 0.0, piece.length)
    for _ in range(NEWTON_STEPS):
        p, dp, ddp = piece.evaluate(s)
        r = p - x
        grad = np.einsum("ij,ij->i", r, dp)
        hess = np.einsum("ij,ij->i", dp, dp) + np.einsum("ij,ij->i", r, ddp)
        step = np.where(hess > 0.0, grad / np.where(hess > 0.0, hess, 1.0), 0.0)
        s_new = np.clip(s - step, 0.0, piece.length)
        done = np.abs(s_new - s).max() <= PROJECTION_TOL
        s = s_new
        if done:
            break
    return s, piece.evaluate(s)[0]


def contour_error(path: Path, points: ArrayLike, *, cut_only: bool = False) -> ContourError:
    """Distance of each tool point [m], shape (N, 3), to the path (see the module).

    Args:
        path: The programmed path.
        points: Tool points [m], shape (N, 3).
        cut_only: Measure against the cutting moves alone (not the rapid moves).

    Raises:
        InvalidParameterError: Bad points (or more than :data:`MAX_POINTS`), a path
            without a move (without a feed move, with ``cut_only``), or one that needs
            more than :data:`MAX_SAMPLES` samples.
    """
    path = instance_of("path", path, Path, "a Path (build_path, or a plan's path)")
    cut_only = instance_of("cut_only", cut_only, bool, "True or False")
    given = float_array(points)  # a view when it can be: counted before any copy
    size_within("points", given.shape, given.size // 3, MAX_POINTS, "points")
    x = finite_rows("points", given, 3, "[m]")
    pieces, lines = _pieces(path, cut_only)
    if not pieces:
        what = "feed move" if cut_only else "move"
        raise InvalidParameterError(
            "path", f"without a {what}", f"a path with at least one {what}"
        )
    count = sum(max(2.0, np.ceil(p.length / DENSE_STEP) + 1.0) for p in pieces)
    length = sum(p.length for p in pieces)
    size_within("path", f"{length:.6g} m", count, MAX_SAMPLES, f"samples every {DENSE_STEP:g} m")
    from scipy.spatial import cKDTree  # after the checks: a refusal costs nothing

    seeds, owner = [], []
    for j, piece in enumerate(pieces):
        s = np.linspace(0.0, piece.length, max(2, int(np.ceil(piece.length / DENSE_STEP)) + 1))
        seeds.append(s)
        owner.append(np.full(s.size, j, dtype=np.intp))
    s_all, owner_all = np.concatenate(seeds), np.concatenate(owner)
    dense = np.concatenate([p.evaluate(s)[0] for p, s in zip(pieces, seeds, strict=True)])
    _, idx = cKDTree(dense).query(x, k=min(SEEDS, s_all.size))
    idx = idx.reshape(x.shape[0], -1)
    best = np.full(x.shape[0], np.inf)
    nearest = np.zeros_like(x)
    line = np.zeros(x.shape[0], dtype=np.intp)
    for column in idx.T:
        candidate = owner_all[column]
        for j in np.unique(candidate):
            sel = np.flatnonzero(candidate == j)
            _, p = _project(pieces[j], x[sel], s_all[column[sel]])
            d = np.linalg.norm(p - x[sel], axis=1)
            better = d < best[sel]
            best[sel[better]] = d[better]
            nearest[sel[better]] = p[better]
            line[sel[better]] = lines[j]
    return ContourError(best, nearest, line)
