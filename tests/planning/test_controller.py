"""What a controller adds: feed and rapid overrides, the default path mode, the stops told."""

from __future__ import annotations

import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning import PlanLimits, plan_program
from orthoglide_pin.planning.controller import (
    default_mode_text,
    stop_reasons,
    with_controller,
)
from orthoglide_pin.planning.gcode import DEFAULT_TOLERANCE, read_program

pytest.importorskip("toppra")

#: A square at a feed after a rapid, no G61 or G64: corners blended by default.
SQUARE = "G21 G90\nG0 X20 Y-20\nG1 Y20 F3000\nG1 X-20\nG1 Y-20\nG4 P0.1\nG1 X0 Y0\n"
LIMITS = PlanLimits(slider_speed=1.0, slider_acceleration=10.0)
#: The feed binds on a long slow line: its time scales as 1 / override [-].
FEED_RTOL = 0.02


def test_a_program_without_g61_or_g64_is_blended_as_g64() -> None:
    program = read_program(SQUARE)
    assert program.mode_line == 0
    run = with_controller(program)
    assert all(not b.exact_stop and b.tolerance == DEFAULT_TOLERANCE for b in run.blocks[:-2])
    assert "says neither G61 nor G64" in default_mode_text(program, None)
    exact = with_controller(read_program("G1 X5 F600\nG61\nG1 X9\n"), blend=2e-5)
    assert read_program("G1 X5 F600\nG61\nG1 X9\n").mode_line == 2
    assert [b.exact_stop for b in exact.blocks] == [False, True]
    assert exact.blocks[0].tolerance == 2e-5


def test_the_stops_are_counted_with_their_reasons(dyn: og.ClosedLoopDynamics) -> None:
    plan = plan_program(read_program(SQUARE), dyn, LIMITS)
    stops = stop_reasons(plan.path)
    assert stops["rapid/feed change"] == 1 and stops["dwell"] == 1 and stops["end"] == 1
    assert stops["sharp corner"] == 0 and stops["exact stop (G61)"] == 0
    exact = plan_program(read_program("G61\n" + SQUARE), dyn, LIMITS)
    assert stop_reasons(exact.path)["exact stop (G61)"] == 3  # the square's corners
    sharp = plan_program(read_program(SQUARE), dyn, LIMITS, blend=0.0)
    assert stop_reasons(sharp.path)["sharp corner"] == 2


def test_the_feed_override_scales_the_feed(dyn: og.ClosedLoopDynamics) -> None:
    text = "G21\nG1 X40 F300\n"
    base = plan_program(read_program(text), dyn, LIMITS).cycle_time
    half = plan_program(read_program(text), dyn, LIMITS, feed_override=0.5).cycle_time
    assert half == pytest.approx(2.0 * base, rel=FEED_RTOL)


def test_the_rapid_override_caps_the_slider_speed(dyn: og.ClosedLoopDynamics) -> None:
    text = "G0 X60\nG0 X-60\n"
    full = plan_program(read_program(text), dyn, LIMITS)
    slow = plan_program(read_program(text), dyn, LIMITS, rapid_override=0.5)
    assert full.worst["slider_speed"] == pytest.approx(1.0, abs=1e-3)
    assert slow.worst["slider_speed"] == pytest.approx(0.5, abs=1e-2)
    assert slow.cycle_time > full.cycle_time


@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("feed_override", 0.0),
        ("feed_override", 2.5),
        ("rapid_override", 1.5),
        ("rapid_override", -1.0),
        ("blend", -1e-3),
        ("blend", 1.0),
        ("blend", float("nan")),
    ],
)
def test_bad_controller_options_are_refused(
    dyn: og.ClosedLoopDynamics, option: str, value: float
) -> None:
    with pytest.raises(InvalidParameterError, match=option):
        plan_program(read_program(SQUARE), dyn, LIMITS, **{option: value})  # type: ignore[arg-type]


def test_a_rapid_override_needs_a_speed_limit(dyn: og.ClosedLoopDynamics) -> None:
    with pytest.raises(InvalidParameterError, match="rapid_override"):
        plan_program(
            read_program("G0 X30\n"), dyn, PlanLimits(slider_acceleration=5.0), rapid_override=0.5
        )


def test_the_progress_counts_the_blocks(dyn: og.ClosedLoopDynamics) -> None:
    calls: list[tuple[int, int]] = []
    plan = plan_program(
        read_program("G61\n" + SQUARE), dyn, LIMITS, progress=lambda d, t: calls.append((d, t))
    )
    assert calls[-1] == (len(plan.blocks), len(plan.blocks))
    done = [d for d, _ in calls]
    assert done == sorted(done)
