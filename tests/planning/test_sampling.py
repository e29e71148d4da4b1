"""The plan sampled in time: with and without the forces, the same motion."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.planning.sampling import sample_chunks, sample_plan

pytest.importorskip("toppra")

#: Blended short blocks, an arc, a dwell, a rapid: every kind of piece and a rest.
PROGRAM = "G21 G90 G64 P0.02\nG1 X10 F3000\nG3 X20 Y0 R5\nG4 P0.01\nG0 X0 Y5\n" + "".join(
    f"G1 X{0.5 * k:.2f} Y{5 + 0.2 * (k % 2):.2f} F2400\n" for k in range(1, 12)
)
DT = 0.002


@pytest.fixture(scope="module")
def planned(dyn: og.ClosedLoopDynamics) -> og.Plan:
    drive = og.load_drive(str(og.example_drive_file()))
    return og.plan_program(og.read_program(PROGRAM), dyn, og.PlanLimits(drive=drive))


def test_without_forces_the_motion_is_the_same_to_the_last_digit(
    planned: og.Plan, dyn: og.ClosedLoopDynamics
) -> None:
    whole = sample_plan(planned, dyn, DT)
    assert {"F1", "tau1"} <= whole.keys()
    parts = list(sample_chunks(planned, dyn, DT, chunk=97, forces=False))
    assert len(parts) > 2
    light = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    assert not {"F1", "F2", "F3", "tau1", "tau2", "tau3"} & light.keys()
    assert set(light) == set(whole) - {"F1", "F2", "F3", "tau1", "tau2", "tau3"}
    for name, values in light.items():
        np.testing.assert_array_equal(values, whole[name], err_msg=name)
