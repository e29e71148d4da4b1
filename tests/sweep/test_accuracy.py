"""A cut file in a sweep: each design's surface error and stability margin, and its keys."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import DriveTrain
from orthoglide_pin.exceptions import CutConditionsError, OutputPathError
from orthoglide_pin.machining.accuracy import accuracy_along_plan
from orthoglide_pin.machining.plan_stability import stability_along_plan
from orthoglide_pin.report.accuracy import accuracy_dict, accuracy_section
from orthoglide_pin.sweep import accuracy as sweep_accuracy
from orthoglide_pin.sweep.accuracy import ACCURACY_COLUMNS, accuracy_metrics, check_cut
from orthoglide_pin.sweep.labels import display_unit, label
from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec, design_key
from orthoglide_pin.sweep.store import part_problem
from orthoglide_pin.sweep.table import table_columns

pytest.importorskip("toppra")

#: A contour 2 mm deep: rapid, plunge (line 3), three cutting lines (4 to 6), rapid out.
PROGRAM = "G21 G90 G17\nG0 X-20 Y-10 Z5\nG1 Z-2 F600\nG1 X20 F3000\nG1 Y10\nG1 X-20\nG0 Z5\n"
CUT = {
    "tool": {"diameter": 0.01, "teeth": 3, "helix_angle": 0.5},
    "material": "aluminium_7075",
    "engagement": {"axial_depth": 0.002, "radial_width": 0.001, "milling": "down"},
    "spindle_speed": 10000,
}
SHALLOW = {**CUT, "engagement": {**CUT["engagement"], "axial_depth": 0.0005}}
LEGS = "0.31,0.34075"  # the prototype and another design
COARSE = {"grid": 3, "requirement_grid": 2}
#: The sweep's figures and a direct computation of the same machine.
SAME_RTOL = 1e-9
#: The three routes (accuracy, report, sweep) run the same computation.
SAME = 1e-12


def _spec(cut: object = CUT, program: str | None = PROGRAM, **kw: object) -> SweepSpec:
    return SweepSpec(
        axes=(SweepAxis.parse(f"leg_length={LEGS}"),), program=program, cut=cut, **COARSE, **kw
    )  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def done(tmp_path_factory: pytest.TempPathFactory) -> og.SweepResult:
    return run_sweep(_spec(), tmp_path_factory.mktemp("cut"), workers=1)


def _machine(spec: SweepSpec, leg: float) -> og.OrthoglideParams:
    return og.OrthoglideParams.from_dict(
        {
            **spec.base.to_dict(),
            "leg_length": leg,
            "workspace_corner": list(spec.corner()),
            "workspace_side": spec.cube_side,
            "slider_lower": None,
            "slider_upper": None,
        }
    )


def test_each_design_has_its_surface_error_and_margin(done: og.SweepResult) -> None:
    table = done.table
    assert list(table.columns) == table_columns(["leg_length"], program=True, cut=True)
    assert list(table.columns)[-2:] == list(ACCURACY_COLUMNS)
    spec = _spec()
    cut = og.cut_conditions(CUT)
    for row in table.itertuples():
        params = _machine(spec, row.leg_length)
        program = og.read_program(PROGRAM, axes=og.design_axes(params))
        plan = og.plan_program(program, params, og.PlanLimits(spec.speed, spec.acceleration))
        assert row.cycle_time == pytest.approx(plan.cycle_time, rel=SAME_RTOL)
        result = accuracy_along_plan(plan, cut, params)
        surface = float(np.abs(result.surface_generated).max())
        assert row.surface_error_max == pytest.approx(surface, rel=SAME_RTOL)
        stability = stability_along_plan(plan, result, params, drive=DriveTrain())
        assert stability.lines.tolist() == [3, 4, 5, 6]  # the blend out of the plunge cuts
        assert row.stability_margin_min == pytest.approx(stability.margin.min(), rel=SAME_RTOL)
    # a down-milling finishing pass leaves tens of micrometres; the longer legs a little more
    first, second = table.itertuples()
    assert 1e-5 < first.surface_error_max < second.surface_error_max < 2e-4


def test_the_cut_is_part_of_the_keys_and_the_record(done: og.SweepResult) -> None:
    with_cut = {design_key(d) for d in _spec().designs()}
    without = {design_key(d) for d in _spec(None).designs()}
    other = {design_key(d) for d in _spec(SHALLOW).designs()}
    assert not with_cut & without and not with_cut & other
    assert all("cut" not in d for d in _spec(None).designs())  # earlier keys unchanged
    record = json.loads((done.out / "sweep.json").read_text())
    assert record["cut"]["conditions"] == CUT and len(record["cut"]["sha256"]) == 64
    again = run_sweep(_spec(), done.out, workers=1)
    assert (again.computed, again.skipped) == (0, 2)
    with pytest.raises(OutputPathError, match=r"cut\.sha256"):
        run_sweep(_spec(SHALLOW), done.out, workers=1)
    with pytest.raises(OutputPathError, match="cut"):
        run_sweep(_spec(None), done.out, workers=1)


def test_a_part_without_the_cut_columns_is_not_done(done: og.SweepResult) -> None:
    design = _spec().designs()[0]
    part = json.loads((done.out / "parts" / f"{design_key(design)}.json").read_text())
    assert part_problem(part, design) is None
    short = {k: v for k, v in part.items() if k != "stability_margin_min"}
    assert part_problem(short, design) == "no stability_margin_min"
    assert "not a number" in str(part_problem({**part, "surface_error_max": "x"}, design))


def test_the_cut_file_is_checked_before_any_design(tmp_path: Path) -> None:
    with pytest.raises(og.InvalidParameterError, match="program"):
        _spec(program=None)
    with pytest.raises(CutConditionsError, match="spindle_speed"):
        _spec({**CUT, "spindle_speed": "program"})  # the program has no S
    with_s = PROGRAM.replace("G1 X20 F3000", "G1 X20 F3000 S9000")
    assert check_cut({**CUT, "spindle_speed": "program"}, with_s)["spindle_speed"] == "program"
    with pytest.raises(CutConditionsError, match="teeth"):
        _spec({**CUT, "tool": {**CUT["tool"], "teeth": 0}})
    with pytest.raises(og.InvalidParameterError, match="cut"):
        _spec(3)
    path = tmp_path / "cut.yaml"
    path.write_text(Path(og.shipped_cut_file()).read_text())
    assert check_cut(path, PROGRAM) == check_cut(str(path), PROGRAM)
    assert check_cut(path, PROGRAM)["spindle_speed"] == 12000
    with pytest.raises(CutConditionsError, match="cut file"):
        check_cut(tmp_path / "none.yaml", PROGRAM)


def test_the_programs_speed_and_a_program_that_never_cuts() -> None:
    params = og.prototype()
    design = _spec().designs()[0]
    rapid = "G21 G90\nG0 X10 Y5 Z-3 S8000\nG0 X0 Y0 Z0\n"
    plan = og.plan_program(og.read_program(rapid), params, og.PlanLimits(1.2, 20.0))
    found = accuracy_metrics(params, plan, {**design, "program": {"text": rapid}})
    assert found["surface_error_max"] == 0.0 and math.isnan(found["stability_margin_min"])
    # the cut file says "program": the program's S (9,000 rpm) is the spindle speed
    with_s = PROGRAM.replace("G1 X20 F3000", "G1 X20 F3000 S9000")
    plan = og.plan_program(og.read_program(with_s), params, og.PlanLimits(1.2, 20.0))
    entry = sweep_accuracy.design_entry({**CUT, "spindle_speed": "program"})
    found = accuracy_metrics(params, plan, {**design, "program": {"text": with_s}, "cut": entry})
    speed = 9000.0 * 2.0 * math.pi / 60.0
    result = accuracy_along_plan(plan, og.cut_conditions(CUT), params, spindle_speed=speed)
    assert found["surface_error_max"] == pytest.approx(
        float(np.abs(result.surface_generated).max()), rel=SAME_RTOL
    )


@pytest.mark.parametrize("leg", [0.31, 0.34075], ids=["prototype", "340.75 mm legs"])
def test_the_three_routes_give_the_same_figures(leg: float) -> None:
    """accuracy (its route), the report's section and the sweep's columns, matched settings."""
    spec = _spec()
    params = _machine(spec, leg)
    design = next(d for d in spec.designs() if d["leg_length"] == leg)
    program = og.read_program(PROGRAM, axes=og.design_axes(params))
    plan = og.plan_program(program, params, og.PlanLimits(spec.speed, spec.acceleration))
    cut = og.cut_conditions(CUT)
    # the route of ``orthoglide accuracy``
    result = accuracy_along_plan(plan, cut, params)
    stability = stability_along_plan(plan, result, params, drive=og.Drive().train)
    surface = float(np.abs(result.surface_generated).max())
    # the report's section (its default drive: the default drive train)
    section = accuracy_dict(accuracy_section(params, cut, plan, drive=og.Drive()))
    # the sweep's columns (its drive train: the default one)
    swept = accuracy_metrics(params, plan, design)
    assert abs(section["surface_error"]["generated"]["max"]) == pytest.approx(surface, rel=SAME)
    assert swept["surface_error_max"] == pytest.approx(surface, rel=SAME)
    assert section["stability"]["min"] == pytest.approx(stability.margin.min(), rel=SAME)
    assert swept["stability_margin_min"] == pytest.approx(stability.margin.min(), rel=SAME)
    assert section["stability"]["line"] == stability.lines[stability.worst]
    assert section["stability"]["unstable_blocks"] == stability.unstable
    assert section["drive_train"] == design["drive"]


def test_the_columns_read_in_the_reports_units() -> None:
    assert display_unit("surface_error_max") == (1e6, "um")
    assert label("surface_error_max") == "largest surface error [um]"
    assert label("stability_margin_min") == "least chatter stability margin [-]"
