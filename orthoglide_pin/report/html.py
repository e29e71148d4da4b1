"""The report as one self-contained HTML page: images embedded, inline style, no links out.

:func:`render_html` lays out the verdict table, the machine's parameters and
the assumptions, the worst-case maxima and where they occur, the maps, what the
motors guarantee, the standard cycle and the operating points. The figures
(:mod:`orthoglide_pin.report.figures`) are embedded as base64 ``data:`` URIs, the
style is inline and nothing refers outside the page, so the file can be moved,
mailed or archived alone. Units as on every page (:mod:`~orthoglide_pin.report.units`):
lengths in mm, speeds in mm/s, motor speeds in rpm, the rest in SI; the JSON
and CSV files carry the same numbers in SI.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Final

import numpy as np

from orthoglide_pin.kinetostatics.design import prototype_note
from orthoglide_pin.machine.criterion import CRITERION_FIELDS, describe
from orthoglide_pin.machine.cube import Cube
from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES
from orthoglide_pin.report.accuracy import accuracy_html
from orthoglide_pin.report.assemble import NO_MOTOR_HINT, ReportData, VerdictRow
from orthoglide_pin.report.page import escape as _e
from orthoglide_pin.report.page import image as _img
from orthoglide_pin.report.page import page
from orthoglide_pin.report.page import table as _table
from orthoglide_pin.report.program import program_html
from orthoglide_pin.report.stiffness import stiffness_html
from orthoglide_pin.report.units import quantity
from orthoglide_pin.report.vibration import vibration_html

_MM: Final = 1e3


def _mm(point: Iterable[float]) -> str:
    return "(" + ", ".join(f"{_MM * float(v):.1f}" for v in point) + ") mm"


def _dir(vector: Iterable[float], kind: str) -> str:
    """``"1200 mm/s x (+0.577, ...)"``: the norm in the display unit of ``kind``, the direction."""
    v = np.asarray(list(vector), dtype=float)
    n = float(np.linalg.norm(v))
    if n == 0.0:
        return "0"
    return f"{quantity(kind, n, '.4g')} x (" + ", ".join(f"{x:+.3f}" for x in v / n) + ")"


def _available(row: VerdictRow) -> str:
    return "no motor datum" if row.available is None else f"{row.available:.4g} {row.unit}"


def _margin(row: VerdictRow) -> str:
    if row.margin is None:
        return "not judged"
    return "none left" if row.margin == -np.inf else f"{100 * row.margin:.1f} %"


def _verdict(data: ReportData) -> str:
    def state(row: VerdictRow) -> str:
        return "none" if row.passed is None else ("pass" if row.passed else "fail")

    rows = [
        (
            r.criterion if r.motor is None else f"motor {r.motor}: {r.criterion}",
            f"{r.required:.4g} {r.unit}",
            _available(r),
            _margin(r),
            {"none": "no data", "pass": "PASS", "fail": "FAIL"}[state(r)],
        )
        for r in data.verdict
    ]
    hint = NO_MOTOR_HINT[0].upper() + NO_MOTOR_HINT[1:]
    if data.passed is None:
        banner = (
            '<p class="banner none">No motor data: no verdict on limits (requirements below).</p>'
            f'<p class="note">{_e(hint)}.</p>'
        )
    elif data.passed:
        machine = any(r.motor is None for r in data.verdict)
        judged = "every criterion is met" if machine else "every motor meets every criterion"
        banner = f'<p class="banner pass">PASS: {judged}.</p>'
    else:
        banner = '<p class="banner fail">FAIL: some criterion is not met (see the margins).</p>'
    if data.passed is not None and not data.motor_given:
        banner += f'<p class="note">No motor data: the motors are not judged. {_e(hint)}.</p>'
    factor = (
        f"Safety factor {data.safety_factor:g}: every required torque below is the computed "
        "torque multiplied by it (speeds are not). "
        if data.safety_factor != 1.0
        else "No safety factor: the required torques are as computed. "
    )
    note = (
        f'<p class="note">{_e(factor)}'
        "Margin = 1 - required / available: the share of the motor left. "
        "Worst case: every direction of the tool velocity and acceleration, the whole cube; "
        "the torque available at a point is the peak torque capped by the speed-torque "
        "curve up to the motor's speed there.</p>"
    )
    table = _table(
        ("criterion", "required", "available", "margin", "verdict"),
        rows,
        [state(r) for r in data.verdict],
    )
    return banner + table + note


def _cube_text(corner: np.ndarray, side: float) -> str:
    """The cube in words, in mm (:meth:`~orthoglide_pin.machine.cube.Cube.describe`)."""
    x, y, z = (float(c) for c in corner)
    return Cube((x, y, z), float(side)).describe()


def _machine(data: ReportData) -> str:
    rows = []
    derived = data.params.derived_limits
    for name, value in data.params.to_dict().items():
        if name == "meshes":  # CAD data: the inertias are in the assumptions
            rows.append(
                (name, "; ".join(f"{k}: {Path(m['file']).name}" for k, m in value.items()))
            )
            continue
        if name == "inertias":
            rows.append((name, "measured (CAD) for " + ", ".join(value)))
            continue
        unit = PLAUSIBLE_RANGES[name][2] if name in PLAUSIBLE_RANGES else "m"
        if name in CRITERION_FIELDS:
            shown = f"{value:g} (criterion on the transmission factors)"
        elif value is None:
            shown = "derived from sizes and density"
        elif unit != "m":
            shown = f"{value:g} {unit}"
        elif isinstance(value, list):
            shown = ", ".join(f"{_MM * v:.1f}" for v in value) + " mm"
        else:
            shown = f"{_MM * value:.1f} mm" + (
                " (derived from the cube)" if name in derived else ""
            )
        rows.append((name, shown))
    train = data.drive.train
    rows += [
        ("workspace (prescribed cube)", _cube_text(data.corner, data.side)),
        ("stroke", f"{_MM * data.params.stroke:.1f} mm"),
        ("gravity", "(" + ", ".join(f"{g:g}" for g in data.gravity) + ") m/s^2"),
        ("screw lead", f"{_MM * train.lead:g} mm/rev"),
        ("reflected inertia at the motor", f"{train.reflected_inertia:.4g} kg.m^2"),
    ]
    motor = data.drive.motor
    if motor is not None:
        for label, value, unit in (
            ("motor", motor.name, ""),
            ("rated torque", motor.rated_torque, "N.m"),
            ("peak torque", motor.peak_torque, "N.m"),
            ("maximum speed", motor.max_speed, "rpm"),
        ):
            rows.append((label, "-" if value is None else f"{value} {unit}".strip()))
    lists = "".join(
        f"<h3>{_e(topic.capitalize())}</h3><ul>"
        + "".join(f"<li>{_e(s)}</li>" for s in lines)
        + "</ul>"
        for topic, lines in data.assumptions.items()
    )
    return _table(("parameter", "value"), rows) + "<h2>Assumptions</h2>" + lists


def _maxima(data: ReportData) -> str:
    wc = data.cube
    forces, torques = wc.peak("force"), wc.peak("torque")
    speeds, rpm = wc.peak("slider_speed"), wc.peak("motor_speed_rpm")
    exact = wc.torque_exact[np.argmax(wc.torque, axis=0), np.arange(3)]
    rows = []
    for i, motion in enumerate(data.worst_motions):
        how = (
            f"v = {_dir(motion['velocity'], 'speed')}, "
            f"a = {_dir(motion['acceleration'], 'acceleration')}; "
            f"direct dynamics: {motion['force']:.1f} N"
        )
        rows.append((f"slider {i + 1}: max |F|", f"{forces[0][i]:.1f} N", _mm(forces[1][i]), how))
    for i in range(3):
        kind = "exact load part" if exact[i] else "bound (back-driven case larger)"
        rows.append(
            (
                f"motor {i + 1}: max |T|",
                f"{torques[0][i]:.3f} N.m",
                _mm(torques[1][i]),
                f"{kind}; friction bound {wc.friction.max(axis=0)[i]:.3f} N.m",
            )
        )
    for i in range(3):
        rows.append(
            (
                f"slider {i + 1}: max speed",
                quantity("speed", speeds[0][i], ".1f"),
                _mm(speeds[1][i]),
                f"motor {rpm[0][i]:.0f} rpm",
            )
        )
    n = wc.grid.shape[0] if wc.grid is not None else len(wc)
    intro = (
        f"<p>Over a {n} x {n} x {n} grid of the cube (corners included), every direction of "
        f"|v| &lt;= {quantity('speed', data.v_max)} and "
        f"|a| &lt;= {quantity('acceleration', data.a_max)}.</p>"
    )
    per_slice = []
    for s in data.slices:
        f, t = s.worst.peak("force"), s.worst.peak("torque")
        per_slice.append(
            (
                s.label + f" ({_MM * s.value:.1f} mm)",
                *(f"{x:.1f} N" for x in f[0]),
                *(f"{x:.3f} N.m" for x in t[0]),
            )
        )
    slices = _table(("slice", "F1", "F2", "F3", "T1", "T2", "T3"), per_slice)
    return (
        intro
        + _table(("quantity", "value", "where", "worst motion / note"), rows)
        + "<h3>Maxima on the slices</h3>"
        + slices
    )


def _transmission(data: ReportData) -> str:
    """The factors over the cube and the machine's criterion there."""
    fr = data.transmission
    if fr is None:
        return ""
    rows = [
        ("criterion (psi_min, psi_max)", describe(fr.psi_min, fr.psi_max, fr.tolerance)),
        ("factors over the cube", fr.describe()),
        ("smallest factor at", _mm(fr.lowest_at)),
        ("largest factor at", _mm(fr.highest_at)),
        ("verdict", f"the criterion {fr.verdict} over the cube"),
    ]
    prototype = prototype_note(data.params)
    note = (
        '<p class="note">The kinematic criterion is not part of the motors\' verdict above; '
        "<code>orthoglide certify</code> proves it over the whole cube."
        + ("" if prototype is None else " Note: " + _e(prototype) + ".")
        + "</p>"
    )
    classes = ["", "", "", "", "pass" if fr.holds else "fail"]
    return _table(("transmission factors", "value"), rows, classes) + note


def _guarantees(data: ReportData, images: Mapping[str, bytes]) -> str:
    if not data.motor_given:
        return '<p class="note">No motor data: nothing to guarantee (give --motor FILE.yaml).</p>'
    g, pts = data.cube.guarantees, data.cube.points
    rows = []
    at_speed = f"tool acceleration at up to {quantity('speed', data.v_max)}"
    for label, values, kind in (
        ("tool speed", g.speed, "speed"),
        ("tool acceleration from rest", g.acceleration_at_rest, "acceleration"),
        (at_speed, g.acceleration_at_speed, "acceleration"),
    ):
        if values is None:
            rows.append((label, "no motor datum", "nowhere"))
        else:
            k = int(np.argmin(values))
            spec = ".1f" if kind == "speed" else ".3f"
            rows.append((label, quantity(kind, values[k], spec), _mm(pts[k])))
    text = "<p>The least, over the cube, of what the motors guarantee in the worst direction:</p>"
    return (
        text
        + _table(("guaranteed in every direction", "at least", "where (least)"), rows)
        + _img(images, "guarantee_maps", "guarantee maps")
    )


def _cycle(data: ReportData, images: Mapping[str, bytes]) -> str:
    stats, res = data.sizing.statistics, data.cycle_dynamics
    rows = [
        (
            f"motor {i + 1}",
            f"{np.abs(res.forces[:, i]).max():.1f}",
            f"{stats.peak_torque[i]:.3f}",
            f"{stats.rms_torque[i]:.3f}",
            f"{stats.peak_speed_rpm[i]:.0f}",
            f"{stats.peak_power[i]:.0f}",
        )
        for i in range(3)
    ]
    table = _table(
        (
            "axis",
            "peak |F| [N]",
            "peak |T| [N.m]",
            "RMS T [N.m]",
            "peak speed [rpm]",
            "peak power [W]",
        ),
        rows,
    )
    c = data.cycle
    text = (
        f"<p>{len(c.labels)} segments (moves and rests), {c.duration:.2f} s sampled every "
        f"{c.dt * 1e3:g} ms: approach, main diagonal both ways, tour of the corners, square "
        "and circles in the mid-planes, return.</p>"
    )
    return text + table + _img(images, "cycle", "standard cycle")


def render_html(data: ReportData, images: Mapping[str, bytes], companions: Sequence[str]) -> str:
    """The self-contained page of the report (see the module).

    Args:
        data: The report's numbers.
        images: PNG figures by name (:func:`~orthoglide_pin.report.figures.figures`).
        companions: Names of the files written next to the page (JSON, CSV).

    Returns:
        The HTML page.
    """
    motor = data.drive.motor
    subtitle = (
        f"Leg length {_MM * data.params.leg_length:.1f} mm, cube of {_MM * data.side:.0f} mm; "
        f"{quantity('speed', data.v_max)} and {quantity('acceleration', data.a_max)} "
        "in every direction; motor: " + ("none given" if motor is None else _e(motor.name))
    )
    files = ", ".join(companions)
    sections = [
        ("Verdict", _verdict(data)),
        ("Machine and drive", _machine(data)),
        ("Transmission factors over the cube", _transmission(data)),
        ("Worst case over the cube: maxima and where they occur", _maxima(data)),
        (
            "Worst-case maps",
            _img(images, "force_maps", "force maps") + _img(images, "torque_maps", "torque maps"),
        ),
        ("What the motors guarantee", _guarantees(data, images)),
        ("Standard cycle", _cycle(data, images)),
        ("Motor operating points", _img(images, "operating_points", "operating points")),
        *([] if data.program is None else [("Part program", program_html(data.program))]),
        *(
            []
            if data.stiffness is None
            else [
                (
                    "Stiffness of the tool",
                    stiffness_html(
                        data.stiffness, _img(images, "stiffness_maps", "stiffness maps")
                    ),
                )
            ]
        ),
        *(
            []
            if data.vibration is None
            else [
                (
                    "Vibration: the lowest natural frequency over the cube",
                    vibration_html(
                        data.vibration, _img(images, "vibration_maps", "natural frequency maps")
                    ),
                )
            ]
        ),
        *(
            []
            if data.accuracy is None
            else [
                (
                    "Part accuracy: surface error, error budget, chatter stability",
                    accuracy_html(
                        data.accuracy, _img(images, "accuracy_lobes", "stability lobes")
                    ),
                )
            ]
        ),
        (
            "Files",
            f'<p class="note">Every number of this page, in SI units: {_e(files)} '
            "(next to this file).</p>",
        ),
    ]
    return page("Orthoglide torque-requirement report", subtitle, sections)
