"""Simulating a planned part program in MuJoCo: servo periods per second.

Run on demand: ``python benchmarks/bench_simulate.py [--json]``. The shipped
``contour`` program is planned with the example drive, then run under the
default servo (``pid_ff`` at 4 kHz, one MuJoCo step a period). Timed in turn,
best of 3 (the ratios survive a loaded machine): ``simulate_s`` (the whole
:func:`~orthoglide_pin.simulation.run.simulate`), ``prepare_s`` (what it does
before its loop, in batch: the plan sampled every period, the feedforward's
inverse dynamics, the model compiled) and ``mj_step_s``, MuJoCo's bare
``mj_step`` for as many periods on the same model, held at the program's start
by its feedforward. Printed: ``periods``, those times, ``periods_per_s``, and
the ratios ``overhead`` (``simulate_s`` over the bare steps: 1 would be MuJoCo
alone) and ``loop_overhead`` (the loop alone, ``simulate_s - prepare_s``, over
the bare steps); and the contour error found, so a change that speeds the loop
by breaking it shows.
"""

from __future__ import annotations

import math
import time

import numpy as np
from _timing import emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.simulation.outputs import simulation_summary
from orthoglide_pin.simulation.run import prepare

REPEATS = 3


def bench_simulate() -> dict[str, float]:
    """Time the run of the contour program, its preparation and MuJoCo's bare steps."""
    import mujoco

    drive = og.load_drive(str(og.example_drive_file()))
    dyn = og.ClosedLoopDynamics()
    # the whole motor torque, as when the guide's figures were measured
    limits = og.PlanLimits(drive=drive, torque_reserve=0.0)
    plan = og.plan_program(og.read_program(og.example_program_text("contour")), dyn, limits)
    best = {"simulate_s": math.inf, "prepare_s": math.inf, "mj_step_s": math.inf}
    run = None
    for _ in range(REPEATS):
        start = time.perf_counter()
        run = og.simulate(plan, dyn, drive)
        best["simulate_s"] = min(best["simulate_s"], time.perf_counter() - start)
        start = time.perf_counter()
        ready = prepare(plan, dyn, drive)
        best["prepare_s"] = min(best["prepare_s"], time.perf_counter() - start)
        model, data, inputs = ready.model, ready.data, ready.inputs
        data.ctrl[:] = inputs.feedforward[0] * inputs.ratio * inputs.efficiency  # at rest
        step = mujoco.mj_step
        start = time.perf_counter()
        for _ in range(inputs.q_ref.shape[0]):
            step(model, data)
        best["mj_step_s"] = min(best["mj_step_s"], time.perf_counter() - start)
    assert run is not None
    summary = simulation_summary(run, og.contour_error(plan.path, run.p), plan)
    periods = run.t.size
    return {
        "periods": periods,
        **best,
        "periods_per_s": periods / best["simulate_s"],
        "overhead": best["simulate_s"] / best["mj_step_s"],
        "loop_overhead": (best["simulate_s"] - best["prepare_s"]) / best["mj_step_s"],
        "max_contour_error": summary["max_contour_error"],
        "max_tracking_error": float(np.abs(run.tracking_error).max()),
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
