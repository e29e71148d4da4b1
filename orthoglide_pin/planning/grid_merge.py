"""The points a refinement adds to many sections' grids, merged in one pass.

:func:`~orthoglide_pin.planning.grid.refine_grid` adds, after each plan, the
switch points of every section to its planning grid, and those points with the
middles of the intervals next to them to its verification grid. A program that
stops at every block has as many sections as blocks; merging them section by
section costs a few dozen array calls each. :func:`merge_added` merges all the
sections' points at once: each arc length is replaced by its rank among all
the arc lengths involved, so that ``section * ranks + rank`` orders the points
of every section by arc length, exactly (no arc length is rounded, as adding a
section's offset would), and one sort, one set test and one split replace the
per-section ones. The grids are the same as merged section by section.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.blend import BlendPiece
from orthoglide_pin.planning.path import Samples, Section
from orthoglide_pin.planning.run_batch import cut

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


def _member(keys: IntArray, sorted_keys: IntArray) -> NDArray[np.bool_]:
    """Whether each key is in ``sorted_keys`` (ascending), as ``np.isin``."""
    if not sorted_keys.size:
        return np.zeros(keys.shape, dtype=bool)
    at = np.minimum(np.searchsorted(sorted_keys, keys), sorted_keys.size - 1)
    return np.asarray(sorted_keys[at] == keys)


def _joined(
    olds: list[Samples] | list[PathForms], new: Samples | PathForms, names: tuple[str, ...]
) -> list[FloatArray]:
    """Each field of the ``olds`` then of ``new``, concatenated."""
    return [np.concatenate([*(getattr(x, n) for x in olds), getattr(new, n)]) for n in names]


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
    ids_g, ids_f = _ids(gs), _ids(fs)
    ids_a, a_all = (_ids(added), np.concatenate(added)) if isinstance(added, list) else added
    g_all, f_all = np.concatenate(gs), np.concatenate(fs)
    (k_g, k_f, k_a), values, r = _ranked(
        [(ids_g, g_all), (ids_f, f_all), (ids_a.astype(np.int64), a_all)]
    )
    k_a = np.unique(k_a)
    k_a = k_a[~_member(k_a, k_f)]  # k_f ascending: sections in order, each sorted
    if not k_a.size:
        return {}
    a_ids, a_s = k_a // r, values[k_a % r]
    # the middles of the intervals next to each added point, in its grid with the added
    k_all = np.sort(np.concatenate([k_g, k_a]))
    s_all, all_ids = values[k_all % r], k_all // r
    j = np.searchsorted(k_all, k_a)
    lo = np.searchsorted(all_ids, a_ids, side="left")
    hi = np.searchsorted(all_ids, a_ids, side="right") - 1
    left = 0.5 * (s_all[np.maximum(j - 1, lo)] + s_all[j])
    right = 0.5 * (s_all[j] + s_all[np.minimum(j + 1, hi)])
    (k_g, k_f, k_a, k_c), values, r = _ranked(
        [
            (ids_g, g_all),
            (ids_f, f_all),
            (a_ids, a_s),
            (np.concatenate([a_ids] * 3), np.concatenate([a_s, left, right])),
        ]
    )
    k_p = np.unique(k_c)
    k_p = k_p[~_member(k_p, k_f)]
    p_ids = k_p // r
    new = _evaluate(sections, p_ids, values[k_p % r])
    new_forms = forms_of([new])[0]
    pick = _member(k_p, k_a)
    grid_new = Samples(*(getattr(new, n)[pick] for n in _SAMPLES))
    forms_new = calibrate(PathForms(*(getattr(new_forms, n)[pick] for n in _FORMS)), grid_new)
    n = len(grids)
    gained = np.bincount(p_ids, minlength=n)
    gained_g = np.bincount(p_ids[pick], minlength=n)
    merged = np.flatnonzero(gained_g)  # only the sections that gain are merged
    on_f, on_g = gained_g[ids_f] > 0, gained_g[ids_g] > 0
    fine_order = np.argsort(np.concatenate([k_f[on_f], k_p]), kind="stable")
    grid_order = np.argsort(np.concatenate([k_g[on_g], k_p[pick]]), kind="stable")
    fine_sizes = (np.array([x.size for x in fs]) + gained)[merged].tolist()
    grid_sizes = (np.array([x.size for x in gs]) + gained_g)[merged].tolist()
    kept = [grids[k] for k in merged.tolist()]

    def split(parts: list[FloatArray], order: NDArray[np.intp], sizes: list[int]) -> list[list]:  # type: ignore[type-arg]
        return [cut(np.asarray(x)[order], sizes) for x in parts]

    fine = split(_joined([x[2] for x in kept], new, _SAMPLES), fine_order, fine_sizes)
    fine_f = split(_joined([x[3] for x in kept], new_forms, _FORMS), fine_order, fine_sizes)
    grid = split(_joined([x[0] for x in kept], grid_new, _SAMPLES), grid_order, grid_sizes)
    grid_f = split(_joined([x[1] for x in kept], forms_new, _FORMS), grid_order, grid_sizes)
    return {
        k: (
            Samples(*(col[j] for col in grid)),
            PathForms(*(col[j] for col in grid_f)),
            Samples(*(col[j] for col in fine)),
            PathForms(*(col[j] for col in fine_f)),
        )
        for j, k in enumerate(merged.tolist())
    }
