"""Planning a CAM relief that local tightening cannot settle: its cycle time and fallbacks.

Run on demand: ``python benchmarks/bench_fallback.py [--json]``. LinuxCNC's
``blur_torus.ngc`` (1,905 lines of short G1 and G2/G3 blocks over a blurred
torus, inch, ``G64 P0.0001``; ``tests/program/corpus/linuxcnc-tp-blur_torus.ngc``)
is read and planned under slider limits of 1 m/s and 15 m/s^2, the verification
on the finer grid included, once. Its sections whose local tightening does not
settle after its rounds are planned slower on the whole (the fallbacks); it used
to be refused ("line 852: the plan still uses 1.2125 of the limit
slider_acceleration"); the slow test of ``tests/planning/test_tighten.py`` holds
it planned. Printed: ``blocks``, ``plan_s`` and ``plan_cpu_s``,
``cycle_time``, ``fallbacks`` (how many sections), ``fallback_cost_s`` (the time
they cost together), ``worst_use`` (the largest use of a limit the verification
found: at most 1.001) and ``peak_rss_mb``.
"""

from __future__ import annotations

import resource
import time
from pathlib import Path

from _timing import emit, parse_args

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.planning import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program

TORUS = (
    Path(__file__).resolve().parents[1]
    / "tests"
    / "program"
    / "corpus"
    / "linuxcnc-tp-blur_torus.ngc"
)


def bench_fallback() -> dict[str, float]:
    """Read and plan the relief; the figures (see the module)."""
    dyn = ClosedLoopDynamics()
    program = read_program(TORUS.read_text())
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=15.0)
    wall, cpu = time.perf_counter(), time.process_time()
    plan = plan_program(program, dyn, limits)
    plan_s, plan_cpu = time.perf_counter() - wall, time.process_time() - cpu
    for f in plan.fallbacks:
        print(f"  line {f.line}: {f.limit} at {f.use:.4f}, x {f.factor:.4f}, {f.cost:.4f} s")
    return {
        "blocks": len(program.blocks),
        "plan_s": plan_s,
        "plan_cpu_s": plan_cpu,
        "cycle_time": plan.cycle_time,
        "fallbacks": len(plan.fallbacks),
        "fallback_cost_s": sum(f.cost for f in plan.fallbacks),
        "worst_use": max(plan.worst.values()),
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    figures = bench_fallback()
    for key, value in figures.items():
        print(f"{key:20s} {value:.6g}")
    emit(args, figures)


if __name__ == "__main__":
    main()
