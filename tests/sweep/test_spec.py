"""The grid of designs: parsing of the axes, the designs and their keys, the tidy table."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.sweep.spec import (
    METRIC_COLUMNS,
    PARAMETER_COLUMNS,
    SweepAxis,
    SweepSpec,
    design_key,
    parse_values,
    sweepable_names,
)
from orthoglide_pin.sweep.table import sweep_table, table_columns

#: Evenly spaced values against numpy's linspace (after the 12-digit rounding).
SPACING_TOL = 1e-12

#: The key of the prototype's one design (schema 2), as stored by earlier sweeps.
PROTOTYPE_KEY = "a062e2e37dd0636c"


def test_range_values_are_evenly_spaced_with_both_ends() -> None:
    values = parse_values("0.25:0.45:21")
    assert len(values) == 21
    assert values[0] == 0.25 and values[-1] == 0.45
    assert values[8] == 0.33  # rounded: no 0.33000000000000002
    assert np.allclose(values, np.linspace(0.25, 0.45, 21), rtol=0.0, atol=SPACING_TOL)
    assert np.allclose(np.diff(values), 0.01, rtol=0.0, atol=SPACING_TOL)


def test_lists_and_single_values() -> None:
    assert parse_values("0.3, 0.31,0.35") == (0.3, 0.31, 0.35)
    assert parse_values("0.31") == (0.31,)
    assert parse_values("0.31:0.31:1") == (0.31,)


@pytest.mark.parametrize(
    "text",
    ["0.2:0.4", "0.2:0.4:0", "0.2:0.4:1", "0.2:0.4:x", "a,b", "", "nan", "0.3,0.3", "1:2:3:4"],
)
def test_bad_values_are_refused(text: str) -> None:
    with pytest.raises(og.InvalidParameterError, match="expected"):
        parse_values(text, "leg_length")


def test_axis_names() -> None:
    names = sweepable_names()
    assert names[0] == "leg_length"
    for name in ("psi_min", "psi_max", "cube_side", "speed", "acceleration", "bar_radius"):
        assert name in names
    for name in ("slider_lower", "slider_upper", "tool_offset", "carriage_size"):
        assert name not in names
    axis = SweepAxis.parse("parallelogram_width=0.06,0.08")
    assert axis == SweepAxis("parallelogram_width", (0.06, 0.08))
    with pytest.raises(og.InvalidParameterError, match="slider_lower"):
        SweepAxis.parse("slider_lower=-0.1,-0.05")
    with pytest.raises(og.InvalidParameterError, match="NAME=START:STOP:N"):
        SweepAxis.parse("0.25:0.45:21")


def test_spec_is_validated() -> None:
    with pytest.raises(og.InvalidParameterError, match="mode"):
        SweepSpec(mode="other")
    with pytest.raises(og.InvalidParameterError, match="each axis given once"):
        SweepSpec(axes=(SweepAxis("psi_max", (2.0,)), SweepAxis("psi_max", (3.0,))))
    with pytest.raises(og.InvalidParameterError, match="not both"):
        SweepSpec(
            axes=(SweepAxis("leg_length", (0.3,)), SweepAxis("cube_side", (0.2,))),
            mode="redesign",
        )
    with pytest.raises(og.InvalidParameterError, match="grid"):
        SweepSpec(grid=1)
    with pytest.raises(og.InvalidParameterError, match="cube_corner"):
        SweepSpec(cube_corner=(0.0, 0.0))  # type: ignore[arg-type]


def test_designs_are_the_product_first_axis_slowest() -> None:
    spec = SweepSpec(
        axes=(SweepAxis.parse("leg_length=0.3,0.31,0.32"), SweepAxis.parse("psi_max=2,3"))
    )
    designs = spec.designs()
    assert len(designs) == len(spec) == 6
    got = [(d["leg_length"], d["psi_max"]) for d in designs]
    assert got == [(L, p) for L in (0.3, 0.31, 0.32) for p in (2.0, 3.0)]
    for d in designs:
        assert d["cube_corner"] == [CUBE_CORNER] * 3
        assert d["cube_side"] == CUBE_SIDE
        assert "slider_lower" not in d["params"] and "leg_length" not in d["params"]
        json.dumps(d)  # plain data, ready for a worker and a hash


def test_redesign_derives_one_of_leg_and_cube() -> None:
    from_side = SweepSpec(axes=(SweepAxis.parse("psi_max=2,3"),), mode="redesign").designs()
    assert all(d["leg_length"] is None and d["cube_side"] == CUBE_SIDE for d in from_side)
    assert all(d["cube_corner"] is None for d in from_side)
    from_leg = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3,0.31"),), mode="redesign")
    assert all("cube_side" not in d for d in from_leg.designs())


def test_a_parameter_axis_reaches_the_parameters() -> None:
    spec = SweepSpec(axes=(SweepAxis.parse("parallelogram_width=0.06,0.1"),))
    widths = [d["params"]["parallelogram_width"] for d in spec.designs()]
    assert widths == [0.06, 0.1]
    assert all(d["leg_length"] == PROTOTYPE_LEG for d in spec.designs())


def test_keys_are_stable_and_tell_designs_apart() -> None:
    spec = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3:0.32:3"),))
    keys = [design_key(d) for d in spec.designs()]
    again = [design_key(d) for d in SweepSpec(axes=spec.axes).designs()]
    assert keys == again
    assert len(set(keys)) == 3
    assert all(len(k) == 16 and int(k, 16) >= 0 for k in keys)
    design = spec.designs()[0]
    for change in ({"grid": 51}, {"speed": 1.0}, {"requirement_grid": 7}):
        assert design_key({**design, **change}) != keys[0]
    params = {**design["params"], "density": 7800.0}
    assert design_key({**design, "params": params}) != keys[0]
    reordered = dict(reversed(list(design.items())))
    assert design_key(reordered) == keys[0]


def test_table_columns_and_types() -> None:
    columns = table_columns(["leg_length", "bar_radius"])
    assert columns[:4] == ["key", "status", "error", "mode"]
    assert columns[4 : 4 + len(PARAMETER_COLUMNS)] == list(PARAMETER_COLUMNS)
    assert columns.count("leg_length") == 1 and "bar_radius" in columns
    assert columns[-len(METRIC_COLUMNS) :] == list(METRIC_COLUMNS)
    rows = [
        {"key": "a", "status": "ok", "mode": "redesign", "leg_length": 0.31, "bounds_hold": True},
        {"key": "b", "status": "invalid", "error": "too short", "leg_length": 0.1},
    ]
    table = sweep_table(rows, ["leg_length"])
    assert list(table.columns) == table_columns(["leg_length"])
    assert table["bounds_hold"].dtype == "boolean"
    assert table["bounds_hold"].isna().tolist() == [False, True]
    assert table["stroke"].dtype == np.float64 and table["stroke"].isna().all()
    assert table["error"].tolist() == ["", "too short"]
    assert isinstance(table, pd.DataFrame) and len(table) == 2
    assert math.isnan(table.loc[1, "psi_max"])


def test_the_criterion_comes_from_the_base_machine() -> None:
    # the prototype's bounds by default; a design's own when it is the base
    assert (SweepSpec().psi_min, SweepSpec().psi_max) == (0.5, 2.0)
    base = og.prototype().replace(leg_length=0.34, psi_min=0.4, psi_max=2.5)
    spec = SweepSpec(base=base)
    assert (spec.psi_min, spec.psi_max) == (0.4, 2.5)
    (design,) = spec.designs()
    assert (design["psi_min"], design["psi_max"]) == (0.4, 2.5)
    assert "psi_min" not in design["params"]  # a setting, not a parameter of the design
    # given settings and axes win over the base's
    assert SweepSpec(base=base, psi_max=3.0).designs()[0]["psi_max"] == 3.0
    axis = SweepAxis.parse("psi_max=2,3")
    assert [d["psi_max"] for d in SweepSpec(base=base, axes=(axis,)).designs()] == [2.0, 3.0]
    assert sweepable_names().count("psi_min") == 1  # a setting, listed once
    # the prototype's design keeps the key it had before the machine carried its
    # criterion (the bounds were settings already): earlier sweeps' parts still count
    assert design_key(SweepSpec().designs()[0]) == PROTOTYPE_KEY
    assert design_key(SweepSpec(psi_min=0.5, psi_max=2.0).designs()[0]) == PROTOTYPE_KEY
