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

A long run is measured and summed up a chunk of periods at a time
(:class:`RunContour`, :class:`Summary`, :func:`column_chunks`): only the
running figures (peaks, sums of squares, counts) stay in memory, and the
figures and the columns are those of the whole run at once (the path speed of
a chunk's first and last periods from their neighbours in the chunks around it).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sampling import csv_text as plan_csv_text
from orthoglide_pin.simulation.contour import ContourError, ContourMeter
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


class Timeline:
    """The plan's blocks that take time, to find the one that runs at given times.

    Args:
        plan: The plan.
    """

    def __init__(self, plan: Plan) -> None:
        timed = [b for b in plan.blocks if b.end > b.start]
        self.empty = not timed
        self.starts = np.array([b.start for b in timed])
        self.lines = np.array([b.line for b in timed], dtype=np.intp)
        self.rapid = np.array([b.kind == "rapid" for b in timed], dtype=bool)
        self.cutting = np.array([b.kind in CUTTING_KINDS for b in timed], dtype=bool)

    def at(self, t: FloatArray) -> tuple[NDArray[np.intp], NDArray[np.bool_], NDArray[np.bool_]]:
        """The program line, whether a rapid move and whether a feed move, at times ``t`` [s]."""
        if self.empty:
            none = np.zeros(t.size, dtype=bool)
            return np.zeros(t.size, dtype=np.intp), none, none.copy()
        k = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, self.starts.size - 1)
        return np.asarray(self.lines[k]), np.asarray(self.rapid[k]), np.asarray(self.cutting[k])


def running_blocks(plan: Plan, t: FloatArray) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """The program line the plan runs at times ``t`` [s], (N,), and whether it is a rapid move.

    A block that takes no time runs at no time; past the end, the last block that takes time.
    """
    lines, rapid, _ = Timeline(plan).at(t)
    return lines, rapid


def cutting_samples(plan: Plan, t: FloatArray) -> NDArray[np.bool_]:
    """Whether the plan runs a feed move (a line, an arc) at times ``t`` [s], (N,).

    Each time is given to its block as by :func:`running_blocks`: rapid moves and dwells
    do not cut.
    """
    return Timeline(plan).at(t)[2]


class RunContour:
    """The contour error of a run's periods (see the module), a chunk at a time.

    The periods when the plan cuts are measured against the feed moves only
    (``cut_only=True``); the others (rapid moves, dwells) against the whole
    path. Each path is sampled once, when first needed.

    Args:
        plan: The plan.
    """

    def __init__(self, plan: Plan) -> None:
        self.plan, self.timeline = plan, Timeline(plan)
        self.meters: dict[bool, ContourMeter] = {}

    def _meter(self, cut_only: bool) -> ContourMeter:
        if cut_only not in self.meters:
            self.meters[cut_only] = ContourMeter(self.plan.path, cut_only=cut_only)
        return self.meters[cut_only]

    def measure(self, t: FloatArray, p: FloatArray) -> ContourError:
        """The contour error of tool points ``p`` [m], (n, 3), at times ``t`` [s], (n,)."""
        cutting = self.timeline.at(t)[2]
        if not cutting.any():
            return self._meter(False).measure(p)
        if cutting.all():
            return self._meter(True).measure(p)
        cut = self._meter(True).measure(p[cutting])
        rest = self._meter(False).measure(p[~cutting])
        distance = np.empty(t.size)
        nearest = np.empty_like(p)
        line = np.empty(t.size, dtype=np.intp)
        for mask, part in ((cutting, cut), (~cutting, rest)):
            distance[mask], nearest[mask], line[mask] = part.distance, part.nearest, part.line
        return ContourError(distance, nearest, line)


def run_contour_error(plan: Plan, run: SimulationRun) -> ContourError:
    """The contour error of a run (see the module): cutting periods against the cut alone."""
    return RunContour(plan).measure(run.t, run.p)


def simulation_columns(
    run: SimulationRun,
    contour: ContourError,
    plan: Plan,
    *,
    before: tuple[float, FloatArray] | None = None,
    after: tuple[float, FloatArray] | None = None,
    timeline: Timeline | None = None,
) -> dict[str, FloatArray]:
    """The run every servo period: column name -> values (see :data:`COLUMNS`).

    ``before`` and ``after`` are the time [s] and tool point [m] of the periods
    just before and just after ``run`` when it is a chunk of a longer run
    (``None`` at the run's start and end): the path speed, a centred
    difference, is then that of the whole run.
    """
    t_ext = [run.t]
    p_ext = [run.p]
    if before is not None:
        t_ext.insert(0, np.array([before[0]]))
        p_ext.insert(0, np.asarray(before[1], dtype=float)[None, :])
    if after is not None:
        t_ext.append(np.array([after[0]]))
        p_ext.append(np.asarray(after[1], dtype=float)[None, :])
    t_all, p_all = np.concatenate(t_ext), np.concatenate(p_ext)
    first = 0 if before is None else 1
    speed = (
        np.linalg.norm(np.gradient(p_all, t_all, axis=0), axis=1)[first : first + run.t.size]
        if t_all.size > 1
        else np.zeros(run.t.size)
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
    lines, rapid, cutting = (timeline or Timeline(plan)).at(run.t)
    out["contour_error"] = contour.distance
    out["line"] = lines.astype(float)
    out["rapid"] = rapid.astype(float)
    out["cutting"] = cutting.astype(float)
    return out


def column_chunks(
    parts: Iterable[tuple[SimulationRun, ContourError]], plan: Plan
) -> Iterator[dict[str, FloatArray]]:
    """:func:`simulation_columns` of consecutive chunks of one run, as the whole run has them."""
    timeline = Timeline(plan)
    pending: tuple[SimulationRun, ContourError] | None = None
    before: tuple[float, FloatArray] | None = None
    for run, contour in parts:
        if pending is not None:
            after = (float(run.t[0]), run.p[0])
            yield simulation_columns(*pending, plan, before=before, after=after, timeline=timeline)
            before = (float(pending[0].t[-1]), pending[0].p[-1])
        pending = (run, contour)
    if pending is not None:
        yield simulation_columns(*pending, plan, before=before, timeline=timeline)


def csv_text(columns: dict[str, FloatArray]) -> str:
    """The columns as CSV text: a header, then one row per servo period (10 significant digits)."""
    return plan_csv_text(columns, COLUMNS)


class Summary:
    """The figures of a run (see :func:`simulation_summary`), summed up a chunk at a time.

    Only running figures are kept: peaks and where they are, sums of squares, counts.

    Args:
        plan: The plan.
    """

    def __init__(self, plan: Plan) -> None:
        self.plan, self.timeline = plan, Timeline(plan)
        self.samples, self.feed_count, self.saturated_count = 0, 0, 0
        self.feed_max, self.feed_squares, self.rapid_max = -np.inf, 0.0, -np.inf
        self.at: dict[str, Any] | None = None
        self.err_max = np.full(3, -np.inf)
        self.err_time = np.zeros(3)
        self.err_squares = np.zeros(3)
        self.slider_saturated = np.zeros(3, dtype=np.int64)
        self.peak = np.full(3, -np.inf)
        self.duration = 0.0

    def add(self, run: SimulationRun, contour: ContourError) -> None:
        """Count the periods of ``run`` (the next chunk of the run) and their contour error."""
        lines, rapid, feed = self.timeline.at(run.t)
        dist = contour.distance
        if feed.any():
            k = int(np.flatnonzero(feed)[np.argmax(dist[feed])])
            if dist[k] > self.feed_max:
                self.feed_max = float(dist[k])
                self.at = {
                    "t": float(run.t[k]),
                    "x": float(run.p[k, 0]),
                    "y": float(run.p[k, 1]),
                    "z": float(run.p[k, 2]),
                    "line": int(lines[k]),
                }
            self.feed_squares += float(np.sum(dist[feed] ** 2))
            self.feed_count += int(feed.sum())
        if rapid.any():
            self.rapid_max = max(self.rapid_max, float(dist[rapid].max()))
        err = np.abs(run.tracking_error)
        for i in range(3):
            j = int(np.argmax(err[:, i]))
            if err[j, i] > self.err_max[i]:
                self.err_max[i], self.err_time[i] = err[j, i], run.t[j]
        self.err_squares += np.sum(err**2, axis=0)
        self.saturated_count += int(run.saturated.any(axis=1).sum())
        self.slider_saturated += run.saturated.sum(axis=0)
        self.peak = np.maximum(self.peak, np.abs(run.torque).max(axis=0))
        self.samples += int(run.t.size)
        self.duration = float(run.t[-1])

    def figures(self, run: SimulationRun) -> dict[str, Any]:
        """The figures of the periods added (keys of ``simulate --json``); ``run``, any chunk."""
        plan, settings, motor = self.plan, run.settings, run.drive.motor
        cutting_time = sum(b.end - b.start for b in plan.blocks if b.kind in CUTTING_KINDS)
        feed = self.feed_count > 0
        n = max(self.samples, 1)
        return {
            "max_contour_error": self.feed_max if feed else 0.0,
            "rms_contour_error": float(np.sqrt(self.feed_squares / self.feed_count))
            if feed
            else 0.0,
            "max_contour_error_at": self.at if feed else None,
            "max_rapid_deviation": self.rapid_max if np.isfinite(self.rapid_max) else 0.0,
            "cutting_time": float(cutting_time),
            "cutting_share": float(cutting_time / plan.cycle_time) if plan.cycle_time > 0 else 0.0,
            "max_tracking_error": [float(v) for v in self.err_max],
            "max_tracking_error_time": [float(v) for v in self.err_time],
            "rms_tracking_error": [float(v) for v in np.sqrt(self.err_squares / n)],
            "saturation_time": float(self.saturated_count * settings.period),
            "saturation_time_per_slider": [
                float(v) for v in self.slider_saturated * settings.period
            ],
            "peak_torque": [float(v) for v in self.peak],
            "duration": self.duration,
            "samples": self.samples,
            "controller": settings.controller,
            "rate": settings.rate,
            "timestep": run.timestep,
            "encoder_counts": settings.encoder_counts,
            "mass_error": settings.mass_error,
            "friction_error": settings.friction_error,
            "motor": None if motor is None else motor.name,
        }


def simulation_summary(run: SimulationRun, contour: ContourError, plan: Plan) -> dict[str, Any]:
    """The figures of a run (keys of ``simulate --json``), SI units.

    The contour figures count the periods when the plan cuts (:func:`cutting_samples`);
    ``contour`` is :func:`run_contour_error`'s. Without a feed move, they are 0 and
    ``max_contour_error_at`` is ``None``.
    """
    summary = Summary(plan)
    summary.add(run, contour)
    return summary.figures(run)
