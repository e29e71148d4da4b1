"""Natural frequencies: the platform model against the full model, symmetry, bad input."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
from elasticity._support import cube_points

import orthoglide_pin as og
from orthoglide_pin.elasticity.modes import FULL_MODES, natural_frequencies
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    SingularConfigurationError,
    UnreachablePointError,
)

SEED = 2112
#: Platform model against the full model on the three lowest frequencies
#: (measured over 5^3 grids of the cube of the prototype, a 340.75 mm leg and a
#: second design, with and without a drive: at most 1.7 %).
THREE_TOL = 0.025
#: Equal frequencies of a symmetric machine on its diagonal (eigensolver rounding).
PAIR_TOL = 1e-7
#: Pairs that the spindle splits by at most this much on the diagonal.
SPINDLE_SPLIT = 0.03


def _designs() -> list[og.OrthoglideParams]:
    base = og.prototype()
    other = og.design_from_workspace(0.15, 0.5, 2.0).to_params(base)
    return [base, dataclasses.replace(other, bar_radius=0.012, actuator_stiffness=6e7)]


def _points(params: og.OrthoglideParams, count: int) -> np.ndarray:
    return cube_points(params, count, SEED)


@pytest.mark.parametrize("design", [0, 1])
def test_platform_model_against_the_full_model(design: int, drive: og.Drive) -> None:
    params = _designs()[design]
    points = _points(params, 5)
    fast = natural_frequencies(params, points, drive)
    full = natural_frequencies(params, points, drive, model="full")
    error = fast.frequencies / full.frequencies - 1.0
    assert np.all(np.abs(error[:, :3]) < THREE_TOL)
    assert full.segments is not None and np.all(full.segments >= 3)
    for result in (fast, full):
        assert np.all(np.diff(result.frequencies, axis=-1) >= 0.0)
        np.testing.assert_allclose(result.energy.sum(axis=-1), 1.0, rtol=1e-9)
        np.testing.assert_allclose(np.linalg.norm(result.direction, axis=-1), 1.0, rtol=1e-9)


@pytest.mark.slow
def test_the_platform_model_where_it_is_least_close(drive: og.Drive) -> None:
    # the 340.75 mm leg, where the platform model was measured least close (about 1 %)
    params = og.prototype().replace(leg_length=0.34075)
    points = [[-0.073, 0.027, -0.073], [0.077, 0.077, -0.073]]
    fast = natural_frequencies(params, points, drive, count=3)
    full = natural_frequencies(params, points, drive, count=3, model="full")
    assert np.all(np.abs(fast.frequencies / full.frequencies - 1.0) < THREE_TOL)


def test_long_bars_bend_first_in_both_models() -> None:
    # a 0.73 m leg: the bars' own bending (pinned-pinned in their plane, ~98 Hz)
    # comes first; the platform model has each bar's first bending mode
    params = og.design_from_workspace(0.15, 0.8, 1.2).to_params(og.prototype())
    point = params.workspace.center
    full = natural_frequencies(params, point, model="full")
    fast = natural_frequencies(params, point)
    for result in (full, fast):
        assert np.all(result.energy[:3, 2] > 0.95)  # the members carry the energy
    assert np.all(np.abs(fast.frequencies[:3] / full.frequencies[:3] - 1.0) < THREE_TOL)


def test_the_prototype_lowest_frequencies() -> None:
    params = og.prototype()
    cube = params.workspace
    f = natural_frequencies(params, [cube.center, cube.q1, cube.q2], model="full").lowest
    # measured: 206.3 Hz at the centre, 145.6 Hz at Q1, 107.9 Hz at Q2
    np.testing.assert_allclose(f, [206.3, 145.6, 107.9], atol=0.2)


def test_vectorised_shapes_and_a_single_point(drive: og.Drive) -> None:
    params = og.prototype()
    grid = og.cube_grid(params.workspace.q1, params.workspace.side, 3)
    points = grid.points().reshape(3, 9, 3)
    result = natural_frequencies(params, points, drive, count=4)
    assert result.frequencies.shape == (*points.shape[:-1], 4)
    one = natural_frequencies(params, points.reshape(-1, 3)[5], drive, count=4)
    np.testing.assert_allclose(one.frequencies, result.frequencies.reshape(-1, 4)[5], rtol=1e-12)
    text = json.dumps(one.to_dict(), allow_nan=False)
    assert '"frequencies"' in text and "carriage side" in text


def test_the_drive_inertia_lowers_the_modes_where_the_carriages_move(drive: og.Drive) -> None:
    params = og.prototype()
    point = params.workspace.center
    alone = natural_frequencies(params, point, None, model="full")
    driven = natural_frequencies(params, point, drive, model="full")
    assert np.all(driven.frequencies <= alone.frequencies * (1.0 + 1e-9))
    assert driven.energy[..., 1].max() > alone.energy[..., 1].max()
    assert "No drive" in alone.assumptions()[-1]


def test_symmetry_on_the_diagonal() -> None:
    params = og.prototype()
    sym = dataclasses.replace(params, tool_offset=(0.0, 0.0, 0.0), spindle_mass=0.0)
    for t in (-0.05, 0.03):
        f = natural_frequencies(sym, [t, t, t], model="full").frequencies
        gaps = np.diff(f) / f[1:]
        assert np.sum(gaps < PAIR_TOL) >= 2  # at least two exact pairs
    # with the spindle, the second and third modes stay a close pair
    p = np.array([-0.05, -0.05, -0.05]) + np.asarray(params.tool_offset)
    f = natural_frequencies(params, p, model="full").frequencies
    assert 1e-3 < f[2] / f[1] - 1.0 < SPINDLE_SPLIT


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"count": 0}, InvalidParameterError, "count"),
        ({"count": 7}, InvalidParameterError, "count"),
        ({"count": FULL_MODES + 1, "model": "full"}, InvalidParameterError, "count"),
        ({"count": 2.5}, InvalidParameterError, "count"),
        ({"model": "beam"}, InvalidParameterError, "model"),
        ({"points": [1.0, 0.0, 0.0]}, UnreachablePointError, "unreachable"),
        ({"points": [math.nan, 0.0, 0.0]}, InvalidParameterError, "points"),
        ({"drive": "motor.yaml"}, InvalidParameterError, "drive"),
    ],
)
def test_bad_input(kwargs: dict, error: type, match: str) -> None:
    args = {"points": [0.0, 0.0, 0.0], **kwargs}
    with pytest.raises(error, match=match):
        natural_frequencies(og.prototype(), **args)


def test_a_singular_point_is_refused() -> None:
    params = og.prototype()
    with pytest.raises((SingularConfigurationError, UnreachablePointError)):
        natural_frequencies(params, [0.31, 0.0, 0.0])


def test_tool_mass_is_the_force_forms_mass() -> None:
    from orthoglide_pin.dynamics.motion_forms import as_dynamics, requirement_forms
    from orthoglide_pin.elasticity.modes import tool_mass
    from orthoglide_pin.kinematics.closed_form import ik_and_jacobian

    params = _designs()[1]
    points = _points(params, 6)
    forms = requirement_forms(as_dynamics(params), points, gravity=(0.0, 0.0, 0.0))
    _, jac = ik_and_jacobian(points, params.leg_length)
    # slider forces F = J^T M_x a: the forms' linear part
    np.testing.assert_allclose(
        np.swapaxes(jac, 1, 2) @ tool_mass(params, points),
        forms.forces.linear,
        rtol=1e-10,
        atol=1e-12,
    )
