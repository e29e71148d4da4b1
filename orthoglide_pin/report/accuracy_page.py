"""Part accuracy along a program as one self-contained HTML page.

:func:`accuracy_html` takes what ``orthoglide accuracy`` writes (the columns of
``accuracy.csv`` and the summary of ``accuracy.json``, as plain mappings) and
lays out the surface error, the chatter stability and the error budget, with
figures drawn with the report's machinery (matplotlib on an Agg canvas, PNG
``data:`` URIs, inline style): the part's path coloured by the surface error
as the wall is generated, the same path coloured by the stability margin of
each block, the stability lobes at the point of smallest margin with the
engaged depth and the spindle speed marked, and the surface errors over time.
A long program is plotted from at most :data:`PLOT_POINTS` samples, which keep
the extremes of the plotted columns. Lengths in mm, errors in µm, depths in
mm, spindle speeds in rpm; the JSON and CSV next to the page are in SI.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.program.axes import ProgramAxes
from orthoglide_pin.report.page import escape as _e
from orthoglide_pin.report.page import figure as _figure
from orthoglide_pin.report.page import image as _img
from orthoglide_pin.report.page import page as _page
from orthoglide_pin.report.page import png as _png
from orthoglide_pin.report.page import table as _table

#: Most samples plotted (the extremes of the plotted columns always among them).
PLOT_POINTS: Final[int] = 20_000
#: Most rows of the per-block table shown (the JSON has them all).
MAX_ROWS: Final[int] = 200
#: Range of the stability margin's colour scale [-] (logarithmic, 1 in the middle).
MARGIN_RANGE: Final = (0.1, 10.0)
_UM: Final = 1e6
_MM: Final = 1e3
_PLOTTED: Final = ("surface_error_generated", "surface_error_peak", "stability_margin")


def plot_rows(columns: Mapping[str, Any], most: int = PLOT_POINTS) -> NDArray[np.intp]:
    """Rows of about ``most`` samples at most, evenly spread, each plotted column's extremes in."""
    n = int(np.asarray(columns["t"]).size)
    if n <= most:
        return np.arange(n)
    per_bucket = 1 + 2 * len(_PLOTTED)  # its first row, each column's smallest and largest
    bucket = -(-n // (most // per_bucket))
    keep = [np.arange(0, n, bucket), np.array([n - 1])]
    starts = np.arange(0, n, bucket)
    for name in _PLOTTED:
        if name not in columns:
            continue
        values = np.nan_to_num(np.asarray(columns[name], dtype=float), nan=0.0)
        pad = np.concatenate([values, np.full(starts.size * bucket - n, values[-1])])
        table = pad.reshape(-1, bucket)
        for pick in (np.argmin(table, axis=1), np.argmax(table, axis=1)):
            keep.append(np.minimum(starts + pick, n - 1))
    return np.unique(np.concatenate(keep))


def _program_points(columns: Mapping[str, Any], axes: ProgramAxes) -> Any:
    world = np.stack([np.asarray(columns[c], dtype=float) for c in "xyz"], axis=1)
    return (_MM * axes.to_program(world)).T


def _path_figure(
    columns: Mapping[str, Any], axes: ProgramAxes, values: Any, what: str, margin: bool
) -> bytes:
    """The path in 3D and from above, cutting samples coloured by ``values``."""
    from matplotlib.colors import LogNorm

    fig = _figure(11.0, 4.6)
    cut = np.asarray(columns["cutting"]) != 0.0
    x, y, z = _program_points(columns, axes)
    style: dict[str, Any] = {"cmap": "viridis"}
    if margin:  # red where it chatters, green where it is stable
        lo, hi = MARGIN_RANGE
        values = np.clip(values, lo, hi)
        style = {"cmap": "RdYlGn", "norm": LogNorm(vmin=lo, vmax=hi)}
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot(x[~cut], y[~cut], z[~cut], ".", color="lightgrey", ms=1, label="not cutting")
    sc = ax.scatter(x[cut], y[cut], z[cut], c=values[cut], s=2, **style)
    fig.colorbar(sc, ax=ax, shrink=0.7, label=what)
    ax.set_title(what.split(" [")[0])
    ax.set_xlabel("program X [mm]")
    ax.set_ylabel("program Y [mm]")
    ax.set_zlabel("program Z [mm]")
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(x[~cut], y[~cut], ".", color="lightgrey", ms=1)
    sc2 = ax2.scatter(x[cut], y[cut], c=values[cut], s=2, **style)
    fig.colorbar(sc2, ax=ax2, label=what)
    ax2.set_aspect("equal")
    ax2.set_title("seen from above")
    ax2.set_xlabel("program X [mm]")
    ax2.set_ylabel("program Y [mm]")
    return _png(fig)


def _lobes_figure(lobes: Mapping[str, Any], rpm: float, depth_mm: float) -> bytes:
    fig = _figure(11.0, 4.0)
    ax = fig.subplots()
    speeds = np.asarray(lobes["speeds_rpm"], dtype=float)

    def mm(values: Sequence[float | None]) -> Any:
        return np.array([np.nan if v is None else v for v in values], dtype=float)

    sd = mm(lobes["limit_depth_mm"])
    ax.plot(speeds, sd, color="k", lw=1.2, label="limit (semi-discretization)")
    if lobes.get("zero_order_depth_mm") is not None:
        zo = mm(lobes["zero_order_depth_mm"])
        ax.plot(speeds, zo, color="tab:blue", ls="--", lw=0.8, label="zero-order solution")
    ax.fill_between(speeds, sd, np.nanmax(np.append(sd, depth_mm)) * 1.2, color="tab:red",
                    alpha=0.08, label="chatter")  # fmt: skip
    stable = depth_mm < float(np.interp(rpm, speeds, np.nan_to_num(sd, nan=np.inf)))
    ax.plot([rpm], [depth_mm], "o" if stable else "X", ms=9, color="tab:green" if stable
            else "tab:red", label=f"the cut: {rpm:.0f} rpm, {depth_mm:.3g} mm deep")  # fmt: skip
    ax.axvline(rpm, color="grey", lw=0.6, ls=":")
    ax.axhline(depth_mm, color="grey", lw=0.6, ls=":")
    top = np.nanmax(np.append(sd, depth_mm))
    ax.set_ylim(0.0, 1.25 * top if math.isfinite(top) and top > 0 else 1.0)
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("limiting axial depth [mm]")
    ax.legend(fontsize=7, loc="upper left")
    return _png(fig)


def _time_figure(columns: Mapping[str, Any]) -> bytes:
    fig = _figure(11.0, 5.0)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    t = np.asarray(columns["t"], dtype=float)
    cut = np.asarray(columns["cutting"]) != 0.0
    for name, colour, text in (
        ("surface_error_static", "tab:blue", "static"),
        ("surface_error_generated", "k", "as the wall is generated"),
        ("surface_error_peak", "tab:red", "peak over a revolution"),
    ):
        values = _UM * np.asarray(columns[name], dtype=float)
        ax1.plot(t, np.where(cut, values, np.nan), color=colour, lw=0.8, label=text)
    ax1.set_ylabel("surface error [µm]")
    ax1.legend(fontsize=7)
    margin = np.asarray(columns["stability_margin"], dtype=float)
    ax2.plot(t, margin, color="k", lw=0.8, label="stability margin of the block")
    ax2.axhline(1.0, color="tab:red", ls="--", lw=0.8, label="chatter below 1")
    ax2.set_yscale("log")
    ax2.set_ylabel("stability margin [-]")
    ax2.set_xlabel("time [s]")
    ax2.legend(fontsize=7)
    return _png(fig)


def _um(value: float | None) -> str:
    return "-" if value is None else f"{_UM * value:.2f} µm"


def _at(where: Mapping[str, Any] | None) -> str:
    if where is None:
        return ""
    p = ", ".join(f"{_MM * v:.1f}" for v in where["point"])
    return f" (line {where['line']}, t = {where['t']:.3f} s, ({p}) mm)"


def _budget_table(budget: Mapping[str, Any]) -> str:
    rows = [
        (term, _um(value), str(budget["dominant_count"].get(term, 0)))
        for term, value in budget["max"].items()
    ]
    rows.append(("worst case (sum of the norms)", _um(budget["worst_case_max"]), ""))
    rows.append(("root sum of squares", _um(budget["rss_max"]), ""))
    return _table(("term", "largest over the part", "cutting samples where it dominates"), rows)


def _margin_text(value: float | None) -> str:
    return "stable at any depth searched" if value is None else f"{value:.3f}"


def _block_table(summary: Mapping[str, Any]) -> str:
    margins = {b["line"]: b for b in summary["stability"]["blocks"]}
    rows, classes = [], []
    for b in summary["blocks"][:MAX_ROWS]:
        m = margins.get(b["line"])
        margin = None if m is None else m["margin"]
        rows.append(
            (
                str(b["line"]),
                str(b["samples"]),
                f"{b['force_mean']:.1f}",
                f"{b['force_peak']:.1f}",
                f"{_UM * b['surface_static']:.2f}",
                f"{_UM * b['surface_generated']:.2f}",
                f"{_UM * b['surface_peak']:.2f}",
                "-" if m is None else _margin_text(margin),
            )
        )
        classes.append("" if m is None else ("pass" if margin is None or margin > 1 else "fail"))
    header = (
        "line", "samples", "mean force [N]", "peak force [N]", "static [µm]",
        "generated [µm]", "peak [µm]", "stability margin",
    )  # fmt: skip
    more = (
        f'<p class="note">First {MAX_ROWS} of {len(summary["blocks"])} lines; the JSON lists '
        "all.</p>"
        if len(summary["blocks"]) > MAX_ROWS
        else ""
    )
    return _table(header, rows, classes) + more


def accuracy_html(
    columns: Mapping[str, Any],
    summary: Mapping[str, Any],
    axes: ProgramAxes,
    title: str,
    companions: Sequence[str],
) -> str:
    """The page of a program's accuracy (see the module).

    Args:
        columns: The columns of ``accuracy.csv`` (name -> values, SI units).
        summary: The content of ``accuracy.json``.
        axes: The program's axes on the machine (the figures are in program coordinates).
        title: The program's name.
        companions: Names of the files written next to the page.
    """
    rows = plot_rows(columns)
    shown = {k: np.asarray(v)[rows] for k, v in columns.items()}
    margin = np.nan_to_num(np.asarray(shown["stability_margin"], dtype=float), nan=1.0)
    images = {
        "error": _path_figure(
            shown, axes, _UM * np.asarray(shown["surface_error_generated"], dtype=float),
            "surface error as generated [µm]", margin=False,
        ),
        "margin": _path_figure(shown, axes, margin, "stability margin [-]", margin=True),
        "time": _time_figure(shown),
    }  # fmt: skip
    stab = summary["stability"]
    worst = stab["worst"]
    if summary.get("lobes") is not None and worst is not None:
        images["lobes"] = _lobes_figure(
            summary["lobes"], summary["spindle_speed_rpm"], 1e3 * worst["depth"]
        )
    at = summary["surface_error_at"]
    if worst is None:
        verdict = '<p class="banner none">Nothing cuts: no stability to judge.</p>'
    elif stab["unstable_blocks"]:
        verdict = (
            f'<p class="banner fail">{stab["unstable_blocks"]} of {stab["cutting_blocks"]} '
            f"cutting lines chatter: smallest margin {worst['margin']:.3f}.</p>"
        )
    else:
        verdict = (
            f'<p class="banner pass">Every cutting line is stable: smallest margin '
            f"{_margin_text(worst['margin'])}.</p>"
        )
    text = (
        f"<p>{summary['cutting_samples']} of {summary['samples']} samples cut "
        f"({summary['material']['name']}, {summary['spindle_speed_rpm']:.0f} rpm). Surface "
        f"error (positive: material left on the wall): static "
        f"<b>{_um(summary['surface_error_static_max'])}</b>{_e(_at(at['static']))}, as the "
        f"wall is generated <b>{_um(summary['surface_error_generated_max'])}</b>"
        f"{_e(_at(at['generated']))}, peak over a revolution "
        f"<b>{_um(summary['surface_error_peak_max'])}</b>{_e(_at(at['peak']))}. "
        f"Largest mean force {summary['force_mean_max']:.1f} N, "
        f"peak {summary['force_peak_max']:.1f} N.</p>"
    )
    lobes_text = ""
    if worst is not None:
        p = ", ".join(f"{_MM * v:.1f}" for v in worst["point"])
        limit = worst["limit"]
        lobes_text = (
            f"<p>At the point of smallest margin, line {worst['line']}, ({_e(p)}) mm: the "
            f"limiting depth at {summary['spindle_speed_rpm']:.0f} rpm is "
            + ("beyond the depths searched" if limit is None else f"{_MM * limit:.3f} mm")
            + f" for {_MM * worst['depth']:.3f} mm engaged. "
            f"{stab['points_per_block']} points per line were computed.</p>"
        )
    sections = [
        ("Surface error and stability", verdict + text),
        ("Surface error along the path", _img(images, "error", "path by surface error")),
        ("Stability margin along the path", _img(images, "margin", "path by stability margin")),
        ("Lobes at the point of smallest margin", lobes_text + _img(images, "lobes", "lobes")),
        ("Surface error and margin over time", _img(images, "time", "errors over time")),
        ("Error budget", _budget_table(summary["budget"])),
        ("By program line", _block_table(summary)),
        (
            "Files",
            f'<p class="note">Every number in SI units: {_e(", ".join(companions))} '
            "(next to this file).</p>",
        ),
    ]
    subtitle = (
        "The planned program cut with the cut file's tool, material and engagement: "
        "milling forces from the planned feed, the tool's deflection from the stiffness "
        "model, chatter stability with the machine's modes where the tool is."
    )
    return _page(f"Part accuracy of {title}", _e(subtitle), sections)
