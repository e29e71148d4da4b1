"""The report's accuracy section: what the machine does to the part, given a cut file.

With a part program (``orthoglide report --program P --cut CUT.yaml``),
:func:`accuracy_section` takes the plan of the program section
(:mod:`~orthoglide_pin.report.program`) and computes along it
(:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`):

* the surface error, static (under the revolution's mean force), as the wall
  is generated and peak over a revolution: each its value of largest
  magnitude (signed; positive leaves material) and where (point and line);
* the error budget at the cutting samples (compliance, thermal when a
  temperature rise is given): the largest norm of each term, the worst case
  and the root sum of squares, and how often each term dominates;
* the chatter stability margin of every program line that cuts, as
  ``orthoglide accuracy`` computes it
  (:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`, its
  default points per line): the limiting axial depth at the spindle speed at
  up to five of the line's cutting samples of the plan, along the planned feed
  there, with the report's drive train reflected onto the carriages, divided
  by the line's engaged depth; the line's margin is the smallest of its
  points'. The smallest margin, where, and the number of lines that are not
  stable (margin at most 1).

The surface error and the margin are those of ``orthoglide accuracy`` for the
same plan, drive train and cut (the report plans the program at its slider
limits ``v_max``, ``a_max``, without a motor limit: :mod:`~orthoglide_pin.report.program`).

Without a program (``--cut`` alone) it gives the stability lobes at the
cube's home, Q1 and Q2 (:data:`POINTS`), the feed along program +X: the lowest
limiting depth over :data:`REPORT_SPEEDS` and, when the cut file gives the
spindle speed, the limit there and the margin. The modes move with the tool,
so the lobes do too.
"""

from __future__ import annotations

import dataclasses
import html
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._io import strict_json
from orthoglide_pin._validation import instance_of
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.exceptions import CutConditionsError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import RPM_PER_RAD_S, CutConditions
from orthoglide_pin.machining.plan_stability import PlanStability, stability_along_plan
from orthoglide_pin.machining.stability import StabilityLobes, stability_lobes

if TYPE_CHECKING:
    from orthoglide_pin.machining.accuracy import AccuracyResult
    from orthoglide_pin.planning.plan import Plan

FloatArray = NDArray[np.float64]

__all__ = [
    "POINTS",
    "REPORT_SPEEDS",
    "SURFACE_KINDS",
    "AccuracySection",
    "accuracy_dict",
    "accuracy_html",
    "accuracy_section",
    "check_cut",
    "lobes_figure",
]

#: Spindle speeds of the lobes without a program [rad/s]: 100 from 2,000 to 24,000 rpm.
REPORT_SPEEDS: Final = np.linspace(2000.0, 24000.0, 100) / RPM_PER_RAD_S
#: The points of the lobes without a program, by name.
POINTS: Final = ("home", "Q1", "Q2")
#: The surface errors of the section: key -> (attribute of the result, words).
SURFACE_KINDS: Final = {
    "static": ("surface_static", "static (mean force)"),
    "generated": ("surface_generated", "as the wall is generated"),
    "peak": ("surface_peak", "peak over a revolution"),
}


@dataclass(frozen=True)
class AccuracySection:
    """The report's accuracy section (see the module).

    Attributes:
        cut_name: The cut file's name, for the page.
        cut: The cutting conditions.
        spindle_speed: The spindle speed [rad/s] (the cut file's or the
            program's), or ``None`` (no program, and the cut file says ``program``).
        result: Accuracy along the program, or ``None`` without a program.
        stability: The stability margin of each program line that cuts, or
            ``None`` without a program.
        drive: The drive train reflected onto the carriages (the margin, the
            lobes), or ``None`` for none.
        lobes: Without a program, the lobes at :data:`POINTS`; else empty.
    """

    cut_name: str
    cut: CutConditions
    spindle_speed: float | None
    result: AccuracyResult | None = None
    stability: PlanStability | None = None
    drive: DriveTrain | None = None
    lobes: tuple[tuple[str, StabilityLobes], ...] = ()


def check_cut(cut: CutConditions, spindle_speed: float | None, program: bool) -> CutConditions:
    """The cut, checked before any work: with a program, a spindle speed must be known.

    Raises:
        InvalidParameterError: ``cut`` is not cutting conditions.
        CutConditionsError: A program, and neither the cut file nor the program
            gives the spindle speed.
    """
    cut = instance_of("cut", cut, CutConditions, "CutConditions (read_cut_file) or None")
    if program and cut.spindle_speed is None and spindle_speed is None:
        raise CutConditionsError(
            "spindle_speed", "program", "a speed in the cut file, or S words in the program"
        )
    return cut


def accuracy_section(
    params: OrthoglideParams,
    cut: CutConditions,
    plan: Plan | None,
    *,
    cut_name: str = "cut",
    spindle_speed: float | None = None,
    drive: Drive | DriveTrain | None = None,
    temperature_rise: float | None = None,
) -> AccuracySection:
    """The section along ``plan``, or the lobes at :data:`POINTS` without one (see the module).

    Args:
        params: The machine.
        cut: The cutting conditions.
        plan: The program's plan, or ``None``.
        cut_name: The cut file's name, for the page.
        spindle_speed: The program's spindle speed [rad/s] (its ``S``); the
            cut file's when ``None``.
        drive: A drive whose rotary inertia is reflected onto the carriages
            (the modes of the stability margin and of the lobes); the report
            passes its own, the default drive train when no motor file is given.
        temperature_rise: Uniform temperature rise [K] for the budget's thermal term.

    Raises:
        CutConditionsError: A program but no spindle speed (neither given nor in the cut file).
    """
    speed = cut.spindle_speed if spindle_speed is None else spindle_speed
    train = drive.train if isinstance(drive, Drive) else drive
    if plan is None:
        cube = params.workspace
        where = {"home": np.zeros(3), "Q1": cube.q1, "Q2": cube.q2}
        lobes = tuple(
            (
                name,
                stability_lobes(
                    cut,
                    where[name],
                    params=params,
                    speeds=REPORT_SPEEDS,
                    drive=drive,
                    zero_order=False,
                ),
            )
            for name in POINTS
        )
        return AccuracySection(cut_name, cut, speed, drive=train, lobes=lobes)
    from orthoglide_pin.machining.accuracy import accuracy_along_plan

    result = accuracy_along_plan(
        plan, cut, params, spindle_speed=speed, temperature_rise=temperature_rise
    )
    stability = stability_along_plan(plan, result, params, drive=train)
    return AccuracySection(cut_name, cut, result.spindle_speed, result, stability, train)


def _where(result: AccuracyResult, attribute: str) -> dict[str, Any]:
    values: FloatArray = getattr(result, attribute)
    if not result.samples.cutting.any():
        return {"max": 0.0, "point": None, "line": None}
    k = int(np.argmax(np.abs(values)))
    return {
        "max": float(values[k]),
        "point": result.samples.points[k].tolist(),
        "line": int(result.samples.line[k]),
    }


def _margin_dict(section: AccuracySection) -> dict[str, Any]:
    m = section.stability
    if m is None or m.worst < 0:
        return {"min": None, "line": None, "point": None, "blocks": 0, "unstable_blocks": 0}
    k = m.worst
    return {
        "min": float(m.margin[k]) if math.isfinite(m.margin[k]) else None,
        "line": int(m.lines[k]),
        "point": m.points[k].tolist(),
        "limit_depth": float(m.limits[k]),
        "axial_depth": float(m.depths[k]),
        "blocks": int(m.lines.size),
        "unstable_blocks": m.unstable,
        "points_per_block": m.points_per_block,
        "per_block": [
            {"line": int(ln), "margin": float(v), "limit_depth": float(lim)}
            for ln, v, lim in zip(m.lines, m.margin, m.limits, strict=True)
        ],
    }


def _lobes_dict(name: str, lobes: StabilityLobes, speed: float | None) -> dict[str, Any]:
    limit = None if speed is None else lobes.limit_at(speed)
    depth = lobes.engagement.axial_depth
    finite = limit is not None and math.isfinite(limit)
    return {
        "point_name": name,
        "point": lobes.point.tolist(),
        "lowest_frequency": float(lobes.model.frequencies[0]),
        "minimum_depth": lobes.minimum,
        "limit_depth_at_speed": limit if finite else None,
        "margin": limit / depth if finite and limit is not None else None,
    }


def accuracy_dict(section: AccuracySection) -> dict[str, Any]:
    """The section's figures, strict JSON (SI units; the spindle speed also in rpm)."""
    speed = section.spindle_speed
    eng = section.cut.engagements[0]
    out: dict[str, Any] = {
        "cut": section.cut_name,
        "material": section.cut.material.name,
        "spindle_speed": speed,
        "spindle_speed_rpm": None if speed is None else speed * RPM_PER_RAD_S,
        "axial_depth": eng.axial_depth,
        "radial_width": eng.radial_width,
        "drive_train": None if section.drive is None else dataclasses.asdict(section.drive),
    }
    r = section.result
    if r is None:
        out["program"] = False
        out["lobes"] = [_lobes_dict(n, lb, speed) for n, lb in section.lobes]
        out["lobe_speeds_rpm"] = [float(REPORT_SPEEDS[k]) * RPM_PER_RAD_S for k in (0, -1)]
    else:
        summary = r.summary()
        out["program"] = True
        out["samples"] = summary["samples"]
        out["cutting_samples"] = summary["cutting_samples"]
        out["force_peak_max"] = summary["force_peak_max"]
        out["surface_error"] = {k: _where(r, a) for k, (a, _) in SURFACE_KINDS.items()}
        out["budget"] = summary["budget"]
        out["stability"] = _margin_dict(section)
    return dict(strict_json(out))


def _um(value: float) -> str:
    return f"{value * 1e6:+.2f} µm"


def _mm(point: Any) -> str:
    return "(" + ", ".join(f"{1e3 * v:.1f}" for v in point) + ") mm"


def accuracy_html(section: AccuracySection, image: str = "") -> str:
    """The page's section (``image``: the lobes figure's ``<img>`` tag, without a program)."""
    d = accuracy_dict(section)
    e = html.escape
    speed = "the program's S" if d["spindle_speed_rpm"] is None else (
        f"{d['spindle_speed_rpm']:.0f} rpm"
    )  # fmt: skip
    head = (
        f"<p>Cut file {e(section.cut_name)}: {e(d['material'])}, "
        f"{section.cut.tool.teeth} teeth, {1e3 * section.cut.tool.diameter:g} mm tool, "
        f"{1e3 * d['axial_depth']:g} mm deep and {1e3 * d['radial_width']:g} mm wide, {speed}, "
        f"modal damping {section.cut.modal_damping:g}.</p>"
    )
    if not d["program"]:
        rows = "".join(
            f"<tr><td class='text'>{e(lb['point_name'])}</td><td>{_mm(lb['point'])}</td>"
            f"<td>{lb['lowest_frequency']:.1f}</td><td>{1e3 * lb['minimum_depth']:.3f}</td>"
            + (
                "<td>-</td><td>-</td>"
                if lb["limit_depth_at_speed"] is None
                else f"<td>{1e3 * lb['limit_depth_at_speed']:.3f}</td><td>{lb['margin']:.2f}</td>"
            )
            + "</tr>"
            for lb in d["lobes"]
        )
        return (
            head + "<p>No program given: the chatter stability lobes where the modes are "
            "(feed along program +X, semi-discretization). Give --program for the "
            "surface error, the error budget and the margin of every line that cuts.</p>"
            + "<table><tr><th class='text'>point</th><th>where (world frame)</th>"
            "<th>lowest mode [Hz]</th><th>lowest limit [mm]</th>"
            "<th>limit at the speed [mm]</th><th>margin [-]</th></tr>" + rows + "</table>" + image
        )
    surface = "".join(
        f"<tr><td class='text'>{e(words)}</td><td>{_um(s['max'])}</td>"
        f"<td>{'-' if s['point'] is None else _mm(s['point'])}</td>"
        f"<td>{'-' if s['line'] is None else s['line']}</td></tr>"
        for key, (_, words) in SURFACE_KINDS.items()
        for s in (d["surface_error"][key],)
    )
    b = d["budget"]
    terms = ", ".join(f"{k} {1e6 * v:.2f} µm" for k, v in b.get("max", {}).items())
    dominant = ", ".join(f"{k} {n}" for k, n in b.get("dominant_count", {}).items())
    st = d["stability"]
    if st["min"] is None:
        margin = "<p>No line cuts: no stability margin.</p>"
    else:
        cls = "pass" if st["unstable_blocks"] == 0 else "fail"
        margin = (
            f"<table><tr class='{cls}'><td class='text'>least stability margin</td>"
            f"<td>{st['min']:.3f} on line {st['line']} at {_mm(st['point'])} (limit "
            f"{1e3 * st['limit_depth']:.3f} mm for {1e3 * st['axial_depth']:g} mm)</td></tr>"
            f"<tr class='{cls}'><td class='text'>lines that chatter (margin &le; 1)</td>"
            f"<td>{st['unstable_blocks']} of {st['blocks']}</td></tr></table>"
        )
    return (
        head + f"<p>Along the program: {d['cutting_samples']} cutting samples of {d['samples']}, "
        f"peak cutting force {d['force_peak_max']:.1f} N (feed per tooth from the planned "
        "speed). Surface error: positive leaves material.</p>"
        + "<table><tr><th class='text'>surface error</th><th>largest</th>"
        "<th>where (world frame)</th><th>line</th></tr>"
        + surface
        + "</table>"
        + f"<p>Error budget at the cutting samples: largest term {terms or 'none'}; "
        f"worst case {1e6 * b.get('worst_case_max', 0.0):.2f} µm, root sum of squares "
        f"{1e6 * b.get('rss_max', 0.0):.2f} µm; dominant term (samples): "
        f"{dominant or 'none'}.</p>"
        + margin
        + '<p class="note">Stability margin, as <code>orthoglide accuracy</code> computes it: '
        "the limiting axial depth (semi-discretization, the machine's modes with the "
        "report's drive train at up to 5 points of each program line along the planned "
        "feed) over the engaged depth, the smallest of the line's points; above 1 the "
        "line cuts without chatter.</p>"
    )


def lobes_figure(section: AccuracySection) -> bytes | None:
    """The lobes at :data:`POINTS` as PNG bytes (``None`` with a program)."""
    from orthoglide_pin.report.page import figure, png

    if not section.lobes:
        return None
    fig = figure(7.5, 3.2)
    ax = fig.add_subplot(1, 1, 1)
    for name, lb in section.lobes:
        depth = np.where(np.isfinite(lb.depths), lb.depths, np.nan)
        ax.plot(
            lb.speeds * RPM_PER_RAD_S,
            1e3 * depth,
            label=f"{name} ({lb.model.frequencies[0]:.0f} Hz)",
        )
    if section.spindle_speed is not None:
        rpm = section.spindle_speed * RPM_PER_RAD_S
        ax.axvline(rpm, color="k", ls=":", lw=0.8, label=f"the cut's speed, {rpm:.0f} rpm")
    cut = 1e3 * section.cut.engagements[0].axial_depth
    ax.axhline(cut, color="r", ls="--", lw=0.8, label=f"the cut's depth, {cut:g} mm")
    ax.set(xlabel="spindle speed [rpm]", ylabel="limiting axial depth [mm]")
    ax.set_yscale("log")
    ax.legend(fontsize=8)
    return png(fig)
