"""Rigorous bounds of the factors over a box, against LAPACK at points of the box."""

from __future__ import annotations

import math

import numpy as np
from conftest import lapack_factors

import orthoglide_pin as og
from orthoglide_pin.kinetostatics.interval_jacobian import (
    SERIAL,
    down,
    factor_bounds_on_box,
    inverse_jacobian_enclosure,
    up,
)

#: Random boxes and points per box.
BOXES, POINTS = 40, 50
SEED = 20261127
L = 0.3105828541230249  # the paper's design (200 mm cube, [0.5, 2])


def test_box_bounds_hold_at_random_points_of_random_boxes() -> None:
    rng = np.random.default_rng(SEED)
    for _ in range(BOXES):
        lo = rng.uniform(-0.12, 0.12, 3)
        hi = lo + rng.uniform(1e-4, 0.05, 3)
        c = 0.5 * (lo + hi)
        u, s, vt = np.linalg.svd(og.inverse_jacobian(c, L))
        # a poor reference (identity) must keep the bounds valid, only looser
        for ref in ((u, s, vt), (np.eye(3), np.ones(3), np.eye(3))):
            b = factor_bounds_on_box(lo, hi, L, *ref)
            f = lapack_factors(rng.uniform(lo, hi, (POINTS, 3)), L)
            corners = np.array([[(lo, hi)[k >> i & 1][i] for i in range(3)] for k in range(8)])
            f = np.vstack([f, lapack_factors(corners, L)])
            assert b.lower <= f[:, 0].min() and f[:, 2].max() <= b.upper


def test_a_box_on_the_serial_singular_surface_has_no_finite_bound() -> None:
    lo, hi = np.array([0.0, 0.25, 0.1]), np.array([0.01, 0.3, 0.2])  # y^2 + z^2 > L^2 inside
    assert inverse_jacobian_enclosure(lo, hi, L) == 1
    b = factor_bounds_on_box(lo, hi, L, np.eye(3), np.ones(3), np.eye(3))
    assert b.singular == SERIAL and b.leg == 1 and b.lower == 0.0 and b.upper == math.inf


def test_the_enclosure_of_the_inverse_jacobian_holds_its_values() -> None:
    rng = np.random.default_rng(SEED)
    lo = np.array([-0.05, 0.02, -0.01])
    hi = lo + np.array([0.01, 0.03, 0.02])
    m = inverse_jacobian_enclosure(lo, hi, L)
    assert not isinstance(m, int)
    for p in rng.uniform(lo, hi, (POINTS, 3)):
        exact = og.inverse_jacobian(p, L)
        for i in range(3):
            for j in range(3):
                assert m[i, j].contains(float(exact[i, j]))


def test_outward_rounding_of_a_ball() -> None:
    from flint import arb

    x = arb(1) / 3  # not a float: a ball around 1/3
    assert down(x) < 1 / 3 < up(x) and up(x) - down(x) < 1e-15
    assert down(arb("nan")) == -math.inf and up(arb("nan")) == math.inf
