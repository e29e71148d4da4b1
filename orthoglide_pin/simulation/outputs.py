"""What a simulation writes: the columns of ``simulation.csv`` and its JSON summary.

:func:`simulation_columns` samples the run at every servo period
(:data:`COLUMNS`, SI units): the simulated tool and sliders, the planned ones,
the tracking errors, the motor torques against the torque available, the
saturation flags and the contour error with the program line it refers to.
The file keeps the columns ``t, x, y, z, path_speed, q1..q3`` of a planned
trajectory, so that ``orthoglide view --trajectory DIR/simulation.csv`` plays
the simulated tool. :func:`simulation_summary` gives the figures of
``simulate --json``.

The contour error is measured where the tool cuts (:func:`run_contour_error`):
only in the periods when the plan runs a feed move (``G1``, ``G2``, ``G3``;
not a rapid move, not a dwell), and against the cutting path alone (the feed
moves, not the rapid ones), so that a tool lagging on a rapid line while the
plan plunges is measured against the plunge. The other periods are measured
against the whole path: rapid moves (``G0``) position the tool, and its
largest distance to the path while they run is reported apart
(``max_rapid_deviation``). Each period is given to the block the plan runs at
that time (:func:`running_blocks`), whose line the CSV names; ``cutting_time``
and ``cutting_share`` say how much of the cycle cuts.
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sampling import csv_text as plan_csv_text
from orthoglide_pin.simulation.contour import ContourError, contour_error
from orthoglide_pin.simulation.run import SimulationRun

FloatArray = NDArray[np.float64]

#: The columns of ``simulation.csv``, SI units.
COLUMNS: Final = (
    "t", "x", "y", "z", "path_speed", "q1", "q2", "q3",
    "x_ref", "y_ref", "z_ref", "q1_ref", "q2_ref", "q3_ref",
    "e1", "e2", "e3", "tau1", "tau2", "tau3",
    "tau_available1", "tau_available2", "tau_available3",
    "saturated1", "saturated2", "saturated3",
    "contour_error", "line", "rapid", "cutting",
)  # fmt: skip
#: The kinds of the plan's blocks that cut (feed moves).
CUTTING_KINDS: Final = ("line", "arc")


def running_blocks(plan: Plan, t: FloatArray) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """The program line the plan runs at times ``t`` [s], (N,), and whether it is a rapid move.

    A block that takes no time runs at no time; past the end, the last block that takes time.
    """
    timed = [b for b in plan.blocks if b.end > b.start]
    if not timed:
        return np.zeros(t.size, dtype=np.intp), np.zeros(t.size, dtype=bool)
    starts = np.array([b.start for b in timed])
    k = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(timed) - 1)
    lines = np.array([b.line for b in timed], dtype=np.intp)[k]
    rapid = np.array([b.kind == "rapid" for b in timed], dtype=bool)[k]
    return np.asarray(lines), np.asarray(rapid)


def cutting_samples(plan: Plan, t: FloatArray) -> NDArray[np.bool_]:
    """Whether the plan runs a feed move (a line, an arc) at times ``t`` [s], (N,).

    Each time is given to its block as by :func:`running_blocks`: rapid moves and dwells
    do not cut.
    """
    timed = [b for b in plan.blocks if b.end > b.start]
    if not timed:
        return np.zeros(t.size, dtype=bool)
    starts = np.array([b.start for b in timed])
    k = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(timed) - 1)
    return np.asarray(np.array([b.kind in CUTTING_KINDS for b in timed], dtype=bool)[k])


def run_contour_error(plan: Plan, run: SimulationRun) -> ContourError:
    """The contour error of a run (see the module): cutting periods against the cut alone.

    The periods when the plan cuts are measured against the feed moves only
    (``contour_error(..., cut_only=True)``); the others (rapid moves, dwells) against the
    whole path.
    """
    cutting = cutting_samples(plan, run.t)
    if not cutting.any():
        return contour_error(plan.path, run.p)
    if cutting.all():
        return contour_error(plan.path, run.p, cut_only=True)
    cut = contour_error(plan.path, run.p[cutting], cut_only=True)
    rest = contour_error(plan.path, run.p[~cutting])
    distance = np.empty(run.t.size)
    nearest = np.empty_like(run.p)
    line = np.empty(run.t.size, dtype=np.intp)
    for mask, part in ((cutting, cut), (~cutting, rest)):
        distance[mask], nearest[mask], line[mask] = part.distance, part.nearest, part.line
    return ContourError(distance, nearest, line)


def simulation_columns(
    run: SimulationRun, contour: ContourError, plan: Plan
) -> dict[str, FloatArray]:
    """The run every servo period: column name -> values (see :data:`COLUMNS`)."""
    speed = (
        np.linalg.norm(np.gradient(run.p, run.t, axis=0), axis=1)
        if run.t.size > 1
        else (np.zeros(run.t.size))
    )
    out: dict[str, FloatArray] = {"t": run.t}
    for k, c in enumerate("xyz"):
        out[c] = run.p[:, k]
    out["path_speed"] = np.asarray(speed)
    for i in range(3):
        out[f"q{i + 1}"] = run.q[:, i]
    for k, c in enumerate("xyz"):
        out[f"{c}_ref"] = run.p_ref[:, k]
    err = run.tracking_error
    for i in range(3):
        out[f"q{i + 1}_ref"] = run.q_ref[:, i]
    for i in range(3):
        out[f"e{i + 1}"] = err[:, i]
    for i in range(3):
        out[f"tau{i + 1}"] = run.torque[:, i]
    available = np.where(np.isfinite(run.available), run.available, -1.0)
    for i in range(3):
        out[f"tau_available{i + 1}"] = available[:, i]
    for i in range(3):
        out[f"saturated{i + 1}"] = run.saturated[:, i].astype(float)
    lines, rapid = running_blocks(plan, run.t)
    out["contour_error"] = contour.distance
    out["line"] = lines.astype(float)
    out["rapid"] = rapid.astype(float)
    out["cutting"] = cutting_samples(plan, run.t).astype(float)
    return out


def csv_text(columns: dict[str, FloatArray]) -> str:
    """The columns as CSV text: a header, then one row per servo period (10 significant digits)."""
    return plan_csv_text(columns, COLUMNS)


def simulation_summary(run: SimulationRun, contour: ContourError, plan: Plan) -> dict[str, Any]:
    """The figures of a run (keys of ``simulate --json``), SI units.

    The contour figures count the periods when the plan cuts (:func:`cutting_samples`);
    ``contour`` is :func:`run_contour_error`'s. Without a feed move, they are 0 and
    ``max_contour_error_at`` is ``None``.
    """
    lines, rapid = running_blocks(plan, run.t)
    feed = cutting_samples(plan, run.t)
    cutting_time = sum(b.end - b.start for b in plan.blocks if b.kind in CUTTING_KINDS)
    dist = contour.distance
    at: dict[str, Any] | None = None
    if feed.any():
        k = int(np.flatnonzero(feed)[np.argmax(dist[feed])])
        at = {
            "t": float(run.t[k]),
            "x": float(run.p[k, 0]),
            "y": float(run.p[k, 1]),
            "z": float(run.p[k, 2]),
            "line": int(lines[k]),
        }
    err = np.abs(run.tracking_error)
    worst_t = [float(run.t[int(np.argmax(err[:, i]))]) for i in range(3)]
    settings = run.settings
    motor = run.drive.motor
    return {
        "max_contour_error": float(dist[feed].max()) if feed.any() else 0.0,
        "rms_contour_error": float(np.sqrt(np.mean(dist[feed] ** 2))) if feed.any() else 0.0,
        "max_contour_error_at": at,
        "max_rapid_deviation": float(dist[rapid].max()) if rapid.any() else 0.0,
        "cutting_time": float(cutting_time),
        "cutting_share": float(cutting_time / plan.cycle_time) if plan.cycle_time > 0 else 0.0,
        "max_tracking_error": [float(v) for v in err.max(axis=0)],
        "max_tracking_error_time": worst_t,
        "rms_tracking_error": [float(v) for v in np.sqrt(np.mean(err**2, axis=0))],
        "saturation_time": run.any_saturation_time,
        "saturation_time_per_slider": [float(v) for v in run.saturation_time],
        "peak_torque": [float(v) for v in np.abs(run.torque).max(axis=0)],
        "duration": float(run.t[-1]),
        "samples": int(run.t.size),
        "controller": settings.controller,
        "rate": settings.rate,
        "timestep": run.timestep,
        "encoder_counts": settings.encoder_counts,
        "mass_error": settings.mass_error,
        "friction_error": settings.friction_error,
        "motor": None if motor is None else motor.name,
    }
