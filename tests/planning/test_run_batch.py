"""A run of sections handled as one: the same numbers and errors as section by section."""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.parametrize import laws_at, time_law
from orthoglide_pin.planning.path import Path, Samples, Section, build_path, check_inside
from orthoglide_pin.planning.run_batch import (
    check_run,
    run_feeds,
    run_lines,
    segment_search,
    time_laws,
    unique_pairs,
)
from orthoglide_pin.planning.sample_batch import sample_sections

#: Stops at every block (G61): lines at two feeds, a rapid, an arc.
PROGRAM = (
    "G61\nG1 X30 Y10 F9000\nG1 X35 Y12 F3000\nG0 X20 Y0\nG2 X30 Y-10 Z5 I10 J0 F6000\n"
    "G1 X0 Y0 Z0\n"
)
STEP = 2e-3  # [m]
#: Blended corners (G64) between lines at F3000, F9000 and F6000, then a rapid.
BLENDED = "G64 P0.05\nG1 X30 Y10 F3000\nG1 X35 Y12 F9000\nG1 X30 Y20 F6000\nG1 X0 Y20\nG0 X0 Y0\n"


def _run() -> tuple[og.OrthoglideParams, Path, list[Section], list[Samples]]:
    path = build_path(read_program(PROGRAM))
    sections = [sec for sec in path.sections if sec.pieces]
    return og.OrthoglideParams(), path, sections, sample_sections(sections, STEP, refine=3)


def test_lines_and_feeds_are_those_of_each_section() -> None:
    _, path, sections, samples = _run()
    assert len(sections) > 3
    lines = run_lines(path, sections, samples)
    ends = np.cumsum([0] + [x.s.size for x in samples])
    blocks = path.program.blocks
    for k, (sec, x) in enumerate(zip(sections, samples, strict=True)):
        want = [blocks[sec.pieces[j].block].line for j in x.piece]
        np.testing.assert_array_equal(lines[ends[k] : ends[k + 1]], want)
    for feed, sec, x in zip(run_feeds(sections, samples), sections, samples, strict=True):
        np.testing.assert_array_equal(feed, _feeds_one_by_one(sec, x))


def _feeds_one_by_one(sec: Section, x: Samples) -> list[float]:
    """Each sample's piece feed (inf on a rapid), the lower of two at a junction."""
    caps = [math.inf if p.feed is None else p.feed for p in sec.pieces]
    out = []
    for j, k in enumerate(x.piece):
        cap = caps[k]
        if j and x.piece[j - 1] != k:
            cap = min(cap, caps[x.piece[j - 1]])
        out.append(cap)
    return out


def test_feeds_at_the_junctions_of_blended_pieces_are_the_lower() -> None:
    """One blended section of pieces at three feeds, then a rapid: each junction the lower."""
    path = build_path(read_program(BLENDED))
    sections = [sec for sec in path.sections if sec.pieces]
    samples = sample_sections(sections, STEP, refine=3)
    assert max(len(sec.pieces) for sec in sections) > 3
    feeds = run_feeds(sections, samples)
    for feed, sec, x in zip(feeds, sections, samples, strict=True):
        np.testing.assert_array_equal(feed, _feeds_one_by_one(sec, x))
    joined = np.concatenate(feeds)
    assert {0.05, 0.1, 0.15} <= set(joined.tolist()) and np.isinf(joined).any()


def test_the_first_bad_point_is_named_as_section_by_section() -> None:
    params, path, sections, samples = _run()
    lines = run_lines(path, sections, samples)
    check_run(params, None, samples, lines)  # every point inside
    # a point of section 2, then one of section 1, leave the cube: section 1's is named
    samples[2].p[3] = params.workspace.q2 + 1.0
    low = samples[1].p[5].copy()
    samples[1].p[5] = [low[0], low[1], params.workspace.q1[2] - 1.0]
    with pytest.raises(ProgramError) as batch:
        check_run(params, None, samples, lines)
    first = int(np.sum([x.s.size for x in samples[:1]]))
    part = lines[first : first + samples[1].s.size]
    with pytest.raises(ProgramError) as alone:
        check_inside(params, samples[1].p, part)
    assert str(batch.value) == str(alone.value)


def test_time_laws_and_their_values_are_those_of_each_section() -> None:
    rng = np.random.default_rng(7)
    grids = [np.cumsum(rng.uniform(1e-4, 2e-3, n)) for n in (2, 5, 9, 3)]
    xs = [rng.uniform(0.0, 0.04, g.size) for g in grids]
    for x in xs:
        x[[0, -1]] = 0.0
    laws = time_laws(np.concatenate(grids), np.concatenate(xs), [g.size for g in grids], 1e-12)
    alone = [time_law(g, x) for g, x in zip(grids, xs, strict=True)]
    for got, want in zip(laws, alone, strict=True):
        for j, name in enumerate(("s", "x", "u", "t")):
            np.testing.assert_array_equal(got[j], getattr(want, name))
    queries = [np.linspace(g[0], g[-1], 7) for g in grids]
    joined = laws_at(alone, queries)
    ends = np.cumsum([0] + [q.size for q in queries])
    for k, (law, q) in enumerate(zip(alone, queries, strict=True)):
        for mine, theirs in zip(joined, law.at_lengths(q)[:3], strict=True):
            np.testing.assert_array_equal(mine[ends[k] : ends[k + 1]], theirs)


def test_a_search_stays_in_its_own_segment() -> None:
    values = np.array([0.0, 1.0, 2.0, 0.0, 0.5, 3.0])
    starts = np.array([0, 3, 6])
    ids = np.array([0, 0, 1, 1, 1])
    queries = np.array([1.0, 5.0, -1.0, 0.5, 9.0])
    got = segment_search(values, starts, ids, queries)
    np.testing.assert_array_equal(got, [1, 3, 3, 4, 6])
    pair_ids, pair_values = unique_pairs(np.array([1, 0, 1, 0]), np.array([2.0, 3.0, 2.0, 1.0]))
    np.testing.assert_array_equal(pair_ids, [0, 0, 1])
    np.testing.assert_array_equal(pair_values, [1.0, 3.0, 2.0])
