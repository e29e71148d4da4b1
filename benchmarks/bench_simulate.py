"""Simulating a planned part program in MuJoCo: its cost against MuJoCo's bare steps, its memory.

Run on demand: ``python benchmarks/bench_simulate.py [--json] [--blocks N] [--feed F]
[--format csv|parquet]``.
Two programs, each planned with the example drive (not timed), then run under the
default servo (``pid_ff`` at 4 kHz, one MuJoCo step a period) the way ``orthoglide
simulate`` runs it: :func:`~orthoglide_pin.simulation.stream.write_simulation`, a
chunk of periods at a time, with the contour error, the summary and the file
(``simulation.csv``, or ``.parquet``) written to a temporary directory. Then, in
the same process, MuJoCo's bare ``mj_step`` as many times on the same model, held
at the program's start by its feedforward. Measured on processor time (the machine
is shared; the wall times are printed too):

* ``contour``, the shipped program (best of 3);
* ``relief``, a raster over a relief of ``--blocks`` G1 blocks of 0.1 to 0.5 mm
  (``G64 P0.01``; 6,604 blocks at F1500 by default: 78 s, 312,000 periods), once.

Printed for each: ``periods`` (the samples written), ``simulate_cpu_s`` and
``simulate_wall_s`` (the whole streamed run), ``mj_step_cpu_s`` and ``mj_step_wall_s``
(the bare steps), ``ratio`` (``simulate_cpu_s`` over ``mj_step_cpu_s``: 1 would be
MuJoCo alone; the target is at most 2.5), ``file_mb``, and ``max_contour_error``
(so a change that speeds the run by breaking it shows); for the relief also
``plan_rss_mb`` (the process's peak resident memory once planned) and
``peak_rss_mb`` (once simulated: what the run adds does not grow with the program).
"""

from __future__ import annotations

import argparse
import math
import resource
import tempfile
import time
from pathlib import Path
from typing import Any

from _timing import emit
from bench_plan_scale import relief_program

import orthoglide_pin as og
from orthoglide_pin.simulation.run import _start
from orthoglide_pin.simulation.stream import write_simulation

REPEATS = 3
#: The relief's blocks and feed [mm/min] by default (a 78 s program).
BLOCKS, FEED = 6604, 1500.0


def peak_rss_mb() -> float:
    """The process's peak resident memory [MB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def bare_steps(plan: og.Plan, dyn: Any, drive: Any, steps: int) -> tuple[float, float]:
    """Processor and wall time [s] of ``steps`` bare ``mj_step`` on the run's model."""
    import mujoco

    start = _start(plan, dyn, drive, None, capped=False)
    model, data, constants = start.model, start.data, start.constants
    first = next(iter(start.references(1)))
    data.ctrl[:] = first.feedforward[0] * constants.ratio * constants.efficiency  # at rest
    step = mujoco.mj_step
    wall, cpu = time.perf_counter(), time.process_time()
    for _ in range(steps):
        step(model, data)
    return time.process_time() - cpu, time.perf_counter() - wall


def measure(
    plan: og.Plan, dyn: Any, drive: Any, repeats: int, file_format: str
) -> dict[str, float]:
    """Time the streamed run and the bare steps (best of ``repeats``)."""
    best = {
        k: math.inf
        for k in ("simulate_cpu_s", "simulate_wall_s", "mj_step_cpu_s", "mj_step_wall_s")
    }
    out: Any = None
    size = 0
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            target = Path(tmp) / f"simulation.{file_format}"
            wall, cpu = time.perf_counter(), time.process_time()
            out = write_simulation(target, plan, dyn, drive, file_format=file_format)
            best["simulate_cpu_s"] = min(best["simulate_cpu_s"], time.process_time() - cpu)
            best["simulate_wall_s"] = min(best["simulate_wall_s"], time.perf_counter() - wall)
            size = target.stat().st_size
        substeps = max(1, round(og.ServoSettings().period / out.timestep))
        cpu_s, wall_s = bare_steps(plan, dyn, drive, out.samples * substeps)
        best["mj_step_cpu_s"] = min(best["mj_step_cpu_s"], cpu_s)
        best["mj_step_wall_s"] = min(best["mj_step_wall_s"], wall_s)
    return {
        "periods": out.samples,
        **best,
        "ratio": best["simulate_cpu_s"] / best["mj_step_cpu_s"],
        "ratio_wall": best["simulate_wall_s"] / best["mj_step_wall_s"],
        "file_mb": size / 1e6,
        "max_contour_error": out.summary["max_contour_error"],
    }


def bench_simulate(blocks: int, feed: float, file_format: str) -> dict[str, float]:
    """The figures of both programs (see the module), keys prefixed by the program's name."""
    drive = og.load_drive(str(og.example_drive_file()))
    dyn = og.ClosedLoopDynamics()
    # the whole motor torque, as when the guide's figures were measured
    limits = og.PlanLimits(drive=drive, torque_reserve=0.0)
    contour = og.plan_program(og.read_program(og.example_program_text("contour")), dyn, limits)
    figures = {
        f"contour_{k}": v for k, v in measure(contour, dyn, drive, REPEATS, file_format).items()
    }
    text = relief_program(blocks).replace("F3000", f"F{feed:g}")
    relief = og.plan_program(og.read_program(text), dyn, og.PlanLimits(drive=drive))
    figures["relief_blocks"] = blocks
    figures["relief_cycle_time"] = relief.cycle_time
    figures["relief_plan_rss_mb"] = peak_rss_mb()
    figures.update(
        {f"relief_{k}": v for k, v in measure(relief, dyn, drive, 1, file_format).items()}
    )
    figures["relief_peak_rss_mb"] = peak_rss_mb()
    return figures


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--json",
        action="store_true",
        help="after the table, print one JSON object of the figures on the last line",
    )
    parser.add_argument("--blocks", type=int, default=BLOCKS, help="blocks of the relief")
    parser.add_argument("--feed", type=float, default=FEED, help="its feed [mm/min]")
    parser.add_argument("--format", choices=("csv", "parquet"), default="csv")
    args = parser.parse_args()
    figures = bench_simulate(args.blocks, args.feed, args.format)
    for key, value in figures.items():
        print(f"{key:28s} {value:.6g}")
    emit(args, figures)


if __name__ == "__main__":
    main()
