"""Sweeps: serial against the default, and against a real two-worker Dask cluster.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_sweep.py [--json]``.

* **large sweep**: 256 leg lengths with the default metrics (50^3 grid of
  transmission factors, worst-case requirements on a 5^3 grid, inertial
  model, footprint): serial (``workers=1``) against the default (this process,
  joined by workers when the work pays for them), start-up included;
* **small sweep**: 16 leg lengths, serial against the default;
* **Dask**: the large sweep on a real cluster started beforehand on
  127.0.0.1 (``dask scheduler`` and two ``dask worker --nworkers 1
  --nthreads 1``), the cluster's start left out (a cluster outlives its
  sweeps), the workers' first imports included.

The URDF of every design is rendered once beforehand into a fresh cache, so
each run measures the same work. Runs alternate and the best of
``--repeats`` is kept; every table is checked equal to the serial one. All
figures come from one run.
"""

from __future__ import annotations

import argparse
import os
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pandas as pd
from _timing import emit

from orthoglide_pin.kinematics.closed_form import slider_range_over_cube
from orthoglide_pin.machine.description import CACHE_ENV, render_urdf
from orthoglide_pin.machine.params import (
    PROTOTYPE_CUBE_CORNER,
    PROTOTYPE_WORKSPACE_SIDE,
    prototype,
)
from orthoglide_pin.sweep.pool import cpu_count
from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

#: Leg lengths [m] of the large and small sweeps (the prototype's fixed cube).
LARGE = "0.26:0.45:256"
SMALL = "0.30:0.40:16"
#: Seconds to wait for the cluster's workers.
CLUSTER_TIMEOUT = 60.0


def _spec(legs: str) -> SweepSpec:
    return SweepSpec(axes=(SweepAxis.parse(f"leg_length={legs}"),))


def _warm(spec: SweepSpec) -> None:
    """Render each design's URDF once (the disk cache every process reads)."""
    corner = (PROTOTYPE_CUBE_CORNER,) * 3
    for design in spec.designs():
        L = design["leg_length"]
        lo, hi = slider_range_over_cube(L, corner, PROTOTYPE_WORKSPACE_SIDE)
        render_urdf(prototype().replace(leg_length=L, slider_lower=lo, slider_upper=hi))


def _cpu() -> float:
    """CPU seconds of this process and of its reaped children (the local workers)."""
    own, children = (
        resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _timed(spec: SweepSpec, out: Path, **kwargs: Any) -> tuple[float, float, pd.DataFrame]:
    """Wall seconds, CPU seconds (this process and its workers) and the table of a run."""
    cpu, start = _cpu(), time.perf_counter()
    result = run_sweep(spec, out, progress=False, **kwargs)
    return time.perf_counter() - start, _cpu() - cpu, result.table


def _cluster_cpu(pids: list[int]) -> float:
    """CPU seconds used so far by the cluster's processes and their children."""
    import psutil

    total = 0.0
    for pid in pids:
        try:
            parent = psutil.Process(pid)
            for process in (parent, *parent.children(recursive=True)):
                times = process.cpu_times()
                total += times.user + times.system
        except psutil.Error:
            pass
    return total


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def real_cluster(workers: int = 2) -> Iterator[tuple[str, list[int]]]:
    """A Dask scheduler and ``workers`` single-threaded workers on 127.0.0.1.

    Yields:
        Its address and the process ids of the cluster (scheduler, then workers).
    """
    import distributed

    dask = str(Path(sys.executable).with_name("dask"))
    port = _port()
    address = f"tcp://127.0.0.1:{port}"
    quiet: dict[str, Any] = {
        "stdout": subprocess.DEVNULL,
        "stderr": subprocess.DEVNULL,
        "start_new_session": True,
    }
    procs = [
        subprocess.Popen(
            [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
            **quiet,
        )
    ]  # fmt: skip
    try:
        for _ in range(workers):
            procs.append(
                subprocess.Popen(
                    [dask, "worker", address, "--nworkers", "1", "--nthreads", "1",
                     "--host", "127.0.0.1", "--no-dashboard"],
                    **quiet,
                )
            )  # fmt: skip
        with distributed.Client(address, timeout=CLUSTER_TIMEOUT) as client:
            client.wait_for_workers(workers, timeout=CLUSTER_TIMEOUT)
        yield address, [proc.pid for proc in procs]
    finally:
        for proc in reversed(procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def bench_sweep(repeats: int = 2, dask: bool = True) -> dict[str, Any]:
    """Seconds and ratios of the serial, default and Dask runs (see the module)."""
    large, small = _spec(LARGE), _spec(SMALL)
    times: dict[str, float] = {}

    def keep(name: str, seconds: float) -> None:
        times[name] = min(times.get(name, seconds), seconds)

    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        os.environ[CACHE_ENV] = str(root / "cache")
        _warm(large)
        _warm(small)
        reference: dict[str, pd.DataFrame] = {}
        run = 0
        for _ in range(repeats):
            for name, spec, workers in (
                ("serial", large, 1),
                ("default", large, None),
                ("small_serial", small, 1),
                ("small_default", small, None),
            ):
                run += 1
                seconds, cpu, table = _timed(spec, root / f"run{run}", workers=workers)
                keep(name, seconds)
                keep(f"{name}_cpu", cpu)
                ref = reference.setdefault("small" if spec is small else "large", table)
                pd.testing.assert_frame_equal(table, ref, check_exact=True)
        if dask:
            with real_cluster() as (address, pids):
                for _ in range(repeats):
                    run += 1
                    cluster_cpu = _cluster_cpu(pids)
                    seconds, own_cpu, table = _timed(large, root / f"run{run}", scheduler=address)
                    keep("dask", seconds)
                    keep("dask_cpu", own_cpu + _cluster_cpu(pids) - cluster_cpu)
                    pd.testing.assert_frame_equal(table, reference["large"], check_exact=True)
    n, cpus = len(large), cpu_count()
    figures: dict[str, Any] = {
        "designs": n,
        "small_designs": len(small),
        "cpus": cpus,
        "serial_s": times["serial"],
        "default_s": times["default"],
        "speedup_default": times["serial"] / times["default"],
        "small_serial_s": times["small_serial"],
        "small_default_s": times["small_default"],
        "small_default_over_serial": times["small_default"] / times["small_serial"],
        "serial_cpu_s": times["serial_cpu"],
        "default_cpu_s": times["default_cpu"],
        "default_cpu_over_serial": times["default_cpu"] / times["serial_cpu"],
        "load_average": os.getloadavg()[0],
        "dask_s": times.get("dask"),
        "speedup_dask": times["serial"] / times["dask"] if "dask" in times else None,
        "dask_cpu_over_serial": times["dask_cpu"] / times["serial_cpu"] if dask else None,
    }
    per = 1e3 * times["serial"] / n
    print(f"Sweep of {n} designs (leg lengths {LARGE} m), default metrics, {cpus} CPUs")
    print(f"  serial (workers=1)              : {times['serial']:7.2f} s  ({per:.1f} ms/design)")
    print(
        f"  default, start-up included      : {times['default']:7.2f} s  "
        f"({figures['speedup_default']:.2f}x serial; target >= 1.6x on 2 CPUs)"
    )
    print(
        f"  CPU of the default / serial     : {figures['default_cpu_over_serial']:7.2f}    "
        "(this process and its workers: the cost of running in parallel)"
    )
    if dask:
        print(
            f"  Dask, 2 workers x 1 thread      : {times['dask']:7.2f} s  "
            f"({figures['speedup_dask']:.2f}x serial; target >= 1.4x; cluster started before)"
        )
        print(
            f"  CPU of Dask / serial            : {figures['dask_cpu_over_serial']:7.2f}    "
            "(this process, the scheduler and its workers)"
        )
    print(f"Sweep of {len(small)} designs (leg lengths {SMALL} m)")
    print(f"  serial (workers=1)              : {times['small_serial']:7.2f} s")
    print(
        f"  default                         : {times['small_default']:7.2f} s  "
        f"({figures['small_default_over_serial']:.2f}x the serial time; target <= 1.10x)"
    )
    print(f"  tables identical in every run   : yes (best of {repeats} runs each)")
    print(f"  load average at the end         : {figures['load_average']:.1f} on {cpus} CPUs")
    return figures


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print one JSON object last")
    parser.add_argument("--repeats", type=int, default=2, help="runs of each case (2)")
    parser.add_argument("--no-dask", action="store_true", help="leave the Dask cluster out")
    args = parser.parse_args()
    emit(args, bench_sweep(max(1, args.repeats), dask=not args.no_dask))


if __name__ == "__main__":
    main()
