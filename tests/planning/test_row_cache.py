"""The rows kept between plans: the same numbers as computed anew at every point."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import row_cache
from orthoglide_pin.planning.batch import coarse_forms, section_forms
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits, Scales, rows
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.verify import REFINE

PROGRAM = "G1 X30 Y10 F9000\nG2 X40 Y-20 Z10 I-10 J-20\n"
GRAVITY = np.array([0.0, 0.0, -9.81])


@pytest.fixture(params=[True, False], ids=["compiled", "numpy"])
def compiled(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    from orthoglide_pin.planning import limits as limits_module

    if request.param and not limits_module.COMPILED:
        pytest.skip("numba is not installed")
    monkeypatch.setattr(limits_module, "COMPILED", request.param)


def test_rows_computed_only_where_their_inputs_changed(compiled: None) -> None:
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(
        str(example_drive_file())
    ))  # fmt: skip
    sec = next(s for s in build_path(read_program(PROGRAM)).sections if s.pieces)
    fine = sample_section(sec, 2e-3, refine=REFINE)
    forms = coarse_forms(section_forms(og.ClosedLoopDynamics(), [fine], GRAVITY, None)[0])
    n = forms.q.shape[0]
    rng = np.random.default_rng(5)
    x_high = rng.uniform(0.05, 0.2, n)
    x0 = 0.5 * x_high
    cache = row_cache.RowCache(limits, forms)
    steps = [
        (x_high, x0, Scales()),
        (x_high, x0, Scales()),  # nothing changed
        (x_high, np.where(np.arange(n) == 4, 0.3 * x_high, x0), Scales()),
        (x_high, x0, Scales({"slider_acceleration": np.where(np.arange(n) < 3, 0.9, 1.0)})),
        (x_high, x0, Scales({"motor_torque": 0.95})),  # the whole section
        (np.where(np.arange(n) == 6, 0.5 * x_high, x_high), x0, Scales({"motor_torque": 0.95})),
    ]
    counts = []
    for xh, x_prev, scales in steps:
        before = cache.computed
        ours = cache.rows(xh, x_prev, scales)
        counts.append(cache.computed - before)
        for mine, theirs in zip(ours, rows(limits, forms, xh, x_prev, scales), strict=True):
            assert np.array_equal(mine, theirs)
    assert counts == [n, 0, 1, 4, n, 1]  # the first and last points are ends: recomputed alike
