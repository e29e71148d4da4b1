from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.machine.params import field_names

#: The paper's stroke is given to the millimetre (section 4).
PAPER_STROKE = 0.257
PAPER_TOL = 0.5e-3
EXACT = 1e-15


def test_prototype_is_the_papers_machine(params: og.OrthoglideParams) -> None:
    assert params.leg_length == 0.31
    assert abs(params.stroke - PAPER_STROKE) < PAPER_TOL
    # Q1 = -L/sqrt(18) (1,1,1) is the cube corner on the slider side: its slider values
    # are the lower limit.
    assert params.slider_lower == pytest.approx(-0.31 / math.sqrt(18.0), abs=EXACT)
    # The ratio Lw / stroke of the paper: 200/257 = 0.78.
    assert round(0.2 / params.stroke, 2) == 0.78


def test_defaults_are_the_prototype(params: og.OrthoglideParams) -> None:
    assert og.OrthoglideParams() == params


def test_yaml_round_trip(params: og.OrthoglideParams, tmp_path) -> None:
    rng = np.random.default_rng(7)
    changed = params.replace(
        leg_length=0.3 + 0.1 * rng.random(),
        tool_offset=tuple(rng.normal(size=3) * 0.1),
        bar_mass=0.2,
        density=7800.0,
    )
    assert og.OrthoglideParams.from_yaml(changed.to_yaml()) == changed
    path = changed.save(tmp_path / "machine.yaml")
    assert og.OrthoglideParams.load(path) == changed
    assert [p.name for p in tmp_path.iterdir()] == ["machine.yaml"]  # no temp file left


def test_partial_yaml_keeps_prototype_values(params: og.OrthoglideParams) -> None:
    got = og.OrthoglideParams.from_yaml("leg_length: 0.4\n")
    assert got == params.replace(leg_length=0.4)
    assert og.OrthoglideParams.from_yaml("") == params


def test_vector_parameters_accept_strings(params: og.OrthoglideParams) -> None:
    assert params.replace(tool_offset="0, 0.01, 0.3").tool_offset == (0.0, 0.01, 0.3)


def test_immutable(params: og.OrthoglideParams) -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        params.leg_length = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(
    ("name", "value", "fragment"),
    [
        ("leg_length", -0.3, "positive"),
        ("leg_length", 0.0, "positive"),
        ("leg_length", float("nan"), "finite"),
        ("density", float("inf"), "finite"),
        ("parallelogram_width", "abc", "finite"),
        ("bar_radius", True, "finite"),
        ("bar_wall", 0.02, "bar_radius"),
        ("slider_lower", 0.01, "<= 0"),
        ("slider_upper", -0.01, ">= 0"),
        ("leg_length", 0.18, "slider excursion"),
        ("tool_offset", (0.0, 0.1), "three"),
        ("carriage_size", (0.1, -0.1, 0.04), "positive"),
        ("bar_mass", -1.0, "non-negative"),
    ],
)
def test_invalid_values_name_the_value(
    params: og.OrthoglideParams, name: str, value: object, fragment: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(**{name: value})
    assert fragment in str(info.value)
    assert isinstance(info.value, og.OrthoglideError)


def test_unknown_name_lists_the_allowed_ones(params: og.OrthoglideParams) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(leg_lenght=0.3)
    assert info.value.value == "leg_lenght"
    assert "leg_length" in str(info.value)
    with pytest.raises(og.InvalidParameterError):
        og.OrthoglideParams.from_yaml("foo: 1\n")


def test_bad_yaml_and_missing_file(tmp_path) -> None:
    with pytest.raises(og.InvalidParameterError):
        og.OrthoglideParams.from_yaml("leg_length: [0.3\n")
    with pytest.raises(og.InvalidParameterError):
        og.OrthoglideParams.from_yaml("- 1\n- 2\n")
    with pytest.raises(og.InvalidParameterError) as info:
        og.OrthoglideParams.load(tmp_path / "missing.yaml")
    assert "missing.yaml" in str(info.value)


def test_masses_may_be_zero(params: og.OrthoglideParams) -> None:
    light = params.replace(bar_mass=0.0, link_mass=0.0, carriage_mass=0.0)
    assert light.bar_mass == 0.0


def test_field_names_cover_the_dict(params: og.OrthoglideParams) -> None:
    assert tuple(params.to_dict()) == field_names()


# ------------------------------------------------ the cube and the slider limits
#: Brute-force slider range on a grid vs the closed form [m] (the grid holds the extremes).
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
    # another cube within the same given limits gives the same URDF
    given = params.replace(slider_lower=-0.1, slider_upper=0.25)
    moved = given.replace(workspace_corner=(CUBE_CORNER, CUBE_CORNER, -0.05), workspace_side=0.15)
    assert moved.workspace != given.workspace
    assert xacro_args(moved) == xacro_args(given)


def test_the_criterion_is_part_of_the_machine(params: og.OrthoglideParams, tmp_path) -> None:
    # the prototype carries the paper's bounds; another design its own, through its file
    assert (params.psi_min, params.psi_max) == og.PAPER_BOUNDS == (0.5, 2.0)
    design = params.replace(leg_length=0.34, psi_min=0.4, psi_max=2.5)
    path = design.save(tmp_path / "d.yaml")
    text = path.read_text()
    assert "psi_min: 0.4\n" in text and "psi_max: 2.5\n" in text
    again = og.OrthoglideParams.load(path)
    assert again == design and (again.psi_min, again.psi_max) == (0.4, 2.5)
    # replace() keeps the criterion, whatever else changes; a file without it is the paper's
    moved = again.replace(leg_length=0.36, workspace_side=0.15)
    assert (moved.psi_min, moved.psi_max) == (0.4, 2.5)
    assert og.OrthoglideParams.from_yaml("leg_length: 0.34\n").psi_max == 2.0
    # the criterion is not a description argument: the same URDF whatever the bounds
    from orthoglide_pin.machine.description import parameter_arguments, xacro_args

    assert not any(a.startswith("psi") for a in parameter_arguments())
    assert xacro_args(params.replace(psi_max=3.0)) == xacro_args(params)


@pytest.mark.parametrize(
    ("changes", "name", "fragment"),
    [
        ({"psi_min": 0.0}, "psi_min", "in (0, 1)"),
        ({"psi_min": 1.0}, "psi_min", "in (0, 1)"),
        ({"psi_min": -0.5}, "psi_min", "in (0, 1)"),
        ({"psi_max": 1.0}, "psi_max", "> 1"),
        ({"psi_max": 0.8}, "psi_max", "> 1"),
        ({"psi_min": float("nan")}, "psi_min", "finite"),
        ({"psi_max": float("inf")}, "psi_max", "finite"),
        ({"psi_max": "two"}, "psi_max", "finite"),
        ({"psi_min": True}, "psi_min", "finite"),
        ({"psi_max": 1e300}, "psi_max", "[1, 1e+06] (dimensionless)"),
    ],
)
def test_a_bad_criterion_is_refused_by_name(
    params: og.OrthoglideParams, changes: dict[str, object], name: str, fragment: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        params.replace(**changes)
    assert info.value.name == name and fragment in str(info.value)
    key, value = next(iter(changes.items()))
    if isinstance(value, float) and math.isfinite(value):  # the same from a file
        with pytest.raises(og.InvalidParameterError, match=name):
            og.OrthoglideParams.from_yaml(f"{key}: {value!r}\n")
