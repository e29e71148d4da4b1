"""The motor-torque rows compiled against the array version."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning import limits as lim
from orthoglide_pin.planning import rows_compiled
from orthoglide_pin.planning.limits import PlanLimits, Scales, rows
from orthoglide_pin.planning.path import sample_section

#: Rows of the two versions, relative to their largest [-] (the same operations).
ROWS_RTOL = 1e-13

needs_numba = pytest.mark.skipif(not rows_compiled.AVAILABLE, reason="numba is not installed")


def _drives() -> list[og.Drive]:
    """The example drive, then its motor with the curve alone, then with the peak alone."""
    drive = og.load_drive(str(og.example_drive_file()))
    assert drive.motor is not None
    curve = dataclasses.replace(drive.motor, peak_torque=None)
    peak = dataclasses.replace(drive.motor, speed_torque_curve=None, max_speed=None)
    return [drive, dataclasses.replace(drive, motor=curve), dataclasses.replace(drive, motor=peak)]


@needs_numba
@pytest.mark.parametrize("which", [0, 1, 2])
def test_the_compiled_rows_give_the_array_versions_rows(
    which: int, dyn: og.ClosedLoopDynamics, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = og.build_path(og.read_program("G21 G90\nG1 X30 Y-10 Z5 F9000\nG3 X10 Y-30 I-20 J0\n"))
    grid = sample_section(path.sections[0], 2e-3)
    forms = path_forms(dyn, grid.p, grid.dp, grid.ddp)
    rng = np.random.default_rng(7)
    n = grid.s.size
    x_high = rng.uniform(0.0, 4.0, n)
    x_high[3] = 0.0  # a point that must rest: its lines from x = 0 alone
    x0 = x_high * rng.uniform(-0.1, 1.2, n)
    limits = PlanLimits(slider_acceleration=15.0, drive=_drives()[which])
    for scales in (Scales(), Scales({"motor_torque": rng.uniform(0.8, 1.0, n)})):
        monkeypatch.setattr(lim, "COMPILED", True)
        ours = rows(limits, forms, x_high, x0, scales)
        monkeypatch.setattr(lim, "COMPILED", False)
        theirs = rows(limits, forms, x_high, x0, scales)
        for mine, other in zip(ours, theirs, strict=True):
            np.testing.assert_allclose(
                mine, other, rtol=ROWS_RTOL, atol=ROWS_RTOL * np.abs(other).max()
            )
        # the values at the samples of [0, X], passed back, give the same rows exactly
        monkeypatch.setattr(lim, "COMPILED", True)
        values = rows_compiled.sample_values(lim.motors(limits), forms.dq, lim.samples(x_high))
        kept = rows(limits, forms, x_high, x0, scales, values=values)
        for mine, other in zip(kept, ours, strict=True):
            assert np.array_equal(mine, other)


def test_without_numba_the_compiled_rows_say_so(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(rows_compiled, "AVAILABLE", False)
    limits = PlanLimits(drive=_drives()[0])
    with pytest.raises(RuntimeError, match="numba"):
        rows_compiled.sample_values(lim.motors(limits), np.zeros((1, 3)), np.zeros((1, 1)))
