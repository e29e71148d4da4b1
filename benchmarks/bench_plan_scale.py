"""Planning a long program: a synthetic 3D relief of many short G1 blocks.

Run on demand: ``python benchmarks/bench_plan_scale.py [--json] [--blocks N] [--mode G61]``.
A raster over a relief (seeded; G1 blocks of 0.1 to 0.5 mm, ``G64 P0.01``, F3000,
inside the prototype's cube), :data:`BLOCKS` blocks by default, is read, then
planned with the slider limits and the example drive's motor limits, the
verification on the grid :data:`~orthoglide_pin.planning.verify.REFINE` times
finer included, once (a long run: no best-of). Printed: ``blocks``,
``grid_points``, ``read_s`` (the reader alone), ``plan_s`` and ``plan_cpu_s``
(the plan, path built from the program read), ``blocks_per_s`` (blocks over
``plan_s``), ``blocks_per_cpu_s`` (over ``plan_cpu_s``), ``peak_rss_mb``
(the process's peak resident memory) and ``cycle_time``. ``--mode G61``
plans the same raster with a stop at every block (as many sections as
blocks). Target: at least 6,000 blocks per second on 2 cores and a peak
resident memory of at most 1.5 GB for the 169,000-block relief (``G64``);
``G61`` is measured, not held to it (see the planning guide).
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time

import numpy as np

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program

#: Blocks of the default program (the size of a real 3D relief).
BLOCKS = 169_000
#: Raster pass length and step over [mm].
PASS_MM, STEP_OVER_MM = 120.0, 0.5
#: The first line of the program in each path-control mode of ``--mode``.
MODES = {"G64": "G21 G90 G64 P0.01", "G61": "G21 G90 G61"}


def relief_program(blocks: int, seed: int = 11, mode: str = "G64") -> str:
    """A raster over a relief: G1 blocks of 0.1 to 0.5 mm, passes joined by a short step over.

    ``mode``: ``"G64"`` blends the corners within 0.01 mm (one long section),
    ``"G61"`` stops at every block (as many short sections as blocks).
    """
    rng = np.random.default_rng(seed)
    lines = [MODES[mode], "G0 X-60 Y-60 Z20", "F3000"]
    x, y, direction = -60.0, -60.0, 1.0

    def height(x: float, y: float) -> float:
        return 20.0 + 8.0 * np.sin(x / 17.0) * np.cos(y / 23.0) + 3.0 * np.sin((x + y) / 7.0)

    while len(lines) - 3 < blocks:
        x_next = x + direction * rng.uniform(0.1, 0.45)
        if not -60.0 <= x_next <= -60.0 + PASS_MM:  # end of the pass: step over
            y = -60.0 + (y + 60.0 + STEP_OVER_MM) % PASS_MM
            direction = -direction
        else:
            x = x_next
        lines.append(f"G1 X{x:.4f} Y{y:.4f} Z{height(x, y):.4f}")
    return "\n".join(lines) + "\n"


def peak_rss_mb() -> float:
    """The process's peak resident memory [MB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def bench_plan_scale(blocks: int, mode: str = "G64") -> dict[str, float]:
    """Read and plan the relief; the figures (see the module)."""
    text = relief_program(blocks, mode=mode)
    dyn = og.ClosedLoopDynamics()
    limits = PlanLimits(
        slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(str(example_drive_file()))
    )
    plan_program(read_program(relief_program(50, mode=mode)), dyn, limits)  # warm-up
    start = time.perf_counter()
    prog = read_program(text)
    read_s = time.perf_counter() - start
    before = peak_rss_mb()
    start, start_cpu = time.perf_counter(), time.process_time()
    plan = plan_program(prog, dyn, limits)
    plan_s = time.perf_counter() - start
    cpu = time.process_time() - start_cpu
    return {
        "blocks": len(prog.blocks),
        "grid_points": plan.grid_points,
        "read_s": read_s,
        "plan_s": plan_s,
        "plan_cpu_s": cpu,
        "blocks_per_s": len(prog.blocks) / plan_s,
        "blocks_per_cpu_s": len(prog.blocks) / cpu,
        "peak_rss_mb": peak_rss_mb(),
        "rss_before_plan_mb": before,
        "cycle_time": plan.cycle_time,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print a JSON object last")
    parser.add_argument("--blocks", type=int, default=BLOCKS, help="G1 blocks of the program")
    parser.add_argument(
        "--mode", choices=sorted(MODES), default="G64",
        help="G64: corners blended (one long section); G61: a stop at every block",
    )  # fmt: skip
    args = parser.parse_args()
    figures = bench_plan_scale(args.blocks, args.mode)
    print(f"plan of {figures['blocks']} blocks, {figures['grid_points']} grid points")
    for name, value in figures.items():
        print(f"  {name:24s} {value:12.4g}")
    if args.json:
        sys.stdout.flush()
        print(json.dumps(figures, sort_keys=True), flush=True)


if __name__ == "__main__":
    main()
