"""Part accuracy along a plan: the feed per tooth, the forces in the world, the summary."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
from machining._support import CUT, DT

import orthoglide_pin as og
from orthoglide_pin.machining.accuracy import accuracy_along_plan
from orthoglide_pin.machining.forces import milling_forces

#: Rotations and the model's own formulas, relative.
EXACT_TOL = 1e-9


def test_feed_per_tooth_and_world_forces_follow_the_plan(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    cut = og.cut_conditions(CUT)
    result = accuracy_along_plan(plan, cut, params, dt=DT)
    s = result.samples
    n_rev = 10000 / 60.0
    plane = np.linalg.norm(s.plane_tangent, axis=1)
    expected = np.where(s.cutting, s.speed * plane / (3 * n_rev), 0.0)
    np.testing.assert_allclose(result.feed_per_tooth, expected, rtol=EXACT_TOL)
    programmed = 0.05 / (3 * n_rev)  # F3000 mm/min
    assert result.feed_per_tooth.max() <= programmed * (1 + 1e-6)
    assert result.feed_per_tooth[s.cutting].min() < 0.5 * programmed  # the corners slow down
    # line 4 feeds along program +X: the feed frame is (X, Y, Z) of the program
    k = int(
        np.flatnonzero(s.cutting & (s.line == 4))[
            len(np.flatnonzero(s.cutting & (s.line == 4))) // 2
        ]
    )
    e = cut.engagements[0]
    local = milling_forces(
        result.feed_per_tooth[k], e.axial_depth, e.immersion(0.01), cut.tool, cut.material
    )
    r = plan.path.program.axes.matrix
    np.testing.assert_allclose(
        result.force_mean[k], r @ local.mean[0], rtol=EXACT_TOL, atol=EXACT_TOL
    )
    assert result.force_peak[k] == pytest.approx(local.peak[0], rel=EXACT_TOL)
    assert not result.force_mean[~s.cutting].any() and not result.surface_static[~s.cutting].any()
    # a down-milling finishing pass leaves material; the peak bounds the static error
    assert (result.surface_static[s.cutting] > 0).all()
    assert (np.abs(result.surface_peak) >= np.abs(result.surface_static) - 1e-15).all()
    lines = [b.line for b in result.blocks]
    assert lines == sorted(lines) and {4, 5, 6} <= set(lines)
    assert (result.surface_generated[s.cutting] > 0).all()
    block4 = next(b for b in result.blocks if b.line == 4)
    on4 = result.surface_generated[s.line == 4]
    assert block4.surface_generated == on4[np.argmax(np.abs(on4))]
    assert block4.surface_peak == pytest.approx(
        result.surface_peak[s.line == 4][np.argmax(np.abs(result.surface_peak[s.line == 4]))]
    )


def test_the_summary_is_strict_json_and_the_budget_has_its_terms(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    servo = ([0.0, plan.cycle_time], [1e-6, 3e-6])
    result = accuracy_along_plan(
        plan, og.cut_conditions(CUT), params, dt=DT, servo=servo, temperature_rise=2.0
    )
    assert set(result.budget.terms) == {"servo", "compliance", "thermal"}
    at = np.interp(result.samples.t[result.samples.cutting], *servo)
    np.testing.assert_allclose(np.linalg.norm(result.budget.terms["servo"], axis=1), at)
    text = json.dumps(result.summary(), allow_nan=False)
    data = json.loads(text)
    assert data["spindle_speed_rpm"] == pytest.approx(10000)
    assert data["cutting_samples"] == int(result.samples.cutting.sum())
    assert data["worst"]["line"] in (4, 5, 6)
    assert math.isclose(
        data["surface_error_peak_max"], result.surface_peak[np.argmax(np.abs(result.surface_peak))]
    )
    columns = result.columns()
    assert all(v.shape == result.samples.t.shape for v in columns.values())


def test_the_spindle_speed_and_the_design_are_checked(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    from_program = og.cut_conditions({**CUT, "spindle_speed": "program"})
    with pytest.raises(og.CutConditionsError, match="spindle_speed"):
        accuracy_along_plan(plan, from_program, params, dt=DT)
    given = accuracy_along_plan(
        plan, from_program, params, dt=DT, spindle_speed=10000 / 60 * 2 * math.pi
    )
    assert given.spindle_speed == pytest.approx(10000 / 60 * 2 * math.pi)
    other = params.replace(leg_length=params.leg_length + 0.01)
    with pytest.raises(og.DesignMismatchError):
        accuracy_along_plan(plan, from_program, other, dt=DT, spindle_speed=1000.0)


def test_a_plan_that_never_cuts_has_no_force_and_an_empty_budget(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    elsewhere = og.cut_conditions({**CUT, "engagement": {**CUT["engagement"], "lines": [90, 99]}})
    result = accuracy_along_plan(plan, elsewhere, params, dt=DT, temperature_rise=1.0)
    assert not result.samples.cutting.any() and result.blocks == ()
    assert not result.force_peak.any() and result.budget.terms == {}
    data = json.loads(json.dumps(result.summary(), allow_nan=False))
    assert data["cutting_samples"] == 0 and data["worst"] is None


def test_a_calibration_of_this_design_gives_the_geometric_term(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    nominal = og.GeometricModel.nominal(params.leg_length)
    std = np.full(18, 1e-5)
    ours = og.Calibration(nominal, nominal, std, 1e-6, 1e-4, 1e-5, (), (), 30, "0" * 64,
                          design=og.design_digest(params))  # fmt: skip
    result = accuracy_along_plan(plan, og.cut_conditions(CUT), params, dt=DT, calibration=ours)
    geometric = result.budget.terms["geometric"]
    assert geometric.shape == (int(result.samples.cutting.sum()), 3) and (geometric > 0).all()
    other = dataclasses.replace(ours, design=og.design_digest(params.replace(leg_length=0.3)))
    with pytest.raises(og.DesignMismatchError):
        accuracy_along_plan(plan, og.cut_conditions(CUT), params, dt=DT, calibration=other)
