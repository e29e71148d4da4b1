"""Stiffness maps, the worst point and compliance ellipsoids, against direct evaluations."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, cube_points

import orthoglide_pin as og
from orthoglide_pin.elasticity.maps import (
    DEFAULT_CUTTING_FORCE,
    compliance_ellipsoid,
    stiffness_map,
)
from orthoglide_pin.elasticity.stiffness import cartesian_stiffness
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.workspace import cube_grid

SEED = 5
REL_TOL = 1e-9


@pytest.fixture(scope="module")
def smap(params: og.OrthoglideParams) -> og.elasticity.maps.StiffnessMap:
    return stiffness_map(cube_grid([CUBE_CORNER] * 3, CUBE_SIDE, 7), params)


def test_map_values_are_the_pointwise_model(
    params: og.OrthoglideParams, smap: og.elasticity.maps.StiffnessMap
) -> None:
    assert smap.min_stiffness.shape == (7, 7, 7)
    for index in (0, 100, 342):
        point = smap.grid.point(index)
        k = cartesian_stiffness(point, params)
        weakest = np.linalg.eigh(k.K)
        assert smap.min_stiffness.reshape(-1)[index] == pytest.approx(weakest[0][0], rel=REL_TOL)
        # The deflection under F in the softest direction, by the 6x6 compliance.
        wrench = np.concatenate([DEFAULT_CUTTING_FORCE * weakest[1][:, 0], np.zeros(3)])
        d = k.deflection(wrench)[:3]
        assert smap.deflection.reshape(-1)[index] == pytest.approx(np.linalg.norm(d), rel=1e-9)


def test_worst_point_and_summary(smap: og.elasticity.maps.StiffnessMap) -> None:
    point, k_min = smap.worst()
    assert k_min == pytest.approx(smap.min_stiffness.min())
    assert np.all(smap.min_stiffness >= k_min)
    assert k_min < np.median(smap.min_stiffness)
    summary = smap.summary()
    json.dumps(summary, allow_nan=False)
    assert summary["worst_point"] == pytest.approx(list(point))
    assert summary["max_deflection"] == pytest.approx(DEFAULT_CUTTING_FORCE / k_min)
    assert summary["assumptions"]["youngs_modulus"] == 70.0e9
    # Prototype: a few N/um in its softest direction (the 200 mm tool offset).
    assert 2e5 < k_min < 2e6


def test_leg_length_trade_off(params: og.OrthoglideParams) -> None:
    """Same cube: longer bars are softer where the machine is well conditioned, but
    shorter legs work nearer their singularities, so the worst point gets worse."""
    grid = cube_grid([CUBE_CORNER] * 3, CUBE_SIDE, 4)
    short = stiffness_map(grid, params, "links").min_stiffness
    longer = stiffness_map(grid, params.replace(leg_length=0.40), "links").min_stiffness
    assert longer.max() < short.max()
    assert longer.min() > short.min()
    home = [
        cartesian_stiffness(np.zeros(3), params.replace(leg_length=L), "links").K[0, 0]
        for L in (0.31, 0.40)
    ]
    assert home[1] < home[0]


def test_compliance_ellipsoid(params: og.OrthoglideParams) -> None:
    points = cube_points(5, SEED)
    axes, rot = compliance_ellipsoid(points, params)
    c = cartesian_stiffness(points, params).compliance[:, :3, :3]
    rebuilt = rot @ (axes[:, :, None] * np.swapaxes(rot, 1, 2))
    np.testing.assert_allclose(rebuilt, c, rtol=0, atol=REL_TOL * np.abs(c).max())
    np.testing.assert_allclose(np.linalg.det(rot), 1.0, rtol=1e-12)
    assert np.all(np.diff(axes, axis=1) >= 0.0)
    k = cartesian_stiffness(points, params).K
    np.testing.assert_allclose(axes[:, -1], 1.0 / np.linalg.eigvalsh(k)[:, 0], rtol=1e-9)


def test_bad_force(params: og.OrthoglideParams) -> None:
    grid = cube_grid([CUBE_CORNER] * 3, CUBE_SIDE, 2)
    with pytest.raises(InvalidParameterError, match="cutting_force"):
        stiffness_map(grid, params, cutting_force=-5.0)
