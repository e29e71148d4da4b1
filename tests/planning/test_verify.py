"""The verification from the path forms against the one by the point-by-point inverse dynamics."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.verify import evaluate_forms, evaluate_motion

#: Forces and uses of both routes, relative to their size [-] (both round the same value).
RTOL = 1e-10
#: Absolute floors: forces [N], slider motion [m/s, m/s^2], uses [-].
FORCE_ATOL, MOTION_ATOL, USE_ATOL = 1e-9, 1e-10, 1e-12
GRAVITY = np.array([1.5, -2.0, 9.6])
WRENCH = np.array([40.0, -25.0, 60.0, 2.0, -1.0, 3.0])
PROGRAM = "G1 X30 Y10 F9000\nG2 X40 Y-20 Z10 I-10 J-20\nG1 X-20 Y-10\n"


@pytest.mark.parametrize("leg_length", [0.31, 0.35])
def test_both_routes_give_the_same_motion_and_uses(leg_length: float) -> None:
    params = og.prototype().replace(leg_length=leg_length)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(
        str(example_drive_file())
    ))  # fmt: skip
    section = next(s for s in build_path(read_program(PROGRAM)).sections if s.pieces)
    fine = sample_section(section, 2e-3, refine=10)
    rng = np.random.default_rng(5)
    n = fine.s.size
    t = np.cumsum(rng.uniform(1e-4, 1e-3, n))
    sd, sdd = rng.uniform(0.0, 0.8, n), rng.uniform(-15.0, 15.0, n)
    feed = np.full(n, 0.5)
    forms = path_forms(dyn, fine.p, fine.dp, fine.ddp, gravity=GRAVITY, wrench=WRENCH)
    ours = evaluate_forms(forms, fine, t, sd, sdd, feed, limits)
    ref = evaluate_motion(dyn, fine, t, sd, sdd, feed, limits, wrench=WRENCH, gravity=GRAVITY)
    scale = np.linalg.norm(ref.forces, axis=1, keepdims=True)
    assert np.all(np.abs(ours.forces - ref.forces) <= RTOL * scale + FORCE_ATOL)
    for name in ("q", "qd", "qdd"):
        np.testing.assert_allclose(getattr(ours, name), getattr(ref, name), atol=MOTION_ATOL)
    assert ours.uses.keys() == ref.uses.keys() == {
        "slider_speed", "slider_acceleration", "motor_torque", "motor_speed", "feed"
    }  # fmt: skip
    for name, use in ref.uses.items():
        np.testing.assert_allclose(ours.uses[name], use, rtol=RTOL, atol=USE_ATOL)
