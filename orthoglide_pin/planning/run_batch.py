"""A run of sections handled as one: lines, checks, feeds, time laws and searches in batch.

A program that stops at every block has as many sections as blocks, and
:func:`~orthoglide_pin.planning.plan.plan_program` plans them in runs of a few
thousand. What is done once per section costs a few numpy calls each; the
helpers here do it once per run on the sections' arrays laid end to end, with
the same numbers: :func:`run_lines` (the program line of every sample),
:func:`check_run` (the workspace and slider checks, the first bad point named
as section by section), :func:`run_feeds` (the path-speed caps of each
section, the lower feed at a junction; a window of a long section takes its
own, :mod:`~orthoglide_pin.planning.window_prep`),
:func:`time_laws` (each section's time law,
:func:`~orthoglide_pin.planning.parametrize.time_law`), :func:`joined_at_lengths`
(the laws at arc lengths,
:meth:`~orthoglide_pin.planning.parametrize.SectionPlan.at_lengths`),
:func:`segment_search` (``searchsorted`` within each section's part) and
:func:`cut` (an array cut into consecutive parts, as ``np.split`` but
without its cost per part). The loops run compiled with numba when it is
installed (:mod:`orthoglide_pin._compiled`), section by section in numpy
without it.
"""

from __future__ import annotations

import itertools
import math
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import AVAILABLE, jit
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.calibrated import CalibratedKinematics, check_sliders
from orthoglide_pin.planning.path import Path, Samples, Section, check_inside

FloatArray = NDArray[np.float64]
_Array = TypeVar("_Array", bound=NDArray[Any])


def cut(x: _Array, sizes: list[int]) -> list[_Array]:
    """``x`` cut into consecutive parts of ``sizes`` along its first axis (views)."""
    out, start = [], 0
    for n in sizes:
        out.append(x[start : start + n])
        start += n
    return out  # type: ignore[return-value]


def _piece_starts(sections: list[Section]) -> NDArray[np.intp]:
    """The index of each section's first piece among all the sections' pieces."""
    counts = np.array([len(sec.pieces) for sec in sections], dtype=np.intp)
    return np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)


def _flat_pieces(sections: list[Section], samples: list[Samples]) -> NDArray[np.intp]:
    """The index of each sample's piece among all the sections' pieces, laid end to end."""
    sizes = [x.s.size for x in samples]
    first = np.repeat(_piece_starts(sections), sizes)
    return np.asarray(np.concatenate([x.piece for x in samples]) + first, dtype=np.intp)


def run_lines(path: Path, sections: list[Section], samples: list[Samples]) -> NDArray[np.intp]:
    """The program line of every sample of the sections, laid end to end, (m,)."""
    blocks = path.program.blocks
    lines = np.array([blocks[p.block].line for sec in sections for p in sec.pieces], dtype=np.intp)
    return np.asarray(lines[_flat_pieces(sections, samples)])


def check_run(
    params: OrthoglideParams,
    calibration: CalibratedKinematics | None,
    samples: list[Samples],
    lines: NDArray[np.intp],
) -> None:
    """Every sample inside the cube and the slider limits (the calibrated ones too).

    All the samples are checked at once; when one is not, the sections are
    checked one by one, in order, so that the error names the point a
    section-by-section check names.

    Raises:
        ProgramError: Naming the line, the point in mm and the bound it breaks.
    """
    points = np.concatenate([x.p for x in samples])
    try:
        check_inside(params, points, lines)
        if calibration is not None:
            check_sliders(calibration, params, points, lines)
    except ProgramError:
        for x, part in zip(samples, cut(lines, [x.s.size for x in samples]), strict=True):
            check_inside(params, x.p, part)
            if calibration is not None:
                check_sliders(calibration, params, x.p, part)
        raise  # pragma: no cover (the batch and the sections agree)


def run_feeds(sections: list[Section], samples: list[Samples]) -> list[FloatArray]:
    """Each section's path-speed cap at its samples [m/s] (``inf`` on rapid moves).

    Each sample takes its piece's feed; the first sample of a piece (its
    junction with the piece before, in the same section) takes the lower of
    the two pieces' feeds.
    """
    if not sections:
        return []
    caps = np.array([math.inf if p.feed is None else p.feed for s in sections for p in s.pieces])
    sizes = [x.s.size for x in samples]
    piece = _flat_pieces(sections, samples)
    feed = caps[piece]
    step = np.diff(piece) != 0
    starts = np.cumsum(sizes)[:-1]
    step[starts - 1] = False  # a section's first sample starts no junction
    first = np.flatnonzero(step) + 1
    feed[first] = np.minimum(feed[first], caps[piece[first] - 1])
    return cut(feed, sizes)


def _segment_times(dt: FloatArray, starts: NDArray[np.intp], out: FloatArray) -> None:
    """``out``: each section's times, the running sum of its ``dt`` from 0 (in order)."""
    for k in range(starts.size - 1):
        lo, hi = starts[k], starts[k + 1]
        out[lo] = 0.0
        acc = 0.0
        for i in range(lo, hi - 1):
            acc += dt[i - k]
            out[i + 1] = acc


if AVAILABLE:
    _segment_times = jit(_segment_times)


def time_laws(
    s: FloatArray, x: FloatArray, sizes: list[int], rest_speed: float
) -> list[tuple[FloatArray, FloatArray, FloatArray, FloatArray]]:
    """Each section's ``(s, x, u, t)`` from grids and squared speeds laid end to end.

    The same numbers as :func:`~orthoglide_pin.planning.parametrize.time_law`
    of each section (the times summed in order, from the section's start).

    Args:
        s: The sections' grids, end to end [m], (m,).
        x: Their squared speeds [(m/s)^2], (m,).
        sizes: The points of each section (2 at least).
        rest_speed: Speeds below this are rest [m/s].
    """
    ends = np.cumsum(sizes)
    inner = np.ones(s.size - 1, dtype=bool)
    inner[ends[:-1] - 1] = False  # the step from a section's last point to the next one's first
    ds = np.diff(s)[inner]
    u = np.diff(x)[inner] / (2.0 * ds)
    sd = np.sqrt(np.maximum(x, 0.0))
    dt = 2.0 * ds / np.maximum(sd[:-1][inner] + sd[1:][inner], rest_speed)
    starts = np.concatenate([[0], ends]).astype(np.intp)
    t = np.empty(s.size)
    if AVAILABLE:
        _segment_times(dt, starts, t)
    else:
        for k, (lo, hi) in enumerate(itertools.pairwise(starts.tolist())):
            t[lo] = 0.0
            t[lo + 1 : hi] = np.cumsum(dt[lo - k : hi - k - 1])
    u_sizes = [n - 1 for n in sizes]
    return list(zip(cut(s, sizes), cut(x, sizes), cut(u, u_sizes), cut(t, sizes), strict=True))


def _at_lengths(
    law: tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]],
    query: tuple[FloatArray, NDArray[np.intp]],
    out: tuple[FloatArray, FloatArray, FloatArray],
) -> None:
    """``out``: time, speed and acceleration of each law at its queries (see :func:`laws_at`)."""
    big_s, big_x, big_u, big_t, starts = law
    s_all, q_starts = query
    t_out, sd_out, u_out = out
    for k in range(starts.size - 1):
        g0, n = starts[k], starts[k + 1] - starts[k]
        for q in range(q_starts[k], q_starts[k + 1]):
            s = s_all[q]
            lo, hi = 0, n  # searchsorted(grid, s, side="right")
            while lo < hi:
                mid = (lo + hi) // 2
                if big_s[g0 + mid] <= s:
                    lo = mid + 1
                else:
                    hi = mid
            i = min(max(lo - 1, 0), n - 2)
            ds = s - big_s[g0 + i]
            u = big_u[g0 - k + i]
            x = big_x[g0 + i] + 2.0 * u * ds
            if not (x >= 0.0 or math.isnan(x)):
                x = 0.0
            sd = math.sqrt(x)
            sd0 = math.sqrt(big_x[g0 + i])
            dt = 0.0
            if ds > 0.0:
                dt = (sd - sd0) / u if abs(u) > 0.0 else ds / sd0
            t_out[q] = big_t[g0 + i] + dt
            sd_out[q] = sd
            u_out[q] = u


if AVAILABLE:
    _at_lengths = jit(_at_lengths)


def joined_at_lengths(
    law: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
    sizes: list[int],
    lengths: list[FloatArray],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Time, speed and acceleration of time laws laid end to end at their arc lengths.

    Args:
        law: The laws' ``s``, ``x``, ``u`` and ``t``, each law's laid end to end
            (:class:`~orthoglide_pin.planning.parametrize.SectionPlan`).
        sizes: The grid points of each law.
        lengths: The arc lengths of each law [m].

    Returns:
        Time [s], speed [m/s] and acceleration [m/s^2] at the arc lengths, end to
        end: the numbers of
        :meth:`~orthoglide_pin.planning.parametrize.SectionPlan.at_lengths`, in one
        compiled pass (numba must be installed).
    """
    assert AVAILABLE
    starts = np.concatenate([[0], np.cumsum(sizes)]).astype(np.intp)
    q_starts = np.concatenate([[0], np.cumsum([s.size for s in lengths])]).astype(np.intp)
    s_all = np.concatenate(lengths).astype(np.float64)
    out = (np.empty(s_all.size), np.empty(s_all.size), np.empty(s_all.size))
    _at_lengths((*law, starts), (s_all, q_starts), out)
    return out


def _segment_search(
    values: FloatArray, starts: NDArray[np.intp], ids: NDArray[np.intp], queries: FloatArray,
    out: NDArray[np.intp],
) -> None:  # fmt: skip
    """``out``: where each query falls in its segment of ``values`` (bisection, side left)."""
    for q in range(queries.size):
        lo, hi, x = starts[ids[q]], starts[ids[q] + 1], queries[q]
        while lo < hi:
            mid = (lo + hi) // 2
            if values[mid] < x:
                lo = mid + 1
            else:
                hi = mid
        out[q] = lo


if AVAILABLE:
    _segment_search = jit(_segment_search)


def segment_search(
    values: FloatArray, starts: NDArray[np.intp], ids: NDArray[np.intp], queries: FloatArray
) -> NDArray[np.intp]:
    """``searchsorted`` of each query in its own segment, as an index into ``values``.

    Args:
        values: Sorted segments laid end to end, (m,).
        starts: The first index of each segment, and ``m``, (k + 1,).
        ids: The segment of each query, (q,).
        queries: The values searched, (q,).

    Returns:
        For each query, the index in ``values`` of its segment's first element not
        below it (side left).
    """
    out = np.empty(queries.size, dtype=np.intp)
    if AVAILABLE:
        _segment_search(values, starts, ids.astype(np.intp), queries.astype(np.float64), out)
        return out
    for k in np.unique(ids).tolist():  # pragma: no cover - without numba
        sel = ids == k
        part = values[starts[k] : starts[k + 1]]
        out[sel] = starts[k] + np.searchsorted(part, queries[sel], side="left")
    return out


def unique_pairs(ids: NDArray[np.intp], values: FloatArray) -> tuple[NDArray[np.intp], FloatArray]:
    """The distinct ``(id, value)`` pairs, sorted by id then value."""
    order = np.lexsort((values, ids))
    ids, values = ids[order], values[order]
    new = np.ones(values.size, dtype=bool)
    new[1:] = (values[1:] != values[:-1]) | (ids[1:] != ids[:-1])
    return ids[new], values[new]
