"""Plausible ranges of the SI parameters (orthoglide_pin.machine.ranges)."""

from __future__ import annotations

import pytest

import orthoglide_pin as og
from orthoglide_pin.machine.ranges import LEAD_RANGE, check_plausible


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
    def numbers(value: object) -> list[float] | None:
        items = value if isinstance(value, list) else [value]
        ok = all(isinstance(v, float) or v is None for v in items)
        return [v for v in items if v is not None] if ok else None

    # every SI number of the machine (a scalar, a vector, an optional mass) has a range
    checked = 0
    for name, value in params.to_dict().items():
        values = numbers(value)
        if values is None:
            continue  # not a number: tables of parts, say
        low, high, _ = og.PLAUSIBLE_RANGES[name]
        assert all(low <= v <= high for v in values), name
        checked += 1
    assert checked >= 25  # the prototype's numeric parameters, the cube included
    # out of range without a unit slip: the range alone
    with pytest.raises(og.InvalidParameterError, match=r"in \[0.02, 5\] m"):
        params.replace(leg_length=7.0)


def test_a_slip_is_only_suggested_when_it_lands_in_range() -> None:
    check_plausible("lead", 0.025, *LEAD_RANGE)  # in range: nothing to say
    with pytest.raises(og.InvalidParameterError) as info:
        check_plausible("lead", 25.0, *LEAD_RANGE)
    assert "metres per revolution: did you mean 0.025?" in str(info.value)
    with pytest.raises(og.InvalidParameterError) as info:
        check_plausible("lead", 1e6, *LEAD_RANGE)  # neither mm nor m: no guess
    assert "did you mean" not in str(info.value)
