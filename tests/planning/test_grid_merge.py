"""Points added to many sections' grids in one pass: the grids merged section by section."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

import orthoglide_pin as og
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.batch import coarse_forms, coarse_samples, section_forms
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.grid_merge import merge_added
from orthoglide_pin.planning.path import Samples, Section, build_path
from orthoglide_pin.planning.sample_batch import sample_sections
from orthoglide_pin.planning.verify import REFINE

#: Stops at every block (G61), lines and an arc, then blended corners (G64).
PROGRAM = (
    "G61\nG1 X30 Y10 F9000\nG1 X35 Y12\nG2 X45 Y-18 Z10 I-10 J-20\nG1 X-20 Y-10\n"
    "G64 P0.05\nG1 X-10 Y-10\nG1 X-10 Y0\nG1 X0 Y0 Z5\n"
)
GRAVITY = np.array([0.0, 0.0, -9.81])
_FORMS = ("q", "dq", "ddq", "a", "b", "c")


def _samples_at(section: Section, s: NDArray[np.float64]) -> Samples:
    k = np.clip(np.searchsorted(section.offsets, s, side="right") - 1, 0, len(section.pieces) - 1)
    p, dp, ddp = (np.zeros((s.size, 3)) for _ in range(3))
    for j in np.unique(k):
        sel = k == j
        p[sel], dp[sel], ddp[sel] = section.pieces[j].evaluate(s[sel] - section.offsets[j])
    return Samples(s, p, dp, ddp, np.asarray(k, dtype=np.intp))


def _one_by_one(sec, grid, forms, fine, fine_forms, added, dyn):
    """The section-by-section merge (the reference)."""
    added = np.unique(added)
    added = added[~np.isin(added, fine.s)]
    if not added.size:
        return None
    s_all = np.unique(np.concatenate([grid.s, added]))
    j = np.searchsorted(s_all, added)
    left = 0.5 * (s_all[np.maximum(j - 1, 0)] + s_all[j])
    right = 0.5 * (s_all[j] + s_all[np.minimum(j + 1, s_all.size - 1)])
    pts = np.unique(np.concatenate([added, left, right]))
    pts = pts[~np.isin(pts, fine.s)]
    new = _samples_at(sec, pts)
    new_forms = section_forms(dyn, [new], GRAVITY, None)[0]
    pick = np.isin(pts, added)

    def merge(a, b, bf_a, bf_b):
        order = np.argsort(np.concatenate([a.s, b.s]), kind="stable")
        names = ("s", "p", "dp", "ddp", "piece")
        out = Samples(*(np.concatenate([getattr(a, n), getattr(b, n)])[order] for n in names))
        f = PathForms(
            *(np.concatenate([getattr(bf_a, n), getattr(bf_b, n)])[order] for n in _FORMS)
        )
        return out, f

    sub = Samples(*(getattr(new, n)[pick] for n in ("s", "p", "dp", "ddp", "piece")))
    sub_f = PathForms(*(getattr(new_forms, n)[pick] for n in _FORMS))
    return (*merge(grid, sub, forms, sub_f), *merge(fine, new, fine_forms, new_forms))


def test_merged_at_once_as_section_by_section() -> None:
    dyn = og.ClosedLoopDynamics()
    sections = [s for s in build_path(read_program(PROGRAM)).sections if s.pieces]
    assert len(sections) >= 4 and any(len(s.pieces) > 1 for s in sections)
    fines = sample_sections(sections, 2e-3, refine=REFINE)
    fine_forms = section_forms(dyn, fines, GRAVITY, None)
    grids = [
        (coarse_samples(f), coarse_forms(ff), f, ff)
        for f, ff in zip(fines, fine_forms, strict=True)
    ]
    rng = np.random.default_rng(7)
    added = []
    for k, (grid, _, fine, _) in enumerate(grids):
        if k == 1:
            added.append(fine.s[[3, 5]])  # already on the fine grid: nothing gained
            continue
        pts = rng.uniform(0.0, grid.s[-1], 6)
        added.append(np.concatenate([pts, pts[:2], fine.s[[2]], [grid.s[1] * 0.5]]))
    ours = merge_added(
        sections, grids, added, lambda xs: section_forms(dyn, xs, GRAVITY, None), lambda f, x: f
    )
    for k, sec in enumerate(sections):
        ref = _one_by_one(sec, *grids[k], added[k], dyn)
        if ref is None:
            assert k not in ours
            continue
        for mine, theirs in zip(ours[k], ref, strict=True):
            for name in mine.__dataclass_fields__:
                assert np.array_equal(getattr(mine, name), getattr(theirs, name)), (k, name)
