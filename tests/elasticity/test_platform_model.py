"""The platform vibration model: the bounds physics sets, and its stiffness and mass."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from elasticity._support import cube_points

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.elasticity import platform_model as pm
from orthoglide_pin.elasticity.mass import member_masses, platform_inertia
from orthoglide_pin.elasticity.modes import natural_frequencies, tool_mass
from orthoglide_pin.kinematics.closed_form import inverse_jacobian

SEED = 2612
#: Eigensolver rounding on frequency ratios [-].
RATIO_TOL = 1e-9
#: The carriages condensed out against the stiffness model's ``K6`` (relative).
K6_TOL = 1e-9
#: The model's mass with rigid members against Pinocchio's ``crba`` reduced to
#: the tool: they differ only by the small links' spin about their own axes
#: and the bars' section inertia (measured below 1e-3).
CRBA_TOL = 2e-3


def _designs() -> list[og.OrthoglideParams]:
    base = og.prototype()
    other = og.design_from_workspace(0.15, 0.5, 2.0).to_params(base)
    return [
        base,
        base.replace(leg_length=0.34075),
        dataclasses.replace(other, bar_radius=0.012, actuator_stiffness=6e7),
    ]


def _points(params: og.OrthoglideParams, count: int) -> np.ndarray:
    return cube_points(params, count, SEED)


def _freq(params: og.OrthoglideParams, points: np.ndarray, drive: og.Drive | None) -> np.ndarray:
    return natural_frequencies(params, points, drive).frequencies


#: Actuators 30 times softer than the prototype's: with the drive, the carriages
#: carry most of the energy and the ratio comes within 1e-4 of sqrt(2) (a model
#: whose carriage mass depends on the actuators' stiffness gave 1.48 there).
SOFT_ACTUATORS = 3e6


@pytest.mark.parametrize("design", [0, 1, 2, "soft"])
@pytest.mark.parametrize("use_drive", [False, True])
def test_doubling_the_actuators_raises_each_frequency_by_at_most_sqrt2(
    design: int | str, use_drive: bool, drive: og.Drive
) -> None:
    params = (
        og.prototype().replace(actuator_stiffness=SOFT_ACTUATORS)
        if design == "soft"
        else _designs()[int(design)]
    )
    points = _points(params, 24)
    d = drive if use_drive else None
    ratio = _freq(
        params.replace(actuator_stiffness=2.0 * params.actuator_stiffness), points, d
    ) / _freq(params, points, d)
    assert np.all(ratio >= 1.0 - RATIO_TOL)
    assert np.all(ratio <= math.sqrt(2.0) * (1.0 + RATIO_TOL))


@pytest.mark.parametrize("scale", [0.25, 3.0])
def test_scaling_every_stiffness_scales_every_frequency_by_its_root(
    scale: float, drive: og.Drive
) -> None:
    params = _designs()[1]
    points = _points(params, 12)
    stiffer = params.replace(
        actuator_stiffness=scale * params.actuator_stiffness,
        youngs_modulus=scale * params.youngs_modulus,
        shear_modulus=scale * params.shear_modulus,
    )
    np.testing.assert_allclose(
        _freq(stiffer, points, drive), math.sqrt(scale) * _freq(params, points, drive), rtol=1e-9
    )


def test_adding_mass_lowers_no_frequency(drive: og.Drive) -> None:
    params = _designs()[0]
    points = _points(params, 24)
    alone = _freq(params, points, None)
    assert np.all(_freq(params, points, drive) <= alone * (1.0 + RATIO_TOL))
    heavy = params.replace(spindle_mass=2.0 * params.spindle_mass)
    assert np.all(_freq(heavy, points, None) <= alone * (1.0 + RATIO_TOL))


def _matrices(
    params: og.OrthoglideParams, points: np.ndarray
) -> tuple[np.ndarray, list[np.ndarray]]:
    table = inertia_table(params)
    carriage = table.kind("carriage")[0].mass
    return pm.platform_matrices(
        points, params, member_masses(params, table), platform_inertia(params, table), carriage
    )


@pytest.mark.parametrize("design", [0, 2])
def test_the_carriages_condensed_out_give_the_stiffness_models_k6(design: int) -> None:
    params = _designs()[design]
    points = _points(params, 10)
    k, _ = _matrices(params, points)
    k_ps = k[:, :6, 6:]
    k6 = k[:, :6, :6] - k_ps @ np.linalg.solve(k[:, 6:, 6:], np.swapaxes(k_ps, 1, 2))
    ref = og.cartesian_stiffness(points, params, check_limits=False).K6
    assert ref is not None
    scale = np.abs(ref).max(axis=(1, 2), keepdims=True)
    assert np.all(np.abs(k6 - ref) <= K6_TOL * scale)


@pytest.mark.parametrize("design", [0, 2])
def test_the_mass_moving_rigidly_is_pinocchios(design: int) -> None:
    params = _designs()[design]
    points = _points(params, 6)
    _, parts = _matrices(params, points)
    mass = parts[0] + parts[1] + parts[2]
    # a rigid machine: the platform translates, the carriages follow J^-1
    t = np.zeros((points.shape[0], pm.SIZE, 3))  # the bars do not bend
    t[:, :3, :] = np.eye(3)
    t[:, 6:9, :] = inverse_jacobian(points, params.leg_length)
    reduced = np.swapaxes(t, 1, 2) @ mass @ t
    ref = tool_mass(params, points)
    scale = np.abs(ref).max(axis=(1, 2), keepdims=True)
    assert np.all(np.abs(reduced - ref) <= CRBA_TOL * scale)
    assert all(np.all(np.linalg.eigvalsh(m) >= -1e-12) for m in parts)


def test_a_batch_of_several_blocks_is_its_points_one_by_one(drive: og.Drive) -> None:
    from orthoglide_pin.elasticity.stiffness import BLOCK

    params = _designs()[0]
    cube = params.workspace
    points = cube.q1 + cube.side * np.random.default_rng(SEED).uniform(0, 1, (BLOCK + 5, 3))
    batch = natural_frequencies(params, points, drive)
    for k in (0, BLOCK - 1, BLOCK, BLOCK + 4):
        one = natural_frequencies(params, points[k], drive)
        np.testing.assert_allclose(one.frequencies, batch.frequencies[k], rtol=1e-12)
        np.testing.assert_allclose(one.energy, batch.energy[k], atol=1e-12)
