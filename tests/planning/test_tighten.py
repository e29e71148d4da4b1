"""Local tightening: only the grid points around a violation are tightened."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
import orthoglide_pin.planning.plan as plan_module
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits, Scales
from orthoglide_pin.planning.tighten import (
    FALLBACK_MARGIN,
    interval_uses,
    on_fine_grid,
    point_ratios,
    tighten,
    whole_section,
)
from orthoglide_pin.planning.verify import USE_TOL

pytest.importorskip("toppra")

#: A square corner blended within 0.01 mm: the torque overshoots in the blend only.
CORNER = "G64 P0.01\nG1 X60 F60000\nG1 X60 Y60\nG1 X0 Y60\n"
#: Far from the violation: at least this far from every tightened grid point [m].
FAR = 0.01
#: Speeds far from the violation against the untightened plan [-].
FAR_RTOL = 1e-9


def test_interval_and_point_uses_match_a_brute_force() -> None:
    rng = np.random.default_rng(3)
    grid = np.cumsum(rng.uniform(0.5, 1.5, 12))
    fine = np.concatenate([np.linspace(a, b, 6)[:-1] for a, b in itertools.pairwise(grid)])
    fine = np.append(fine, grid[-1])
    use = rng.uniform(0.0, 2.0, fine.size)
    per = interval_uses(grid, fine, use)
    for i in range(grid.size - 1):
        inside = (fine >= grid[i]) & (fine <= grid[i + 1])
        assert per[i] == use[inside].max()
    for width in (1, 2):
        ratio = point_ratios(grid, fine, use, width)
        for i in range(grid.size):
            near = [per[j] for j in range(i - width, i + width) if 0 <= j < per.size]
            assert ratio[i] == max(near)


def test_only_the_points_around_an_overshoot_are_tightened() -> None:
    grid = np.linspace(0.0, 1.0, 11)
    fine = np.linspace(0.0, 1.0, 101)
    use = np.full(fine.size, 0.5)
    use[55] = 1.2  # in the interval [0.5, 0.6]
    scales = Scales({"feed": 0.9})
    over = tighten(scales, {"feed": use, "slider_speed": 0.5 * use}, grid, fine, USE_TOL, 1)
    assert over == {"feed": 1.2} and "slider_speed" not in scales.factors
    f = np.asarray(scales.get("feed"))
    changed = np.flatnonzero(f < 0.9)
    assert changed.tolist() == [4, 5, 6, 7]  # the interval's ends and one point either side
    assert np.allclose(f[changed] * 1.2, 0.9, rtol=1e-3) and np.all(f[f >= 0.9] == 0.9)
    at_fine = np.asarray(on_fine_grid(scales, grid, fine).get("feed"))
    assert at_fine[55] == f[5] and at_fine[5] == 0.9


def _plans(params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch) -> tuple:
    drive = load_drive(str(example_drive_file()))
    prog = read_program(CORNER)
    plan = plan_module.plan_program(prog, params, PlanLimits(drive=drive))
    with monkeypatch.context() as m:  # the first, untightened plan
        m.setattr(plan_module, "tighten", lambda *args, **kwargs: {})
        first = plan_module.plan_program(prog, params, PlanLimits(drive=drive))
    return plan, first


@pytest.mark.parametrize("leg", [None, 0.36])
def test_a_local_overshoot_leaves_the_rest_at_the_untightened_optimum(
    params: og.OrthoglideParams, leg: float | None, monkeypatch: pytest.MonkeyPatch
) -> None:
    design = params if leg is None else params.replace(leg_length=leg)
    plan, first = _plans(design, monkeypatch)
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    assert max(first.worst.values()) > 1.0 + USE_TOL  # the first plan overshoots
    r, r0 = plan.sections[0], first.sections[0]
    assert r.rounds > 1 and r.grid is not None and r0.motion is not None
    scales = Scales()
    tighten(scales, r0.motion.uses, r.grid.s, r0.motion.s, USE_TOL, 1)
    s = r.grid.s
    tight = np.asarray(scales.get("motor_torque")) < 1.0
    assert 0 < tight.sum() < 0.2 * s.size  # a few points, around the corner
    far = np.min(np.abs(s[:, None] - s[tight][None, :]), axis=1) > FAR
    far[[0, -1]] = False
    assert far.sum() > 0.5 * s.size
    assert r.plan is not None and r0.plan is not None
    assert np.allclose(r.plan.x[far], r0.plan.x[far], rtol=FAR_RTOL, atol=0.0)
    # the torque binds there: a factor for the whole section would have slowed it
    use0 = r0.motion.uses["motor_torque"]
    at = np.clip(np.searchsorted(r0.motion.s, s[far]), 0, use0.size - 1)
    assert use0[at].max() > 0.99
    assert plan.cycle_time <= first.cycle_time * (1.0 + 0.01)


def test_a_plan_that_does_not_converge_even_slowed_is_refused_naming_the_limit(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(plan_module, "MAX_ROUNDS", 1)
    monkeypatch.setattr(plan_module, "FALLBACK_ROUNDS", 0)
    drive = load_drive(str(example_drive_file()))
    with pytest.raises(ProgramError, match="motor_torque after 1 plans"):
        plan_module.plan_program(read_program(CORNER), params, PlanLimits(drive=drive))


def test_a_plan_that_does_not_converge_falls_back_and_says_what_it_cost(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    drive = load_drive(str(example_drive_file()))
    optimum = plan_module.plan_program(read_program(CORNER), params, PlanLimits(drive=drive))
    assert optimum.fallbacks == ()
    monkeypatch.setattr(plan_module, "MAX_ROUNDS", 1)
    plan = plan_module.plan_program(read_program(CORNER), params, PlanLimits(drive=drive))
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    (fall,) = plan.fallbacks
    assert fall.limit == "motor_torque" and fall.use > 1.0 + USE_TOL and fall.line in (2, 3)
    assert 0.0 < fall.factor < 1.0 and fall.cost >= 0.0
    assert plan.cycle_time >= optimum.cycle_time * (1.0 - 1e-9)
    assert set(fall.as_dict()) == {"line", "limit", "use", "factor", "cost"}


def test_whole_section_lowers_every_exceeded_limit_by_its_overshoot() -> None:
    scales = Scales({"motor_torque": np.array([1.0, 0.5, 1.0])})
    applied: dict[str, float] = {}
    whole_section(scales, {"motor_torque": 1.25, "slider_acceleration": 2.0}, applied)
    lowered = 1.0 / (1.25 * (1.0 + FALLBACK_MARGIN))
    np.testing.assert_allclose(scales.get("motor_torque"), np.array([1.0, 0.5, 1.0]) * lowered)
    assert applied["slider_acceleration"] == pytest.approx(1.0 / (2.0 * (1.0 + FALLBACK_MARGIN)))


#: A dense relief of short G64 segments (0.1 to 0.5 mm) whose curvature changes at each
#: block: local tightening of the motor torque keeps moving its overshoot (1.0017 after
#: its 8 plans), so the section is planned slower on the whole.
RELIEF = """G21 G90 G64 P0.01
G0 X53.4561 Y-0.0733 Z-0.4315
F6000
G1 X53.8707 Y-0.4919 Z-0.6733
G1 X54.2065 Y-0.3384 Z-1.7787
G1 X54.4471 Y-0.0107 Z1.6336
G1 X54.7555 Y0.3928 Z-0.5948
G1 X54.9162 Y0.4915 Z0.5673
G1 X55.3379 Y0.2357 Z0.9115
G1 X55.4911 Y0.0156 Z0.3958
G1 X55.9418 Y-0.4845 Z1.2565
G1 X56.3243 Y-0.3117 Z1.9353
G1 X56.6967 Y0.2148 Z1.5289
G1 X57.1953 Y0.4663 Z0.5873
G1 X57.6154 Y-0.0293 Z-1.1789
G1 X57.8604 Y-0.3564 Z1.2499
G1 X58.1084 Y-0.4997 Z0.0295
"""


def test_a_dense_relief_that_tightening_cannot_settle_is_planned(
    params: og.OrthoglideParams,
) -> None:
    drive = load_drive(str(example_drive_file()))
    limits = PlanLimits(drive=drive, torque_reserve=0.0)  # the whole peak torque, as found
    plan = plan_module.plan_program(read_program(RELIEF), params, limits)
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    assert [f.limit for f in plan.fallbacks] == ["motor_torque"]
    assert plan.fallbacks[0].cost < 0.01 * plan.cycle_time


#: LinuxCNC's blurred torus: a CAM relief of 1,905 lines (tests/program/corpus/SOURCES.md).
TORUS = Path(__file__).parents[1] / "program" / "corpus" / "linuxcnc-tp-blur_torus.ngc"
#: What its slower sections may cost together, as a share of the cycle time [-].
FALLBACK_SHARE = 0.1


@pytest.mark.slow
def test_a_cam_relief_that_tightening_cannot_settle_is_planned(
    params: og.OrthoglideParams,
) -> None:
    """It used to stop after its re-plans ("line 852: ... 1.2125 of slider_acceleration")."""
    program = read_program(TORUS.read_text())
    assert len(program.blocks) > 1800
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0)
    plan = plan_module.plan_program(program, params, limits)
    assert max(plan.worst.values()) <= 1.0 + USE_TOL  # the verification holds
    assert {f.limit for f in plan.fallbacks} == {"slider_acceleration"}
    assert 852 in {f.line for f in plan.fallbacks}
    assert sum(f.cost for f in plan.fallbacks) < FALLBACK_SHARE * plan.cycle_time
