"""The simulated drive against the drives layer's model (motor_demand) and the planner's limit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.simulation.slider_drive import (
    available_torque,
    drive_terms,
    feedforward_torque,
    plant_terms,
    slider_ratio,
    torque_curve,
)

DRIVE = og.load_drive(str(og.example_drive_file()))
#: Relative agreement of two routes to one torque.
TORQUE_RTOL = 1e-12
#: Motor speeds well beyond the planner's smoothing of the Coulomb sign [rad/s].
FAST = 40.0


def _other_drive() -> og.Drive:
    """A geared drive with another screw and a motor given by its peak torque only."""
    train = dataclasses.replace(DRIVE.train, lead=0.01, gear_ratio=2.0, efficiency=0.8)
    return og.Drive(train, og.MotorData(peak_torque=2.0, max_speed=4000.0))


@pytest.mark.parametrize("drive", [DRIVE, _other_drive()], ids=["example", "geared"])
def test_available_torque_is_the_planners(drive: og.Drive) -> None:
    w = np.linspace(0.0, 700.0, 1401)
    ours = available_torque(drive, np.concatenate([w, -w]))
    # the motor's whole torque; a plan keeps its reserve for the servo loop
    whole = og.PlanLimits(drive=drive, torque_reserve=0.0)
    theirs = whole.available_torque(np.concatenate([w, -w]))
    assert np.allclose(ours, theirs, rtol=TORQUE_RTOL, atol=1e-12)
    planned = og.PlanLimits(drive=drive).available_torque(np.concatenate([w, -w]))
    assert np.allclose(planned, (1.0 - og.PlanLimits().torque_reserve) * ours, rtol=TORQUE_RTOL)
    _, _, peak = torque_curve(og.Drive(drive.train))  # no motor: no limit
    assert np.isinf(peak) and np.isinf(available_torque(og.Drive(drive.train), w)).all()


@pytest.mark.parametrize("drive", [DRIVE, _other_drive()], ids=["example", "geared"])
def test_feedforward_is_the_motor_demand_at_speed(drive: og.Drive) -> None:
    rng = np.random.default_rng(4)
    force = 400.0 * rng.standard_normal((200, 3))
    k = slider_ratio(drive.train)
    speed = rng.choice([-1.0, 1.0], (200, 3)) * rng.uniform(FAST, 300.0, (200, 3)) / k
    acc = 30.0 * rng.standard_normal((200, 3))
    ours = feedforward_torque(drive, force, speed, acc)
    theirs = og.motor_demand(force, speed, acc, drive.train).torque
    assert np.allclose(ours, theirs, rtol=TORQUE_RTOL, atol=0.0)


@pytest.mark.parametrize("drive", [DRIVE, _other_drive()], ids=["example", "geared"])
def test_the_plant_gives_the_carriage_the_thrust_asked(drive: og.Drive) -> None:
    """``eta^s k T = F + eta^s (armature q'' + friction)`` with the MJCF's terms scaled."""
    rng = np.random.default_rng(5)
    k = slider_ratio(drive.train)
    for _ in range(50):
        force = 400.0 * rng.standard_normal(3)
        speed = rng.choice([-1.0, 1.0], 3) * rng.uniform(FAST, 300.0, 3) / k
        acc = 30.0 * rng.standard_normal(3)
        torque = og.motor_demand(force[None], speed[None], acc[None], drive.train).torque[0]
        driving = force * speed >= 0.0
        eta = np.where(driving, drive.train.efficiency, 1.0 / drive.train.efficiency)
        arm, friction, damping = plant_terms(drive, driving)
        thrust = eta * k * torque - arm * acc - friction * np.sign(speed) - damping * speed
        assert np.allclose(thrust, force, rtol=1e-10, atol=1e-9)
    terms = drive_terms(drive)
    arm, friction, damping = plant_terms(drive, np.ones(3, dtype=bool))
    assert arm == pytest.approx(drive.train.efficiency * terms["armature"], rel=1e-15)
