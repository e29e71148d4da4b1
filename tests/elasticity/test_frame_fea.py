"""The frame FEA check (PyNite) on its own: properties any linear structure has.

Its agreement with the elastostatic model is tested with that model
(``tests/elasticity/test_stiffness.py``). Here: Maxwell-Betti reciprocity
(a symmetric, positive-definite compliance), homogeneity (every modulus and
spring times ``s`` divides the compliance by ``s``, exactly), the machine's
three-fold symmetry at home with the tool at the platform centre, the actuator
springs in series (rigid actuators make the tool stiffer), and clear errors.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, cube_points

import orthoglide_pin as og
from orthoglide_pin.elasticity.frame_fea import frame_compliance
from orthoglide_pin.exceptions import InvalidParameterError, UnreachablePointError

SEED = 20261204
#: Asymmetry of C relative to its largest entry (the solver's round-off).
SYMMETRY_TOL = 1e-8
#: Homogeneity and symmetry relations, relative (exact up to round-off).
EXACT_TOL = 1e-8
#: Factor applied to every modulus and spring.
SCALE = 3.0
#: A design other than the prototype: longer legs, tool at the platform centre.
LONG_LEGS = 0.40


@pytest.fixture(scope="module")
def long_legs(params: og.OrthoglideParams) -> og.OrthoglideParams:
    scale = LONG_LEGS / params.leg_length
    return params.replace(
        leg_length=LONG_LEGS,
        tool_offset=(0.0, 0.0, 0.0),
        workspace_corner=(CUBE_CORNER * scale,) * 3,
        workspace_side=CUBE_SIDE * scale,
        slider_lower=None,
        slider_upper=None,
    )


@pytest.mark.parametrize("design", ["prototype", "long legs"])
def test_reciprocity(params: og.OrthoglideParams, long_legs: og.OrthoglideParams, design: str):
    machine = params if design == "prototype" else long_legs
    for point in cube_points(2, SEED) * machine.leg_length / params.leg_length:
        c = frame_compliance(point, machine)
        assert c.shape == (6, 6)
        assert np.abs(c - c.T).max() < SYMMETRY_TOL * np.abs(c).max()
        assert np.linalg.eigvalsh((c + c.T) / 2).min() > 0.0


def test_homogeneity_in_the_moduli(params: og.OrthoglideParams) -> None:
    point = cube_points(1, SEED + 1)[0]
    stiffer = params.replace(
        youngs_modulus=SCALE * params.youngs_modulus,
        shear_modulus=SCALE * params.shear_modulus,
        actuator_stiffness=SCALE * params.actuator_stiffness,
    )
    np.testing.assert_allclose(
        SCALE * frame_compliance(point, stiffer),
        frame_compliance(point, params),
        rtol=EXACT_TOL,
        atol=EXACT_TOL * np.abs(frame_compliance(point, params)).max(),
    )


def test_three_fold_symmetry_at_home(long_legs: og.OrthoglideParams) -> None:
    c = frame_compliance(np.zeros(3), long_legs)
    diagonal = np.diag(c)
    np.testing.assert_allclose(diagonal[:3], diagonal[0], rtol=EXACT_TOL)
    np.testing.assert_allclose(diagonal[3:], diagonal[3], rtol=EXACT_TOL)


def test_rigid_actuators_make_the_tool_stiffer(params: og.OrthoglideParams) -> None:
    point = cube_points(1, SEED + 2)[0]
    elastic = frame_compliance(point, params)
    rigid = frame_compliance(point, params, actuators=False)
    extra = np.linalg.eigvalsh(elastic[:3, :3] - rigid[:3, :3])
    assert extra.min() > -SYMMETRY_TOL * np.abs(elastic).max()
    assert extra.max() > 0.0


@pytest.mark.parametrize(
    ("kwargs", "mentions"),
    [
        ({"point": [0.0, 0.0]}, "point"),
        ({"point": [0.0, np.nan, 0.0]}, "point"),
        ({"point": "home"}, "point"),
        ({"params": "prototype"}, "params"),
        ({"actuators": "yes"}, "actuators"),
        ({"rigid": -1.0}, "rigid"),
        ({"rigid": True}, "rigid"),
    ],
)
def test_bad_arguments(kwargs: dict[str, object], mentions: str) -> None:
    call = {"point": np.zeros(3), **kwargs}
    with pytest.raises(InvalidParameterError, match=mentions):
        frame_compliance(**call)  # type: ignore[arg-type]


def test_points_out_of_reach_or_beyond_the_limits(params: og.OrthoglideParams) -> None:
    with pytest.raises(UnreachablePointError):
        frame_compliance([0.4, 0.0, 0.0], params)
    beyond = np.array([CUBE_CORNER - 0.03, 0.0, 0.0])  # reachable, slider 1 beyond its limit
    with pytest.raises(UnreachablePointError, match="check_limits=False"):
        frame_compliance(beyond, params)
    c = frame_compliance(beyond, params, check_limits=False)
    assert np.isfinite(c).all()
