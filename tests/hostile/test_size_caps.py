"""Sizes counted and refused against their announced caps before anything is allocated.

Each huge request costs less than :data:`REFUSAL_MEMORY` before its refusal
(the points are a broadcast view, so the test allocates nothing either), and
the message names the argument, the cap and the size asked.
"""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin._validation import MAX_BATCH_POINTS
from orthoglide_pin.calibration import sensitivities
from orthoglide_pin.calibration.identification import MAX_POSES
from orthoglide_pin.elasticity import modes
from orthoglide_pin.exceptions import InvalidParameterError, ProgramError
from orthoglide_pin.kinetostatics.certify import BOX_BUDGET_CAP, DEPTH_CAP
from orthoglide_pin.planning.plan import MAX_GRID_POINTS
from orthoglide_pin.simulation import contour
from tests.conftest import run

#: Most memory a refused size may cost before its refusal [bytes].
REFUSAL_MEMORY = 1_000_000


def _refusal(call: Callable[..., Any], *args: Any, **kwargs: Any) -> InvalidParameterError:
    """The error of ``call``, checked to cost less than ``REFUSAL_MEMORY``."""
    tracemalloc.start()
    try:
        with pytest.raises(InvalidParameterError) as info:
            call(*args, **kwargs)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < REFUSAL_MEMORY, f"{peak} bytes before the refusal"
    return info.value


def _points(n: int) -> np.ndarray:
    return np.broadcast_to(np.zeros(3), (n, 3))


@pytest.mark.parametrize("step", [1e-12, 1e-300, 1e-8])
def test_plan_program_counts_its_grid_before_making_it(
    dyn: og.ClosedLoopDynamics, step: float
) -> None:
    program = og.read_program("G1 X10 F600\nG1 Y10\n")
    limits = og.PlanLimits(slider_acceleration=20.0)
    error = _refusal(og.plan_program, program, dyn, limits, step=step)
    assert error.name == "step" and error.value == step
    assert f"at most {MAX_GRID_POINTS:,} points of the verification grid" in str(error)


def test_the_grid_cap_counts_what_is_held_at_once_not_the_programs_length(
    params: og.OrthoglideParams,
) -> None:
    from orthoglide_pin.planning.plan_inputs import check_before_grids

    stops = "G21 G90 G61\nF3000\n" + "".join(f"G1 X{k % 2 * 20 + 1}\n" for k in range(30))
    path = og.build_path(og.read_program(stops))
    moving = [sec for sec in path.sections if sec.pieces]
    limits = og.PlanLimits(slider_acceleration=20.0)
    each = 10 * 10 + 1  # 20 mm at 2 mm: 10 intervals, 10 fine points each, and the end
    assert len(moving) == 30 and 30 * each > 2 * each
    check_before_grids(path, params, moving, limits, 2e-3, cap=2 * each)  # each fits: no
    with pytest.raises(InvalidParameterError, match="points of the verification grid"):
        check_before_grids(path, params, moving, limits, 2e-3 / 8, cap=2 * each)


def test_plan_program_refuses_a_far_move_before_sampling_it(dyn: og.ClosedLoopDynamics) -> None:
    program = og.read_program("G1 X999000 F600\n")  # 999 m: within the coordinates' range
    limits = og.PlanLimits(slider_acceleration=20.0)
    tracemalloc.start()
    try:
        with pytest.raises(ProgramError, match="outside the machine's"):
            og.plan_program(program, dyn, limits)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < REFUSAL_MEMORY


@pytest.mark.parametrize("n", [modes.MAX_POINTS + 1, 10**7])
def test_natural_frequencies_counts_the_points_first(n: int) -> None:
    error = _refusal(og.natural_frequencies, None, _points(n))
    assert error.name == "points" and f"at most {modes.MAX_POINTS:,} points" in str(error)
    assert f"(here {n:,})" in str(error)


@pytest.mark.parametrize("call", [og.sensitivity, og.sensitivity_indices])
@pytest.mark.parametrize("n", [sensitivities.MAX_POINTS + 1, 10**8])
def test_sensitivity_counts_the_points_first(call: Callable[..., Any], n: int) -> None:
    error = _refusal(call, 0.31, _points(n))
    assert error.name == "points" and f"at most {sensitivities.MAX_POINTS:,} points" in str(error)


def test_contour_error_counts_the_points_and_the_path_samples_near_them_first() -> None:
    path = og.build_path(og.read_program("G1 X10 F600\n"))
    error = _refusal(og.contour_error, path, _points(10**8))
    assert error.name == "points" and f"at most {contour.MAX_POINTS:,} points" in str(error)
    far = og.build_path(og.read_program("G1 X999000 F600\nG1 X-999000\n"))
    assert og.contour_error(far, np.zeros((1, 3))).maximum < 1e-12  # its samples near the point
    ends = np.array([p.evaluate(np.array([0.0, p.length]))[0] for p in far.sections[0].pieces])
    error = _refusal(og.contour_error, far, ends.reshape(-1, 3))  # near 3 km of it at once
    assert error.name == "path" and f"at most {contour.MAX_SAMPLES:,} samples" in str(error)


def test_the_caps_leave_room_for_real_work() -> None:
    assert sensitivities.MAX_POINTS >= 100**3
    assert modes.MAX_POINTS >= 41**3  # the sweep's largest requirement grid
    assert contour.MAX_POINTS >= 250 * 4000  # 250 s at the default servo rate


@pytest.mark.parametrize(
    "call",
    [
        lambda p: og.inverse_kinematics(p, 0.31),
        lambda p: og.jacobian(p, 0.31),
        lambda p: og.kinetostatic_indices(p, 0.31),
        lambda p: og.direct_kinematics(p, 0.31),
        lambda p: og.cartesian_stiffness(p),
        lambda p: og.leg_motion(p, p, p, 0.31),
    ],
)
def test_every_function_over_points_counts_them_first(call: Callable[..., Any]) -> None:
    error = _refusal(call, _points(MAX_BATCH_POINTS + 1))
    assert f"at most {MAX_BATCH_POINTS:,} points" in str(error)


def test_the_dynamics_count_their_rows_first(dyn: og.ClosedLoopDynamics) -> None:
    huge = _points(MAX_BATCH_POINTS + 1)
    error = _refusal(dyn.inverse_dynamics, huge, huge, huge)
    assert f"at most {MAX_BATCH_POINTS:,} rows" in str(error)


@pytest.mark.parametrize(
    ("options", "needle"),
    [
        ({"max_boxes": BOX_BUDGET_CAP + 1}, f"invalid max_boxes={BOX_BUDGET_CAP + 1}"),
        ({"max_boxes": 10**12}, "invalid max_boxes=1000000000000"),
        ({"max_depth": DEPTH_CAP + 1}, f"[1, {DEPTH_CAP}]"),
    ],
)
def test_certify_cube_caps_its_budget(options: dict[str, int], needle: str) -> None:
    error = _refusal(og.certify_cube, 0.31, (-0.05, -0.05, -0.05), 0.1, **options)
    assert needle in str(error)


def test_certify_caps_its_budget_on_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "certify", "--max-boxes", str(10**12))
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert (
        f"invalid --max-boxes=1000000000000: expected an integer in [1, {BOX_BUDGET_CAP}]" in err
    )


def test_identify_counts_the_poses_first() -> None:
    nominal = og.GeometricModel.nominal(0.31)
    huge = _points(MAX_POSES + 1)
    error = _refusal(og.identify, huge, huge, nominal)
    assert error.name == "q" and f"at most {MAX_POSES:,} poses" in str(error)
