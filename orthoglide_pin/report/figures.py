"""The report's figures: worst-case maps, the standard cycle and the operating points.

:func:`figures` draws the report's figures with matplotlib on its Agg canvas
(no display, pyplot's global state untouched) as PNG bytes:
``force_maps`` and ``torque_maps`` (the worst case on each slice, one column
per slider or motor, with the largest value marked), ``guarantee_maps`` (with
motor data), ``cycle`` (slider positions, speeds, forces and motor torques over
the standard cycle) and ``operating_points`` (the cycle's speed-torque points
of each motor against the motor's limits and the worst-case envelope);
``accuracy_lobes`` (a cut file without a program: the stability lobes at the
cube's home, Q1 and Q2).
Units as on every page (:mod:`~orthoglide_pin.report.units`): lengths in mm,
speeds in mm/s, motor speeds in rpm; every axis and colour bar is labelled in
words with its unit. :mod:`orthoglide_pin.report.html` lays the figures out in the page.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

import numpy as np

from orthoglide_pin.report.accuracy import lobes_figure
from orthoglide_pin.report.assemble import Progress, ReportData
from orthoglide_pin.report.page import DPI
from orthoglide_pin.report.page import figure as _figure
from orthoglide_pin.report.page import png as _png
from orthoglide_pin.report.stiffness import stiffness_figure
from orthoglide_pin.report.units import label as _label
from orthoglide_pin.report.units import quantity, shown
from orthoglide_pin.report.vibration import vibration_figure

#: Figure names in drawing order (``guarantee_maps`` only with motor data).
FIGURES: Final = (
    "force_maps",
    "torque_maps",
    "guarantee_maps",
    "cycle",
    "operating_points",
    "stiffness_maps",
    "vibration_maps",
    "accuracy_lobes",
)
_MM: Final = 1e3
_COLOURS: Final = ("tab:red", "tab:green", "tab:blue")


def _maps(
    data: ReportData, columns: Sequence[tuple[str, str, int | None, str]], title: str
) -> bytes:
    """One row per slice; per column ``(title, field, slider or None, label)``, shared colours.

    The largest value of a slider's field (the smallest of a guarantee) on each
    slice is marked.
    """
    rows = len(data.slices)
    fig = _figure(4.0 * len(columns) + 0.6, 3.3 * rows + 0.6)
    axes = fig.subplots(rows, len(columns), squeeze=False, sharex=True, sharey=True)
    for col, (name, field, slider, label) in enumerate(columns):
        fields = []
        for s in data.slices:
            values = s.worst.grid_field(field)[:, :, 0]
            if field == "speed":  # the guaranteed tool speed [m/s], shown in mm/s
                values = shown("speed", values)
            fields.append(values if slider is None else values[..., slider])
        lo, hi = min(float(f.min()) for f in fields), max(float(f.max()) for f in fields)
        mesh = None
        for row, (s, values) in enumerate(zip(data.slices, fields, strict=True)):
            ax, grid = axes[row, col], s.worst.grid
            assert grid is not None
            x, y = grid.x * _MM, grid.y * _MM
            mesh = ax.pcolormesh(x, y, values.T, shading="gouraud", vmin=lo, vmax=hi)
            flat = np.argmax(values) if slider is not None else np.argmin(values)
            i, j = np.unravel_index(flat, values.shape)
            ax.plot(x[i], y[j], "o", ms=9, mfc="none", mec="red", mew=2, clip_on=False)
            ax.set_title(f"{name}, z = {s.value * _MM:.1f} mm", fontsize=9)
            ax.set_aspect("equal")
        fig.colorbar(mesh, ax=axes[:, col], label=label, shrink=0.8)
    fig.supxlabel("tool position x [mm]")
    fig.supylabel("tool position y [mm]")
    fig.suptitle(title + " (circle: the extreme of each slice)")
    return _png(fig)


def _cycle(data: ReportData) -> bytes:
    res, demand, t = data.cycle_dynamics, data.sizing.demand, data.cycle.t
    fig = _figure(11.0, 10.0)
    axes = fig.subplots(4, 1, sharex=True)
    panels = (
        (res.slider_positions * _MM, "slider position [mm]", "slider"),
        (shown("speed", res.slider_velocities), _label("slider speed", "speed"), "slider"),
        (res.forces, "slider force [N]", "slider"),
        (demand.torque, "motor torque [N.m]", "motor"),
    )
    for ax, (values, label, what) in zip(axes, panels, strict=True):
        for i in range(3):
            ax.plot(t, values[:, i], color=_COLOURS[i], lw=0.8, label=f"{what} {i + 1}")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=4)
    axes[1].plot(t, shown("speed", data.cycle.speed), "k--", lw=0.7, label="tool speed")
    axes[1].legend(loc="upper right", fontsize=8, ncol=4)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(
        f"Standard cycle at {quantity('speed', data.v_max)}, "
        f"{quantity('acceleration', data.a_max)}, {quantity('jerk', data.jerk)} "
        f"({data.cycle.duration:.2f} s)"
    )
    return _png(fig)


def _operating_points(data: ReportData) -> bytes:
    demand, motor = data.sizing.demand, data.drive.motor
    fig = _figure(10.5, 6.5)
    ax = fig.subplots()
    for i in range(3):
        ax.plot(
            demand.speed_rpm[:, i],
            demand.torque[:, i],
            ".",
            ms=1.5,
            color=_COLOURS[i],
            label=f"motor {i + 1} (cycle)",
        )
    w, tq = float(data.cube.motor_speed_rpm.max()), float(data.cube.torque.max())
    ax.plot(
        [-w, w, w, -w, -w], [-tq, -tq, tq, tq, -tq], ":", color="0.3", label="worst case (bound)"
    )
    if motor is not None:
        if motor.peak_torque is not None:
            ax.axhline(motor.peak_torque, color="k", lw=1.2, label="peak torque")
            ax.axhline(-motor.peak_torque, color="k", lw=1.2)
        if motor.rated_torque is not None:
            ax.axhline(motor.rated_torque, color="k", ls="--", lw=1.0, label="rated torque")
            ax.axhline(-motor.rated_torque, color="k", ls="--", lw=1.0)
        if motor.max_speed is not None:
            ax.axvline(motor.max_speed, color="purple", lw=1.2, label="maximum speed")
            ax.axvline(-motor.max_speed, color="purple", lw=1.2)
        if motor.speed_torque_curve is not None:
            s, c = np.array(motor.speed_torque_curve).T
            for sx, sy in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                ax.plot(
                    sx * s,
                    sy * c,
                    color="orange",
                    lw=1.2,
                    label="speed-torque curve" if sx == sy == 1 else None,
                )
        title = f"Operating points against {motor.name}"
    else:
        title = "Operating points (no motor data: no limits drawn)"
    ax.set_xlabel("motor speed [rpm]")
    ax.set_ylabel("motor torque [N.m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), markerscale=6)
    ax.set_title(title)
    return _png(fig)


def figures(data: ReportData, *, progress: Progress | None = None) -> dict[str, bytes]:
    """The report's figures as PNG bytes, by name (see :data:`FIGURES`)."""
    sliders = [(f"slider {i + 1}", i) for i in range(3)]
    jobs = {
        "force_maps": lambda: _maps(
            data,
            [(n, "force", i, f"worst-case force of {n} [N]") for n, i in sliders],
            "Worst-case slider force",
        ),
        "torque_maps": lambda: _maps(
            data,
            [
                (f"motor {i + 1}", "torque", i, f"worst-case torque of motor {i + 1} [N.m]")
                for _, i in sliders
            ],
            "Worst-case motor torque (bound)",
        ),
        "cycle": lambda: _cycle(data),
        "operating_points": lambda: _operating_points(data),
    }
    g = data.cube.guarantees
    if data.motor_given and any(
        x is not None for x in (g.speed, g.acceleration_at_rest, g.acceleration_at_speed)
    ):
        columns = [
            (title, field, None, _label(f"guaranteed {title}", kind))
            for title, field, kind in (
                ("tool speed", "speed", "speed"),
                ("acceleration from rest", "acceleration_at_rest", "acceleration"),
                (
                    f"acceleration at {quantity('speed', data.v_max)}",
                    "acceleration_at_speed",
                    "acceleration",
                ),
            )
            if getattr(g, field) is not None
        ]
        jobs["guarantee_maps"] = lambda: _maps(data, columns, "Guaranteed in every direction")
    section = data.stiffness
    if section is not None:
        jobs["stiffness_maps"] = lambda: stiffness_figure(section, DPI)
    vibration = data.vibration
    if vibration is not None:
        jobs["vibration_maps"] = lambda: vibration_figure(vibration, DPI)
    accuracy = data.accuracy
    if accuracy is not None and accuracy.lobes:
        jobs["accuracy_lobes"] = lambda: lobes_figure(accuracy) or b""
    names = [n for n in FIGURES if n in jobs]
    bar = None if progress is None else progress("figures", len(names))
    out: dict[str, bytes] = {}
    for name in names:
        out[name] = jobs[name]()
        if bar is not None:
            bar.update(1)
    if bar is not None:
        bar.close()
    return out
