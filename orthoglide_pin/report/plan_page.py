"""The plan of a part program as one self-contained HTML page, like the report.

:func:`plan_html` lays out the cycle time and its breakdown by block, the
worst use of every limit and the share of the time each binds, and four
figures drawn with the report's machinery (matplotlib on an Agg canvas,
embedded as PNG ``data:`` URIs, inline style, nothing referred outside the
page): the tool path coloured by feed, the path coloured by the limit that
binds, the slider speeds and the motor torques over time against their
limits; with a jerk limit, the slider jerks over time against it and the time
the limit costs. Units as on every page (:mod:`~orthoglide_pin.report.units`):
lengths in mm, the feed in mm/min, slider speeds in mm/s, motor speeds in rpm,
the rest in SI; the JSON and CSV files next to the page are in SI.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Final

import numpy as np

from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.verify import BINDING, LIMIT_NAMES
from orthoglide_pin.report.page import STYLE as _STYLE
from orthoglide_pin.report.page import escape as _e
from orthoglide_pin.report.page import figure as _figure
from orthoglide_pin.report.page import image as _img
from orthoglide_pin.report.page import png as _png
from orthoglide_pin.report.page import table as _table
from orthoglide_pin.report.units import LIMIT_KINDS, label, quantity, shown

_COLOURS: Final = ("tab:red", "tab:green", "tab:blue")
#: Most rows of the per-block table shown (the JSON has them all).
MAX_ROWS: Final[int] = 200


def _path_figure(plan: Plan, columns: Mapping[str, Any]) -> bytes:
    fig = _figure(11.0, 4.6)
    ax1 = fig.add_subplot(1, 2, 1, projection="3d")
    axes = plan.path.program.axes  # drawn in the program's axes: Z up, the table below
    world = np.stack([np.asarray(columns[c], dtype=float) for c in "xyz"], axis=1)
    x, y, z = shown("length", axes.to_program(world)).T
    feed = shown("feed", np.asarray(columns["path_speed"], dtype=float))
    sc = ax1.scatter(x, y, z, c=feed, s=2, cmap="viridis")
    fig.colorbar(sc, ax=ax1, shrink=0.7, label=label("feed (path speed)", "feed"))
    ax1.set_title("tool path coloured by feed")
    ax1.set_xlabel("program X [mm]")
    ax1.set_ylabel("program Y [mm]")
    ax1.set_zlabel("program Z [mm]")
    ax2 = fig.add_subplot(1, 2, 2, projection="3d")
    names = [n for n in LIMIT_NAMES if n in plan.worst]
    for r in plan.sections:
        m = r.motion
        if m is None:
            continue
        uses = np.stack([m.uses.get(n, np.zeros(m.t.size)) for n in names], axis=1)
        which = np.where(uses.max(axis=1) >= BINDING, uses.argmax(axis=1), -1)
        for k, name in [(-1, "none"), *enumerate(names)]:
            sel = which == k
            if sel.any():
                pts = shown("length", axes.to_program(m.p[sel]))
                colour = "lightgrey" if k < 0 else f"C{k}"
                ax2.scatter(*pts.T, s=2, color=colour, label=name)
    handles, labels = ax2.get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    ax2.legend(unique.values(), unique.keys(), fontsize=7, markerscale=4)
    ax2.set_title(f"binding limit (use >= {BINDING:g})")
    ax2.set_xlabel("program X [mm]")
    ax2.set_ylabel("program Y [mm]")
    ax2.set_zlabel("program Z [mm]")
    return _png(fig)


def slider_speed_limits(plan: Plan) -> dict[str, float]:
    """The limits on the slider speed [m/s] drawn on the page, by name.

    ``"slider speed limit"`` (``--max-slider-speed``) and ``"motor speed limit"``,
    the motor's largest speed [rad/s] seen at the slider through the drive train.
    """
    lim, out = plan.limits, {}
    if lim.slider_speed is not None:
        out["slider speed limit"] = float(lim.slider_speed)
    w = lim.motor_speed
    if w is not None and lim.drive is not None:
        out["motor speed limit"] = float(w / lim.drive.train.motor_speed(1.0))
    return out


def _time_figure(plan: Plan, columns: Mapping[str, Any]) -> bytes:
    has_tau = "tau1" in columns
    fig = _figure(11.0, 6.4 if has_tau else 3.4)
    axes = fig.subplots(2 if has_tau else 1, 1, squeeze=False, sharex=True)[:, 0]
    t = columns["t"]
    for i in range(3):
        qd = shown("speed", np.asarray(columns[f"qd{i + 1}"], dtype=float))
        axes[0].plot(t, qd, color=_COLOURS[i], lw=0.8, label=f"slider {i + 1}")
    for k, (name, v) in enumerate(slider_speed_limits(plan).items()):
        style = {"color": "k" if k == 0 else "tab:purple", "ls": "--", "lw": 0.8}
        axes[0].axhline(shown("speed", v), label=name, **style)
        axes[0].axhline(-shown("speed", v), **style)
    axes[0].set_ylabel(label("slider speed", "speed"))
    axes[0].legend(fontsize=7)
    if has_tau:
        for i in range(3):
            axes[1].plot(
                t, columns[f"tau{i + 1}"], color=_COLOURS[i], lw=0.8, label=f"motor {i + 1}"
            )
        drive = plan.limits.drive
        if plan.limits.limits_torque and drive is not None:
            w = np.abs(np.stack([columns[f"qd{i + 1}"] for i in range(3)], axis=1))
            avail = plan.limits.available_torque(drive.train.motor_speed(w)).min(axis=1)
            kept = plan.limits.torque_reserve
            what = f"available less {kept:.0%} reserve" if kept > 0.0 else "available"
            axes[1].plot(t, avail, color="k", ls="--", lw=0.8, label=f"{what} (worst motor)")
            axes[1].plot(t, -avail, color="k", ls="--", lw=0.8)
        axes[1].set_ylabel("motor torque [N.m]")
        axes[1].legend(fontsize=7)
    axes[-1].set_xlabel("time [s]")
    return _png(fig)


def _jerk_figure(plan: Plan) -> bytes:
    """The slider jerks on the verification grid over time, against the limit."""
    fig = _figure(11.0, 3.4)
    ax = fig.subplots()
    seen = False
    for r in plan.sections:
        m = r.motion
        if m is None or m.qddd is None:
            continue
        for i in range(3):
            label = f"slider {i + 1}" if not seen else None
            ax.plot(r.start + m.t, m.qddd[:, i], color=_COLOURS[i], lw=0.8, label=label)
        seen = True
    jerk = plan.limits.slider_jerk
    assert jerk is not None
    for sign in (1, -1):
        ax.axhline(sign * jerk, color="k", ls="--", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("slider jerk [m/s^3]")
    if seen:
        ax.legend(fontsize=7)
    return _png(fig)


def limit_text(plan: Plan, name: str) -> str:
    """The value of limit ``name`` of the plan in its display unit, e.g. ``"1200 mm/s"``.

    The motor torque is the largest torque available (the peak torque, or the
    speed-torque curve's at rest); the feed is the program's (its ``F`` words,
    the largest given).
    """
    lim = plan.limits
    values = {
        "slider_speed": lim.slider_speed,
        "slider_acceleration": lim.slider_acceleration,
        "slider_jerk": lim.slider_jerk,
        "motor_speed": lim.motor_speed,
        "motor_torque": lim.reference_torque() if lim.limits_torque else None,
    }
    if name == "feed":
        feeds = [b.feed for b in plan.path.program.blocks if b.feed is not None]
        return "" if not feeds else "F up to " + quantity("feed", max(feeds), ".0f")
    value = values.get(name)
    return "" if value is None else quantity(LIMIT_KINDS[name], value, ".4g")


def peaks_text(columns: Mapping[str, Any]) -> str:
    """``"peak feed 3000 mm/min, peak slider speed 50.0 mm/s"`` of the sampled plan.

    The same words on the terminal (``orthoglide plan``) and on the page; the
    viewer's legend of the same ``trajectory.csv`` ends at the same peak feed.
    """
    feed = float(np.max(columns["path_speed"]))
    qd = max(float(np.max(np.abs(columns[f"qd{i}"]))) for i in (1, 2, 3))
    return (
        f"peak feed {quantity('feed', feed, '.0f')}, "
        f"peak slider speed {quantity('speed', qd, '.1f')}"
    )


def plan_html(plan: Plan, columns: Mapping[str, Any], title: str, companions: list[str]) -> str:
    """The page of a plan (see the module).

    Args:
        plan: The plan.
        columns: The plan sampled in time (:func:`~orthoglide_pin.planning.sampling.sample_plan`).
        title: The program's name.
        companions: Names of the files written next to the page.
    """
    images = {"path": _path_figure(plan, columns), "time": _time_figure(plan, columns)}
    if plan.limits.slider_jerk is not None:
        images["jerk"] = _jerk_figure(plan)
    rows = [
        (
            name,
            limit_text(plan, name),
            f"{plan.worst[name]:.4f}",
            f"{100 * plan.binding.get(name, 0):.1f} %",
        )
        for name in LIMIT_NAMES
        if name in plan.worst
    ]
    limits = _table(("limit", "value", "peak use", "binding share of the time"), rows)
    blocks = plan.blocks[:MAX_ROWS]
    per_block = _table(
        ("line", "kind", "start [s]", "end [s]", "duration [s]"),
        [
            (b.line, b.kind, f"{b.start:.4f}", f"{b.end:.4f}", f"{b.end - b.start:.4f}")
            for b in blocks
        ],
    )
    more = (
        f'<p class="note">First {MAX_ROWS} of {len(plan.blocks)} blocks; the JSON lists all.</p>'
        if len(plan.blocks) > MAX_ROWS
        else ""
    )
    summary = (
        f"<p>Cycle time <b>{plan.cycle_time:.4f} s</b> for {len(plan.blocks)} blocks, "
        f"{quantity('length', plan.path.length, '.1f')} of path, "
        f"{plan.grid_points} planning-grid points; "
        "every limit verified on a grid 10 times finer with the closed-loop inverse dynamics.</p>"
        f"<p>{_e(peaks_text(columns))}.</p>"
    )
    cost = plan.jerk_time_cost
    if cost is not None:
        summary += (
            f"<p>The jerk limit costs {cost['with_jerk'] - cost['second_order']:.4f} s: "
            f"{cost['with_jerk']:.4f} s against {cost['second_order']:.4f} s for the "
            f"second-order optimum ({100 * (cost['ratio'] - 1):.1f} %), with "
            f"{int(cost['curvature_stops'])} stops where the path's curvature steps.</p>"
        )
    sections = [
        ("Cycle time and limits", summary + limits),
        ("Tool path", _img(images, "path", "tool path")),
        ("Slider speeds and motor torques", _img(images, "time", "speeds and torques")),
        *([("Slider jerks", _img(images, "jerk", "slider jerks"))] if "jerk" in images else []),
        ("Breakdown by block", per_block + more),
        (
            "Files",
            f'<p class="note">Every number in SI units: {_e(", ".join(companions))} '
            "(next to this file).</p>",
        ),
    ]
    body = "".join(f"<h2>{_e(t)}</h2>{c}" for t, c in sections)
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>Orthoglide plan: {_e(title)}</title><style>{_STYLE}</style></head><body>"
        f"<h1>Plan of {_e(title)}</h1>{body}</body></html>\n"
    )
