"""Running sweeps: executors, Dask, chunks, atomic parts, resume after a kill."""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.sweep import runner as sweep_runner
from orthoglide_pin.sweep.metrics import evaluate_designs
from orthoglide_pin.sweep.runner import MAX_CHUNK, load_parts, run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec, design_key

#: A small sweep: leg lengths from too short (invalid) to long, coarse grids.
LEGS = "0.2:0.4:9"
GRID = 12
#: Designs of the interrupted sweep, and parts to wait for before the kill.
KILL_LEGS = "0.25:0.45:41"
KILL_AFTER = 3
#: Seconds to wait for the first parts of the interrupted sweep.
KILL_TIMEOUT = 60.0
#: The port of Dask's web server unless told otherwise.
DASK_WEB_PORT = 8787


def _spec(legs: str = LEGS) -> SweepSpec:
    return SweepSpec(axes=(SweepAxis.parse(f"leg_length={legs}"),), grid=GRID)


@pytest.fixture(scope="module")
def serial(tmp_path_factory: pytest.TempPathFactory) -> og.SweepResult:
    return run_sweep(_spec(), tmp_path_factory.mktemp("serial"), workers=1)


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(a, b, check_exact=True)


def test_serial_run_writes_parts_and_tables(serial: og.SweepResult) -> None:
    assert serial.designs == serial.computed == 9
    assert serial.skipped == 0
    assert serial.invalid == 1  # 0.2 m is too short for the prototype's cube
    keys = [design_key(d) for d in _spec().designs()]
    assert serial.table["key"].tolist() == keys
    assert sorted(p.stem for p in (serial.out / "parts").glob("*.json")) == sorted(keys)
    assert json.loads((serial.out / "sweep.json").read_text())["axes"]["leg_length"][0] == 0.2
    _same(pd.read_parquet(serial.parquet), serial.table)
    csv = pd.read_csv(serial.csv, float_precision="round_trip")
    assert csv["key"].tolist() == keys
    np.testing.assert_array_equal(csv["stroke"], serial.table["stroke"])  # every digit kept


def test_any_executor_gives_the_same_table(serial: og.SweepResult, tmp_path: Path) -> None:
    submitted: list[int] = []

    class Counting(cf.ThreadPoolExecutor):
        def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future[Any]:
            submitted.append(len(args[0]))
            return super().submit(fn, *args, **kwargs)

    with Counting(max_workers=1) as pool:
        result = run_sweep(_spec(), tmp_path, executor=pool, chunk_size=4)
    assert submitted == [4, 4, 1]
    _same(result.table, serial.table)


def test_default_chunks_are_small(tmp_path: Path) -> None:
    submitted: list[int] = []

    class Counting(cf.ThreadPoolExecutor):
        def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> cf.Future[Any]:
            submitted.append(len(args[0]))
            f: cf.Future[Any] = cf.Future()
            f.set_result([])
            return f

    with Counting(max_workers=1) as pool:
        run_sweep(_spec("0.3:0.4:101"), tmp_path, executor=pool, workers=2)
    assert sum(submitted) == 101
    assert max(submitted) <= MAX_CHUNK and len(submitted) >= 4 * 2


def test_process_pool_gives_the_same_table(serial: og.SweepResult, tmp_path: Path) -> None:
    result = run_sweep(_spec(), tmp_path, workers=2, progress=False)
    _same(result.table, serial.table)


def test_dask_local_cluster(serial: og.SweepResult, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=False,
            protocol="tcp",
            host="127.0.0.1",
            dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        assert client.scheduler.address.startswith("tcp://127.0.0.1:")
        result = run_sweep(_spec(), tmp_path, scheduler=client, chunk_size=3)
    _same(result.table, serial.table)


def test_dask_local_scheduler_by_name(serial: og.SweepResult, tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    with contextlib.ExitStack() as stack:
        with contextlib.suppress(OSError):  # Dask's default web port, taken (here, or already)
            stack.enter_context(socket.create_server(("127.0.0.1", DASK_WEB_PORT)))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = run_sweep(_spec(), tmp_path, scheduler="local", workers=1)
    _same(result.table, serial.table)
    assert not [w for w in caught if "already in use" in str(w.message)]  # no fixed port tried


def test_bad_execution_settings(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with pytest.raises(og.InvalidParameterError, match="scheduler"):
        run_sweep(_spec(), tmp_path, scheduler="udp://somewhere")
    monkeypatch.setattr(sweep_runner, "CONNECT_TIMEOUT", 0.5)
    with pytest.raises(og.InvalidParameterError, match="reachable"):
        run_sweep(_spec(), tmp_path, scheduler="tcp://127.0.0.1:9")
    for name, value in (("workers", 0), ("chunk_size", -1)):
        with pytest.raises(og.InvalidParameterError, match=name):
            run_sweep(_spec(), tmp_path, **{name: value})


def test_an_error_keeps_what_is_done(tmp_path: Path) -> None:
    calls: list[int] = []

    def flaky(chunk: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
        calls.append(len(chunk))
        if len(calls) == 2:
            raise RuntimeError("worker lost")
        return evaluate_designs(chunk)

    with cf.ThreadPoolExecutor(max_workers=1) as pool, pytest.raises(RuntimeError, match="lost"):
        run_sweep(_spec(), tmp_path, executor=pool, chunk_size=2, task=flaky)
    assert len(list((tmp_path / "parts").glob("*.json"))) == 2  # the first chunk is kept
    again = run_sweep(_spec(), tmp_path, workers=1)
    assert again.skipped == 2 and again.computed == again.designs - 2


def test_rerun_skips_what_is_done(serial: og.SweepResult, tmp_path: Path) -> None:
    first = run_sweep(_spec(), tmp_path, workers=1)
    parts = sorted((tmp_path / "parts").glob("*.json"))
    for path in parts[::3]:
        path.unlink()
    parts[1].write_text('{"key": "truncated')  # unreadable: computed again
    again = run_sweep(_spec(), tmp_path, workers=1)
    assert again.computed == len(parts[::3]) + 1
    assert again.skipped == again.designs - again.computed
    _same(again.table, first.table)
    _same(again.table, serial.table)
    done = run_sweep(_spec(), tmp_path, workers=1)
    assert done.computed == 0 and done.skipped == done.designs


def test_other_settings_do_not_reuse_parts(tmp_path: Path) -> None:
    first = run_sweep(_spec("0.3,0.31"), tmp_path / "a", workers=1)
    finer = SweepSpec(axes=(SweepAxis.parse("leg_length=0.3,0.31"),), grid=GRID + 1)
    assert not {design_key(d) for d in finer.designs()} & set(first.table["key"])
    with pytest.raises(OutputPathError, match=r"another spec \(grid: 13 now, 12 there\)"):
        run_sweep(finer, tmp_path / "a", workers=1)  # one directory, one spec
    result = run_sweep(finer, tmp_path / "b", workers=1)
    assert result.computed == 2 and len(result.table) == 2


def _cli(out: Path) -> list[str]:
    return [
        sys.executable,
        "-m",
        "orthoglide_pin",
        "sweep",
        "--leg-length",
        KILL_LEGS,
        "--grid",
        str(GRID),
        "--workers",
        "1",
        "--chunk-size",
        "1",
        "--no-plot",
        "--out",
        str(out),
    ]


def test_killed_sweep_resumes_to_the_same_table(tmp_path: Path) -> None:
    killed, whole = tmp_path / "killed", tmp_path / "whole"
    proc = subprocess.Popen(
        _cli(killed), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )
    try:
        deadline = time.monotonic() + KILL_TIMEOUT
        while len(list((killed / "parts").glob("*.json"))) < KILL_AFTER:
            assert proc.poll() is None, "the sweep ended before it could be killed"
            assert time.monotonic() < deadline, "no parts written"
            time.sleep(0.005)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    spec = SweepSpec(axes=(SweepAxis.parse(f"leg_length={KILL_LEGS}"),), grid=GRID)
    keys = [design_key(d) for d in spec.designs()]
    left = load_parts(killed, spec.designs())
    assert KILL_AFTER <= len(left) < len(keys)
    assert not (killed / "results.csv").exists()
    for row in left.values():  # every part is whole
        assert row["status"] == "ok" and len(row) > 30
    resumed = subprocess.run(_cli(killed), capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert f"{len(left)} already done" in resumed.stdout
    result = run_sweep(spec, whole, workers=1)
    _same(pd.read_parquet(killed / "results.parquet"), result.table)
    assert (killed / "results.csv").read_text() == result.csv.read_text()


# ------------------------------------------- a real Dask cluster that loses a worker
DASK = Path(sys.executable).with_name("dask")
CLUSTER_LEGS = "0.26:0.4:24"
#: Parts written before one cluster worker is killed.
CLUSTER_KILL_AFTER = 2
#: Seconds to wait for the cluster, the first parts and the whole sweep.
CLUSTER_TIMEOUT = 60.0
SWEEP_TIMEOUT = 300.0


def _scheduler_address(file: Path, proc: subprocess.Popen[bytes]) -> str:
    """The address the scheduler wrote to ``file`` once listening (its port chosen by itself)."""
    deadline = time.monotonic() + CLUSTER_TIMEOUT
    while True:
        assert proc.poll() is None, "the scheduler exited"
        with contextlib.suppress(OSError, ValueError):
            address = json.loads(file.read_text())["address"]
            if isinstance(address, str) and address.startswith("tcp://127.0.0.1:"):
                return address
        assert time.monotonic() < deadline, "no scheduler file"
        time.sleep(0.05)


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
def cluster(tmp_path: Path) -> Iterator[tuple[str, list[subprocess.Popen[bytes]]]]:
    """A scheduler and two single-threaded workers on 127.0.0.1; all killed afterwards.

    The scheduler takes a free port itself (port 0) and writes its address to a
    file: no port is chosen here and freed for another process to take first.
    """
    distributed = pytest.importorskip("distributed")
    if not DASK.exists():
        pytest.skip("no dask command next to the interpreter")
    file = tmp_path / "scheduler.json"
    procs = [
        _start(
            "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
            "--scheduler-file", str(file),
        )
    ]  # fmt: skip
    try:
        address = _scheduler_address(file, procs[0])
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
        sys.executable, "-m", "orthoglide_pin", "sweep", "--leg-length", CLUSTER_LEGS,
        "--grid", str(GRID), "--scheduler", address, "--chunk-size", "1",
        "--no-plot", "--no-progress", "--json", "--out", str(out),
    ]  # fmt: skip
    sweep = subprocess.Popen(
        argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True
    )
    try:
        deadline = time.monotonic() + CLUSTER_TIMEOUT
        while len(list((out / "parts").glob("*.json"))) < CLUSTER_KILL_AFTER:
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
    spec = SweepSpec(axes=(SweepAxis.parse(f"leg_length={CLUSTER_LEGS}"),), grid=GRID)
    serial = run_sweep(spec, tmp_path / "serial", workers=1, progress=False)
    clustered = pd.read_parquet(out / "results.parquet")
    pd.testing.assert_frame_equal(clustered, serial.table, check_exact=True)
