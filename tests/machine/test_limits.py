"""Slider limits against the prescribed cube and tool points (orthoglide_pin.machine.limits)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE

import orthoglide_pin as og
from orthoglide_pin.machine.limits import (
    check_slider_limits,
    check_slider_values,
    cube_slider_range,
)

#: A step beyond the limits that rounding cannot explain [m].
BEYOND = 1e-9


def _corners(cube: og.Cube) -> np.ndarray:
    return np.array(list(itertools.product(*zip(cube.q1, cube.q2, strict=True))))


def test_the_cube_is_within_its_derived_limits(params: og.OrthoglideParams) -> None:
    for machine in (params, params.replace(leg_length=0.28), params.replace(leg_length=0.45)):
        check_slider_limits(machine, _corners(machine.workspace))  # corners reach the limits
        lo, hi = cube_slider_range(machine)
        assert (machine.slider_lower, machine.slider_upper) == (lo, hi)


def test_a_point_just_beyond_is_refused_with_its_slider(params: og.OrthoglideParams) -> None:
    q2 = params.workspace.q2
    check_slider_limits(params, q2)  # on the limit (rounding there): accepted
    with pytest.raises(og.UnreachablePointError) as info:
        check_slider_limits(params, [np.zeros(3), q2 + BEYOND])
    assert info.value.leg == 1  # the first slider past its upper limit
    np.testing.assert_array_equal(info.value.point, q2 + BEYOND)
    assert "outside the limits" in str(info.value) and "check_limits=False" in str(info.value)
    # a caller without that option names another way out, or none
    for hint in ("keep the path inside the cube", None):
        with pytest.raises(og.UnreachablePointError) as info:
            check_slider_limits(params, q2 + BEYOND, hint=hint)
        assert "check_limits" not in str(info.value)
        assert str(info.value).endswith(f" m ({hint})" if hint else "] m")
    check_slider_limits(params, q2 + BEYOND, tol=10 * BEYOND)  # within a given slack


def test_other_bad_points(params: og.OrthoglideParams) -> None:
    with pytest.raises(og.UnreachablePointError):
        check_slider_limits(params, [0.4, 0.4, 0.0])  # no leg reaches it
    with pytest.raises(og.InvalidParameterError):
        check_slider_limits(params, [0.0, np.nan, 0.0])
    with pytest.raises(og.InvalidParameterError):
        check_slider_limits(params, [0.0, 0.0])


def test_a_cube_away_from_home_keeps_home_within_the_limits(params: og.OrthoglideParams) -> None:
    away = params.replace(workspace_corner=(0.02, 0.03, 0.01), workspace_side=0.1)
    lo, hi = cube_slider_range(away)
    assert lo > 0.0  # the cube alone would not need home
    assert away.slider_lower == 0.0 and away.slider_upper == hi
    check_slider_limits(away, [np.zeros(3), *_corners(away.workspace)])
    assert CUBE_CORNER < 0.0 < CUBE_CORNER + CUBE_SIDE  # the prototype's cube holds home


def test_slider_values_beyond_the_limits_name_their_slider(params: og.OrthoglideParams) -> None:
    lo, hi = params.slider_lower, params.slider_upper
    check_slider_values(params, [[lo, 0.0, hi], [0.0, 0.0, 0.0]])  # the limits themselves
    with pytest.raises(og.InvalidParameterError) as info:
        check_slider_values(params, [[0.0, 0.0, 0.0], [0.0, lo - BEYOND, 0.0]])
    assert info.value.name == "q2" and info.value.value == lo - BEYOND
    assert "check_limits=False" in str(info.value)
    with pytest.raises(og.InvalidParameterError) as info:
        check_slider_values(params, [0.0, 0.0, hi + BEYOND], hint=None)
    assert info.value.name == "q3" and str(info.value).endswith(" m")  # no hint on the CLI
    with pytest.raises(og.InvalidParameterError, match="invalid q"):
        check_slider_values(params, [0.0, np.nan, 0.0])


def test_the_command_line_says_no_escape(params: og.OrthoglideParams) -> None:
    with pytest.raises(og.UnreachablePointError) as info:
        check_slider_limits(params, params.workspace.q2 + BEYOND, hint=None)
    assert str(info.value).endswith(" m") and "check_limits" not in str(info.value)
