"""Local tightening: only the grid points around a violation are tightened."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import orthoglide_pin as og
import orthoglide_pin.planning.plan as plan_module
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits, Scales
from orthoglide_pin.planning.tighten import interval_uses, on_fine_grid, point_ratios, tighten
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


def test_a_plan_that_does_not_converge_is_refused_naming_the_limit(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(plan_module, "MAX_ROUNDS", 1)
    drive = load_drive(str(example_drive_file()))
    with pytest.raises(ProgramError, match="motor_torque after 1 plans"):
        plan_module.plan_program(read_program(CORNER), params, PlanLimits(drive=drive))
