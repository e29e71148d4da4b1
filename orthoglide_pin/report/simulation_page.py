"""A simulated run of a part program as one self-contained HTML page.

:func:`simulation_html` takes what ``orthoglide simulate`` writes (the columns
of ``simulation.csv`` and the JSON summary, as plain mappings: the page needs
nothing from the simulation layer) and lays out the contour and tracking
errors, the saturation of the motors, and three figures drawn with the
report's machinery (matplotlib on an Agg canvas, PNG ``data:`` URIs, inline
style): the tool path coloured by the contour error, the errors over time, and
the motor torques against the torque available. Lengths in µm or mm, the rest SI.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Final

import numpy as np

from orthoglide_pin.program.axes import design_axes
from orthoglide_pin.report.page import escape as _e
from orthoglide_pin.report.page import figure as _figure
from orthoglide_pin.report.page import image as _img
from orthoglide_pin.report.page import page as _page
from orthoglide_pin.report.page import png as _png
from orthoglide_pin.report.page import table as _table
from orthoglide_pin.report.units import DISPLAY, quantity

_MM: Final = DISPLAY["length"][1]
_UM: Final = DISPLAY["error"][1]
_COLOURS: Final = ("tab:red", "tab:green", "tab:blue")


def _cutting(columns: Mapping[str, Any]) -> Any:
    """Whether each period cuts: the ``cutting`` column, else not a rapid move (older files)."""
    if "cutting" in columns:
        return np.asarray(columns["cutting"]) != 0.0
    return np.asarray(columns["rapid"]) == 0.0


def _path_figure(columns: Mapping[str, Any]) -> bytes:
    fig = _figure(11.0, 4.6)
    feed = _cutting(columns)
    err = _UM * np.asarray(columns["contour_error"])
    # drawn in the program's axes: Z up, the table below, "from above" along -Z
    world = np.stack([np.asarray(columns[c], dtype=float) for c in "xyz"], axis=1)
    x, y, z = (_MM * design_axes().to_program(world)).T
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot(x[~feed], y[~feed], z[~feed], ".", color="lightgrey", ms=1, label="not cutting")
    sc = ax.scatter(x[feed], y[feed], z[feed], c=err[feed], s=2, cmap="viridis")
    fig.colorbar(sc, ax=ax, shrink=0.7, label="contour error [µm]")
    ax.set_title("tool path coloured by the contour error")
    ax.set_xlabel("program X [mm]")
    ax.set_ylabel("program Y [mm]")
    ax.set_zlabel("program Z [mm]")
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(x[~feed], y[~feed], ".", color="lightgrey", ms=1)
    sc2 = ax2.scatter(x[feed], y[feed], c=err[feed], s=2, cmap="viridis")
    fig.colorbar(sc2, ax=ax2, label="contour error [µm]")
    ax2.set_aspect("equal")
    ax2.set_title("seen from above")
    ax2.set_xlabel("program X [mm]")
    ax2.set_ylabel("program Y [mm]")
    return _png(fig)


def _error_figure(columns: Mapping[str, Any]) -> bytes:
    fig = _figure(11.0, 5.6)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    t = np.asarray(columns["t"])
    feed = _cutting(columns)
    err = _UM * np.asarray(columns["contour_error"])
    ax1.plot(t, np.where(feed, err, np.nan), color="k", lw=0.8, label="cutting (feed moves)")
    ax1.plot(t, np.where(feed, np.nan, err), color="lightgrey", lw=0.8,
             label="rapid moves, dwells: to the whole path")  # fmt: skip
    ax1.set_ylabel("contour error [µm]")
    ax1.legend(fontsize=7)
    for i in range(3):
        e = _UM * np.asarray(columns[f"e{i + 1}"])
        ax2.plot(t, e, color=_COLOURS[i], lw=0.8, label=f"slider {i + 1}")
    ax2.set_ylabel("tracking error [µm]")
    ax2.set_xlabel("time [s]")
    ax2.legend(fontsize=7)
    return _png(fig)


def _torque_figure(columns: Mapping[str, Any]) -> bytes:
    fig = _figure(11.0, 6.4)
    axes = fig.subplots(3, 1, sharex=True)
    t = np.asarray(columns["t"])
    for i, ax in enumerate(axes):
        tau = np.asarray(columns[f"tau{i + 1}"])
        avail = np.asarray(columns[f"tau_available{i + 1}"])
        sat = np.asarray(columns[f"saturated{i + 1}"]) > 0.0
        ax.plot(t, tau, color=_COLOURS[i], lw=0.8, label=f"motor {i + 1}")
        if (avail >= 0.0).any():
            ax.plot(t, np.where(avail >= 0, avail, np.nan), color="k", ls="--", lw=0.8)
            ax.plot(t, np.where(avail >= 0, -avail, np.nan), color="k", ls="--", lw=0.8,
                    label="available")  # fmt: skip
        if sat.any():
            ax.plot(t[sat], tau[sat], "x", color="k", ms=3, label="saturated")
        ax.set_ylabel("torque [N.m]")
        ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("time [s]")
    return _png(fig)


def _um(value: float) -> str:
    return quantity("error", value, ".3f")


def simulation_html(
    columns: Mapping[str, Any], summary: Mapping[str, Any], title: str, companions: Sequence[str]
) -> str:
    """The page of a simulated run (see the module).

    Args:
        columns: The columns of ``simulation.csv`` (name -> values).
        summary: The JSON summary of the run (``simulate --json``).
        title: The program's name.
        companions: Names of the files written next to the page.
    """
    images = {
        "path": _path_figure(columns),
        "errors": _error_figure(columns),
        "torques": _torque_figure(columns),
    }
    at = summary.get("max_contour_error_at")
    where = (
        ""
        if at is None
        else f" at t = {at['t']:.4f} s, line {at['line']}, ("
        + ", ".join(f"{_MM * at[c]:.3f}" for c in "xyz")
        + ") mm"
    )
    saturated = summary["saturation_time"] > 0.0
    verdict = (
        '<p class="banner fail">The motors saturate: the torque asked was not available '
        f"for {summary['saturation_time']:.4f} s.</p>"
        if saturated
        else '<p class="banner pass">No motor saturates.</p>'
    )
    share = summary.get("cutting_share")
    cutting = (
        ""
        if share is None
        else f" ({100 * share:.1f} % of the cycle, {summary['cutting_time']:.4f} s)"
    )
    contour = (
        f"<p>Contour error while cutting{_e(cutting)}, against the feed moves alone: largest "
        f"<b>{_um(summary['max_contour_error'])}</b>"
        f"{_e(where)}, RMS {_um(summary['rms_contour_error'])}; largest deviation on the "
        f"rapid moves {_um(summary['max_rapid_deviation'])}.</p>"
    )
    rows = [
        (
            f"slider {i + 1}",
            _um(summary["max_tracking_error"][i]),
            _um(summary["rms_tracking_error"][i]),
            f"{summary['saturation_time_per_slider'][i]:.4f}",
            f"{summary['peak_torque'][i]:.4f}",
        )
        for i in range(3)
    ]
    sliders = _table(
        (
            "slider",
            "max tracking error",
            "RMS tracking error",
            "saturated [s]",
            "peak torque [N.m]",
        ),
        rows,
    )
    encoder = summary.get("encoder_counts")
    wrench = summary.get("wrench")
    load = "none" if wrench is None else " ".join(f"{v:g}" for v in wrench)
    setup = _table(
        ("setting", "value"),
        [
            ("controller", summary["controller"]),
            ("servo rate [Hz]", f"{summary['rate']:g}"),
            ("MuJoCo step [s]", f"{summary['timestep']:.6g}"),
            ("encoder [counts/rev]", "exact" if encoder is None else str(encoder)),
            ("mass error [-]", f"{summary['mass_error']:g}"),
            ("friction error [-]", f"{summary['friction_error']:g}"),
            ("simulated motor", str(summary.get("motor"))),
            ("plan's motor", str(summary.get("plan_motor"))),
            ("tool wrench [N, N.m]", load),
            ("duration [s]", f"{summary['duration']:.4f}"),
        ],
    )
    sections = [
        ("Contour and saturation", verdict + contour + sliders),
        ("Tool path", _img(images, "path", "tool path by contour error")),
        ("Errors over time", _img(images, "errors", "contour and tracking errors")),
        ("Motor torques and their limits", _img(images, "torques", "torques")),
        ("Set-up", setup),
        (
            "Files",
            f'<p class="note">Every number in SI units: {_e(", ".join(companions))} '
            "(next to this file).</p>",
        ),
    ]
    subtitle = (
        "The planned program run in MuJoCo: one position loop per slider, the motor "
        "torque cut by its speed-torque curve."
    )
    return _page(f"Simulation of {title}", _e(subtitle), sections)
