from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import orthoglide_pin as og
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
