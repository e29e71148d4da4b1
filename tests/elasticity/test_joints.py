"""Compliant joints: their limits, scaling, symmetry and series effect.

The joints' springs have no outside reference to compare with, so the checks
are the model's exact properties: as the bearings stiffen the results tend to
the joint-free model's (elastic links) and to the closed form
``J^-T diag(k_a) J^-1`` (rigid links), linearly in the bearings' compliance;
joints alone scale exactly with the bearings' stiffness; adding the joints in
series can only soften the machine; symmetry and positive definiteness hold.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import cube_points

import orthoglide_pin as og
from orthoglide_pin.elasticity.joints import joint_spring
from orthoglide_pin.elasticity.stiffness import cartesian_stiffness
from orthoglide_pin.kinematics.closed_form import inverse_jacobian

SEED = 31
#: Bearings made stiffer by these factors (within the plausible ranges).
FACTORS = (100.0, 1000.0)
#: Ratio of the gaps to the joint-free limit for bearings 10 times stiffer.
CONVERGENCE = 0.1
CONVERGENCE_RTOL = 0.05
SYMMETRY_TOL = 1e-9


def _stiffer(params: og.OrthoglideParams, factor: float) -> og.OrthoglideParams:
    return params.replace(
        joint_stiffness=factor * params.joint_stiffness,
        joint_tilt_stiffness=factor * params.joint_tilt_stiffness,
    )


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def test_spring_is_free_about_its_axis() -> None:
    axis = np.array([0.6, 0.0, 0.8])
    s = joint_spring(axis, 1e8, 2e4)
    assert np.allclose(s @ np.concatenate([np.zeros(3), axis]), 0.0)
    np.testing.assert_allclose(s[:3, :3], 1e8 * np.eye(3))
    assert np.linalg.matrix_rank(s) == 5


@pytest.mark.parametrize(
    ("with_joints", "without"),
    [("links,joints", "links"), ("actuators,links,joints", "actuators,links")],
)
def test_stiff_bearings_tend_to_ideal_joints(
    params: og.OrthoglideParams, with_joints: str, without: str
) -> None:
    point = np.array([0.04, -0.03, 0.06])
    ideal = cartesian_stiffness(point, params, without).K6
    assert ideal is not None
    gaps = []
    for factor in FACTORS:
        k6 = cartesian_stiffness(point, _stiffer(params, factor), with_joints).K6
        assert k6 is not None
        gaps.append(_gap(k6, ideal))
    assert gaps[0] < 1e-2
    assert gaps[1] / gaps[0] == pytest.approx(CONVERGENCE, rel=CONVERGENCE_RTOL)


def test_stiff_bearings_on_rigid_links_tend_to_the_closed_form(
    params: og.OrthoglideParams,
) -> None:
    """With the tool at the platform centre (no lever arm on the bearings' tilt)."""
    centred = params.replace(tool_offset=(0.0, 0.0, 0.0))
    point = np.array([-0.02, 0.05, 0.01])
    j_inv = inverse_jacobian(point, params.leg_length)
    closed = params.actuator_stiffness * j_inv.T @ j_inv
    gaps = [
        _gap(cartesian_stiffness(point, _stiffer(centred, f), "actuators,joints").K, closed)
        for f in FACTORS
    ]
    assert gaps[0] < 0.05
    assert gaps[1] / gaps[0] == pytest.approx(CONVERGENCE, rel=CONVERGENCE_RTOL)


def test_joints_alone_scale_with_the_bearings(params: og.OrthoglideParams) -> None:
    points = cube_points(5, SEED)
    base = cartesian_stiffness(points, params, "joints")
    scaled = cartesian_stiffness(points, _stiffer(params, 3.0), "joints")
    assert base.K6 is not None and scaled.K6 is not None
    np.testing.assert_allclose(
        scaled.K6, 3.0 * base.K6, rtol=1e-8, atol=1e-6 * np.abs(base.K6).max()
    )


def test_joints_soften_and_keep_the_symmetries(params: og.OrthoglideParams) -> None:
    points = cube_points(8, SEED + 1)
    links = cartesian_stiffness(points, params, "actuators,links")
    every = cartesian_stiffness(points, params, "actuators,links,joints")
    assert every.K6 is not None
    diff = every.compliance - links.compliance
    assert np.linalg.eigvalsh(diff).min() > -1e-9 * np.abs(diff).max()  # softer
    asym = np.abs(every.K6 - np.swapaxes(every.K6, 1, 2)).max(axis=(1, 2))
    assert (asym / np.abs(every.K6).max(axis=(1, 2))).max() < SYMMETRY_TOL
    assert np.linalg.eigvalsh(every.K6).min() > 0.0
    centred = params.replace(tool_offset=(0.0, 0.0, 0.0))
    diagonal = cartesian_stiffness(np.full(3, 0.03), centred, "actuators,links,joints").K
    assert np.ptp(np.diag(diagonal)) < SYMMETRY_TOL * np.abs(diagonal).max()
