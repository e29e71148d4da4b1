"""The prescribed cube in the parameters, and the slider limits derived from it."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.kinematics.closed_form import inverse_kinematics

#: Same formula, same inputs: bit-for-bit equal.
EXACT = 0.0
#: Brute-force slider range on a grid vs the closed form [m] (grid spacing).
GRID_TOL = 1e-12
#: Points per edge of the brute-force grid (the extremes are at corners or on
#: the face points nearest to the axes, which this grid contains: 0 is on it).
GRID_POINTS = 41
#: Designs other than the prototype: leg lengths [m] and cubes (corner, side) [m].
OTHER_LEGS = (0.28, 0.35, 0.45)
OTHER_CUBES = (((-0.05, -0.06, -0.04), 0.12), ((-0.1, -0.1, -0.1), 0.25))


def brute_force_range(leg: float, corner: tuple[float, ...], side: float) -> tuple[float, float]:
    """Slider range over a grid of the cube holding 0 on each axis when the cube does."""
    axes = []
    for c in corner:
        ticks = np.linspace(c, c + side, GRID_POINTS)
        axes.append(np.unique(np.append(ticks, 0.0 if c < 0.0 < c + side else c)))
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    q = inverse_kinematics(pts, leg)
    return float(q.min()), float(q.max())


def test_the_prototype_holds_the_papers_cube(params: og.OrthoglideParams) -> None:
    cube = params.workspace
    assert cube == og.Cube((CUBE_CORNER,) * 3, CUBE_SIDE)
    np.testing.assert_array_equal(cube.q1, np.full(3, -PROTOTYPE_LEG / math.sqrt(18.0)))
    np.testing.assert_allclose(cube.q2 - cube.q1, CUBE_SIDE, rtol=1e-15)
    np.testing.assert_allclose(cube.center, cube.q1 + 0.1, rtol=1e-15)
    assert params.derived_limits == ("slider_lower", "slider_upper")
    assert cube.describe() == "200 mm cube, lowest corner Q1 (-73.07, -73.07, -73.07) mm"


@pytest.mark.parametrize("leg", OTHER_LEGS)
def test_changing_the_leg_keeps_the_cube_and_rederives_the_limits(
    params: og.OrthoglideParams, leg: float
) -> None:
    other = params.replace(leg_length=leg)
    assert other.workspace == params.workspace
    lo, hi = brute_force_range(leg, other.workspace_corner, other.workspace_side)
    assert other.slider_lower == pytest.approx(lo, abs=GRID_TOL)
    assert other.slider_upper == pytest.approx(hi, abs=GRID_TOL)
    # every point of the cube is within the limits, and the corners reach them
    corners = np.array(list(itertools.product(*[(c, c + CUBE_SIDE) for c in (CUBE_CORNER,) * 3])))
    q = inverse_kinematics(corners, leg)
    assert q.max() == pytest.approx(other.slider_upper, abs=GRID_TOL)
    # and back: the prototype's limits again, exactly
    back = other.replace(leg_length=PROTOTYPE_LEG)
    assert (back.slider_lower, back.slider_upper) == (params.slider_lower, params.slider_upper)


@pytest.mark.parametrize(("corner", "side"), OTHER_CUBES)
def test_another_cube_derives_its_own_limits(
    params: og.OrthoglideParams, corner: tuple[float, float, float], side: float
) -> None:
    other = params.replace(workspace_corner=corner, workspace_side=side, leg_length=0.4)
    lo, hi = brute_force_range(0.4, corner, side)
    assert (other.slider_lower, other.slider_upper) == pytest.approx((lo, hi), abs=GRID_TOL)
    assert other.slider_lower == og.slider_range_over_cube(0.4, corner, side)[0]


def test_given_limits_are_kept_and_checked(params: og.OrthoglideParams) -> None:
    wide = params.replace(slider_lower=-0.1, slider_upper=0.25)
    assert wide.derived_limits == ()
    longer = wide.replace(leg_length=0.35)  # given limits stay as given
    assert (longer.slider_lower, longer.slider_upper) == (-0.1, 0.25)
    # one given, one derived: the derived one follows the leg
    half = params.replace(slider_upper=0.25).replace(leg_length=0.35)
    assert half.slider_upper == 0.25
    assert half.slider_lower == params.replace(leg_length=0.35).slider_lower
    assert half.derived_limits == ("slider_lower",)
    # None derives a given limit again
    assert wide.replace(slider_lower=None, slider_upper=None) == params


def test_limits_that_cannot_reach_the_cube_are_refused(params: og.OrthoglideParams) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(slider_upper=0.15)
    message = str(info.value)
    assert "slider_upper=0.15" in message
    assert "200 mm cube, lowest corner Q1 (-73.07, -73.07, -73.07) mm" in message
    assert "[-73.07, 184.19] mm" in message  # what the cube needs
    assert "omit slider_lower and slider_upper" in message  # the fix
    # the prototype's old given limits cannot serve a shorter leg: refused, not kept silently
    given = params.replace(slider_lower=params.slider_lower, slider_upper=params.slider_upper)
    with pytest.raises(og.InvalidParameterError, match="slider_upper"):
        given.replace(leg_length=0.28)


def test_a_cube_out_of_reach_is_refused(params: og.OrthoglideParams) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(leg_length=0.15)
    assert "reaches the whole prescribed 200 mm cube" in str(info.value)
    assert "workspace_side" in str(info.value)


def test_yaml_round_trip_keeps_derived_and_given_limits(
    params: og.OrthoglideParams, tmp_path
) -> None:
    other = params.replace(leg_length=0.35, workspace_side=0.18)
    text = other.to_yaml()
    assert "slider_lower: null" in text and "slider_upper: null" in text
    assert "workspace_side: 0.18" in text
    back = og.OrthoglideParams.from_yaml(text)
    assert back == other and back.derived_limits == other.derived_limits
    # edit the file's leg: the limits follow, the cube stays
    edited = og.OrthoglideParams.from_yaml(text.replace("leg_length: 0.35", "leg_length: 0.4"))
    assert edited == other.replace(leg_length=0.4)
    given = other.replace(slider_lower=-0.09)
    assert "slider_lower: -0.09" in given.to_yaml()
    assert og.OrthoglideParams.load(given.save(tmp_path / "g.yaml")) == given
    # the dictionary has numbers unless asked for the file's form
    assert given.to_dict()["slider_upper"] == given.slider_upper
    assert given.to_dict(derived_as_none=True)["slider_upper"] is None


def test_the_cube_is_not_a_description_argument(params: og.OrthoglideParams) -> None:
    from orthoglide_pin.machine.description import parameter_arguments, xacro_args

    assert not any(a.startswith("workspace") for a in parameter_arguments())
    # a cube that derives the same limits gives the same URDF
    moved = params.replace(workspace_corner=(CUBE_CORNER, CUBE_CORNER, CUBE_CORNER))
    assert xacro_args(moved) == xacro_args(params)


@pytest.mark.parametrize(
    ("name", "value", "meant"),
    [
        ("leg_length", 310.0, "0.31"),
        ("workspace_side", 200.0, "0.2"),
        ("tool_offset", (0.0, 0.0, 200.0), "0.2"),
        ("spindle_mass", 2000.0, "2"),
        ("density", 2.7, "2700"),
    ],
)
def test_values_in_the_wrong_unit_get_a_hint(
    params: og.OrthoglideParams, name: str, value: object, meant: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(**{name: value})
    assert f"did you mean {meant}?" in str(info.value)


def test_every_parameter_has_a_plausible_range(params: og.OrthoglideParams) -> None:
    from orthoglide_pin.machine.params import field_names

    assert set(field_names()) <= set(og.PLAUSIBLE_RANGES)
    for name, value in params.to_dict().items():
        low, high, _ = og.PLAUSIBLE_RANGES[name]
        for v in value if isinstance(value, list) else [value]:
            assert v is None or low <= v <= high, name
    # out of range without a unit slip: the range alone
    with pytest.raises(og.InvalidParameterError, match=r"in \[0.02, 5\] m"):
        params.replace(leg_length=7.0)
