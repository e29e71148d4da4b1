"""Throughput of the transmission-factor map against LAPACK and the memory floor.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_indices.py``.
All figures come from one run, timed in turn, and are printed as ratios.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from _timing import best_times, emit, parse_args

from orthoglide_pin.kinematics.closed_form import ik_and_jacobian
from orthoglide_pin.kinetostatics.transmission import BLOCK
from orthoglide_pin.kinetostatics.workspace import Grid, cube_grid, transmission_factor_map

#: Prototype of the paper (section 4): leg length [m], cube corner [m], cube side [m].
LEG_LENGTH = 0.31
CUBE_CORNER = -LEG_LENGTH / math.sqrt(18.0)
CUBE_SIDE = 0.2
#: Points per edge of the map (100^3 = 1e6 points).
EDGE = 100
SEED = 20240611


def _svd_map(grid: Grid, block: int = BLOCK) -> np.ndarray[Any, Any]:
    """The same map through the Jacobian and batched ``np.linalg.svd``, block-wise."""
    points = grid.points().reshape(-1, 3)
    out = np.empty_like(points)
    q = np.empty((block, 3))
    J = np.empty((block, 3, 3))
    for start in range(0, points.shape[0], block):
        stop = min(start + block, points.shape[0])
        m = stop - start
        ik_and_jacobian(points[start:stop], LEG_LENGTH, out_q=q[:m], out_J=J[:m])
        out[start:stop] = np.linalg.svd(J[:m], compute_uv=False)[:, ::-1]
    return out.reshape(*grid.shape, 3)


def bench_transmission_map(repeats: int = 5) -> dict[str, Any]:
    """Points per second of the closed-form map, the SVD map and ``a * b + c``."""
    grid = cube_grid([CUBE_CORNER] * 3, CUBE_SIDE, EDGE)
    n = grid.size
    rng = np.random.default_rng(SEED)
    a, b, c = (rng.random((n, 3)) for _ in range(3))
    fns: list[Callable[[], Any]] = [
        lambda: transmission_factor_map(grid, LEG_LENGTH),
        lambda: _svd_map(grid),
        lambda: a * b + c,
    ]
    t_map, t_svd, t_floor = best_times(fns, repeats)
    closed, lapack = transmission_factor_map(grid, LEG_LENGTH), _svd_map(grid)
    worst = float(np.max(np.abs(closed / lapack - 1.0)))
    rates = {"closed_form_map": n / t_map, "svd_map": n / t_svd, "memory_floor": n / t_floor}
    print(f"Transmission factors on a {EDGE}^3 grid of the prototype cube ({n:,} points):")
    labels = {
        "closed_form_map": "closed-form map (transmission_factor_map)",
        "svd_map": "same map, IK+J and batched np.linalg.svd",
        "memory_floor": "memory floor, numpy a*b+c on (n, 3)",
    }
    for key, rate in rates.items():
        print(f"  {labels[key]:<42}: {rate / 1e6:7.2f} Mpoints/s")
    fast, svd, floor = rates["closed_form_map"], rates["svd_map"], rates["memory_floor"]
    print(f"  closed-form map vs SVD map     : {fast / svd:7.2f}x faster")
    print(f"  closed-form map vs memory floor: {floor / fast:7.2f}x slower")
    print(f"  SVD map vs memory floor        : {floor / svd:7.2f}x slower")
    print(f"  largest relative difference closed form vs LAPACK: {worst:.2e}")
    return {"n": n, "points_per_s": rates, "max_relative_difference": worst}


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_transmission_map())


if __name__ == "__main__":
    main()
