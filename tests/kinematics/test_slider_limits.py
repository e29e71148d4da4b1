"""The kinematic functions given the machine: its slider limits checked, Q1/Q2 inside."""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.kinematics.slider_limits import BOUNDARY_TOL, leg_and_limits

#: Agreement of the checked and unchecked routes (the same arithmetic).
SAME = 0.0
#: Agreement of J with the inverse of J^-1 (two closed forms).
INVERSE_TOL = 1e-12

#: The prototype and a design with other legs and another cube.
DESIGNS = {
    "prototype": og.prototype(),
    "long legs": og.prototype().replace(
        leg_length=0.36, workspace_corner=(-0.08, -0.07, -0.09), workspace_side=0.22
    ),
}


def _extreme_corner(params: og.OrthoglideParams, slider: int) -> np.ndarray:
    """The cube's vertex where slider ``slider`` (0-based) is highest."""
    cube = params.workspace
    corners = np.array(
        [cube.q1 + cube.side * np.array(c) for c in itertools.product((0.0, 1.0), repeat=3)]
    )
    q = og.inverse_kinematics(corners, params.leg_length)
    return np.asarray(corners[int(np.argmax(q[:, slider]))])


@pytest.fixture(params=sorted(DESIGNS))
def params(request: pytest.FixtureRequest) -> og.OrthoglideParams:
    return DESIGNS[request.param]


def _on_upper_limit(params: og.OrthoglideParams) -> tuple[np.ndarray, int]:
    """A cube vertex where a slider is on the (derived) upper limit, and that slider."""
    highest = [
        og.inverse_kinematics(_extreme_corner(params, i), params.leg_length)[i] for i in range(3)
    ]
    slider = int(np.argmax(highest))
    return _extreme_corner(params, slider), slider


def test_the_highest_vertex_is_on_the_derived_limit(params: og.OrthoglideParams) -> None:
    # independent route: the limit is derived by slider_range_over_cube
    corner, slider = _on_upper_limit(params)
    q = og.inverse_kinematics(corner, params.leg_length)
    assert q[slider] == pytest.approx(params.slider_upper, abs=1e-12)


def test_inside_the_limits_the_machine_gives_the_leg_length_results(
    params: og.OrthoglideParams,
) -> None:
    rng = np.random.default_rng(3)
    cube = params.workspace
    points = rng.uniform(cube.q1, cube.q1 + cube.side, (50, 3))
    L = params.leg_length
    J = og.jacobian(points, params)
    np.testing.assert_allclose(J, og.jacobian(points, L), rtol=0, atol=SAME)
    J_inv = og.inverse_jacobian(points, params)
    np.testing.assert_allclose(J @ J_inv, np.broadcast_to(np.eye(3), J.shape), atol=INVERSE_TOL)
    q = og.inverse_kinematics(points, params)
    np.testing.assert_allclose(q, og.inverse_kinematics(points, L), rtol=0, atol=SAME)
    back = og.direct_kinematics(q, params)
    np.testing.assert_allclose(back, points, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "call",
    [
        lambda p, m, **k: og.jacobian(p, m, **k),
        lambda p, m, **k: og.inverse_jacobian(p, m, **k),
        lambda p, m, **k: og.inverse_kinematics(p, m, **k),
    ],
    ids=["jacobian", "inverse_jacobian", "inverse_kinematics"],
)
@pytest.mark.parametrize("slider", [0, 1, 2])
def test_a_point_beyond_the_limits_is_refused_naming_it_and_the_limits(
    params: og.OrthoglideParams, call: Callable[..., Any], slider: int
) -> None:
    corner = _extreme_corner(params, slider)
    q_corner = og.inverse_kinematics(corner, params.leg_length)[slider]
    # dq_i/dp_i = 1: slider i ends 1 mm beyond the upper limit
    beyond = corner + (params.slider_upper - q_corner + 1e-3) * np.eye(3)[slider]
    q = og.inverse_kinematics(beyond, params.leg_length)  # unchecked: the reference
    first = int(np.argmax(q > params.slider_upper + BOUNDARY_TOL))
    with pytest.raises(og.UnreachablePointError) as info:
        call(beyond, params)
    message = str(info.value)
    assert info.value.leg == first + 1
    assert f"{q[first]:.6g}" in message
    assert f"{params.slider_upper:.6g}" in message and f"{params.slider_lower:.6g}" in message
    np.testing.assert_array_equal(info.value.point, beyond)
    # the escape, and a bare leg length (no machine, no limits), compute there
    out = call(beyond, params, check_limits=False)
    np.testing.assert_allclose(out, call(beyond, params.leg_length), rtol=0, atol=SAME)
    # a batch is refused at its first such point
    with pytest.raises(og.UnreachablePointError):
        call(np.stack([np.zeros(3), beyond]), params)


@pytest.mark.parametrize(
    ("shift", "inside"), [(0.0, True), (0.5 * BOUNDARY_TOL, True), (3.0 * BOUNDARY_TOL, False)]
)
def test_points_on_the_limits_within_the_tolerance_are_inside(
    params: og.OrthoglideParams, shift: float, inside: bool
) -> None:
    vertex, slider = _on_upper_limit(params)
    corner = vertex + shift * np.eye(3)[slider]
    if inside:
        og.jacobian(corner, params)
        og.jacobian(params.workspace.q1, params)  # Q1 and Q2 themselves
        og.jacobian(params.workspace.q1 + params.workspace.side, params)
    else:
        with pytest.raises(og.UnreachablePointError, match="slider limits"):
            og.jacobian(corner, params)


def test_slider_values_beyond_the_limits_are_refused_by_direct_kinematics(
    params: og.OrthoglideParams,
) -> None:
    q = np.array([0.0, params.slider_lower - 3.0 * BOUNDARY_TOL, 0.0])
    with pytest.raises(og.InvalidParameterError, match=r"\bq2\b") as info:
        og.direct_kinematics(q, params)
    assert f"{params.slider_lower:.6g}" in str(info.value)
    on = np.array([0.0, params.slider_lower - 0.5 * BOUNDARY_TOL, 0.0])
    np.testing.assert_array_equal(
        og.direct_kinematics(on, params), og.direct_kinematics(on, params.leg_length)
    )
    np.testing.assert_array_equal(
        og.direct_kinematics(q, params, check_limits=False),
        og.direct_kinematics(q, params.leg_length),
    )


def test_a_bare_leg_length_names_no_limits() -> None:
    assert leg_and_limits(0.31) == (0.31, None)
    p = og.prototype()
    assert leg_and_limits(p) == (p.leg_length, (p.slider_lower, p.slider_upper))
    for bad in (None, "abc", {"a": 1}, float("nan"), np.zeros((4, 5))):
        with pytest.raises(og.InvalidParameterError, match="leg_length"):
            og.jacobian((0.0, 0.0, 0.0), bad)  # type: ignore[arg-type]
    with pytest.raises(og.InvalidParameterError, match="check_limits"):
        og.jacobian((0.0, 0.0, 0.0), p, check_limits="no")  # type: ignore[arg-type]


def test_the_package_calls_the_kinematics_with_leg_lengths_beyond_the_limits() -> None:
    # the design and certification code evaluates J beyond the machine's limits
    # with a bare leg length: unchanged, unchecked
    p = og.prototype()
    beyond = _on_upper_limit(p)[0] + 0.01
    og.transmission_factors(beyond, p.leg_length)
    og.kinetostatic_indices(beyond, p.leg_length)
