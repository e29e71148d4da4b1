"""Sweep of 64 leg lengths, each on a 50^3 grid: serial, 2 local processes, Dask.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_sweep.py``.
The URDF of every design is rendered once beforehand into a fresh cache, so
each run measures the same work: the metrics of every design (transmission
factors on the 50^3 grid of the cube, inertial model, worst-case requirements
on the coarser grid, footprint) and the writing of the parts and tables. All
figures come from one run and are printed with their ratios.
"""

from __future__ import annotations

import os
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import pandas as pd

from orthoglide_pin.kinematics.closed_form import slider_range_over_cube
from orthoglide_pin.machine.description import CACHE_ENV, render_urdf
from orthoglide_pin.machine.params import (
    PROTOTYPE_CUBE_CORNER,
    PROTOTYPE_WORKSPACE_SIDE,
    prototype,
)
from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

#: 64 leg lengths [m] for the prototype's fixed cube, every one of them valid.
LEGS = "0.26:0.45:64"
#: Points per edge of each design's transmission-factor grid.
GRID = 50
WORKERS = 2


def _warm(spec: SweepSpec) -> None:
    """Render each design's URDF once (the disk cache the workers read)."""
    corner = (PROTOTYPE_CUBE_CORNER,) * 3
    for design in spec.designs():
        L = design["leg_length"]
        lo, hi = slider_range_over_cube(L, corner, PROTOTYPE_WORKSPACE_SIDE)
        render_urdf(prototype().replace(leg_length=L, slider_lower=lo, slider_upper=hi))


def _timed(spec: SweepSpec, out: Path, **kwargs: Any) -> tuple[float, pd.DataFrame]:
    start = time.perf_counter()
    result = run_sweep(spec, out, progress=False, **kwargs)
    return time.perf_counter() - start, result.table


def bench_sweep(dask: bool = True) -> dict[str, float]:
    """Seconds of the serial run, the 2-process pool (started by the sweep, and started
    beforehand: the start of the processes left out) and a Dask LocalCluster."""
    spec = SweepSpec(axes=(SweepAxis.parse(f"leg_length={LEGS}"),), grid=GRID)
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        os.environ[CACHE_ENV] = str(root / "cache")
        _warm(spec)
        serial, table = _timed(spec, root / "serial", workers=1)
        pool, pooled = _timed(spec, root / "pool", workers=WORKERS)
        pd.testing.assert_frame_equal(table, pooled)
        with ProcessPoolExecutor(WORKERS, mp_context=get_context("spawn")) as started:
            few = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3,0.31,0.32,0.33"),), grid=GRID)
            run_sweep(few, root / "warm-up", executor=started, chunk_size=1, progress=False)
            warm, warmed = _timed(spec, root / "started", executor=started)
        pd.testing.assert_frame_equal(table, warmed)
        times = {"serial": serial, "pool": pool, "started_pool": warm}
        if dask:
            times["dask"], dasked = _timed(spec, root / "dask", scheduler="local", workers=WORKERS)
            pd.testing.assert_frame_equal(table, dasked)
    n = len(spec)
    print(f"Sweep of {n} designs (leg lengths {LEGS} m), {GRID}^3 grid each:")
    per = 1e3 * serial / n
    print(f"  serial (one process)          : {serial:7.2f} s  ({per:.0f} ms per design)")
    print(f"  local pool, {WORKERS} worker processes: {pool:7.2f} s")
    print(f"  serial / pool                 : {serial / pool:7.2f}x")
    print(f"  same pool, workers started    : {warm:7.2f} s ({serial / warm:.2f}x)")
    if dask:
        print(f"  Dask LocalCluster, {WORKERS} workers  : {times['dask']:7.2f} s (start included)")
        print(f"  serial / Dask                 : {serial / times['dask']:7.2f}x")
    print("  tables identical in every run : yes")
    return times


def main() -> None:
    """Run every benchmark section."""
    bench_sweep()


if __name__ == "__main__":
    main()
