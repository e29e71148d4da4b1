"""The servo settings refuse bad values; the gains place the poles where they say."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.simulation.servo import (
    BANDWIDTH_DIVISOR,
    Encoder,
    PositionLoop,
    ServoSettings,
    servo_gains,
)

POLE_RTOL = 1e-6


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"controller": "bang_bang"}, "controller"),
        ({"rate": 0}, "rate"),
        ({"rate": -4000.0}, "rate"),
        ({"rate": float("nan")}, "rate"),
        ({"rate": "fast"}, "rate"),
        ({"encoder_counts": 0}, "encoder_counts"),
        ({"encoder_counts": 2.5}, "encoder_counts"),
        ({"mass_error": 1.5}, "mass_error"),
        ({"friction_error": float("inf")}, "friction_error"),
        ({"friction_error": True}, "friction_error"),
    ],
)
def test_bad_settings_are_refused_by_name(kwargs: dict[str, object], name: str) -> None:
    with pytest.raises(InvalidParameterError, match=name):
        ServoSettings(**kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize("controller", ["pid_ff", "pd_ff", "pd"])
@pytest.mark.parametrize("rate", [4000.0, 1000.0])
def test_gains_place_the_poles(controller: str, rate: float) -> None:
    settings = ServoSettings(controller=controller, rate=rate)
    mass = np.array([12.0, 9.5, 20.0])
    g = servo_gains(settings, mass)
    w = 2 * np.pi * rate / BANDWIDTH_DIVISOR
    for i in range(3):
        if controller == "pid_ff":
            roots = np.roots([mass[i], g.kd[i], g.kp[i], g.ki[i]])
            expected = 3
        else:
            roots = np.roots([mass[i], g.kd[i], g.kp[i]])
            expected = 2
            assert g.ki[i] == 0.0
        assert len(roots) == expected
        assert np.allclose(roots, -w, rtol=POLE_RTOL * 100)  # a repeated root: sqrt(eps) accuracy
    assert settings.torque_feedforward is (controller != "pd")


def test_encoder_counts_and_differences() -> None:
    enc = Encoder(1e-6, 2.5e-4, 0.0)
    q, qd = enc.read(3.4e-6, 99.0)
    assert q == pytest.approx(3e-6, abs=1e-18) and qd == pytest.approx(3e-6 / 2.5e-4)
    q, qd = enc.read(3.6e-6, 99.0)
    assert q == pytest.approx(4e-6, abs=1e-18) and qd == pytest.approx(1e-6 / 2.5e-4)
    exact = Encoder(None, 2.5e-4, 0.0)
    assert exact.read(1.234e-7, 0.5) == (1.234e-7, 0.5)


def test_the_integral_holds_while_saturated() -> None:
    loop = PositionLoop(10.0, 1.0, 100.0, 0.01)
    assert loop.force(1.0, 0.0, frozen=False) == pytest.approx(10.0 + 100.0 * 0.01)
    assert loop.force(1.0, 0.0, frozen=True) == pytest.approx(10.0 + 100.0 * 0.01)
    assert loop.force(1.0, 0.0, frozen=False) == pytest.approx(10.0 + 100.0 * 0.02)
