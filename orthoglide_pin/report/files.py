"""The report's files: ``report.json``, the CSV tables and the atomic write of the whole.

:func:`write_report` writes, into one directory, atomically (every file is
written into a temporary sibling directory that is renamed into place at the
end, :func:`~orthoglide_pin._outdir.atomic_directory`):

* ``report.html``: the human report (:mod:`orthoglide_pin.report.html`);
* ``report.json``: every number of the report, SI units (:func:`report_dict`);
* ``summary.csv``: the verdict table, one row per motor and criterion;
* ``maps.csv``: the worst case at every point of the map slices;
* ``cube.csv``: the worst case at every point of the cube grid (the maxima);
* ``cycle.csv``: the standard cycle, sample by sample;
* ``vibration.csv``: the lowest natural frequency at every point of its cube grid.

plus a marker, ``.orthoglide-output``, that lists them and marks the
directory as the package's own (:mod:`orthoglide_pin._paths`).

The directory is never a place where the user's files are lost: a new
directory or an empty one is fine; an existing report directory (with the
marker) is replaced whole when it holds nothing else, else only the report's
files in it are replaced; any other non-empty directory (the working
directory included) is refused unless ``force``, which writes the report's
files into it and keeps every other file. An entry named like a report file
that the package did not write is refused too (a directory or a special file
even when forced; a file unless forced), and nothing is removed. The refusal
comes before any computation (:func:`check_report_directory`).

Non-finite numbers (a margin of ``-inf``: torque needed where the motor has
none) are ``null`` in the JSON and empty in the CSV; the JSON is strict (no
``NaN`` or ``Infinity``).
"""

from __future__ import annotations

import dataclasses
import importlib.metadata
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._io import strict_json
from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin._paths import check_replaceable, output_directory
from orthoglide_pin._validation import flag, instance_of, optional_callable, path_argument
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.dynamics.requirements import WorstCase
from orthoglide_pin.report.accuracy import accuracy_dict
from orthoglide_pin.report.assemble import NO_MOTOR_HINT, Progress, ReportData
from orthoglide_pin.report.program import program_dict
from orthoglide_pin.report.stiffness import stiffness_dict
from orthoglide_pin.report.vibration import vibration_csv, vibration_dict

FloatArray = NDArray[np.float64]

#: File names inside the report directory.
HTML_NAME: Final = "report.html"
JSON_NAME: Final = "report.json"
#: The CSV files and what they hold.
CSV_FILES: Final = {
    "summary.csv": "verdict table: one row per motor and criterion",
    "maps.csv": "worst case at every point of the map slices",
    "cube.csv": "worst case at every point of the cube grid",
    "cycle.csv": "standard cycle, one row per sample",
    "vibration.csv": "lowest natural frequency at every point of the cube grid",
}
#: Per-point fields of a worst case, in CSV column order (``_1``.. ``_3`` per slider).
POINT_FIELDS: Final = (
    "force",
    "force_min",
    "force_max",
    "torque",
    "torque_exact",
    "friction",
    "slider_speed",
    "motor_speed_rpm",
)
#: Guarantee fields (one column each), with motor data.
GUARANTEE_FIELDS: Final = ("speed", "acceleration_at_rest", "acceleration_at_speed")
_FMT: Final = "%.12g"


def _worst_dict(wc: WorstCase) -> dict[str, Any]:
    out = wc.to_dict()
    out["force_min"] = wc.force_min.min(axis=0)
    out["force_max"] = wc.force_max.max(axis=0)
    out["torque_exact_fraction"] = float(wc.torque_exact.mean())
    out["friction_max"] = wc.friction.max(axis=0)
    if wc.grid is not None:
        out["grid_shape"] = list(wc.grid.shape)
    return out


def report_dict(data: ReportData) -> dict[str, Any]:
    """Every number of the report, SI units (motor speeds in rpm), JSON-ready."""
    p, train, motor = data.params, data.drive.train, data.drive.motor
    inertia = inertia_table(p)
    res, stats = data.cycle_dynamics, data.sizing.statistics
    cycle = data.cycle
    out: dict[str, Any] = {
        "title": "Orthoglide torque-requirement report",
        "version": importlib.metadata.version("orthoglide-pin"),
        "units": "SI (m, s, kg, N, N.m, rad); motor speeds in rpm",
        "machine": {
            "parameters": p.to_dict(),
            "slider_limits": [p.slider_lower, p.slider_upper],
            "stroke": p.stroke,
            "masses": inertia.to_dict()["by_kind"],
            "total_moving_mass": inertia.total_moving_mass,
        },
        "assumptions": data.assumptions,
        "specification": {
            "v_max": data.v_max,
            "a_max": data.a_max,
            "jerk": data.jerk,
            "gravity": data.gravity,
        },
        "cube": {"corner": data.corner, "side": data.side},
        "drive": {
            "drive_train": dataclasses.asdict(train),
            "screw_inertia": train.screw_inertia_value,
            "reflected_inertia": train.reflected_inertia,
            "motor": None if motor is None else dataclasses.asdict(motor),
        },
        "worst_case": {**_worst_dict(data.cube), "worst_motions": data.worst_motions},
        "slices": [
            {"label": s.label, "axis": s.axis, "value": s.value, **_worst_dict(s.worst)}
            for s in data.slices
        ],
        "cycle": {
            "duration": cycle.duration,
            "samples": len(cycle),
            "dt": cycle.dt,
            "segments": list(cycle.labels),
            "peak_tool_speed": float(cycle.speed.max()),
            "peak_tool_acceleration": float(np.linalg.norm(cycle.a, axis=1).max()),
            "slider_range": [res.slider_positions.min(axis=0), res.slider_positions.max(axis=0)],
            "peak_slider_speed": np.abs(res.slider_velocities).max(axis=0),
            "peak_force": np.abs(res.forces).max(axis=0),
            "peak_torque": stats.peak_torque,
            "rms_torque": stats.rms_torque,
            "peak_speed_rpm": stats.peak_speed_rpm,
            "peak_power": stats.peak_power,
            "check": None if data.sizing.check is None else data.sizing.check.to_dict(),
        },
        "verdict": {
            "passed": data.passed,
            "note": None if data.motor_given else NO_MOTOR_HINT,
            "safety_factor": data.safety_factor,
            "safety_factor_applies_to": "required torques (speeds are not multiplied)",
            "rows": [{**dataclasses.asdict(r), "passed": r.passed} for r in data.verdict],
        },
        "stiffness": None if data.stiffness is None else stiffness_dict(data.stiffness),
        "transmission": None if data.transmission is None else data.transmission.to_dict(),
        "program": None if data.program is None else program_dict(data.program),
        "vibration": None if data.vibration is None else vibration_dict(data.vibration),
        "accuracy": None if data.accuracy is None else accuracy_dict(data.accuracy),
        "files": {"html": HTML_NAME, "csv": CSV_FILES},
    }
    return dict(strict_json(out))


def to_json(data: ReportData) -> str:
    """:func:`report_dict` as indented JSON text."""
    return json.dumps(report_dict(data), indent=2, allow_nan=False) + "\n"


def _table(header: list[str], columns: list[FloatArray], labels: list[str] | None = None) -> str:
    """CSV text of numeric columns after optional text ``labels``; empty for non-finite."""
    matrix = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    buf = io.StringIO()
    np.savetxt(buf, matrix, delimiter=",", fmt=_FMT)
    lines = buf.getvalue().replace("nan", "").replace("-inf", "").replace("inf", "").splitlines()
    if labels is not None:
        lines = [f"{label},{line}" for label, line in zip(labels, lines, strict=True)]
    return ",".join(header) + "\n" + "\n".join(lines) + "\n"


def _point_columns(wc: WorstCase) -> tuple[list[str], list[FloatArray]]:
    names, cols = ["x", "y", "z"], list(wc.points.T)
    for field in POINT_FIELDS:
        values = np.asarray(getattr(wc, field), dtype=float)
        names += [f"{field}_{i + 1}" for i in range(3)]
        cols += list(values.T)
    for field in GUARANTEE_FIELDS:
        values = getattr(wc.guarantees, field)
        if values is not None:
            names.append(f"guaranteed_{field}")
            cols.append(values)
    return names, cols


def csv_tables(data: ReportData) -> dict[str, str]:
    """The CSV files of the report, by name (see the module)."""
    rows = data.verdict
    summary = _table(
        ["criterion", "unit", "motor", "required", "available", "margin", "passed"],
        [
            np.array([math.nan if r.motor is None else r.motor for r in rows]),
            np.array([r.required for r in rows]),
            np.array([math.nan if r.available is None else r.available for r in rows]),
            np.array([math.nan if r.margin is None else r.margin for r in rows]),
            np.array([math.nan if r.passed is None else float(r.passed) for r in rows]),
        ],
        [f"{r.criterion},{r.unit}" for r in rows],
    )
    header, _ = _point_columns(data.slices[0].worst)
    parts = [_point_columns(s.worst)[1] for s in data.slices]
    maps = _table(
        ["slice", *header],
        [np.concatenate(c) for c in zip(*parts, strict=True)],
        [s.label for s in data.slices for _ in range(len(s.worst))],
    )
    cube = _table(*_point_columns(data.cube))
    c, res, demand = data.cycle, data.cycle_dynamics, data.sizing.demand
    groups = [
        ("x y z", c.p),
        ("vx vy vz", c.v),
        ("ax ay az", c.a),
        ("q", res.slider_positions),
        ("q_dot", res.slider_velocities),
        ("q_ddot", res.slider_accelerations),
        ("force", res.forces),
        ("torque", demand.torque),
        ("motor_speed_rpm", demand.speed_rpm),
    ]
    names, cols = ["t", "segment"], [c.t, c.segment.astype(float)]
    for name, values in groups:
        names += name.split() if " " in name else [f"{name}_{i + 1}" for i in range(3)]
        cols += list(values.T)
    out = {"summary.csv": summary, "maps.csv": maps, "cube.csv": cube}
    out["cycle.csv"] = _table(names, cols)
    if data.vibration is not None:
        out["vibration.csv"] = vibration_csv(data.vibration)
    return out


@dataclass(frozen=True)
class ReportFiles:
    """Where the report was written.

    Attributes:
        directory: The report directory.
        html: ``report.html``.
        json: ``report.json``.
        csv: The CSV files, by name.
        passed: The verdict (``None`` without motor data).
    """

    directory: Path
    html: Path
    json: Path
    csv: dict[str, Path]
    passed: bool | None


def check_report_directory(out: str | Path, *, force: bool = False) -> Path:
    """Check that ``out`` may receive a report, before anything is computed.

    Args:
        out: The report directory.
        force: Accept an existing non-empty directory the package did not write.

    Returns:
        ``Path(out)``.

    Raises:
        OutputPathError: See :func:`write_report`.
    """
    target = output_directory(out, force=force)
    if target.is_dir():
        check_replaceable(out, [HTML_NAME, JSON_NAME, *CSV_FILES], force=force)
    return target


def write_report(
    out: str | Path,
    data: ReportData,
    *,
    progress: Progress | None = None,
    force: bool = False,
) -> ReportFiles:
    """Write the report of ``data`` into the directory ``out``, atomically.

    Args:
        out: The report directory (created, or its report files replaced only
            at the end; see the module for what happens to other files).
        data: From :func:`~orthoglide_pin.report.assemble.assemble_report`.
        progress: Makes a progress bar for the figures, or ``None``.
        force: Also write into an existing non-empty directory that holds no
            report (the report's files are added; every other file is kept).

    Returns:
        The paths written.

    Raises:
        OutputPathError: ``out`` is empty, is not a directory, is a non-empty
            directory without a report (unless ``force``), holds an entry
            named like a report file that the package did not write, or
            cannot be written.
    """
    from orthoglide_pin.report import figures as report_figures
    from orthoglide_pin.report import html as report_html

    instance_of("data", data, ReportData, "a ReportData (assemble_report)")
    out, force = path_argument("out", out), flag("force", force)
    progress = optional_callable("progress", progress, "a progress-bar factory or None")
    check_report_directory(out, force=force)
    target = Path(out).absolute()
    tables = csv_tables(data)
    with atomic_directory(out, force=force) as tmp:
        for name, text in tables.items():
            (tmp / name).write_text(text)
        (tmp / JSON_NAME).write_text(to_json(data))
        images = report_figures.figures(data, progress=progress)
        (tmp / HTML_NAME).write_text(report_html.render_html(data, images, [JSON_NAME, *tables]))
    return ReportFiles(
        directory=target,
        html=target / HTML_NAME,
        json=target / JSON_NAME,
        csv={name: target / name for name in tables},
        passed=data.passed,
    )
