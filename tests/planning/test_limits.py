"""The torque reserve of a plan: the share of the motor's torque left to the servo loop."""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.limits import DEFAULT_TORQUE_RESERVE, PlanLimits
from orthoglide_pin.planning.sampling import sample_plan
from orthoglide_pin.planning.verify import USE_TOL

#: Sampling step of the planned torques [s].
DT = 1e-4
#: One rapid move up, then a feed move: the motor torque binds on both.
PROGRAM = "G21 G90\nG0 Z5\nG1 X10 Y-5 F6000\nM30\n"


@pytest.fixture(scope="module")
def drive() -> og.Drive:
    return og.load_drive(str(og.example_drive_file()))


def test_the_reserve_scales_the_available_torque(drive: og.Drive) -> None:
    assert PlanLimits().torque_reserve == DEFAULT_TORQUE_RESERVE == 0.1
    speeds = np.linspace(0.0, 700.0, 9)  # up to beyond the curve's last speed [rad/s]
    whole = PlanLimits(drive=drive, torque_reserve=0.0)
    kept = PlanLimits(drive=drive, torque_reserve=0.25)
    np.testing.assert_allclose(
        kept.available_torque(speeds), 0.75 * whole.available_torque(speeds), rtol=1e-15
    )
    assert drive.motor is not None and whole.reference_torque() == drive.motor.peak_torque
    assert kept.motor_speed == whole.motor_speed  # the speed limit is not reserved


@pytest.mark.parametrize("value", [1.0, -0.1, math.nan, math.inf, True, "0.1", None])
def test_a_bad_reserve_is_refused(value: object) -> None:
    with pytest.raises(InvalidParameterError, match=r"torque_reserve.*from 0 to below 1"):
        PlanLimits(torque_reserve=value)  # type: ignore[arg-type]


def test_the_plan_uses_at_most_the_torque_left(
    drive: og.Drive, dyn: og.ClosedLoopDynamics
) -> None:
    pytest.importorskip("toppra")
    program = og.read_program(PROGRAM)
    assert drive.motor is not None and drive.motor.peak_torque is not None
    peaks, times = {}, {}
    for reserve in (0.0, 0.2):
        plan = og.plan_program(program, dyn, PlanLimits(drive=drive, torque_reserve=reserve))
        cols = sample_plan(plan, dyn, DT)
        torque = np.abs(np.column_stack([cols[f"tau{i}"] for i in (1, 2, 3)]))
        peaks[reserve] = torque.max() / drive.motor.peak_torque
        times[reserve] = plan.cycle_time
        assert plan.worst["motor_torque"] <= 1.0 + USE_TOL
    assert peaks[0.2] <= 0.8 * (1.0 + USE_TOL)
    assert peaks[0.0] > 0.95  # without a reserve the motor torque binds
    assert times[0.2] > times[0.0]


def test_the_rows_of_sections_together_are_those_of_each(
    drive: og.Drive, dyn: og.ClosedLoopDynamics
) -> None:
    from orthoglide_pin.dynamics.path_forms import path_forms
    from orthoglide_pin.planning.limits import Scales, joined_rows, rows

    path = og.build_path(og.read_program("G21 G90 G61\nG1 X10 Y-5 F6000\nG0 Z5\nG1 X0 Y0 Z0\n"))
    forms, highs, guesses = [], [], []
    for sec in path.sections:
        grid = og.planning.path.sample_section(sec, 2e-3)
        forms.append(path_forms(dyn, grid.p, grid.dp, grid.ddp))
        highs.append(np.full(grid.s.size, 0.04))
        guesses.append(np.linspace(0.0, 0.03, grid.s.size))
    n = forms[1].q.shape[0]
    scales = [
        Scales(),
        Scales({"motor_torque": np.linspace(0.9, 1.0, n)}),
        Scales({"motor_torque": 0.8}),
    ]
    limits = PlanLimits(slider_acceleration=15.0, drive=drive)
    together = joined_rows(limits, forms, highs, guesses, scales)
    assert len(together) == len(forms) == 3
    for mine, f, h, g, sc in zip(together, forms, highs, guesses, scales, strict=True):
        for x, y in zip(mine, rows(limits, f, h, g, sc), strict=True):
            np.testing.assert_array_equal(x, y)
