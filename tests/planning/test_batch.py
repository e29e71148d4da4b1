"""Sections evaluated in one batch against each section evaluated alone."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning.batch import (
    changed_samples,
    check_again,
    check_sections,
    coarse_forms,
    coarse_samples,
    section_forms,
)
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import time_law
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.verify import REFINE

#: The batch against one section at a time, relative to the values' size [-].
RTOL = 1e-12
#: Absolute floor of that comparison (forces [N], motion, uses) [-].
ATOL = 1e-9
GRAVITY = np.array([1.5, -2.0, 9.6])
WRENCH = np.array([40.0, -25.0, 60.0, 2.0, -1.0, 3.0])
#: Moving sections parted by a dwell and a corner.
PROGRAM = "G1 X30 Y10 F9000\nG4 P0.1\nG2 X40 Y-20 Z10 I-10 J-20\nG1 X-20 Y-10\n"
ACCELERATION = 4.0  # [m/s^2] of the triangular laws


@pytest.mark.parametrize("leg_length", [0.31, 0.35])
def test_the_batch_equals_each_section_alone(leg_length: float) -> None:
    params = og.prototype().replace(leg_length=leg_length)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(
        str(example_drive_file())
    ))  # fmt: skip
    sections = [s for s in build_path(read_program(PROGRAM)).sections if s.pieces]
    assert len(sections) >= 2
    fines = [sample_section(s, 2e-3, refine=REFINE) for s in sections]
    forms = section_forms(dyn, fines, GRAVITY, WRENCH)
    laws, feeds = [], []
    for sec, fine, f in zip(sections, fines, forms, strict=True):
        alone = path_forms(dyn, fine.p, fine.dp, fine.ddp, gravity=GRAVITY, wrench=WRENCH)
        for name in ("q", "dq", "ddq", "a", "b", "c"):
            assert np.allclose(getattr(f, name), getattr(alone, name), rtol=RTOL, atol=ATOL)
        grid = coarse_samples(fine)
        coarse = coarse_forms(f)
        assert grid.s[0] == fine.s[0] and grid.s.size == (fine.s.size - 1) // REFINE + 1
        assert np.allclose(grid.s, sample_section(sec, 2e-3).s, rtol=0.0, atol=1e-15)  # [m]
        assert np.array_equal(coarse.a, f.a[::REFINE]) and coarse.q.shape == (grid.s.size, 3)
        length = float(grid.s[-1])
        x = np.minimum(2 * ACCELERATION * grid.s, 2 * ACCELERATION * (length - grid.s))
        laws.append(time_law(grid.s, x))
        feeds.append(np.full(fine.s.size, 0.5))
    both = check_sections(forms, fines, laws, feeds, limits)  # type: ignore[arg-type]
    for k in range(len(sections)):
        alone = check_sections([forms[k]], [fines[k]], [laws[k]], [feeds[k]], limits)  # type: ignore[list-item]
        mine = both[k]
        for name in ("t", "s", "sd", "sdd", "q", "qd", "qdd", "forces", "torque"):
            assert np.allclose(getattr(mine, name), getattr(alone[0], name), rtol=RTOL, atol=ATOL)
        assert mine.uses.keys() == alone[0].uses.keys()
        for name, use in mine.uses.items():
            assert np.allclose(use, alone[0].uses[name], rtol=RTOL, atol=ATOL), name


def test_a_re_plan_verified_where_it_changed_equals_the_whole_check() -> None:
    """``check_again`` on the changed samples: the motion of the new plan checked whole."""
    dyn = og.ClosedLoopDynamics()
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(
        str(example_drive_file())
    ))  # fmt: skip
    sec = next(s for s in build_path(read_program(PROGRAM)).sections if s.pieces)
    fine = sample_section(sec, 2e-3, refine=REFINE)
    forms = section_forms(dyn, [fine], GRAVITY, WRENCH)[0]
    grid = coarse_samples(fine)
    length = float(grid.s[-1])
    x = np.minimum(2 * ACCELERATION * grid.s, 2 * ACCELERATION * (length - grid.s))
    feed = np.where(np.arange(fine.s.size) < fine.s.size // 2, 0.5, np.inf)
    first = time_law(grid.s, x)
    x_new = x.copy()
    x_new[3:6] *= 0.9  # a local re-plan
    x_new[-1] = 0.0
    again = time_law(grid.s, x_new)
    old = check_sections([forms], [fine], [first], [feed], limits)[0]
    changed = changed_samples(x, x_new, fine.s.size)
    assert 0 < changed.sum() < fine.s.size // 2
    ours = check_again(forms, fine, again, feed, limits, None, old, changed)
    whole = check_sections([forms], [fine], [again], [feed], limits)[0]
    for name in ("t", "s", "sd", "sdd", "q", "qd", "qdd", "forces", "torque", "speed"):
        assert np.array_equal(getattr(ours, name), getattr(whole, name)), name
    assert ours.uses.keys() == whole.uses.keys()
    for name, use in ours.uses.items():
        assert np.array_equal(use, whole.uses[name]), name
