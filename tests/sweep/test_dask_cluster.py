"""A real Dask cluster: scheduler and workers as separate processes, one of them killed."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pandas as pd
import pytest

from orthoglide_pin.sweep.runner import run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

distributed = pytest.importorskip("distributed")

DASK = Path(sys.executable).with_name("dask")
LEGS = "0.26:0.4:24"
GRID = 12
#: Parts written before one worker is killed.
KILL_AFTER = 2
#: Seconds to wait for the cluster, the first parts and the whole sweep.
CLUSTER_TIMEOUT = 60.0
SWEEP_TIMEOUT = 300.0


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _start(*argv: str) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [str(DASK), *argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,  # its own group: the worker's nanny and process die together
    )


def _stop(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=CLUSTER_TIMEOUT)


@pytest.fixture
def cluster() -> Iterator[tuple[str, list[subprocess.Popen[bytes]]]]:
    """A scheduler and two single-threaded workers on 127.0.0.1; all killed afterwards."""
    if not DASK.exists():
        pytest.skip("no dask command next to the interpreter")
    port = _port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [_start("scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard")]
    try:
        workers = [
            _start(
                "worker", address, "--nworkers", "1", "--nthreads", "1",
                "--host", "127.0.0.1", "--no-dashboard",
            )
            for _ in range(2)
        ]  # fmt: skip
        procs += workers
        with distributed.Client(address, timeout=CLUSTER_TIMEOUT) as client:
            client.wait_for_workers(2, timeout=CLUSTER_TIMEOUT)
        yield address, workers
    finally:
        for proc in reversed(procs):
            _stop(proc)


def test_sweep_survives_a_killed_worker(
    cluster: tuple[str, list[subprocess.Popen[bytes]]], tmp_path: Path
) -> None:
    address, workers = cluster
    out = tmp_path / "cluster"
    argv = [
        sys.executable, "-m", "orthoglide_pin", "sweep", "--leg-length", LEGS,
        "--grid", str(GRID), "--scheduler", address, "--chunk-size", "1",
        "--no-plot", "--no-progress", "--json", "--out", str(out),
    ]  # fmt: skip
    sweep = subprocess.Popen(
        argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True
    )
    try:
        deadline = time.monotonic() + CLUSTER_TIMEOUT
        while len(list((out / "parts").glob("*.json"))) < KILL_AFTER:
            assert sweep.poll() is None, sweep.communicate()[1].decode()
            assert time.monotonic() < deadline, "no parts from the cluster"
            time.sleep(0.02)
        assert sweep.poll() is None, "the sweep ended before a worker could be killed"
        _stop(workers[0])  # the worker and its nanny, mid-sweep
        stdout, stderr = sweep.communicate(timeout=SWEEP_TIMEOUT)
    finally:
        if sweep.poll() is None:
            os.killpg(sweep.pid, signal.SIGKILL)
            sweep.wait()
    assert sweep.returncode == 0, stderr.decode()
    summary = json.loads(stdout)
    assert summary["designs"] == summary["computed"] == 24
    assert workers[0].returncode is not None and workers[1].poll() is None
    spec = SweepSpec(axes=(SweepAxis.parse(f"leg_length={LEGS}"),), grid=GRID)
    serial = run_sweep(spec, tmp_path / "serial", workers=1, progress=False)
    clustered = pd.read_parquet(out / "results.parquet")
    pd.testing.assert_frame_equal(clustered, serial.table, check_exact=True)
