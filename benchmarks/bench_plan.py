"""Planning a part program of 1,000 blocks, dynamics and verification included.

Run on demand: ``python benchmarks/bench_plan.py [--json]``. A program of
1,000 blended G1 moves (about 20,000 planning-grid points) is planned with the
example drive's motor limits: path forms, TOPP-RA, and the verification on a
grid 10 times finer. Printed: ``blocks``, ``grid_points``, ``plan_s`` (the
whole plan, best of 3; ``plan_cpu_s`` its processor time, which a loaded
machine disturbs less) and ``dynamics_us_per_point`` (the path forms of the
planning grid, one batch, per point), with their ratio to one closed-form
inverse-dynamics point measured in the same run (``forms_over_inverse_dynamics``,
``plan_over_inverse_dynamics_point``) and both scaled to a machine where that
point costs :data:`REFERENCE_POINT_US` (``*_at_reference``). Targets: the plan
in at most 3 s on 2 cores, the forms at most 1.5 us per point.
"""

from __future__ import annotations

import time

import numpy as np
from _timing import best_per_call, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.plan import plan_program

BLOCKS = 1_000
#: One closed-form inverse-dynamics point on the machine the targets were set on [us].
REFERENCE_POINT_US = 3.3


def _program() -> str:
    """1,000 G1 moves of 5 to 25 mm, blended within 0.01 mm, inside the prototype's cube."""
    rng = np.random.default_rng(7)
    lines = ["G21 G90 G64 P0.01", "G0 X0 Y0 Z0", "F12000"]
    p = np.zeros(3)
    for _ in range(BLOCKS - 1):
        step = rng.normal(size=3)
        step *= rng.uniform(5.0, 25.0) / np.linalg.norm(step)
        p = np.clip(p + step, -60.0, 110.0)
        lines.append("G1 X{:.3f} Y{:.3f} Z{:.3f}".format(*p))
    return "\n".join(lines) + "\n"


def bench_plan() -> dict[str, float]:
    """Time the plan of the program and the path forms of its grid."""
    dyn = og.ClosedLoopDynamics()
    # the whole motor torque, as when the guide's figures were measured
    limits = PlanLimits(drive=load_drive(str(example_drive_file())), torque_reserve=0.0)
    prog = read_program(_program())
    plan_program(prog, dyn, limits)  # warm-up: models, caches
    best = cpu = np.inf
    for _ in range(3):
        start, start_cpu = time.perf_counter(), time.process_time()
        plan = plan_program(prog, dyn, limits)
        best = min(best, time.perf_counter() - start)
        cpu = min(cpu, time.process_time() - start_cpu)
    grids = [sample_section(s, 2e-3) for s in build_path(prog).sections if s.pieces]
    p, dp, ddp = (np.concatenate([getattr(g, n) for g in grids]) for n in ("p", "dp", "ddp"))
    n = p.shape[0]
    forms = best_per_call(lambda: path_forms(dyn, p, dp, ddp), 1, repeats=3) / n
    zero = np.zeros_like(p)
    one = best_per_call(lambda: dyn.inverse_dynamics(p, dp, zero), 1, repeats=3) / n
    scale = 1e-6 * REFERENCE_POINT_US / one
    return {
        "blocks": len(plan.blocks),
        "grid_points": plan.grid_points,
        "plan_s": best,
        "plan_cpu_s": cpu,
        "dynamics_us_per_point": 1e6 * forms,
        "inverse_dynamics_us_per_point": 1e6 * one,
        "forms_over_inverse_dynamics": forms / one,
        "plan_over_inverse_dynamics_point": best / one,
        "plan_s_at_reference": best * scale,
        "dynamics_us_per_point_at_reference": 1e6 * forms * scale,
        "cycle_time": plan.cycle_time,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    figures = bench_plan()
    print(f"plan of {figures['blocks']} blocks, {figures['grid_points']} grid points")
    for name, value in figures.items():
        print(f"  {name:36s} {value:12.4g}")
    emit(args, figures)


if __name__ == "__main__":
    main()
