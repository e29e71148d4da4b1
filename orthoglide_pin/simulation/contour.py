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

:class:`ContourMeter` samples the path and builds its tree once, then
measures the tool points in as many calls as wanted (a simulated run a chunk
at a time). A path longer than :data:`MAX_SAMPLES` samples is indexed a call
at a time instead: the pieces that can hold the nearest point of one of the
call's points (found by :data:`KNOTS` points of each piece and the distance to
the lines they lie on), and of a line only its samples near the points, so
its memory follows the call's points, not the path's length; the distances
are those of the whole path's index. Lines are projected in closed form and
corner blends by Newton's method on their own parameter, all the points of a
kind at once; arcs and helices piece by piece. The cost grows with the points,
not with the points times the pieces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, float_array, instance_of, size_within
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.path import Path
from orthoglide_pin.planning.quintic import power_coefficients
from orthoglide_pin.planning.sample_batch import evaluate_pieces

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
#: The kinds of pieces, projected each their own way.
_LINE, _ARC, _BLEND, _DONE = 0, 1, 2, 3
#: Most path samples indexed at once (1 km of path every ``DENSE_STEP``), counted before any
#: is made: a longer path is indexed a call at a time, the pieces near its points alone.
MAX_SAMPLES: Final[int] = 5_000_000
#: Points of each piece that bound the distance to the path (a call's pieces are chosen by them).
KNOTS: Final[int] = 5
#: Added to that bound when the pieces near a call's points are chosen [m].
MARGIN: Final[float] = 2e-3


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
            more than :data:`MAX_SAMPLES` samples near the points.
    """
    given = float_array(points)  # a view when it can be: counted before any copy
    size_within("points", given.shape, given.size // 3, MAX_POINTS, "points")
    return ContourMeter(path, cut_only=cut_only).measure(given)


class ContourMeter:
    """The contour error against one path, measured in as many calls as wanted.

    The path's samples and their k-d tree are made once (a path of more than
    :data:`MAX_SAMPLES` samples: those near each call's points, for that call);
    :meth:`measure` then takes the tool points a chunk at a time. Lines are projected in closed
    form and corner blends by Newton's method on their own parameter, all the
    points of a kind at once; arcs and helices piece by piece.

    Args:
        path: The programmed path.
        cut_only: Measure against the cutting moves alone (not the rapid moves).

    Raises:
        InvalidParameterError: A path without a move (without a feed move, with
            ``cut_only``).
    """

    def __init__(self, path: Path, *, cut_only: bool = False) -> None:
        path = instance_of("path", path, Path, "a Path (build_path, or a plan's path)")
        cut_only = instance_of("cut_only", cut_only, bool, "True or False")
        pieces, lines = _pieces(path, cut_only)
        if not pieces:
            what = "feed move" if cut_only else "move"
            raise InvalidParameterError(
                "path", f"without a {what}", f"a path with at least one {what}"
            )
        self.sizes = np.array(
            [max(2, int(np.ceil(p.length / DENSE_STEP)) + 1) for p in pieces], dtype=np.int64
        )
        self.pieces, self.lines = pieces, np.asarray(lines, dtype=np.intp)
        count = len(pieces)
        self.kind = np.array(
            [_BLEND if p.is_blend else (_ARC if p.is_arc else _LINE) for p in pieces],
            dtype=np.intp,
        )
        self.origin = np.array([p.origin for p in pieces], dtype=float).reshape(count, 3)
        self.u = np.array([p.u for p in pieces], dtype=float).reshape(count, 3)
        self.length = np.array([p.length for p in pieces], dtype=float)
        self.coef = np.zeros((count, 6, 3))
        for j in np.flatnonzero(self.kind == _BLEND):
            self.coef[j] = power_coefficients(pieces[j].curve.control)  # type: ignore[attr-defined]
        self.start = np.array(
            [p.curve.control[0] if p.is_blend else np.zeros(3) for p in pieces]  # type: ignore[attr-defined]
        ).reshape(count, 3)
        # each piece at KNOTS points evenly in arc length, and a box that holds it
        # (all together: the blends' arc lengths inverted in one batch, not a call each)
        local = np.linspace(0.0, self.length, KNOTS, axis=1).ravel()
        which = np.repeat(np.arange(count, dtype=np.intp), KNOTS)
        knots = evaluate_pieces(list(pieces), which, local)[0].reshape(count, KNOTS, 3)
        slack = np.where(self.kind == _ARC, self.length / (2 * (KNOTS - 1)), 0.0)
        self.low = knots.min(axis=1) - slack[:, None]
        self.high = knots.max(axis=1) + slack[:, None]
        for j in np.flatnonzero(self.kind == _BLEND):  # a Bezier curve: within its control points
            control: FloatArray = pieces[j].curve.control  # type: ignore[attr-defined]
            self.low[j], self.high[j] = control.min(axis=0), control.max(axis=0)
        self.whole = int(self.sizes.sum()) <= MAX_SAMPLES
        if self.whole:
            every = np.arange(count, dtype=np.intp)
            self.owner, self.param, self.tree = self._index(
                every, np.zeros(count, dtype=np.int64), self.sizes - 1
            )
        else:  # indexed a call at a time: the pieces near its points
            from scipy.spatial import cKDTree

            self.knot_tree = cKDTree(knots.reshape(-1, 3))

    def _index(
        self, chosen: NDArray[np.intp], first: NDArray[np.int64], last: NDArray[np.int64]
    ) -> tuple[NDArray[np.intp], FloatArray, Any]:
        """Samples ``first`` to ``last`` of pieces ``chosen``: owners, parameters and k-d tree."""
        from scipy.spatial import cKDTree

        sizes = self.sizes[chosen]
        counts = last - first + 1
        owner = np.repeat(chosen, counts)
        # the seeds' parameters: arc length on lines and arcs, the curve's own on blends
        spans = zip(sizes.tolist(), first.tolist(), last.tolist(), strict=True)
        unit = np.concatenate(
            [
                np.linspace(0.0, 1.0, n) if b - a == n - 1 else np.arange(a, b + 1) / (n - 1)
                for n, a, b in spans
            ]
        )
        blend = self.kind[owner] == _BLEND
        param = np.where(blend, unit, unit * self.length[owner])
        dense = np.empty((owner.size, 3))
        line = self.kind[owner] == _LINE
        o = owner[line]
        dense[line] = self.origin[o] + param[line, None] * self.u[o]
        dense[blend] = self._blend_at(owner[blend], param[blend])
        edges = np.concatenate([[0], np.cumsum(counts)])
        for k in np.flatnonzero(self.kind[chosen] == _ARC):
            a, b = edges[k], edges[k + 1]
            dense[a:b] = self.pieces[int(chosen[k])].evaluate(param[a:b])[0]
        return owner, param, cKDTree(dense)

    def _near(self, x: FloatArray) -> tuple[NDArray[np.intp], FloatArray, Any]:
        """The samples of the path that can hold the nearest point of each of ``x``.

        A point's nearest point on the path is no farther than its nearest knots,
        nor than the lines they lie on: the pieces whose boxes meet the points'
        box grown by the largest such distance (and :data:`MARGIN`) are indexed,
        no other, and of a line only its samples in that box.

        Raises:
            InvalidParameterError: More than :data:`MAX_SAMPLES` samples near ``x``.
        """
        k = min(SEEDS, self.knot_tree.n)
        gap, idx = self.knot_tree.query(x, k=k)
        gap, idx = gap.reshape(-1, k), idx.reshape(-1, k)
        owner = idx // KNOTS  # a line's own distance is a tighter bound than its knots'
        is_line = self.kind[owner] == _LINE
        u, o = self.u[owner], self.origin[owner]
        s = np.clip(np.einsum("nkj,nkj->nk", x[:, None] - o, u), 0.0, self.length[owner])
        own = np.linalg.norm(o + s[..., None] * u - x[:, None], axis=2)
        reach = float(np.where(is_line, np.minimum(own, gap), gap).min(axis=1).max()) + MARGIN
        low, high = x.min(axis=0) - reach, x.max(axis=0) + reach
        chosen = np.flatnonzero(((self.low <= high) & (self.high >= low)).all(axis=1))
        first = np.zeros(chosen.size, dtype=np.int64)
        last = self.sizes[chosen] - 1
        lines = np.flatnonzero(self.kind[chosen] == _LINE)
        if lines.size:  # the part of each line in the box
            j = chosen[lines]
            u, o, length = self.u[j], self.origin[j], self.length[j]
            flat = u == 0.0
            safe = np.where(flat, 1.0, u)
            t1, t2 = (low - o) / safe, (high - o) / safe
            enter = np.where(flat, -np.inf, np.minimum(t1, t2)).max(axis=1)
            leave = np.where(flat, np.inf, np.maximum(t1, t2)).min(axis=1)
            enter, leave = np.maximum(enter, 0.0), np.minimum(leave, length)
            n = (self.sizes[j] - 1).astype(float)
            scale = np.where(length > 0.0, n / np.where(length > 0.0, length, 1.0), 0.0)
            a = np.clip(np.floor(enter * scale), 0.0, n).astype(np.int64)
            b = np.clip(np.ceil(leave * scale), 0.0, n).astype(np.int64)
            first[lines], last[lines] = a, np.maximum(a, b)
        size_within(
            "path", f"{float(self.length[chosen].sum()):.6g} m of pieces near the points",
            float((last - first + 1).sum()), MAX_SAMPLES, f"samples every {DENSE_STEP:g} m",
        )  # fmt: skip
        return self._index(chosen.astype(np.intp), first, last)

    def measure(self, points: ArrayLike) -> ContourError:
        """Distance of each tool point [m], shape (N, 3), to the path (see the module).

        Raises:
            InvalidParameterError: Bad points, or more than :data:`MAX_SAMPLES`
                samples of the path near them (a path indexed a call at a time).
        """
        x = finite_rows("points", float_array(points), 3, "[m]")
        n = x.shape[0]
        if self.whole:
            owner, param, tree = self.owner, self.param, self.tree
        else:
            owner, param, tree = self._near(x)
        best = np.full(n, np.inf)
        nearest = np.zeros_like(x)
        line = np.zeros(n, dtype=np.intp)
        _, idx = tree.query(x, k=min(SEEDS, owner.size))
        idx = idx.reshape(n, -1)
        owners = owner[idx]
        for c, column in enumerate(idx.T):  # each seed in turn, as near as the tree found it
            j = owners[:, c]
            kind = self.kind[j].copy()
            # a line or a blend already projected from a nearer seed: the same point again
            again = (owners[:, :c] == j[:, None]).any(axis=1) & (kind != _ARC)
            kind[again] = _DONE
            p = np.zeros_like(x)
            sel = kind == _LINE
            if sel.any():
                js = j[sel]
                s = np.einsum("ij,ij->i", x[sel] - self.origin[js], self.u[js])
                s = np.clip(s, 0.0, self.length[js])
                p[sel] = self.origin[js] + s[:, None] * self.u[js]
            sel = kind == _BLEND
            if sel.any():
                p[sel] = self._blend_project(j[sel], x[sel], param[column[sel]])
            arcs = np.flatnonzero(kind == _ARC)
            if arcs.size:
                order = arcs[np.argsort(j[arcs], kind="stable")]
                cuts = np.flatnonzero(np.diff(j[order])) + 1
                for group in np.split(order, cuts):
                    piece = self.pieces[int(j[group[0]])]
                    p[group] = _project(piece, x[group], param[column[group]])[1]
            d = np.linalg.norm(p - x, axis=1)
            better = (d < best) & ~again
            best[better] = d[better]
            nearest[better] = p[better]
            line[better] = self.lines[j[better]]
        return ContourError(best, nearest, line)

    def _blend_at(self, j: NDArray[np.intp], w: FloatArray) -> FloatArray:
        """Points of blends ``j`` at their parameters ``w``, (n, 3)."""
        return np.asarray(_horner([self.coef[j, k] for k in range(6)], w)[0] + self.start[j])

    def _blend_project(self, j: NDArray[np.intp], x: FloatArray, w0: FloatArray) -> FloatArray:
        """Points of blends ``j`` nearest to ``x`` (n, 3), from their parameters ``w0``."""
        c = [self.coef[j, k] for k in range(6)]  # gathered once: (n, 3) each
        local = x - self.start[j]
        w = np.clip(w0, 0.0, 1.0)
        for _ in range(NEWTON_STEPS):
            p, d1, d2 = _horner(c, w)
            r = p - local
            grad = np.einsum("ij,ij->i", r, d1)
            hess = np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", r, d2)
            step = np.where(hess > 0.0, grad / np.where(hess > 0.0, hess, 1.0), 0.0)
            w_new = np.clip(w - step, 0.0, 1.0)
            moved = np.abs(w_new - w) * np.sqrt(np.einsum("ij,ij->i", d1, d1))
            w = w_new
            if moved.max() <= PROJECTION_TOL:
                break
        return np.asarray(_horner(c, w)[0] + self.start[j])


def _horner(c: list[FloatArray], w: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A quintic of power coefficients ``c`` (six (n, 3)) at ``w`` (n,), and two derivatives."""
    wc = w[:, None]
    p, d1, d2 = c[5] * wc + c[4], 5.0 * c[5] * wc + 4.0 * c[4], 20.0 * c[5] * wc + 12.0 * c[4]
    for k in (3, 2):
        p = p * wc + c[k]
        d1 = d1 * wc + k * c[k]
        if k == 3:
            d2 = d2 * wc + 6.0 * c[3]
    d2 = d2 * wc + 2.0 * c[2]
    p = (p * wc + c[1]) * wc + c[0]
    d1 = d1 * wc + c[1]
    return p, d1, d2
