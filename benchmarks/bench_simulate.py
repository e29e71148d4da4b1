"""Simulating a planned part program in MuJoCo: servo periods per second.

Run on demand: ``python benchmarks/bench_simulate.py [--json]``. The shipped
``contour`` program is planned with the example drive, then run under the
default servo (``pid_ff`` at 4 kHz, one MuJoCo step a period). Printed:
``periods`` (servo periods of the run), ``simulate_s`` (best of 2, the
feedforward's inverse dynamics included), ``periods_per_s``, ``mj_step_per_s``
(MuJoCo's bare ``mj_step`` on the same model, measured in the same run) and
their ratio ``overhead`` (the servo loop, the drive and the bookkeeping per
period, in units of one MuJoCo step); and the contour error found, so a
change that speeds the loop by breaking it shows.
"""

from __future__ import annotations

import time

import numpy as np
from _timing import best_per_call, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.simulation.engine import compile_mjcf
from orthoglide_pin.simulation.mjcf import mjcf_text
from orthoglide_pin.simulation.outputs import simulation_summary


def bench_simulate() -> dict[str, float]:
    """Time the run of the contour program and MuJoCo's bare step."""
    import mujoco

    drive = og.load_drive(str(og.example_drive_file()))
    dyn = og.ClosedLoopDynamics()
    plan = og.plan_program(
        og.read_program(og.example_program_text("contour")), dyn, og.PlanLimits(drive=drive)
    )
    best, run = np.inf, None
    for _ in range(2):
        start = time.perf_counter()
        run = og.simulate(plan, dyn, drive)
        best = min(best, time.perf_counter() - start)
    assert run is not None
    model = compile_mjcf(mjcf_text(None, drive))
    data = mujoco.MjData(model)
    step = best_per_call(lambda: mujoco.mj_step(model, data), 2000, repeats=3)
    summary = simulation_summary(run, og.contour_error(plan.path, run.p), plan)
    periods = run.t.size
    return {
        "periods": periods,
        "simulate_s": best,
        "periods_per_s": periods / best,
        "mj_step_per_s": 1.0 / step,
        "overhead": (best / periods) / step,
        "max_contour_error": summary["max_contour_error"],
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    figures = bench_simulate()
    for key, value in figures.items():
        print(f"{key:20s} {value:.6g}")
    emit(args, figures)


if __name__ == "__main__":
    main()
