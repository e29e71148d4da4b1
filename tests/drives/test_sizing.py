from __future__ import annotations

import json
import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import Drive, DriveTrain, MotorData, MotorDemand, motor_demand
from orthoglide_pin.drives.sizing import check_motor, cycle_statistics, size_drives
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics

#: Trapezoidal RMS of a whole period of a sine: exact up to rounding.
RMS_TOL = 1e-12


def _demand(torque: np.ndarray, speed_rpm: np.ndarray) -> MotorDemand:
    speed = speed_rpm / (30.0 / math.pi)
    return MotorDemand(torque, speed, speed_rpm, np.zeros_like(torque), torque * speed, torque)


def test_peak_and_rms_of_synthetic_signals() -> None:
    t = np.linspace(0.0, 2.0, 401)
    amplitude = np.array([1.0, 2.5, 4.0])
    torque = amplitude * np.sin(2 * math.pi * t / 2.0)[:, None]
    speed = np.array([1000.0, -3000.0, 500.0]) * np.cos(2 * math.pi * t)[:, None]
    stats = cycle_statistics(_demand(torque, speed), t)
    np.testing.assert_allclose(stats.rms_torque, amplitude / math.sqrt(2.0), rtol=RMS_TOL)
    np.testing.assert_allclose(stats.peak_torque, amplitude, rtol=1e-12)
    np.testing.assert_allclose(stats.peak_speed_rpm, [1000.0, 3000.0, 500.0])
    # evenly spaced samples without times: the plain root mean square
    steps = np.array([[1.0, 0.0, 2.0], [-3.0, 0.0, 2.0], [2.0, 0.0, -2.0]])
    plain = cycle_statistics(_demand(steps, np.zeros((3, 3))))
    np.testing.assert_allclose(plain.rms_torque, [math.sqrt(14.0 / 3.0), 0.0, 2.0])
    np.testing.assert_allclose(plain.peak_torque, [3.0, 0.0, 2.0])
    # a dwell at zero torque lowers the time-weighted RMS: half the time at 2 N.m
    times = np.array([0.0, 1.0, 1.0 + 1e-9, 2.0])
    square = np.array([[2.0] * 3, [2.0] * 3, [0.0] * 3, [0.0] * 3])
    half = cycle_statistics(_demand(square, np.zeros((4, 3))), times)
    np.testing.assert_allclose(half.rms_torque, math.sqrt(2.0), rtol=1e-8)


def test_margins_and_verdict_against_hand_values() -> None:
    stats = cycle_statistics(
        _demand(
            np.array([[3.0, 1.0, 2.0], [-1.0, -1.0, 0.0]]),
            np.array([[1000.0, 4000.0, 2500.0]] * 2),
        )
    )
    # rms = (sqrt(5), 1, sqrt(2)), peak = (3, 1, 2)
    motor = MotorData(rated_torque=2.0, peak_torque=2.5, max_speed=3000.0)
    check = check_motor(motor, stats)
    np.testing.assert_allclose(
        check.margins["rms_torque"], 1.0 - np.array([5**0.5, 1, 2**0.5]) / 2
    )
    np.testing.assert_allclose(check.margins["peak_torque"], [1 - 3 / 2.5, 0.6, 0.2])
    np.testing.assert_allclose(check.margins["speed"], [2 / 3, -1 / 3, 1 / 6])
    assert not check.passed
    assert "speed_torque_curve" not in check.margins
    relaxed = MotorData(rated_torque=3.0, peak_torque=3.0, max_speed=4000.0)
    assert check_motor(relaxed, stats).passed


def test_speed_torque_curve_is_checked_at_every_sample() -> None:
    curve = ((0.0, 4.0), (3000.0, 2.0))
    demand = _demand(
        np.array([[1.5, 1.0, 0.0], [1.0, 2.5, 0.5]]),
        np.array([[1500.0, 0.0, 0.0], [0.0, 3000.0, 3500.0]]),
    )
    check = check_motor(MotorData(speed_torque_curve=curve), cycle_statistics(demand), demand)
    margins = check.margins["speed_torque_curve"]
    # axis 1: 1.5 of 3 N.m at 1500 rpm; axis 2: 2.5 of 2 N.m at 3000 rpm; axis 3: above the curve
    assert margins[0] == pytest.approx(0.5)
    assert margins[1] == pytest.approx(-0.25)
    assert margins[2] == -math.inf
    assert not check.passed
    data = json.loads(json.dumps(check.to_dict()))
    assert data["margins"]["speed_torque_curve"][2] is None and data["passed"] is False


def test_size_drives_on_an_isotropic_move(model: og.ClosedLoopModel) -> None:
    """At home, 1.2 m/s and 20 m/s^2 along e1 (the paper's sizing point)."""
    dyn = ClosedLoopDynamics(model)
    p, v, a = np.zeros((1, 3)), np.array([[1.2, 0.0, 0.0]]), np.array([[20.0, 0.0, 0.0]])
    result = dyn.inverse_dynamics(p, v, a)
    motor = MotorData(name="m", rated_torque=10.0, peak_torque=10.0, max_speed=3000.0)
    sizing = size_drives(result, Drive(DriveTrain(), motor))
    direct = motor_demand(result.forces, result.slider_velocities, result.slider_accelerations)
    np.testing.assert_allclose(sizing.demand.torque, direct.torque)
    assert sizing.statistics.peak_speed_rpm[0] == pytest.approx(2880.0)
    assert sizing.check is not None and sizing.check.passed
    assert sizing.check.margins["speed"][0] == pytest.approx(1.0 - 2880.0 / 3000.0)
    assert size_drives(result).check is None


def test_bad_times_are_reported() -> None:
    demand = _demand(np.zeros((3, 3)), np.zeros((3, 3)))
    for times in ([0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 2.0, 1.0]):
        with pytest.raises(og.InvalidParameterError):
            cycle_statistics(demand, times)


def test_safety_factor_multiplies_the_torques_only() -> None:
    curve = ((0.0, 4.0), (3000.0, 2.0))
    demand = _demand(
        np.array([[1.5, 1.0, 0.5], [1.0, -1.6, 0.5]]),
        np.array([[1500.0, 0.0, 2000.0], [0.0, 1000.0, 2500.0]]),
    )
    stats = cycle_statistics(demand)
    motor = MotorData(
        rated_torque=3.0, peak_torque=2.5, max_speed=3000.0, speed_torque_curve=curve
    )
    plain = check_motor(motor, stats, demand)
    k = 1.25
    safe = check_motor(motor, stats, demand, safety_factor=k)
    # hand values: the required torques are k times larger, the speeds the same
    np.testing.assert_allclose(
        safe.margins["peak_torque"], 1.0 - k * np.array([1.5, 1.6, 0.5]) / 2.5
    )
    for key in ("rms_torque", "peak_torque", "speed_torque_curve"):
        np.testing.assert_allclose(1.0 - safe.margins[key], k * (1.0 - plain.margins[key]))
    np.testing.assert_array_equal(safe.margins["speed"], plain.margins["speed"])
    # the verdict turns where the least torque margin is used up: 1.6 N.m of 2.5
    assert check_motor(motor, stats, demand, safety_factor=2.5 / 1.6 * 0.999).passed
    assert not check_motor(motor, stats, demand, safety_factor=2.5 / 1.6 * 1.001).passed


@pytest.mark.parametrize("bad", [0.99, 0.0, -2.0, math.nan, math.inf, True, "x"])
def test_bad_safety_factors_are_refused(bad: object) -> None:
    stats = cycle_statistics(_demand(np.ones((2, 3)), np.zeros((2, 3))))
    with pytest.raises(og.InvalidParameterError, match="safety_factor"):
        check_motor(MotorData(peak_torque=2.0), stats, safety_factor=bad)  # type: ignore[arg-type]
