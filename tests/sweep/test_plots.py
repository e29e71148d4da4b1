"""Plots of a sweep: one panel per metric, the paper's prototype marked."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.sweep.plots import (
    DEFAULT_METRICS,
    PAPER_FIGURES,
    label,
    plot_sweep,
    prototype_value,
    sweep_figure,
)
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
GRID = 10


@pytest.fixture(scope="module")
def table(tmp_path_factory: pytest.TempPathFactory) -> pd.DataFrame:
    spec = SweepSpec(
        axes=(SweepAxis.parse("leg_length=0.2:0.4:5"), SweepAxis.parse("psi_max=2,3")),
        grid=GRID,
    )
    return og.run_sweep(spec, tmp_path_factory.mktemp("plots"), workers=1).table


def test_one_panel_per_metric_with_the_prototype_marked(table: pd.DataFrame) -> None:
    fig = sweep_figure(table, "leg_length", group=["psi_max"])
    axes = fig.axes
    assert len(axes) == len(DEFAULT_METRICS)
    for ax, metric in zip(axes, DEFAULT_METRICS, strict=True):
        assert ax.get_ylabel() == label(metric) and "_" not in ax.get_ylabel()
        assert ax.get_xlabel() == "leg length [m]"
        data = [line for line in ax.get_lines() if len(line.get_xdata()) > 2]
        assert len(data) == 2  # one line per psi_max
        for line in data:  # the valid designs only, in order
            assert line.get_xdata().tolist() == [0.25, 0.3, 0.35, 0.4]
        marks = [line for line in ax.get_lines() if line.get_label() == "paper's prototype"]
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [PROTOTYPE_LEG] * 2
    stroke = axes[DEFAULT_METRICS.index("stroke")]
    stars = [line for line in stroke.get_lines() if line.get_label() == "paper"]
    assert stars[0].get_ydata().tolist() == [PAPER_FIGURES["stroke"]]
    ok = table[(table["status"] == "ok") & (table["psi_max"] == 2.0)]
    shown = next(
        line
        for line in stroke.get_lines()
        if line.get_label() == "upper bound of the transmission factors 2"
    )
    np.testing.assert_array_equal(shown.get_ydata(), ok["stroke"])


def test_wide_ranges_go_logarithmic(table: pd.DataFrame) -> None:
    fig = sweep_figure(table, metrics=["condition_max", "ratio"])
    cond, ratio = fig.axes
    spread = table["condition_max"].max() / table["condition_max"].min()
    assert (cond.get_yscale() == "log") == (spread > 10.0)
    assert ratio.get_yscale() == "linear"


def test_prototype_values() -> None:
    assert prototype_value("leg_length") == PROTOTYPE_LEG
    assert prototype_value("psi_max") == 2.0
    assert prototype_value("parallelogram_width") == og.prototype().parallelogram_width
    assert prototype_value("bar_mass") is None  # derived: no value to mark


def test_png_is_written(table: pd.DataFrame, tmp_path: Path) -> None:
    path = plot_sweep(table, tmp_path / "sweep.png", metrics=["stroke", "ratio"])
    assert path.read_bytes().startswith(PNG_MAGIC)
    assert [p.name for p in tmp_path.iterdir()] == ["sweep.png"]  # no temporary left


@pytest.mark.parametrize(
    ("kwargs", "mentions"),
    [
        ({"x": "wheel"}, "column"),
        ({"metrics": ["key"]}, "metrics"),
        ({"metrics": []}, "metrics"),
        ({"columns": 0}, "columns"),
    ],
)
def test_bad_arguments(table: pd.DataFrame, kwargs: dict[str, object], mentions: str) -> None:
    with pytest.raises(og.InvalidParameterError, match=mentions):
        sweep_figure(table, **kwargs)  # type: ignore[arg-type]


def test_labels_are_words_with_units(table: pd.DataFrame) -> None:
    assert label("condition_std") == "spread of the condition number [-]"
    assert label("max_motor_torque") == "worst-case motor torque [N.m]"
    assert label("leg_length") == "leg length [m]"
    assert label("cube_corner_y") == "corner Q1 of the cube, y [m]"
    assert label("density") == "density [kg/m^3]"  # any machine parameter: its SI unit
    for column in table.columns:
        if column not in ("key", "status", "error", "mode"):
            text = label(column)
            assert "_" not in text and text.endswith("]"), column
    fig = sweep_figure(table, "psi_max", ["stroke"])
    assert fig.axes[0].get_xlabel() == "upper bound of the transmission factors [-]"
    assert fig._repr_png_()[:8] == PNG_MAGIC  # an image in a notebook
