"""The exported configuration run headless in LinuxCNC: the certified route.

The session (``controller._session``, started once for the test run) runs
each design's programs with LinuxCNC's own planner under the certified
limits, the joints sampled every servo period. Checks, on the shipped
examples, the diagonals of the cube and a raster of 10,041 short blocks:
joints' peak speed and acceleration within 100.1 % of ``[JOINT_n]``, forward
kinematics in LinuxCNC agreeing with the package's, and the cycle time against
the time-optimal plan (printed).
"""

from __future__ import annotations

import numpy as np
import pytest
from controller._session import (
    CASES,
    PERIOD,
    STREAM_CASES,
    moving,
    peaks,
)

from orthoglide_pin.kinematics.closed_form import direct_kinematics, inverse_kinematics
from orthoglide_pin.program.axes import design_axes

pytestmark = pytest.mark.slow

#: Allowed peak use of a joint limit.
PEAK_USE = 1.001
#: Agreement of LinuxCNC's kinematics with the package's [mm].
TOL_MM = 1e-9
#: Share of status polls allowed to pair joints and pose of different servo periods
#: (and how many, on a short run of a few hundred polls): each is checked alone.
TORN_SHARE, TORN_FEW = 1e-3, 3
#: The sampler's resolution (6 decimals) [mm].
SAMPLE_TOL_MM = 1e-6
#: Where LinuxCNC's run ends against the plan's end [m].
END_TOL = 1e-9
#: Blocks of the long program.
LONG_PROGRAM_BLOCKS = 10_000


@pytest.mark.parametrize(("design", "example"), CASES)
def test_joints_within_their_limits(run: dict, design: str, example: str) -> None:
    data = run[design]["programs"][example]
    assert not data["errors"], data["errors"]
    speed, accel = peaks(data["samples"])
    limit_v, limit_a = run[design]["joint_speed"], run[design]["joint_acceleration"]
    print(
        f"{design} {example}: peak joint speed {1e3 * speed:.1f} mm/s "
        f"({100 * speed / limit_v:.1f} %), acceleration {1e3 * accel:.0f} mm/s^2 "
        f"({100 * accel / limit_a:.1f} %)"
    )
    assert speed <= PEAK_USE * limit_v  # the [JOINT_n] limits
    assert accel <= PEAK_USE * limit_a


def test_the_long_program_runs(run: dict) -> None:
    assert run["prototype"]["plans"]["raster"]["blocks"] >= LONG_PROGRAM_BLOCKS


@pytest.mark.parametrize(
    ("design", "example", "route"),
    [(*c, "programs") for c in CASES] + [(*c, "streams") for c in STREAM_CASES],
)
def test_kinematics_in_linuxcnc_agree(run: dict, design: str, example: str, route: str) -> None:
    """LinuxCNC's pose from its joints (forward) and back (inverse), against the package.

    On both routes: the stream drives the joints and LinuxCNC's motion, the
    machine off, follows them with the component's forward kinematics.

    A status poll during motion may, rarely, pair the joints of one servo
    period with the pose of another (LinuxCNC copies its status while motion
    runs): such a pose must still be the forward kinematics of the joints of a
    sampled servo period, and such pairs must stay rare.
    """
    data = run[design][route][example]
    pairs = np.asarray(data["pairs"])
    joints, poses = pairs[:, 0], pairs[:, 1]
    params = run[design]["params"]
    axes, L = design_axes(params), params.leg_length
    fk = 1e3 * axes.to_program(direct_kinematics(1e-3 * joints, L, check_limits=False))
    ik = 1e3 * inverse_kinematics(axes.to_world(1e-3 * poses), L, check_limits=False)
    agree = np.maximum(np.abs(fk - poses).max(axis=1), np.abs(ik - joints).max(axis=1))
    torn = agree > TOL_MM
    allowed = max(TORN_FEW, TORN_SHARE * len(torn))
    assert torn.sum() <= allowed, f"{torn.sum()} of {len(torn)} pairs disagree"
    sampled = data["samples"][:, 1:4]
    for q in ik[torn]:  # the pose of another servo period: its joints were sampled
        assert np.abs(sampled - q).max(axis=1).min() <= SAMPLE_TOL_MM
    rest_cmd, rest_actual = np.asarray(data["rests"][0])
    assert np.abs(rest_cmd - rest_actual).max() <= TOL_MM  # at rest: inverse then forward


def test_cycle_time_against_the_optimal_plan(run: dict) -> None:
    """The cost of the certified Cartesian limits against the optimal plan (printed).

    Both read the program in the design's program axes (LinuxCNC through the
    exported component, the planner as ``orthoglide plan`` does): LinuxCNC
    ends where the plan ends. Where the programmed feeds bind, both take
    nearly the same time; across the cube at high feed, and on short blocks
    (which LinuxCNC 2.9 runs in at least 1.02 servo periods each), the plan,
    which uses each slider's own limits, is faster.
    """
    costs = {}
    for design, example in CASES:
        done = run[design]
        axes = design_axes(done["params"])
        data, plan = done["programs"][example], done["plans"][example]
        j = moving(data["samples"])
        linuxcnc_time = (len(j) - 5) * PERIOD
        rest = axes.to_world(1e-3 * np.asarray(data["rests"][0][1]))
        assert np.abs(rest - plan["end"]).max() <= END_TOL
        print(
            f"{design} {example}: LinuxCNC {linuxcnc_time:.3f} s, optimal plan "
            f"{plan['cycle_time']:.3f} s (planned in {plan['planned_in']:.1f} s), cost "
            f"{100 * (linuxcnc_time / plan['cycle_time'] - 1):.1f} %"
        )
        costs[design, example] = linuxcnc_time / plan["cycle_time"] - 1
    assert costs["prototype", "diagonals"] > 0.0  # the certified limits bind there
    assert all(abs(c) < 2.0 for c in costs.values())
