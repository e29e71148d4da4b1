"""Throughput benchmarks of orthoglide_pin.kinematics.closed_form.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_kinematics.py``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from _timing import best_times, emit, parse_args

from orthoglide_pin.kinematics.closed_form import ik_and_jacobian

#: Prototype of the paper (section 4): leg length [m], cube corner [m], cube side [m].
LEG_LENGTH = 0.31
CUBE_CORNER = -LEG_LENGTH / math.sqrt(18.0)
CUBE_SIDE = 0.2
SEED = 20240611


def bench_ik_jacobian(n: int = 1_000_000, block: int = 16_384, repeats: int = 7) -> dict[str, Any]:
    """Closed-form IK + Jacobian throughput against the numpy memory floor.

    Args:
        n: Number of random points in the prototype cube.
        block: Points per call of ``ik_and_jacobian`` (preallocated outputs).
        repeats: Timed repeats; the best is kept.

    Returns:
        Timings [s], throughputs [points/s] and the ratio to ``a*b+c``.
    """
    rng = np.random.default_rng(SEED)
    points = CUBE_CORNER + CUBE_SIDE * rng.random((n, 3))
    q = np.empty_like(points)
    J = np.empty((n, 3, 3))

    def run_blocks() -> None:
        for start in range(0, n, block):
            stop = min(start + block, n)
            ik_and_jacobian(
                points[start:stop], LEG_LENGTH, out_q=q[start:stop], out_J=J[start:stop]
            )

    def run_whole() -> None:
        ik_and_jacobian(points, LEG_LENGTH, out_q=q, out_J=J)

    a, b, c = (rng.random((n, 3)) for _ in range(3))
    out = np.empty_like(a)

    def floor_plain() -> None:
        a * b + c

    def floor_inplace() -> None:
        np.multiply(a, b, out=out)
        np.add(out, c, out=out)

    t_blocks, t_whole, t_floor, t_floor_inplace = best_times(
        [run_blocks, run_whole, floor_plain, floor_inplace], repeats
    )
    result = {
        "n": n,
        "block": block,
        "t_ik_jacobian_blocks": t_blocks,
        "t_ik_jacobian_single_call": t_whole,
        "t_floor_a_mul_b_add_c": t_floor,
        "t_floor_inplace": t_floor_inplace,
        "points_per_s": n / t_blocks,
        "ratio_to_floor": t_blocks / t_floor,
        "ratio_to_inplace_floor": t_blocks / t_floor_inplace,
    }
    print(f"IK + Jacobian (closed form), {n:,} points, blocks of {block:,}:")
    for label, t in (("per block", t_blocks), ("one call ", t_whole)):
        print(f"  ik_and_jacobian, {label}   : {t * 1e3:7.2f} ms  {n / t / 1e6:6.2f} Mpoints/s")
    print(f"  numpy a*b+c, (n, 3) arrays   : {t_floor * 1e3:7.2f} ms  (memory floor)")
    print(f"  same with preallocated output: {t_floor_inplace * 1e3:7.2f} ms")
    print(
        f"  ratio IK+J / floor           : {result['ratio_to_floor']:7.2f}x "
        f"({result['ratio_to_inplace_floor']:.2f}x vs preallocated; target <= 10x)"
    )
    return result


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_ik_jacobian())


if __name__ == "__main__":
    main()
