"""Plots of a sweep: each metric against a swept parameter, the base design marked.

:func:`sweep_figure` draws one panel per metric of a table of
:func:`~orthoglide_pin.sweep.runner.run_sweep`, the metric against the swept
parameter ``x`` (valid designs only), one line per value of the ``group``
columns (the other axes). Given the sweep's spec, the design it starts from
(its base machine and settings, :func:`design_value`) is marked in every panel
by a vertical dotted line at its value of ``x``, labelled "base design"; when
the sweep is of the paper's prototype (:func:`of_prototype`) the line reads
"paper's prototype" and, when ``x`` is the leg length, stars mark its
published figures (stroke 257 mm, ratio 0.78; paper, section 4). Without a
spec nothing is marked.

Values are drawn in the report's units (:mod:`~orthoglide_pin.sweep.labels`):
lengths in mm, stiffnesses in N/um, deflections in um; axes are labelled in
words with those units (:func:`label`: ``condition_std`` reads "spread of the
condition number [-]", ``stroke`` "slider stroke [mm]"). :func:`plot_sweep`
writes the figure as PNG, atomically. matplotlib draws on its Agg canvas,
leaving pyplot's global state alone; the figure shows itself as an image in a
notebook (:func:`~orthoglide_pin.kinetostatics.plotting.new_figure`).
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
from orthoglide_pin.kinetostatics.certify import PAPER_BOUNDS
from orthoglide_pin.kinetostatics.plotting import MAX_DPI, new_figure, save_png
from orthoglide_pin.machine.params import prototype
from orthoglide_pin.sweep.accuracy import ACCURACY_COLUMNS
from orthoglide_pin.sweep.labels import WORDS, display_unit, label, setting, words
from orthoglide_pin.sweep.spec import (
    DEFAULT_ACCELERATION,
    DEFAULT_SPEED,
    METRIC_COLUMNS,
    SETTINGS,
    SweepSpec,
)

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
#: Metrics drawn on a logarithmic scale when they span more than a decade.
LOG_METRICS: Final = frozenset(
    {"psi_max_reached", "condition_max", "condition_std", "max_slider_force", "max_motor_torque"}
)
#: The paper's published figures of the prototype (section 4), by metric.
PAPER_FIGURES: Final = {"stroke": 0.257, "ratio": 0.78}
#: The sweep's base design is marked with this label, or with
#: :data:`PROTOTYPE_LABEL` when the sweep is of the paper's prototype.
DESIGN_LABEL: Final = "base design"
PROTOTYPE_LABEL: Final = "paper's prototype"


def of_prototype(spec: SweepSpec) -> bool:
    """Whether a sweep is of the paper's prototype.

    Its base machine is :func:`~orthoglide_pin.machine.params.prototype`, its
    cube the prototype's 200 mm cube, its bounds the paper's [0.5, 2] and its
    requirement the paper's 1.2 m/s and 20 m/s^2 (section 4).
    """
    paper = prototype()
    return (
        spec.base == paper
        and spec.cube() == paper.workspace
        and (spec.psi_min, spec.psi_max) == PAPER_BOUNDS
        and (spec.speed, spec.acceleration) == (DEFAULT_SPEED, DEFAULT_ACCELERATION)
    )


def design_value(spec: SweepSpec, name: str) -> float | None:
    """The base design's value of a column [SI], or ``None`` if it has none.

    The settings (``psi_min``, ``psi_max``, ``cube_side``, ``speed``,
    ``acceleration``) and the cube's corner come from the spec, the machine
    parameters from its base machine; metrics and derived quantities have none.
    """
    if name in SETTINGS:
        return float(getattr(spec, name))
    if name.startswith("cube_corner_") and name[-1] in "xyz":
        return float(spec.corner()["xyz".index(name[-1])])
    value = spec.base.to_dict().get(name)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def sweep_figure(
    table: pd.DataFrame,
    x: str = "leg_length",
    metrics: Sequence[str] = DEFAULT_METRICS,
    *,
    group: Sequence[str] = (),
    columns: int = 3,
    title: str | None = None,
    spec: SweepSpec | None = None,
) -> Figure:
    """One panel per metric against ``x``, the base design marked (see the module).

    Args:
        table: A sweep table (:func:`~orthoglide_pin.sweep.table.sweep_table`).
        x: The swept column on the horizontal axis.
        metrics: Metric columns, one panel each.
        group: Columns whose values each get their own line (the other axes).
        columns: Panels per row.
        title: Figure title.
        spec: The sweep's spec, whose base design is marked; ``None``: no mark.

    Returns:
        The figure (Agg canvas).

    Raises:
        InvalidParameterError: An unknown column, no metric, or a spec that
            is not a :class:`~orthoglide_pin.sweep.spec.SweepSpec`.
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
    unknown = [m for m in metrics if m not in (*METRIC_COLUMNS, "cycle_time", *ACCURACY_COLUMNS)]
    if unknown or not metrics:
        raise InvalidParameterError("metrics", list(metrics), "metric columns of the table")
    columns = integer("columns", columns)
    if title is not None:
        text("title", title, "a title (str) or None")
    if spec is not None:
        instance_of("spec", spec, SweepSpec, "a SweepSpec or None")
    ok = table[table["status"] == "ok"].sort_values(x, kind="stable")
    groups = list(ok.groupby(list(group), sort=True)) if group else [((), ok)]
    ncols = min(columns, len(metrics))
    nrows = math.ceil(len(metrics) / ncols)
    fig = new_figure(4.4 * ncols, 3.3 * nrows, layout="constrained")
    mark = None if spec is None else design_value(spec, x)
    paper = spec is not None and of_prototype(spec)
    sx = display_unit(x)[0]
    for k, metric in enumerate(metrics):
        ax = fig.add_subplot(nrows, ncols, k + 1)
        sm = display_unit(metric)[0]
        for values, rows in groups:
            items = values if isinstance(values, tuple) else (values,)
            legend = ", ".join(setting(g, v) for g, v in zip(group, items, strict=True))
            ax.plot(sx * rows[x], sm * rows[metric], marker=".", label=legend or None)
        if mark is not None:
            name = PROTOTYPE_LABEL if paper else DESIGN_LABEL
            ax.axvline(sx * mark, color="0.3", linestyle=":", label=name)
        if mark is not None and paper and x == "leg_length" and metric in PAPER_FIGURES:
            star = sm * PAPER_FIGURES[metric]
            ax.plot(sx * mark, star, "*", color="red", markersize=10, label="paper")
        values = ok[metric].to_numpy(dtype=float)
        values = values[np.isfinite(values) & (values > 0.0)]
        if metric in LOG_METRICS and values.size and values.max() > 10.0 * values.min():
            ax.set_yscale("log")
        ax.set_xlabel(label(x))
        ax.set_ylabel(label(metric))
        ax.grid(True, alpha=0.3)
        if k == 0 and ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.suptitle(title or f"Sweep of the {words(x)}: {len(ok)} valid designs of {len(table)}")
    return fig


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
        **kwargs: ``group``, ``columns``, ``title``, ``spec`` of :func:`sweep_figure`.
    """
    path_argument("path", path)
    integer("dpi", dpi, 1, MAX_DPI)
    return save_png(sweep_figure(table, x, metrics, **kwargs), path, dpi)


__all__ = [
    "DEFAULT_METRICS",
    "DESIGN_LABEL",
    "PAPER_FIGURES",
    "PROTOTYPE_LABEL",
    "WORDS",
    "design_value",
    "label",
    "of_prototype",
    "plot_sweep",
    "sweep_figure",
    "words",
]
