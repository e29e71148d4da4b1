"""Quintic curves by arc length: the length by adaptive quadrature, derivatives by differences."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from orthoglide_pin.planning.quintic import Quintic

#: Finite-difference step on the arc length [m], and the slack on its truncation bound.
FD_STEP = 1e-6
FD_SAFETY = 4.0
#: Rounding of the second difference: |p| eps / h^2, |p| ~ 0.1 m [1/m].
FD_ROUNDING = 0.1 * 2.2e-16 / FD_STEP**2 * 8


def test_a_quintic_is_parametrised_by_its_arc_length() -> None:
    rng = np.random.default_rng(1)
    for _ in range(5):
        # a control polygon that turns by up to about 60 degrees per leg
        legs = 0.01 * np.array([1.0, 0.0, 0.0]) + rng.uniform(-0.006, 0.006, (5, 3))
        control = np.concatenate([np.zeros((1, 3)), np.cumsum(legs, axis=0)])
        curve = Quintic(control)

        def speed(w: float, c: np.ndarray = control) -> float:  # |B'(w)| in Bernstein form
            d = 5 * np.diff(c, axis=0)
            basis = [math.comb(4, i) * w**i * (1 - w) ** (4 - i) for i in range(5)]
            return float(np.linalg.norm(np.array(basis) @ d))

        length, err = quad(speed, 0.0, 1.0, epsabs=1e-15, epsrel=1e-13, limit=200)
        assert curve.length == pytest.approx(length, rel=1e-12, abs=10 * err)
        p = curve.evaluate(np.array([0.0, curve.length]))[0]
        np.testing.assert_allclose(p, control[[0, 5]], atol=1e-16)
        s = np.linspace(2 * FD_STEP, curve.length - 2 * FD_STEP, 40)
        p0, t0, k0 = curve.evaluate(s)
        pp, _, kp = curve.evaluate(s + FD_STEP)
        pm, _, km = curve.evaluate(s - FD_STEP)
        np.testing.assert_allclose(np.linalg.norm(t0, axis=1), 1.0, atol=1e-14)
        third = curve.third(s)
        fourth = float(np.abs(np.diff(third, axis=0)).max() / np.diff(s).min())
        bound = float(np.abs(third).max())
        np.testing.assert_allclose(
            (pp - pm) / (2 * FD_STEP), t0, atol=FD_SAFETY * FD_STEP**2 * bound / 6 + 1e-9
        )
        np.testing.assert_allclose(
            (pp - 2 * p0 + pm) / FD_STEP**2, k0, atol=FD_SAFETY * FD_STEP**2 * fourth + FD_ROUNDING
        )
        np.testing.assert_allclose(
            (kp - km) / (2 * FD_STEP), third, rtol=1e-4, atol=1e-6 * bound + 1e-3
        )


def test_one_point_distance_is_the_batch_distance() -> None:
    """``distance`` (plain floats) agrees with ``distances`` to rounding."""
    from orthoglide_pin.planning.quintic import distance, distances, power_coefficients

    rng = np.random.default_rng(5)
    for _ in range(200):
        coef = power_coefficients(1e-4 * rng.normal(size=(6, 3)))
        x = 1e-4 * rng.normal(size=3)
        assert distance(coef, x) == pytest.approx(distances(coef, x[None])[0], rel=1e-12)
