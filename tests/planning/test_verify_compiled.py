"""The verification's compiled pass against the array version, and its interval search."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning import verify, verify_compiled
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.verify import evaluate_forms

#: Values of both versions, relative to their largest [-] (the same operations).
RTOL = 1e-14
PROGRAM = "G1 X30 Y10 F9000\nG2 X40 Y-20 Z10 I-10 J-20\nG1 X-20 Y-10\n"

needs_numba = pytest.mark.skipif(not verify_compiled.AVAILABLE, reason="numba is not installed")


def _limits(which: int) -> PlanLimits:
    """The example drive with slider limits; its curve alone; its peak alone, no slider limits."""
    drive = og.load_drive(str(og.example_drive_file()))
    assert drive.motor is not None
    if which == 0:
        return PlanLimits(slider_speed=1.0, slider_acceleration=15.0, drive=drive)
    if which == 1:
        motor = dataclasses.replace(drive.motor, peak_torque=None)
        return PlanLimits(slider_speed=0.5, drive=dataclasses.replace(drive, motor=motor))
    motor = dataclasses.replace(drive.motor, speed_torque_curve=None, max_speed=None)
    return PlanLimits(drive=dataclasses.replace(drive, motor=motor), torque_reserve=0.0)


@pytest.fixture
def case(dyn: og.ClosedLoopDynamics) -> tuple[object, ...]:
    section = next(s for s in build_path(read_program(PROGRAM)).sections if s.pieces)
    fine = sample_section(section, 2e-3, refine=10)
    rng = np.random.default_rng(9)
    n = fine.s.size
    t = np.cumsum(rng.uniform(1e-4, 1e-3, n))
    sd, sdd = rng.uniform(0.0, 1.5, n), rng.uniform(-40.0, 40.0, n)
    sd[:3] = 0.0  # at rest: the driving efficiency
    feed = np.where(np.arange(n) % 3 == 0, np.inf, 0.5)
    forms = path_forms(dyn, fine.p, fine.dp, fine.ddp, gravity=np.array([0.0, 0.0, -9.81]))
    return forms, fine, t, sd, sdd, feed


@needs_numba
@pytest.mark.parametrize("which", [0, 1, 2])
def test_the_compiled_pass_gives_the_array_versions_motion(
    which: int, case: tuple[object, ...], monkeypatch: pytest.MonkeyPatch
) -> None:
    limits = _limits(which)
    monkeypatch.setattr(verify, "COMPILED", True)
    ours = evaluate_forms(*case, limits)  # type: ignore[arg-type]
    monkeypatch.setattr(verify, "COMPILED", False)
    theirs = evaluate_forms(*case, limits)  # type: ignore[arg-type]
    for name in ("q", "qd", "qdd", "forces", "torque", "speed"):
        mine, other = getattr(ours, name), getattr(theirs, name)
        np.testing.assert_allclose(mine, other, rtol=RTOL, atol=RTOL * np.abs(other).max())
    assert list(ours.uses) == list(theirs.uses)
    for name, use in theirs.uses.items():
        np.testing.assert_allclose(ours.uses[name], use, rtol=RTOL, atol=RTOL * use.max())


@needs_numba
def test_a_value_that_is_not_finite_is_named_as_before(case: tuple[object, ...]) -> None:
    forms, fine, t, sd, sdd, feed = case
    sdd = np.array(sdd)
    sdd[5] = np.inf
    with pytest.raises(InvalidParameterError, match="forces"):
        evaluate_forms(forms, fine, t, sd, sdd, feed, _limits(0))  # type: ignore[arg-type]


def test_the_intervals_are_numpys_searchsorted(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(3)
    grid = np.cumsum(rng.uniform(0.1, 1.0, 40))
    fine = np.concatenate([[grid[0] - 1.0], np.linspace(grid[0], grid[-1], 500), grid])
    odd = np.array([grid[3], np.nan, grid[2], np.inf, -np.inf, grid[-1] + 1.0])
    for s in (np.sort(fine), fine, rng.permutation(fine), odd, grid[:0]):
        expected = np.searchsorted(grid, s, side="right") - 1
        np.testing.assert_array_equal(verify_compiled.intervals(grid, s), expected)
        monkeypatch.setattr(verify_compiled, "AVAILABLE", False)
        np.testing.assert_array_equal(verify_compiled.intervals(grid, s), expected)
        monkeypatch.undo()
