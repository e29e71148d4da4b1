"""Plots of a sweep: each metric against a swept parameter, the paper's prototype marked.

:func:`sweep_figure` draws one panel per metric of a table of
:func:`~orthoglide_pin.sweep.runner.run_sweep`, the metric against the swept
parameter ``x`` (valid designs only), one line per value of the ``group``
columns (the other axes). The paper's prototype is marked in every panel by a
vertical dotted line at its value of ``x`` (``leg_length`` 0.31 m, ``psi_min``
0.5, ``psi_max`` 2, ``cube_side`` 0.2 m, the speed and acceleration 1.2 m/s and
20 m/s^2, or the prototype's parameter), and, when ``x`` is the leg length, by
stars at its published figures (stroke 0.257 m, ratio 0.78; paper, section 4).
Axes are labelled in words with their units (:func:`label`: ``condition_std``
reads "spread of the condition number [-]"). :func:`plot_sweep` writes the
figure as PNG, atomically.
matplotlib draws on its Agg canvas, leaving pyplot's global state alone; the
figure shows itself as an image in a notebook
(:func:`~orthoglide_pin.kinetostatics.plotting.new_figure`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from orthoglide_pin._lazy import optional_import
from orthoglide_pin._validation import instance_of, integer, name_list, path_argument, text
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.plotting import MAX_DPI, new_figure, save_png
from orthoglide_pin.machine.params import PROTOTYPE_LEG_LENGTH, PROTOTYPE_WORKSPACE_SIDE, prototype
from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES
from orthoglide_pin.sweep.spec import DEFAULT_ACCELERATION, DEFAULT_SPEED, METRIC_COLUMNS

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

#: Metrics drawn by default: compactness, homogeneity, mass, requirements, size.
DEFAULT_METRICS: Final = (
    "stroke",
    "ratio",
    "design_cube_side",
    "psi_min_reached",
    "psi_max_reached",
    "condition_max",
    "condition_std",
    "moving_mass",
    "max_slider_force",
    "max_motor_torque",
    "footprint_area",
    "in_bounds_fraction",
    "min_stiffness",
    "max_deflection",
)
#: SI unit of each column, for the axis labels ("" for a pure number).
UNITS: Final = {
    **{c: "m" for c in ("stroke", "slider_lower", "slider_upper", "design_cube_side")},
    **{c: "m" for c in ("leg_length", "cube_side", "footprint_x", "footprint_y", "footprint_z")},
    **{f"cube_corner_{a}": "m" for a in "xyz"},
    "footprint_area": "m^2",
    "footprint_volume": "m^3",
    "moving_mass": "kg",
    "max_slider_force": "N",
    "max_motor_torque": "N.m",
    "min_stiffness": "N/m",
    "centre_stiffness": "N/m",
    "max_deflection": "m",
    "speed": "m/s",
    "acceleration": "m/s^2",
}
#: Words for each column of a sweep table, for the axis labels (units apart);
#: short enough for a panel's height. Factors, conditions and shares are over
#: the design's cube (see :mod:`~orthoglide_pin.sweep.metrics`).
WORDS: Final = {
    "leg_length": "leg length",
    "cube_side": "cube side",
    **{f"cube_corner_{a}": f"corner Q1 of the cube, {a}" for a in "xyz"},
    "psi_min": "lower bound of the transmission factors",
    "psi_max": "upper bound of the transmission factors",
    "speed": "required tool speed",
    "acceleration": "required acceleration",
    "slider_lower": "lower slider limit",
    "slider_upper": "upper slider limit",
    "stroke": "slider stroke",
    "ratio": "cube side over stroke",
    "design_cube_side": "largest certified cube side",
    "psi_min_reached": "smallest factor over the cube",
    "psi_max_reached": "largest factor over the cube",
    "bounds_hold": "factors within bounds (1: yes)",
    "in_bounds_fraction": "share of the cube in bounds",
    "condition_min": "smallest condition number",
    "condition_max": "largest condition number",
    "condition_mean": "mean condition number",
    "condition_std": "spread of the condition number",
    "moving_mass": "moving mass",
    "max_slider_force": "worst-case slider force",
    "max_motor_torque": "worst-case motor torque",
    "footprint_x": "machine size along x",
    "footprint_y": "machine size along y",
    "footprint_z": "machine size along z",
    "footprint_area": "floor area",
    "footprint_volume": "bounding-box volume",
    "min_stiffness": "worst tool stiffness",
    "centre_stiffness": "tool stiffness at the centre",
    "max_deflection": "worst deflection, 100 N",
}
#: Metrics drawn on a logarithmic scale when they span more than a decade.
LOG_METRICS: Final = frozenset(
    {"psi_max_reached", "condition_max", "condition_std", "max_slider_force", "max_motor_torque"}
)
#: The paper's published figures of the prototype (section 4), by metric.
PAPER_FIGURES: Final = {"stroke": 0.257, "ratio": 0.78}
_SETTING_VALUES: Final = {
    "leg_length": PROTOTYPE_LEG_LENGTH,
    "cube_side": PROTOTYPE_WORKSPACE_SIDE,
    "psi_min": 0.5,
    "psi_max": 2.0,
    "speed": DEFAULT_SPEED,
    "acceleration": DEFAULT_ACCELERATION,
}


def prototype_value(name: str) -> float | None:
    """The paper's prototype's value of a swept quantity, or ``None`` if it has none."""
    if name in _SETTING_VALUES:
        return _SETTING_VALUES[name]
    value = prototype().to_dict().get(name)
    return float(value) if isinstance(value, (int, float)) else None


def _unit(name: str) -> str:
    """SI unit of a column ("-" for a pure number)."""
    if name in UNITS:
        return UNITS[name]
    if name in WORDS:
        return "-"
    return PLAUSIBLE_RANGES[name][2] if name in PLAUSIBLE_RANGES else "-"


def words(name: str) -> str:
    """A column's name in words, without its unit (``"moving mass"``)."""
    return WORDS.get(name, name.replace("_", " "))


def label(name: str) -> str:
    """An axis label: the column in words and its unit (``"moving mass [kg]"``)."""
    return f"{words(name)} [{_unit(name)}]"


def sweep_figure(
    table: pd.DataFrame,
    x: str = "leg_length",
    metrics: Sequence[str] = DEFAULT_METRICS,
    *,
    group: Sequence[str] = (),
    columns: int = 3,
    title: str | None = None,
) -> Figure:
    """One panel per metric against ``x``, the prototype marked (see the module).

    Args:
        table: A sweep table (:func:`~orthoglide_pin.sweep.spec.sweep_table`).
        x: The swept column on the horizontal axis.
        metrics: Metric columns, one panel each.
        group: Columns whose values each get their own line (the other axes).
        columns: Panels per row.
        title: Figure title.

    Returns:
        The figure (Agg canvas).

    Raises:
        InvalidParameterError: An unknown column, or no metric.
    """
    pd = optional_import("pandas", "tables", "a sweep's plots")
    instance_of("table", table, pd.DataFrame, "a sweep table (a pandas DataFrame)")
    x, metrics, group = text("x", x), name_list("metrics", metrics), name_list("group", group)
    for argument, name in (
        ("x", x),
        *(("metrics", m) for m in metrics),
        *(("group", g) for g in group),
    ):
        if name not in table.columns:
            allowed = "a column of the table: " + ", ".join(table.columns)
            raise InvalidParameterError(argument, name, allowed)
    unknown = [m for m in metrics if m not in METRIC_COLUMNS]
    if unknown or not metrics:
        raise InvalidParameterError("metrics", list(metrics), "metric columns of the table")
    columns = integer("columns", columns)
    if title is not None:
        text("title", title, "a title (str) or None")
    ok = table[table["status"] == "ok"].sort_values(x, kind="stable")
    groups = list(ok.groupby(list(group), sort=True)) if group else [((), ok)]
    ncols = min(columns, len(metrics))
    nrows = math.ceil(len(metrics) / ncols)
    fig = new_figure(4.4 * ncols, 3.3 * nrows, layout="constrained")
    mark = prototype_value(x)
    for k, metric in enumerate(metrics):
        ax = fig.add_subplot(nrows, ncols, k + 1)
        for values, rows in groups:
            items = values if isinstance(values, tuple) else (values,)
            legend = ", ".join(_setting(g, v) for g, v in zip(group, items, strict=True))
            ax.plot(rows[x], rows[metric], marker=".", label=legend or None)
        if mark is not None:
            ax.axvline(mark, color="0.3", linestyle=":", label="paper's prototype")
        if mark is not None and x == "leg_length" and metric in PAPER_FIGURES:
            ax.plot(mark, PAPER_FIGURES[metric], "*", color="red", markersize=10, label="paper")
        values = ok[metric].to_numpy(dtype=float)
        values = values[np.isfinite(values) & (values > 0.0)]
        if metric in LOG_METRICS and values.size and values.max() > 10.0 * values.min():
            ax.set_yscale("log")
        ax.set_xlabel(label(x))
        ax.set_ylabel(label(metric))
        ax.grid(True, alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    fig.suptitle(title or f"Sweep of the {words(x)}: {len(ok)} valid designs of {len(table)}")
    return fig


def _setting(name: str, value: float) -> str:
    """``"upper bound of the transmission factors 2"``, ``"leg length 0.31 m"``."""
    unit = _unit(name)
    return f"{words(name)} {value:.4g}" + ("" if unit == "-" else f" {unit}")


def plot_sweep(
    table: pd.DataFrame,
    path: str | Path,
    x: str = "leg_length",
    metrics: Sequence[str] = DEFAULT_METRICS,
    *,
    dpi: int = 100,
    **kwargs: Any,
) -> Path:
    """Write :func:`sweep_figure` to ``path`` as PNG, atomically; return the path.

    Args:
        table: A sweep table.
        path: Output PNG file.
        x: The swept column on the horizontal axis.
        metrics: Metric columns, one panel each.
        dpi: Resolution [dots per inch].
        **kwargs: ``group``, ``columns``, ``title`` of :func:`sweep_figure`.
    """
    path_argument("path", path)
    integer("dpi", dpi, 1, MAX_DPI)
    return save_png(sweep_figure(table, x, metrics, **kwargs), path, dpi)


__all__ = [
    "DEFAULT_METRICS",
    "PAPER_FIGURES",
    "WORDS",
    "label",
    "plot_sweep",
    "prototype_value",
    "sweep_figure",
    "words",
]
