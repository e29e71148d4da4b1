"""A simulated run written to disk as it goes: :func:`write_simulation`.

The run (:func:`~orthoglide_pin.simulation.run.simulate_chunks`) comes a chunk
of servo periods at a time; each chunk's contour error is measured
(:class:`~orthoglide_pin.simulation.outputs.RunContour`), its figures added to
the running summary (:class:`~orthoglide_pin.simulation.outputs.Summary`), and
its columns (:data:`~orthoglide_pin.simulation.outputs.COLUMNS`) written by the
planned trajectory's writer
(:func:`~orthoglide_pin.planning.trajectory_file.write_trajectory`: CSV, or
Parquet with the ``[tables]`` extra), which also keeps the plotting copy of the
page (:data:`PLOTTED`: every bucket's extremes of the plotted columns). The
memory needed grows with the chunk, not with the program; the file and the
figures are those of the whole run held in memory (the contour error to its
projection's tolerance).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.motion_forms import as_dynamics
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.trajectory_file import write_trajectory
from orthoglide_pin.simulation.contour import ContourError
from orthoglide_pin.simulation.outputs import COLUMNS, RunContour, Summary, column_chunks
from orthoglide_pin.simulation.reference import run_periods
from orthoglide_pin.simulation.run import CHUNK_PERIODS, SimulationRun, simulate_chunks
from orthoglide_pin.simulation.servo import ServoSettings

FloatArray = NDArray[np.float64]

#: The columns whose extremes every bucket of the page's plotting copy keeps.
PLOTTED: Final = (
    "contour_error", "e1", "e2", "e3", "tau1", "tau2", "tau3", "path_speed",
)  # fmt: skip


@dataclass(frozen=True)
class Streamed:
    """What :func:`write_simulation` wrote.

    Attributes:
        summary: The run's figures (:func:`~orthoglide_pin.simulation.outputs.simulation_summary`).
        plot: The plotting copy of the columns: column name -> values, at most a
            few thousand rows, every bucket's extremes of :data:`PLOTTED` kept.
        samples: The periods written.
        timestep: MuJoCo's step [s].
    """

    summary: dict[str, Any]
    plot: dict[str, FloatArray]
    samples: int
    timestep: float


def write_simulation(
    path: str | os.PathLike[str],
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None = None,
    drive: Drive | None = None,
    settings: ServoSettings | None = None,
    *,
    first_line: str = "",
    file_format: str = "csv",
    progress: Callable[[int, int], None] | None = None,
    chunk: int = CHUNK_PERIODS,
) -> Streamed:
    """Run a plan in MuJoCo and write its columns to ``path`` as they come (see the module).

    Args:
        path: The file (``simulation.csv`` or ``simulation.parquet``).
        plan: As :func:`~orthoglide_pin.simulation.run.simulate`.
        machine: As :func:`~orthoglide_pin.simulation.run.simulate`.
        drive: As :func:`~orthoglide_pin.simulation.run.simulate`.
        settings: As :func:`~orthoglide_pin.simulation.run.simulate`.
        first_line: A line written first (CSV), or kept in the metadata (Parquet),
            newline included.
        file_format: ``"csv"`` or ``"parquet"``.
        progress: Called with (periods simulated, periods) as the run goes, or ``None``.
        chunk: Servo periods per chunk (>= 1).

    Returns:
        The summary, the plotting copy and the periods written.

    Raises:
        As :func:`~orthoglide_pin.simulation.run.simulate_chunks` (no limit on the
        periods), and :func:`~orthoglide_pin.planning.trajectory_file.write_trajectory`.
    """
    dyn = as_dynamics(machine)
    runs = simulate_chunks(plan, dyn, drive, settings, progress=progress, chunk=chunk)
    # the arguments are checked: the run's periods are known before any is made
    total = run_periods(plan, (ServoSettings() if settings is None else settings).period)
    contour, summary = RunContour(plan), Summary(plan)
    last: list[SimulationRun] = []

    def measured() -> Iterator[tuple[SimulationRun, ContourError]]:
        for run in runs:
            error = contour.measure(run.t, run.p)
            summary.add(run, error)
            last[:] = [run]
            yield run, error

    written = write_trajectory(
        path,
        column_chunks(measured(), plan),
        total,
        first_line=first_line,
        file_format=file_format,
        order=COLUMNS,
        extremes=PLOTTED,
    )
    return Streamed(summary.figures(last[0]), written.plot, written.samples, last[0].timestep)
