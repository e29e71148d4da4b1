"""Local execution: the default rule, the caps, and workers that never outlive the sweep."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd
import psutil
import pytest

import orthoglide_pin as og
from orthoglide_pin.sweep import pool as sweep_pool
from orthoglide_pin.sweep import runner as sweep_runner
from orthoglide_pin.sweep.metrics import evaluate_designs
from orthoglide_pin.sweep.pool import run_local
from orthoglide_pin.sweep.runner import MAX_DESIGNS, check_sizes, run_sweep
from orthoglide_pin.sweep.spec import (
    HARD_MAX_DESIGNS,
    MAX_GRID,
    MAX_REQUIREMENT_GRID,
    SweepAxis,
    SweepSpec,
)

GRID = 12
#: Seconds to wait for the workers to start, and for them to be gone.
START_TIMEOUT = 60.0
GONE_TIMEOUT = 60.0
#: CPU seconds of work left that start the workers, in the probe's test.
PROBE_CPU = 0.1
#: A sweep long enough to be caught with its workers running.
LONG_LEGS = "0.25:0.45:2000"


def _spec(legs: str = "0.26:0.4:8") -> SweepSpec:
    return SweepSpec(axes=(SweepAxis.parse(f"leg_length={legs}"),), grid=GRID)


def _label(chunk: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    return [{"leg": d["leg_length"]} for d in chunk]


class _Starts:
    """Records the starts of the local workers (and lets them start, or not)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, allow: bool) -> None:
        self.count = 0
        original = sweep_pool.LocalWorkers.start

        def start(workers: sweep_pool.LocalWorkers) -> Any:
            self.count += 1
            if not allow:
                raise AssertionError("a worker process was started")
            return original(workers)

        monkeypatch.setattr(sweep_pool.LocalWorkers, "start", start)


def test_small_default_sweep_stays_in_this_process(monkeypatch: pytest.MonkeyPatch) -> None:
    starts = _Starts(monkeypatch, allow=False)
    chunks = [[d] for d in _spec().designs()]
    rows = [r for rows in run_local(_label, chunks, None, cpus=2) for r in rows]
    assert sorted(r["leg"] for r in rows) == [d[0]["leg_length"] for d in chunks]
    assert starts.count == 0


def test_one_worker_is_this_process_whatever_the_work(monkeypatch: pytest.MonkeyPatch) -> None:
    starts = _Starts(monkeypatch, allow=False)
    monkeypatch.setattr(sweep_pool, "POOL_AFTER", 0.0)
    chunks = [[d] for d in _spec().designs()]
    assert len(list(run_local(_label, chunks, 1, cpus=8))) == len(chunks)
    assert len(list(run_local(_label, chunks, None, cpus=1))) == len(chunks)
    assert starts.count == 0


def test_large_default_sweep_adds_workers_and_keeps_the_table(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    serial = run_sweep(_spec(), tmp_path / "serial", workers=1, progress=False)
    starts = _Starts(monkeypatch, allow=True)
    monkeypatch.setattr(sweep_pool, "POOL_AFTER", 0.0)  # any work left is worth a worker
    monkeypatch.setattr(sweep_pool, "cpu_count", lambda: 2)
    monkeypatch.setattr(sweep_runner, "cpu_count", lambda: 2)
    result = run_sweep(_spec(), tmp_path / "default", chunk_size=1, progress=False)
    assert starts.count == 1
    pd.testing.assert_frame_equal(result.table, serial.table, check_exact=True)


def test_probe_decides_on_the_faster_chunk(monkeypatch: pytest.MonkeyPatch) -> None:
    """The first chunk carries the imports: one slow chunk alone never starts workers."""
    starts = _Starts(monkeypatch, allow=False)
    monkeypatch.setattr(sweep_pool, "POOL_AFTER", PROBE_CPU)
    calls: list[int] = []

    def slow_first(chunk: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
        calls.append(1)
        if len(calls) == 1:  # busy: the estimate counts CPU seconds
            start = time.process_time()
            while time.process_time() - start < 2 * PROBE_CPU:
                pass
        return _label(chunk)

    chunks = [[d] for d in _spec().designs()]
    assert len(list(run_local(slow_first, chunks, None, cpus=2))) == len(chunks)
    assert starts.count == 0


def test_caps_are_checked_before_anything_is_written(tmp_path: Path) -> None:
    cpus = sweep_pool.cpu_count()
    with pytest.raises(og.InvalidParameterError, match=rf"workers={cpus + 1}.*at most {cpus}"):
        run_sweep(_spec(), tmp_path / "w", workers=cpus + 1)
    check_sizes(_spec(), cpus + 1, force_workers=True)  # allowed when forced
    with pytest.raises(og.InvalidParameterError, match="at most 256"):
        check_sizes(_spec(), 10_000, force_workers=True)
    big = SweepSpec(
        axes=(
            SweepAxis.parse("leg_length=0.25:0.45:1000"),
            SweepAxis.parse("psi_max=2:3:1000"),
        )
    )
    assert len(big) == HARD_MAX_DESIGNS
    message = rf"number of designs={HARD_MAX_DESIGNS}: expected at most {MAX_DESIGNS} designs"
    with pytest.raises(og.InvalidParameterError, match=message):
        run_sweep(big, tmp_path / "d")
    check_sizes(big, 1, force_designs=True)  # allowed when forced, up to the hard cap
    assert not (tmp_path / "w").exists() and not (tmp_path / "d").exists()
    with pytest.raises(og.InvalidParameterError, match=r"number of designs=1000000000"):
        SweepSpec(axes=(*big.axes, SweepAxis.parse("psi_min=0.4:0.6:1000")))
    capped = rf"requirement_grid=200.*\[2, {MAX_REQUIREMENT_GRID}\]"
    with pytest.raises(og.InvalidParameterError, match=capped):
        SweepSpec(requirement_grid=200)
    with pytest.raises(og.InvalidParameterError, match=rf"grid=1000000000.*{MAX_GRID}"):
        SweepSpec(grid=1_000_000_000)
    assert SweepSpec(grid=MAX_GRID, requirement_grid=MAX_REQUIREMENT_GRID).grid == MAX_GRID


def _cli(out: Path, *extra: str) -> list[str]:
    return [
        sys.executable,
        "-m",
        "orthoglide_pin",
        "sweep",
        "--leg-length",
        LONG_LEGS,
        "--grid",
        str(GRID),
        "--chunk-size",
        "1",
        "--no-plot",
        "--no-progress",
        "--out",
        str(out),
        *extra,
    ]


def _workers(parent: psutil.Process) -> list[psutil.Process]:
    """The pool's worker processes under ``parent`` (spawned interpreters)."""
    found = []
    for child in parent.children(recursive=True):
        try:
            if any("spawn_main" in part for part in child.cmdline()):
                found.append(child)
        except psutil.Error:
            pass
    return found


def _alive(process: psutil.Process) -> bool:
    try:
        return process.is_running() and process.status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


@pytest.mark.parametrize(
    ("sig", "group"),
    [(signal.SIGKILL, False), (signal.SIGTERM, False), (signal.SIGINT, True)],
    ids=["parent-killed", "parent-terminated", "interrupted"],
)
def test_workers_die_with_their_parent(tmp_path: Path, sig: int, group: bool) -> None:
    if sweep_pool.cpu_count() < 2:
        pytest.skip("one CPU: the sweep is capped at one process")
    proc = subprocess.Popen(
        _cli(tmp_path, "--workers", "2"),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    workers: list[psutil.Process] = []
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + START_TIMEOUT
        while not (workers and list((tmp_path / "parts").glob("*.json"))):
            assert proc.poll() is None, "the sweep ended before it could be stopped"
            assert time.monotonic() < deadline, "no worker started"
            workers = _workers(parent)
            time.sleep(0.05)
        if group:  # Ctrl-C reaches the whole foreground group
            os.killpg(proc.pid, sig)
        else:
            os.kill(proc.pid, sig)
        proc.wait(timeout=GONE_TIMEOUT)
        deadline = time.monotonic() + GONE_TIMEOUT
        while any(_alive(w) for w in workers):
            assert time.monotonic() < deadline, "a worker outlived its parent"
            time.sleep(0.05)
    finally:
        for w in workers:
            if _alive(w):
                w.kill()
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert not (tmp_path / "results.csv").exists()


def test_a_killed_worker_loses_nothing(tmp_path: Path) -> None:
    """A worker killed mid-sweep: this process finishes alone, to the serial table."""
    if sweep_pool.cpu_count() < 2:
        pytest.skip("one CPU: the sweep is capped at one process")
    designs = _spec("0.26:0.4:40").designs()
    killed: list[int] = []

    def kill_the_first_worker() -> None:
        deadline = time.monotonic() + START_TIMEOUT
        while not (workers := _workers(psutil.Process())) and time.monotonic() < deadline:
            time.sleep(0.01)
        if workers:
            workers[0].kill()
            killed.append(workers[0].pid)

    killer = threading.Thread(target=kill_the_first_worker)
    killer.start()
    try:
        rows = [r for rs in run_local(evaluate_designs, [[d] for d in designs], 2) for r in rs]
    finally:
        killer.join()
    assert killed, "no worker was caught running"
    expected = evaluate_designs(designs)
    assert sorted(rows, key=lambda r: r["key"]) == sorted(expected, key=lambda r: r["key"])


def test_a_worker_error_stops_the_sweep(tmp_path: Path) -> None:
    """An error in this process's chunk stops the workers and keeps what is done."""
    calls: list[int] = []

    def fails_third(chunk: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
        calls.append(1)
        if len(calls) == 3:
            raise RuntimeError("broken design")
        return evaluate_designs(chunk)

    with pytest.raises(RuntimeError, match="broken"):
        run_sweep(_spec(), tmp_path, workers=1, chunk_size=1, task=fails_third)
    assert len(list((tmp_path / "parts").glob("*.json"))) == 2
