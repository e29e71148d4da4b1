"""The stability margin of every block along a plan: its points, its minimum, its samples."""

from __future__ import annotations

import numpy as np
import pytest
from machining._support import CUT, DT

import orthoglide_pin as og
from orthoglide_pin.machining.plan_stability import stability_along_plan
from orthoglide_pin.machining.stability_path import stability_margin_along

#: The same limits by the same route, in other batches (rounding of the batched algebra).
EXACT_TOL = 1e-9


@pytest.fixture(scope="module")
def run(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> tuple[og.OrthoglideParams, og.Plan, og.AccuracyResult, og.PlanStability]:
    params, plan = planned
    result = og.accuracy_along_plan(plan, og.cut_conditions(CUT), params, dt=DT)
    return params, plan, result, stability_along_plan(plan, result, params, points_per_block=3)


def test_each_line_gets_the_margin_at_its_point(
    run: tuple[og.OrthoglideParams, og.Plan, og.AccuracyResult, og.PlanStability],
) -> None:
    params, plan, result, st = run
    # the cutting lines, and the plunge's blend into the first of them
    assert st.lines.tolist() in ([4, 5, 6], [3, 4, 5, 6]) and st.points_per_block == 3
    again = stability_margin_along(
        st.points, result.cut, lines=st.lines, angles=st.angles, speeds=result.spindle_speed,
        params=params, axes=plan.path.program.axes,
    )  # fmt: skip
    np.testing.assert_allclose(again.margin, st.margin, rtol=EXACT_TOL)
    np.testing.assert_allclose(st.depths, 0.002)
    assert st.unstable == int(np.sum(st.margin <= 1.0))
    assert st.margin[st.worst] == st.margin.min()
    # line 4 feeds along program +X, line 5 along +Y, line 6 along -X
    np.testing.assert_allclose(np.cos(st.angles[-3:]), [1.0, 0.0, -1.0], atol=1e-6)


def test_a_line_keeps_its_smallest_margin_and_its_samples_carry_it(
    run: tuple[og.OrthoglideParams, og.Plan, og.AccuracyResult, og.PlanStability],
) -> None:
    params, plan, result, st = run
    first = stability_along_plan(plan, result, params, points_per_block=1)  # its first sample
    assert np.all(st.margin <= first.margin * (1 + EXACT_TOL))
    s = result.samples
    assert np.all(np.isnan(st.sample_margin[~s.cutting]))
    for ln, margin in zip(st.lines, st.margin, strict=True):
        sel = s.cutting & (s.line == ln)
        np.testing.assert_array_equal(st.sample_margin[sel], margin)


def test_a_plan_that_never_cuts_has_no_margin(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    idle = {**CUT, "engagement": {**CUT["engagement"], "lines": [100, 200]}}
    result = og.accuracy_along_plan(plan, og.cut_conditions(idle), params, dt=DT)
    st = stability_along_plan(plan, result, params)
    assert st.lines.size == 0 and st.worst == -1 and st.unstable == 0
    assert np.all(np.isnan(st.sample_margin))


@pytest.mark.parametrize("count", [0, 51, 2.5, True])
def test_points_per_block_is_checked(
    run: tuple[og.OrthoglideParams, og.Plan, og.AccuracyResult, og.PlanStability],
    count: object,
) -> None:
    params, plan, result, _ = run
    with pytest.raises(og.InvalidParameterError, match="points_per_block"):
        stability_along_plan(plan, result, params, points_per_block=count)  # type: ignore[arg-type]


def test_its_arguments_are_checked(
    run: tuple[og.OrthoglideParams, og.Plan, og.AccuracyResult, og.PlanStability],
) -> None:
    params, plan, result, _ = run
    with pytest.raises(og.InvalidParameterError, match="result"):
        stability_along_plan(plan, "accuracy", params)  # type: ignore[arg-type]
    with pytest.raises(og.InvalidParameterError, match="plan"):
        stability_along_plan(result, result, params)  # type: ignore[arg-type]
