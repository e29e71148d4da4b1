"""The report's accuracy section: along a program, and the lobes at home, Q1 and Q2 without one."""

from __future__ import annotations

import json
import time

import numpy as np
import pytest
from machining._support import CUT, LIMITS, PROGRAM

import orthoglide_pin as og
from orthoglide_pin.exceptions import CutConditionsError
from orthoglide_pin.machining.accuracy import accuracy_along_plan
from orthoglide_pin.machining.plan_stability import stability_along_plan
from orthoglide_pin.machining.stability import stability_lobes
from orthoglide_pin.report.accuracy import (
    POINTS,
    REPORT_SPEEDS,
    accuracy_dict,
    accuracy_html,
    accuracy_section,
    check_cut,
    lobes_figure,
)

#: The section and the machining layer run the same computation.
SAME_RTOL = 1e-12
#: Seconds the refusal of a cut without a speed may take (it comes before any work).
REFUSAL_S = 0.5
DESIGNS = [0.31, 0.34075]
IDS = ["prototype", "340.75 mm legs"]


@pytest.fixture(scope="module", params=DESIGNS, ids=IDS)
def planned(request: pytest.FixtureRequest) -> tuple[og.OrthoglideParams, og.Plan]:
    params = og.prototype().replace(leg_length=request.param)
    program = og.read_program(PROGRAM, axes=og.design_axes(params))
    return params, og.plan_program(program, params, LIMITS)


def test_along_a_program_the_section_is_the_machining_layers(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    params, plan = planned
    cut = og.cut_conditions(CUT)
    section = accuracy_section(params, cut, plan, cut_name="finish.yaml")
    result = accuracy_along_plan(plan, cut, params)
    d = accuracy_dict(section)
    json.dumps(d, allow_nan=False)  # strict JSON
    summary = result.summary()
    for key, name in (("static", "static"), ("generated", "generated"), ("peak", "peak")):
        assert d["surface_error"][key]["max"] == pytest.approx(
            summary[f"surface_error_{name}_max"], rel=SAME_RTOL
        )
    assert d["surface_error"]["peak"]["line"] == summary["worst"]["line"]
    assert d["budget"] == summary["budget"]
    # the margin of each cutting line as ``orthoglide accuracy`` computes it (no drive given)
    direct = stability_along_plan(plan, result, params)
    stability = section.stability
    assert stability is not None and stability.lines.tolist() == [3, 4, 5, 6]
    np.testing.assert_allclose(stability.points, direct.points, atol=1e-12)
    np.testing.assert_allclose(stability.margin, direct.margin, rtol=SAME_RTOL)
    st = d["stability"]
    assert st["min"] == pytest.approx(float(np.min(direct.margin)), rel=SAME_RTOL)
    assert st["line"] == direct.lines[direct.worst]
    assert st["unstable_blocks"] == direct.unstable and st["blocks"] == 4
    assert [r["line"] for r in st["per_block"]] == [3, 4, 5, 6]
    assert st["points_per_block"] == direct.points_per_block and d["drive_train"] is None
    page = accuracy_html(section)
    assert "finish.yaml" in page and f"{1e6 * summary['surface_error_peak_max']:+.2f} µm" in page
    assert f"{st['unstable_blocks']} of 4" in page
    assert lobes_figure(section) is None


def test_a_program_that_never_cuts_has_no_margin() -> None:
    params = og.prototype()
    program = og.read_program("G21 G90\nG0 X10 Y5 Z-3\nG0 X0 Y0 Z0\n", axes=og.design_axes())
    plan = og.plan_program(program, params, LIMITS)
    section = accuracy_section(params, og.cut_conditions(CUT), plan)
    d = accuracy_dict(section)
    assert section.stability is not None and section.stability.lines.size == 0
    assert d["stability"]["min"] is None
    assert d["surface_error"]["peak"] == {"max": 0.0, "point": None, "line": None}
    assert "No line cuts" in accuracy_html(section)


@pytest.mark.parametrize("leg", DESIGNS, ids=IDS)
def test_without_a_program_the_lobes_at_home_q1_and_q2(leg: float) -> None:
    params = og.prototype().replace(leg_length=leg)
    cut = og.cut_conditions(CUT)
    section = accuracy_section(params, cut, None)
    d = accuracy_dict(section)
    json.dumps(d, allow_nan=False)
    assert [lb["point_name"] for lb in d["lobes"]] == list(POINTS) and not d["program"]
    q2 = stability_lobes(
        cut, params.workspace.q2, params=params, speeds=REPORT_SPEEDS, zero_order=False
    )
    row = d["lobes"][2]
    assert row["point"] == pytest.approx(params.workspace.q2.tolist())
    assert row["minimum_depth"] == pytest.approx(q2.minimum, rel=SAME_RTOL)
    speed = float(cut.spindle_speed or 0.0)
    assert row["limit_depth_at_speed"] == pytest.approx(q2.limit_at(speed), rel=SAME_RTOL)
    assert row["margin"] == pytest.approx(q2.limit_at(speed) / 0.002, rel=SAME_RTOL)
    # the modes move with the tool: the lowest is lower at Q2 than at home, and so are the lobes
    home = d["lobes"][0]
    assert row["lowest_frequency"] < home["lowest_frequency"]
    assert row["minimum_depth"] < home["minimum_depth"]
    image = lobes_figure(section)
    assert image is not None and image.startswith(b"\x89PNG")
    assert "No program given" in accuracy_html(section)


def test_a_cut_without_a_speed_is_refused_before_any_work() -> None:
    cut = og.cut_conditions({**CUT, "spindle_speed": "program"})
    program = og.read_program(PROGRAM)
    with pytest.raises(CutConditionsError, match="spindle_speed"):
        check_cut(cut, None, program=True)
    assert check_cut(cut, 1000.0, program=True) is cut
    assert check_cut(cut, None, program=False) is cut  # the lobes need no speed
    start = time.perf_counter()
    with pytest.raises(CutConditionsError, match="spindle_speed"):
        og.assemble_report(cut=cut, program=program)
    assert time.perf_counter() - start < REFUSAL_S
    with pytest.raises(og.InvalidParameterError, match="cut"):
        og.assemble_report(cut={"tool": 1})  # type: ignore[arg-type]
