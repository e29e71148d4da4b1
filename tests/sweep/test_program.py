"""A part program in a sweep: each design's cycle time, its binding limit, and its keys."""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import OutputPathError, ProgramError
from orthoglide_pin.planning import PlanLimits, plan_program
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.sweep.program import UNREACHABLE
from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec, design_key
from orthoglide_pin.sweep.store import part_problem
from orthoglide_pin.sweep.table import table_columns

pytest.importorskip("toppra")

#: A short program: a rapid, a square at a feed, back home.
PROGRAM = "G21 G90 G64 P0.02\nG0 X40 Y-30\nG1 Y30 F9000\nG1 X-40\nG0 X0 Y0 Z20\nM2\n"
OTHER = PROGRAM.replace("F9000", "F6000")
LEGS = "0.28,0.31,0.36"
#: Coarse grids keep the sweep fast.
COARSE = {"grid": 8, "requirement_grid": 2}
#: The sweep's plan and a direct plan of the same machine (same computation).
SAME_RTOL = 1e-12


def _spec(program: str | None = PROGRAM, legs: str = LEGS, **kw: object) -> SweepSpec:
    return SweepSpec(
        axes=(SweepAxis.parse(f"leg_length={legs}"),), program=program, **COARSE, **kw
    )  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def done(tmp_path_factory: pytest.TempPathFactory) -> og.SweepResult:
    return run_sweep(_spec(), tmp_path_factory.mktemp("program"), workers=1)


def test_each_design_has_its_own_cycle_time(done: og.SweepResult) -> None:
    table = done.table
    assert list(table.columns) == table_columns(["leg_length"], program=True)
    assert (table["status"] == "ok").all()
    spec = _spec()
    for row in table.itertuples():
        machine = og.OrthoglideParams.from_dict(
            {
                **spec.base.to_dict(),
                "leg_length": row.leg_length,
                "workspace_corner": list(spec.corner()),
                "workspace_side": spec.cube_side,
                "slider_lower": None,
                "slider_upper": None,
            }
        )
        dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(machine))
        limits = PlanLimits(slider_speed=spec.speed, slider_acceleration=spec.acceleration)
        plan = plan_program(read_program(PROGRAM), dyn, limits)
        assert row.cycle_time == pytest.approx(plan.cycle_time, rel=SAME_RTOL)
        most = max(plan.binding, key=plan.binding.__getitem__)
        assert row.binding_limit == most
    # the legs change the transmission factors, so the slider-bound moves take other times
    times = table["cycle_time"].tolist()
    assert len({round(t, 9) for t in times}) == 3 and min(times) > 0.1


def test_the_program_is_part_of_the_keys_and_the_record(done: og.SweepResult) -> None:
    with_program = [design_key(d) for d in _spec().designs()]
    without = [design_key(d) for d in _spec(None).designs()]
    other = [design_key(d) for d in _spec(OTHER).designs()]
    assert not set(with_program) & set(without) and not set(with_program) & set(other)
    assert all("program" not in d for d in _spec(None).designs())  # earlier keys unchanged
    assert "program" not in _spec(None).to_dict()
    record = json.loads((done.out / "sweep.json").read_text())
    sha = hashlib.sha256(PROGRAM.encode()).hexdigest()
    assert record["program"] == {"sha256": sha, "bytes": len(PROGRAM), "blocks": 4}


def test_a_resumed_sweep_keeps_its_program(done: og.SweepResult) -> None:
    again = run_sweep(_spec(), done.out, workers=1)
    assert (again.computed, again.skipped) == (0, 3)
    with pytest.raises(OutputPathError, match=r"program\.sha256"):
        run_sweep(_spec(OTHER), done.out, workers=1)
    with pytest.raises(OutputPathError, match="program"):
        run_sweep(_spec(None), done.out, workers=1)


def test_a_part_without_the_programs_columns_is_not_done(done: og.SweepResult) -> None:
    design = _spec().designs()[0]
    part = json.loads((done.out / "parts" / f"{design_key(design)}.json").read_text())
    assert part_problem(part, design) is None
    assert part_problem({k: v for k, v in part.items() if k != "cycle_time"}, design) == (
        "no cycle_time"
    )
    assert "binding_limit" in str(part_problem({**part, "binding_limit": 3.0}, design))


def test_out_of_reach_designs_keep_their_metrics(tmp_path: Path) -> None:
    """Redesign mode: the cube follows the leg, and a short leg's cube misses the program."""
    far = "G21 G90\nG0 X100\nG0 X0\nM2\n"
    spec = _spec(far, legs="0.2,0.31", mode="redesign")
    table = run_sweep(spec, tmp_path / "r", workers=1).table
    short, long = table.itertuples()
    assert short.status == "ok" and math.isnan(short.cycle_time)
    assert short.binding_limit == UNREACHABLE and math.isfinite(short.max_motor_torque)
    assert long.cycle_time > 0.0 and long.binding_limit != UNREACHABLE


def test_a_bad_program_is_refused() -> None:
    with pytest.raises(ProgramError, match="program line 1"):
        _spec("G1 X10\n")
    with pytest.raises(og.OrthoglideError, match="program"):
        _spec(3)  # type: ignore[arg-type]
