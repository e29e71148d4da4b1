"""The points a refinement adds to many sections' grids, merged in one pass.

:func:`~orthoglide_pin.planning.grid.refine_grid` adds, after each plan, the
switch points of every section to its planning grid, and those points with the
middles of the intervals next to them to its verification grid. A program that
stops at every block has as many sections as blocks; merging them section by
section costs a few dozen array calls each. :func:`merge_added` merges all the
sections' points at once: the sections' grids are laid end to end (each
sorted), the added points sorted by section then arc length, and each is found
in its own section's part by bisection
(:func:`~orthoglide_pin.planning.run_batch.segment_search`): whether it is
already there, its neighbours, and where it goes, so that every section's
merged grid is written in one pass, exactly (no arc length is rounded, as
adding a section's offset would, and nothing is sorted but the added
points). Only the sections that gain a point are merged. The grids are the
same as merged section by section.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.blend import BlendPiece
from orthoglide_pin.planning.path import Samples, Section
from orthoglide_pin.planning.run_batch import cut, segment_search, unique_pairs

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
_FORMS = ("q", "dq", "ddq", "a", "b", "c")
_SAMPLES = ("s", "p", "dp", "ddp", "piece")


def _ids(arrays: list[FloatArray]) -> IntArray:
    """The index of the array each element of their concatenation comes from."""
    return np.repeat(np.arange(len(arrays), dtype=np.int64), [a.size for a in arrays])


def _ranked(
    groups: list[tuple[IntArray, FloatArray]],
) -> tuple[list[IntArray], FloatArray, int]:
    """Keys ``id * R + rank`` of each ``(ids, values)`` group, the ranked values and ``R``."""
    values, rank = np.unique(np.concatenate([v for _, v in groups]), return_inverse=True)
    r = values.size + 1
    sizes = [v.size for _, v in groups]
    parts = np.split(rank.astype(np.int64), np.cumsum(sizes)[:-1])
    keys = [ids * r + part for (ids, _), part in zip(groups, parts, strict=True)]
    return keys, values, r


def _starts(sizes: list[int]) -> NDArray[np.intp]:
    """The first index of each of arrays of ``sizes`` laid end to end, and the end."""
    return np.concatenate([[0], np.cumsum(sizes)]).astype(np.intp)


def _not_on(
    values: FloatArray, starts: NDArray[np.intp], ids: NDArray[np.intp], s: FloatArray
) -> NDArray[np.bool_]:
    """Whether each ``s`` is not in its section's segment of ``values`` (each sorted)."""
    at = segment_search(values, starts, ids, s)
    inside = at < starts[ids + 1]
    found = values[np.minimum(at, max(values.size - 1, 0))] == s
    return np.asarray(~(inside & found))


def _not_in(
    values: FloatArray, starts: NDArray[np.intp], ids: NDArray[np.intp], s: FloatArray
) -> tuple[NDArray[np.intp], FloatArray]:
    """The pairs ``(ids, s)`` whose ``s`` is not in its section's segment of ``values``."""
    keep = _not_on(values, starts, ids, s)
    return ids[keep], s[keep]


def _new_places(
    starts: NDArray[np.intp],
    gained: NDArray[np.int64],
    merged: NDArray[np.intp],
    ids: NDArray[np.intp],
    values: FloatArray,
    s: FloatArray,
) -> NDArray[np.intp]:
    """Where each new point ``(ids, s)`` goes in the merged sections' grids laid end to end.

    Each section's points keep their order; a new point (sorted by section,
    then arc length, none on the old grid ``values``) goes after the old points
    below it and the new points before it.
    """
    sizes = np.diff(starts) + gained
    out_start = np.zeros(gained.size, dtype=np.intp)
    out_start[merged] = _starts(sizes[merged].tolist())[:-1]
    below = segment_search(values, starts, ids, s) - starts[ids]
    rank = np.arange(ids.size) - _starts(gained.tolist())[:-1][ids]
    return np.asarray(out_start[ids] + below + rank, dtype=np.intp)


def _olds(olds: list[Samples] | list[PathForms], names: tuple[str, ...]) -> list[FloatArray]:
    """Each field of the ``olds``, concatenated."""
    return [np.concatenate([getattr(x, n) for x in olds]) for n in names]


def _evaluate(sections: list[Section], ids: IntArray, s: FloatArray) -> Samples:
    """The sections' paths at arc lengths ``s`` (section ``ids``), as ``grid.samples_at``."""
    offsets = [sec.offsets for sec in sections]
    (k_off, k_s), _, _ = _ranked([(_ids(offsets), np.concatenate(offsets)), (ids, s)])
    first = np.concatenate([[0], np.cumsum([o.size for o in offsets])])[:-1]
    counts = np.array([len(sec.pieces) for sec in sections])
    local_k = np.searchsorted(k_off, k_s, side="right") - 1 - first[ids]
    local_k = np.clip(local_k, 0, counts[ids] - 1)
    piece_first = np.concatenate([[0], np.cumsum(counts)])[:-1]
    g = piece_first[ids] + local_k
    pieces = [p for sec in sections for p in sec.pieces]
    starts = np.concatenate([sec.offsets[:-1] for sec in sections])
    local = s - starts[g]
    p, dp, ddp = (np.zeros((s.size, 3)) for _ in range(3))
    line = np.array([not isinstance(q, BlendPiece) and q.v is None for q in pieces])
    at = line[g]
    if at.any():
        origin = np.stack([q.origin if line[i] else np.zeros(3) for i, q in enumerate(pieces)])
        u = np.stack([q.u if line[i] else np.zeros(3) for i, q in enumerate(pieces)])
        p[at] = origin[g[at]] + local[at, None] * u[g[at]]
        dp[at] = u[g[at]]
    for j in np.unique(g[~at]).tolist():
        sel = g == j
        p[sel], dp[sel], ddp[sel] = pieces[j].evaluate(local[sel])
    return Samples(np.asarray(s, dtype=float), p, dp, ddp, np.asarray(local_k, dtype=np.intp))


def merge_added(
    sections: list[Section],
    grids: list[tuple[Samples, PathForms, Samples, PathForms]],
    added: list[FloatArray] | tuple[NDArray[np.intp], FloatArray],
    forms_of: Callable[[list[Samples]], list[PathForms]],
    calibrate: Callable[[PathForms, Samples], PathForms],
) -> dict[int, tuple[Samples, PathForms, Samples, PathForms]]:
    """The sections' grids with the ``added`` arc lengths (see the module), by index.

    Args:
        sections: The sections.
        grids: Each one's planning grid, its forms, verification grid and its forms.
        added: The arc lengths to add to each one's planning grid [m] (any order,
            repeats and points already on its verification grid ignored), or
            all of them with the index of the section of each.
        forms_of: The path forms (nominal machine) at samples, in one batch.
        calibrate: The planning forms from nominal forms at samples.

    Returns:
        The new ``(grid, forms, fine, fine_forms)`` of each section that gains a point.
    """
    gs, fs = [x[0].s for x in grids], [x[2].s for x in grids]
    count = len(grids)
    ids_a, a_all = (_ids(added), np.concatenate(added)) if isinstance(added, list) else added
    g_all, f_all = np.concatenate(gs), np.concatenate(fs)
    g_starts, f_starts = (_starts([x.size for x in xs]) for xs in (gs, fs))
    a_ids, a_s = _not_in(f_all, f_starts, *unique_pairs(ids_a.astype(np.intp), a_all))
    if not a_s.size:
        return {}
    # the middles of the intervals next to each added point, in its grid with the added
    at = segment_search(g_all, g_starts, a_ids, a_s)  # no added point is on the grid
    nan = np.full(a_s.size, np.nan)
    g_prev = np.where(at > g_starts[a_ids], g_all[np.maximum(at - 1, 0)], nan)
    g_next = np.where(at < g_starts[a_ids + 1], g_all[np.minimum(at, g_all.size - 1)], nan)
    same = a_ids[1:] == a_ids[:-1]
    a_prev, a_next = nan.copy(), nan.copy()
    a_prev[1:] = np.where(same, a_s[:-1], np.nan)
    a_next[:-1] = np.where(same, a_s[1:], np.nan)
    before, after = np.fmax(g_prev, a_prev), np.fmin(g_next, a_next)
    left = 0.5 * (np.where(np.isnan(before), a_s, before) + a_s)
    right = 0.5 * (a_s + np.where(np.isnan(after), a_s, after))
    p_ids, p_s = _not_in(
        f_all,
        f_starts,
        *unique_pairs(np.concatenate([a_ids] * 3), np.concatenate([a_s, left, right])),
    )
    new = _evaluate(sections, p_ids, p_s)
    new_forms = forms_of([new])[0]
    a_starts = np.searchsorted(a_ids, np.arange(count + 1)).astype(np.intp)
    pick = ~_not_on(a_s, a_starts, p_ids, p_s)
    grid_new = Samples(*(getattr(new, n)[pick] for n in _SAMPLES))
    forms_new = calibrate(PathForms(*(getattr(new_forms, n)[pick] for n in _FORMS)), grid_new)
    gained = np.bincount(p_ids, minlength=count)
    gained_g = np.bincount(p_ids[pick], minlength=count)
    merged = np.flatnonzero(gained_g)  # only the sections that gain are merged
    fine_at = _new_places(f_starts, gained, merged, p_ids, f_all, p_s)
    grid_at = _new_places(g_starts, gained_g, merged, p_ids[pick], g_all, p_s[pick])
    fine_sizes = (np.diff(f_starts) + gained)[merged].tolist()
    grid_sizes = (np.diff(g_starts) + gained_g)[merged].tolist()
    kept = [grids[k] for k in merged.tolist()]

    def split(
        olds: list[FloatArray], news: list[FloatArray], at: NDArray[np.intp], sizes: list[int]
    ) -> list[list[Any]]:
        out = []
        is_new = np.zeros(sum(sizes), dtype=bool)
        is_new[at] = True
        kept_at = np.flatnonzero(~is_new)
        for old, x in zip(olds, news, strict=True):
            y = np.empty((is_new.size, *old.shape[1:]), dtype=old.dtype)
            y[at], y[kept_at] = x, old
            out.append(cut(y, sizes))
        return out

    olds = [_olds([x[j] for x in kept], _SAMPLES if j % 2 == 0 else _FORMS) for j in range(4)]
    fine = split(olds[2], _olds([new], _SAMPLES), fine_at, fine_sizes)
    fine_f = split(olds[3], _olds([new_forms], _FORMS), fine_at, fine_sizes)
    grid = split(olds[0], _olds([grid_new], _SAMPLES), grid_at, grid_sizes)
    grid_f = split(olds[1], _olds([forms_new], _FORMS), grid_at, grid_sizes)
    return {
        k: (
            Samples(*(col[j] for col in grid)),
            PathForms(*(col[j] for col in grid_f)),
            Samples(*(col[j] for col in fine)),
            PathForms(*(col[j] for col in fine_f)),
        )
        for j, k in enumerate(merged.tolist())
    }
