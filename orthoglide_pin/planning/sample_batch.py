"""A section sampled with its pieces evaluated in batches, not one by one.

:func:`sample_batch` returns what
:func:`~orthoglide_pin.planning.path.sample_section` returns (the same
points, to rounding) for a section of many short pieces, where a Python call
per piece would dominate: the grid of every piece is laid out at once, the
lines are evaluated together, and so are the corner blends (their arc-length
inversion, :class:`~orthoglide_pin.planning.quintic.Quintic`, on all their
samples in one compiled loop that writes them in place,
:mod:`~orthoglide_pin.planning.sample_compiled`, or without numba in one set of
array operations). Arcs keep their own evaluation.
:func:`evaluate_pieces` does the same for any samples of given pieces (the
plan sampled in time, :mod:`~orthoglide_pin.planning.sampling`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.blend import BlendPiece
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.path import MIN_INTERVALS, Samples, Section
from orthoglide_pin.planning.quintic import _FALLING, _GAUSS_W, _GAUSS_X, NEWTON_STEPS
from orthoglide_pin.planning.reach_compiled import AVAILABLE
from orthoglide_pin.planning.sample_compiled import blends_compiled

FloatArray = NDArray[np.float64]


def _horner(coef: FloatArray, w: FloatArray, order: int) -> FloatArray:
    """``order``-th derivatives of power-basis polynomials, one per sample.

    Args:
        coef: Each sample's coefficients, (n, 6, 3).
        w: Parameters, (n,) or (n, k).
        order: Derivative order.

    Returns:
        (n, 3) or (n, k, 3).
    """
    scaled = _FALLING[order, order:, None] * coef[:, order:]
    if w.ndim == 2:
        scaled, wv = scaled[:, None], w[:, :, None]
    else:
        wv = w[:, None]
    out = np.broadcast_to(scaled[..., -1, :], (*w.shape, 3)).copy()
    for j in range(scaled.shape[-2] - 2, -1, -1):
        out *= wv
        out += scaled[..., j, :]
    return np.asarray(out)


def _speed_at(d1: list[FloatArray], w: FloatArray) -> FloatArray:
    """``|B'(w)|`` from the first derivative's coefficients per component, each (5, n, 1)."""
    total = None
    for c in d1:  # one component at a time: contiguous (n, k) arrays, no reduction over 3
        out = np.broadcast_to(c[-1], w.shape).copy()
        for row in c[-2::-1]:
            out *= w
            out += row
        total = out * out if total is None else total + out * out
    assert total is not None
    return np.asarray(np.sqrt(total))


def _blends(
    curves: list[BlendPiece],
    s: FloatArray,
    which: NDArray[np.intp],
    rows: NDArray[np.intp] | None = None,
    out: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``p``, ``p'``, ``p''`` of blends at local arc lengths ``s`` (sample j on ``which[j]``).

    Compiled (numba), they are written into ``out`` at ``rows`` when given
    (:func:`~orthoglide_pin.planning.sample_compiled.blends_compiled`).
    """
    coef_all = np.stack([b.curve._coef for b in curves])
    first = np.stack([b.curve.control[0] for b in curves])
    cum = np.stack([b.curve._cum for b in curves])
    bounds = curves[0].curve._bounds
    if AVAILABLE:
        return blends_compiled(coef_all, first, cum, bounds, s, which, rows=rows, out=out)
    spans = bounds.size - 1
    length = cum[:, -1][which]
    coef, cum_s = coef_all[which], cum[which]
    d1 = _FALLING[1, 1:, None] * coef_all[:, 1:]  # (m, 5, 3)
    comps = [np.ascontiguousarray(d1[:, :, c].T)[:, which, None] for c in range(3)]
    s = np.clip(s, 0.0, length)
    k = np.clip((cum_s <= s[:, None]).sum(axis=1) - 1, 0, spans - 1)
    rows = np.arange(s.size)
    lo, s_lo = bounds[k], cum_s[rows, k]
    span = cum_s[rows, k + 1] - s_lo
    h = 1.0 / spans
    w = lo + h * np.where(span > 0.0, (s - s_lo) / np.where(span > 0.0, span, 1.0), 0.0)
    for _ in range(NEWTON_STEPS):
        nodes = lo[:, None] + 0.5 * (w - lo)[:, None] * (_GAUSS_X + 1.0)
        inner = _speed_at(comps, nodes) @ _GAUSS_W
        residual = s_lo + 0.5 * (w - lo) * inner - s
        w = np.clip(w - residual / _speed_at(comps, w[:, None])[:, 0], lo, lo + h)
    w = np.where(s >= length, 1.0, w)
    d1, d2 = _horner(coef, w, 1), _horner(coef, w, 2)
    speed = np.linalg.norm(d1, axis=1)[:, None]
    t = d1 / speed
    curv = (d2 - np.sum(d2 * t, axis=1)[:, None] * t) / speed**2
    return _horner(coef, w, 0) + first[which], t, curv


def evaluate_pieces(
    pieces: list[Piece], which: NDArray[np.intp], local: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``p``, ``p'``, ``p''`` of samples on pieces, the lines and the blends in batches.

    The values are each piece's :meth:`~orthoglide_pin.planning.geometry.Piece.evaluate`
    (the same for lines and arcs, to rounding for blends).

    Args:
        pieces: The pieces.
        which: The piece of each sample (an index into ``pieces``), (n,).
        local: The samples' arc lengths from their piece's start [m], (n,).

    Returns:
        Each (n, 3).
    """
    n = local.size
    p, dp, ddp = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    if n == 0:
        return p, dp, ddp
    kind = np.array([2 if isinstance(q, BlendPiece) else int(q.v is not None) for q in pieces])
    of = kind[which]
    lines = of == 0
    if lines.any():
        origin = np.stack([q.origin for q in pieces])
        u = np.stack([q.u for q in pieces])
        at = which[lines]
        p[lines] = origin[at] + local[lines, None] * u[at]
        dp[lines] = u[at]
        ddp[lines] = 0.0
    blends = np.flatnonzero(kind == 2)
    if blends.size:
        sel = of == 2
        index = np.full(len(pieces), -1, dtype=np.intp)
        index[blends] = np.arange(blends.size)
        curves = [q for q in pieces if isinstance(q, BlendPiece)]  # in the order of ``blends``
        if AVAILABLE:  # written in place
            _blends(curves, local[sel], index[which[sel]], np.flatnonzero(sel), (p, dp, ddp))
        else:
            p[sel], dp[sel], ddp[sel] = _blends(curves, local[sel], index[which[sel]])
    for k in np.flatnonzero(kind == 1).tolist():
        sel = which == k
        if sel.any():
            p[sel], dp[sel], ddp[sel] = pieces[k].evaluate(local[sel])
    return p, dp, ddp


def sample_batch(
    section: Section,
    step: float,
    *,
    refine: int = 1,
    known: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> Samples:
    """The samples of :func:`~orthoglide_pin.planning.path.sample_section`, in batches.

    Args:
        section: The section.
        step: Largest spacing of the planning grid [m].
        refine: Intervals of this sampling per interval of the planning grid.
        known: ``p``, ``p'`` and ``p''`` of the section's first samples, each
            (m, 3), taken as they are instead of evaluated (a sample's values
            depend only on its piece and its arc length along it), or ``None``.
    """
    return sample_sections([section], step, refine=refine, known=known)[0]


def sample_sections(
    sections: list[Section],
    step: float,
    *,
    refine: int = 1,
    known: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> list[Samples]:
    """:func:`sample_batch` of each section, the pieces of all evaluated together.

    A program of many short sections (a stop at every block) would otherwise
    pay the batches' set-up once per section; the samples are the same.
    ``known``: the values of the first samples of all, as in :func:`sample_batch`.
    """
    if not sections:
        return []
    pieces = [p for sec in sections for p in sec.pieces]
    count = len(pieces)
    firsts = np.concatenate([[0], np.cumsum([len(sec.pieces) for sec in sections])])
    lasts = firsts[1:] - 1  # each section's last piece
    lengths = np.array([p.length for p in pieces])
    n = np.maximum(MIN_INTERVALS, np.ceil(lengths / step)).astype(np.intp) * refine
    taken = n.copy()
    taken[lasts] += 1  # each section's end point
    piece = np.repeat(np.arange(count, dtype=np.intp), taken)
    ends = np.cumsum(taken)
    starts = np.concatenate([[0], ends[:-1]])
    j = np.arange(piece.size) - starts[piece]
    local = j * (lengths / n)[piece]
    local[ends[lasts] - 1] = lengths[lasts]
    offsets = np.concatenate([sec.offsets[:-1] for sec in sections])
    s = offsets[piece] + local
    if known is None:
        p, dp, ddp = evaluate_pieces(pieces, piece, local)
    else:
        m = known[0].shape[0]
        rest = evaluate_pieces(pieces, piece[m:], local[m:])
        p, dp, ddp = (np.concatenate([a, b]) for a, b in zip(known, rest, strict=True))
    out = []
    for a, b, first in zip(starts[firsts[:-1]], ends[lasts], firsts[:-1], strict=True):
        part = slice(int(a), int(b))
        out.append(Samples(s[part], p[part], dp[part], ddp[part], piece[part] - first))
    return out
