"""Plots of a sweep: one panel per metric in the report's units, the base design marked."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.sweep.plots import (
    DEFAULT_METRICS,
    DESIGN_LABEL,
    PAPER_FIGURES,
    PROTOTYPE_LABEL,
    design_value,
    label,
    of_prototype,
    plot_sweep,
    sweep_figure,
)
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
GRID = 10
MM = 1e3
#: The user's design of these tests: longer legs and thicker bars than the prototype.
USER_LEG = 0.35
USER_BAR_RADIUS = 0.012


@pytest.fixture(scope="module")
def spec() -> SweepSpec:
    return SweepSpec(
        axes=(SweepAxis.parse("leg_length=0.2:0.4:5"), SweepAxis.parse("psi_max=2,3")),
        grid=GRID,
    )


@pytest.fixture(scope="module")
def table(spec: SweepSpec, tmp_path_factory: pytest.TempPathFactory) -> pd.DataFrame:
    return og.run_sweep(spec, tmp_path_factory.mktemp("plots"), workers=1).table


@pytest.fixture(scope="module")
def user_spec() -> SweepSpec:
    base = og.prototype().replace(
        leg_length=USER_LEG, bar_radius=USER_BAR_RADIUS, slider_lower=None, slider_upper=None
    )
    return SweepSpec(axes=(SweepAxis.parse("leg_length=0.33,0.37"),), base=base, grid=GRID)


@pytest.fixture(scope="module")
def user_table(user_spec: SweepSpec, tmp_path_factory: pytest.TempPathFactory) -> pd.DataFrame:
    return og.run_sweep(user_spec, tmp_path_factory.mktemp("user"), workers=1).table


def _lines(ax: object, name: str) -> list[object]:
    return [line for line in ax.get_lines() if line.get_label() == name]  # type: ignore[attr-defined]


def test_one_panel_per_metric_with_the_prototype_marked(
    table: pd.DataFrame, spec: SweepSpec
) -> None:
    assert of_prototype(spec)
    fig = sweep_figure(table, "leg_length", group=["psi_max"], spec=spec)
    axes = fig.axes
    assert len(axes) == len(DEFAULT_METRICS)
    for ax, metric in zip(axes, DEFAULT_METRICS, strict=True):
        assert ax.get_ylabel() == label(metric) and "_" not in ax.get_ylabel()
        assert ax.get_xlabel() == "leg length [mm]"
        data = [line for line in ax.get_lines() if len(line.get_xdata()) > 2]
        assert len(data) == 2  # one line per psi_max
        for line in data:  # the valid designs only, in order, in mm
            assert line.get_xdata().tolist() == [250.0, 300.0, 350.0, 400.0]
        marks = _lines(ax, PROTOTYPE_LABEL)
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [MM * PROTOTYPE_LEG] * 2
        assert _lines(ax, DESIGN_LABEL) == []
    stroke = axes[DEFAULT_METRICS.index("stroke")]
    stars = _lines(stroke, "paper")
    assert stars[0].get_ydata().tolist() == [MM * PAPER_FIGURES["stroke"]]
    ok = table[(table["status"] == "ok") & (table["psi_max"] == 2.0)]
    shown = _lines(stroke, "upper bound of the transmission factors 2")[0]
    np.testing.assert_allclose(shown.get_ydata(), MM * ok["stroke"], rtol=1e-15)


def test_metrics_are_drawn_in_the_report_units(table: pd.DataFrame, spec: SweepSpec) -> None:
    metrics = ["min_stiffness", "max_deflection", "footprint_x", "moving_mass"]
    fig = sweep_figure(table, "leg_length", metrics, group=["psi_max"], spec=spec)
    ok = table[(table["status"] == "ok") & (table["psi_max"] == 3.0)]
    expected = {
        "min_stiffness": (ok["min_stiffness"] / 1e6, "worst tool stiffness [N/um]"),
        "max_deflection": (ok["max_deflection"] * 1e6, "worst deflection, 100 N [um]"),
        "footprint_x": (ok["footprint_x"] * MM, "machine size along x [mm]"),
        "moving_mass": (ok["moving_mass"], "moving mass [kg]"),
    }
    for ax, metric in zip(fig.axes, metrics, strict=True):
        values, text = expected[metric]
        assert ax.get_ylabel() == text
        line = _lines(ax, "upper bound of the transmission factors 3")[0]
        np.testing.assert_allclose(line.get_ydata(), values, rtol=1e-15)
    # Plausible magnitudes in those units: tenths of N/um, hundreds of um, metres as mm.
    assert 0.01 < expected["min_stiffness"][0].min() < 10.0
    assert 10.0 < expected["max_deflection"][0].max() < 1e4
    assert expected["footprint_x"][0].min() > 100.0


def test_the_users_design_is_marked_not_the_prototype(
    user_table: pd.DataFrame, user_spec: SweepSpec
) -> None:
    assert not of_prototype(user_spec)
    fig = sweep_figure(user_table, "leg_length", ["stroke", "ratio"], spec=user_spec)
    for ax in fig.axes:
        marks = _lines(ax, DESIGN_LABEL)
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [MM * USER_LEG] * 2
        assert _lines(ax, PROTOTYPE_LABEL) == [] and _lines(ax, "paper") == []
        assert ax.get_lines()[0].get_xdata().tolist() == [330.0, 370.0]


def test_the_prototype_with_other_bounds_is_a_design_of_its_own(table: pd.DataFrame) -> None:
    other = SweepSpec(axes=(SweepAxis.parse("psi_max=2,3"),), psi_min=0.4, grid=GRID)
    assert not of_prototype(other)
    fig = sweep_figure(table, "psi_max", ["stroke"], group=["leg_length"], spec=other)
    marks = _lines(fig.axes[0], DESIGN_LABEL)
    assert len(marks) == 1 and list(marks[0].get_xdata()) == [other.psi_max] * 2
    legs = sweep_figure(table, "leg_length", ["stroke"], group=["psi_max"], spec=other)
    assert _lines(legs.axes[0], "paper") == []  # no published figures for other bounds
    assert list(_lines(legs.axes[0], DESIGN_LABEL)[0].get_xdata()) == [MM * PROTOTYPE_LEG] * 2


def test_without_a_spec_nothing_is_marked(table: pd.DataFrame) -> None:
    fig = sweep_figure(table, "leg_length", ["stroke"], group=["psi_max"])
    names = {line.get_label() for line in fig.axes[0].get_lines()}
    assert not names & {DESIGN_LABEL, PROTOTYPE_LABEL, "paper"}


def test_design_values(spec: SweepSpec, user_spec: SweepSpec) -> None:
    assert design_value(spec, "leg_length") == PROTOTYPE_LEG
    assert design_value(user_spec, "leg_length") == USER_LEG
    assert design_value(user_spec, "bar_radius") == USER_BAR_RADIUS
    assert design_value(spec, "psi_max") == 2.0
    assert design_value(spec, "cube_side") == og.prototype().workspace_side
    assert design_value(spec, "cube_corner_y") == spec.corner()[1]
    assert design_value(spec, "parallelogram_width") == og.prototype().parallelogram_width
    assert design_value(spec, "bar_mass") is None  # derived: no value to mark
    assert design_value(spec, "stroke") is None  # a metric


def test_wide_ranges_go_logarithmic(table: pd.DataFrame) -> None:
    fig = sweep_figure(table, metrics=["condition_max", "ratio"])
    cond, ratio = fig.axes
    spread = table["condition_max"].max() / table["condition_max"].min()
    assert (cond.get_yscale() == "log") == (spread > 10.0)
    assert ratio.get_yscale() == "linear"


def test_png_is_written(table: pd.DataFrame, spec: SweepSpec, tmp_path: Path) -> None:
    path = plot_sweep(table, tmp_path / "sweep.png", metrics=["stroke", "ratio"], spec=spec)
    assert path.read_bytes().startswith(PNG_MAGIC)
    assert [p.name for p in tmp_path.iterdir()] == ["sweep.png"]  # no temporary left


@pytest.mark.parametrize(
    ("kwargs", "mentions"),
    [
        ({"x": "wheel"}, "column"),
        ({"metrics": ["key"]}, "metrics"),
        ({"metrics": []}, "metrics"),
        ({"columns": 0}, "columns"),
        ({"spec": og.prototype()}, "spec"),
    ],
)
def test_bad_arguments(table: pd.DataFrame, kwargs: dict[str, object], mentions: str) -> None:
    with pytest.raises(og.InvalidParameterError, match=mentions):
        sweep_figure(table, **kwargs)  # type: ignore[arg-type]


def test_labels_are_words_with_units(table: pd.DataFrame) -> None:
    assert label("condition_std") == "spread of the condition number [-]"
    assert label("max_motor_torque") == "worst-case motor torque [N.m]"
    assert label("leg_length") == "leg length [mm]"
    assert label("cube_corner_y") == "corner Q1 of the cube, y [mm]"
    assert label("density") == "density [kg/m^3]"  # any machine parameter: its unit
    for column in table.columns:
        if column not in ("key", "status", "error", "mode"):
            text = label(column)
            assert "_" not in text and text.endswith("]"), column
    fig = sweep_figure(table, "psi_max", ["stroke"])
    assert fig.axes[0].get_xlabel() == "upper bound of the transmission factors [-]"
    assert fig._repr_png_()[:8] == PNG_MAGIC  # an image in a notebook
