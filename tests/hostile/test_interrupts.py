"""Ctrl-C, SIGTERM, SIGKILL and closed pipes, on the real ``orthoglide`` console script.

Each command runs in its own session (``spawn``), so a signal can go to the
whole process group as a terminal's Ctrl-C does; whatever is left is killed
when the test ends. Every wait has a timeout.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from hostile._support import (
    ORTHOGLIDE,
    TIMEOUT,
    cpu_seconds,
    first_line,
    group_alive,
    wait_until,
)

from orthoglide_pin._paths import TEMP_TAG

pytestmark = pytest.mark.skipif(
    not Path("/proc/self/stat").is_file(), reason="process groups are read from /proc (Linux)"
)

Spawn = Callable[..., subprocess.Popen[str]]
Cli = Callable[..., subprocess.CompletedProcess[str]]

#: Signal, exit status and the one line printed.
SIGNALS = [
    (signal.SIGINT, 130, "orthoglide: interrupted\n"),
    (signal.SIGTERM, 143, "orthoglide: terminated\n"),
]
SIGNAL_IDS = ["SIGINT", "SIGTERM"]
#: Small report grids: the report command in a few seconds.
FAST_REPORT = ("--quiet", "--resolution", "5", "--cube-resolution", "5")
#: CPU time after which a command is surely past its start-up [s].
BUSY_CPU = 4.0
#: Time left to the processes of a group to exit after their leader [s].
GROUP_EXIT = 30.0
#: The start-up hook that stops a command just before it puts its output in place.
PAUSE_HOOK = Path(__file__).resolve().parent / "_pause"
PAUSE_ENV = "ORTHOGLIDE_TEST_PAUSED_FILE"


def temporaries(folder: Path) -> list[Path]:
    return [p for p in folder.iterdir() if TEMP_TAG in p.name]


def paused_env(flag: Path) -> dict[str, str]:
    """The environment of a command that stops before it installs its output (``_pause/``).

    Once stopped, the command has written its whole output into its temporary
    directory and creates ``flag``: a signal sent then lands in the write, at
    the same point on every run, however fast or busy the machine.
    """
    path = [str(PAUSE_HOOK), *filter(None, [os.environ.get("PYTHONPATH")])]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(path), PAUSE_ENV: str(flag)}


def ended(process: subprocess.Popen[str], status: int, line: str) -> None:
    """The process exits with ``status`` after printing exactly ``line`` on stderr."""
    _, err = process.communicate(timeout=TIMEOUT)
    assert process.returncode == status, err
    assert err == line, err
    wait_until(lambda: not group_alive(process.pid), GROUP_EXIT, "the process group to exit")


@pytest.mark.parametrize(("sig", "status", "line"), SIGNALS, ids=SIGNAL_IDS)
def test_live_viewer(spawn: Spawn, sig: signal.Signals, status: int, line: str) -> None:
    process = spawn("view", "--port", "0", "--json")
    url = json.loads(first_line(process))["url"]
    port = int(url.rsplit(":", 1)[1].strip("/"))
    os.killpg(process.pid, sig)
    ended(process, status, line)
    with pytest.raises(ConnectionRefusedError):
        socket.create_connection(("127.0.0.1", port), timeout=5).close()


@pytest.mark.parametrize(("sig", "status", "line"), SIGNALS, ids=SIGNAL_IDS)
def test_report_while_writing(
    spawn: Spawn, tmp_path: Path, sig: signal.Signals, status: int, line: str
) -> None:
    flag = tmp_path.parent / f"{tmp_path.name}.paused"
    process = spawn("report", "--out", "rep", *FAST_REPORT, env=paused_env(flag))
    wait_until(
        lambda: flag.exists() or process.poll() is not None,
        TIMEOUT,
        "the report to have written its files",
    )
    assert process.poll() is None, "the report ended before it could be interrupted"
    assert temporaries(tmp_path), "no temporary directory to clean up"
    process.send_signal(sig)  # the process alone, as `kill` does
    ended(process, status, line)
    assert list(tmp_path.iterdir()) == []  # no report, no temporary directory


def test_a_second_signal_does_not_stop_the_cleanup() -> None:
    """In-process: the first SIGINT raises, the next ones wait for the cleanup."""
    from orthoglide_pin.cli import _runtime

    before = signal.getsignal(signal.SIGINT)
    cleaned = False
    with pytest.raises(KeyboardInterrupt), _runtime.signals_as_exceptions():
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1.0)  # the handler runs before this returns
        finally:
            os.kill(os.getpid(), signal.SIGINT)  # a second Ctrl-C during the cleanup
            os.kill(os.getpid(), signal.SIGTERM)  # and a SIGTERM
            time.sleep(0.01)
            cleaned = True
    assert cleaned
    assert signal.getsignal(signal.SIGINT) is before  # restored after the command


@pytest.mark.parametrize(("sig", "status", "line"), SIGNALS, ids=SIGNAL_IDS)
def test_sweep_and_its_workers(
    spawn: Spawn, tmp_path: Path, sig: signal.Signals, status: int, line: str
) -> None:
    process = spawn(
        "sweep", "--leg-length", "0.25:0.45:60", "--out", "sw", "--workers", "2", "--no-progress"
    )
    wait_until(
        lambda: (tmp_path / "sw" / "parts").is_dir() or process.poll() is not None,
        TIMEOUT,
        "the sweep to start",
    )
    assert process.poll() is None, "the sweep ended before it could be interrupted"
    os.killpg(process.pid, sig)  # the whole group, as a terminal's Ctrl-C
    ended(process, status, line)
    assert not temporaries(tmp_path / "sw") and not temporaries(tmp_path / "sw" / "parts")


@pytest.mark.parametrize(("sig", "status", "line"), SIGNALS, ids=SIGNAL_IDS)
def test_a_long_computation(
    spawn: Spawn, tmp_path: Path, sig: signal.Signals, status: int, line: str
) -> None:
    process = spawn("map", "--resolution", "3001", "--out", "m.png", "--csv", "m.csv")
    # past the start-up (imports take about 1 s of CPU), into the computation
    wait_until(
        lambda: cpu_seconds(process.pid) > BUSY_CPU or process.poll() is not None,
        TIMEOUT,
        "the map to compute",
    )
    assert process.poll() is None, "the map ended before it could be interrupted"
    process.send_signal(sig)
    ended(process, status, line)
    assert list(tmp_path.iterdir()) == []


def test_sweep_terminated_alone_takes_its_workers_along(spawn: Spawn, tmp_path: Path) -> None:
    process = spawn(
        "sweep", "--leg-length", "0.25:0.45:60", "--out", "sw", "--workers", "2", "--no-progress"
    )
    wait_until(
        lambda: (tmp_path / "sw" / "parts").is_dir() or process.poll() is not None,
        TIMEOUT,
        "the sweep to start",
    )
    assert process.poll() is None, "the sweep ended before it could be interrupted"
    process.send_signal(signal.SIGTERM)  # `kill PID`: the workers get no signal of their own
    ended(process, 143, "orthoglide: terminated\n")


def test_killed_report_leaves_a_temporary_that_the_next_run_removes(
    spawn: Spawn, cli: Cli, tmp_path: Path
) -> None:
    flag = tmp_path.parent / f"{tmp_path.name}.paused"
    process = spawn("report", "--out", "rep", *FAST_REPORT, env=paused_env(flag))
    wait_until(
        lambda: flag.exists() or process.poll() is not None,
        TIMEOUT,
        "the report to have written its files",
    )
    assert process.poll() is None, "the report ended before it could be killed"
    os.killpg(process.pid, signal.SIGKILL)  # no cleanup is possible
    process.communicate(timeout=TIMEOUT)
    left = temporaries(tmp_path)
    assert left, "SIGKILL left no temporary directory"
    done = cli(
        "design",
        "--workspace",
        "0.2",
        "--psi",
        "0.5",
        "2",
        "--grid",
        "3",
        "--write-config",
        "d.yaml",
    )  # any later write into the same directory
    assert done.returncode == 0, done.stderr
    assert temporaries(tmp_path) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.yaml"]


@pytest.mark.parametrize(
    ("argv", "statuses"),
    [(["urdf"], {141}), (["--help"], {0, 141}), (["sweep", "--help"], {0, 141})],
    ids=["urdf", "help", "sweep-help"],
)
def test_a_closed_pipe_ends_quietly(spawn: Spawn, argv: list[str], statuses: set[int]) -> None:
    process = spawn(*argv)
    assert process.stdout is not None
    process.stdout.close()  # the reader is gone before the first write, as `| head -0`
    _, err = process.communicate(timeout=TIMEOUT)
    assert process.returncode in statuses, err  # 141 = 128 + SIGPIPE; argparse's help
    assert err == ""  # ignores a closed pipe itself


def test_head_reads_the_first_line(tmp_path: Path) -> None:
    """``orthoglide urdf | head -1``: head's line, and a quiet exit of the writer."""
    done = subprocess.run(
        ["bash", "-o", "pipefail", "-c", f"'{ORTHOGLIDE}' urdf | head -1"],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        cwd=tmp_path,
        check=False,
    )
    assert done.stdout.startswith("<?xml")
    assert done.stderr == ""
    assert done.returncode in (0, 141)  # 0 when the whole URDF fit in the pipe


@pytest.mark.slow
def test_accuracy_interrupted_while_writing_leaves_nothing(spawn: Spawn, tmp_path: Path) -> None:
    import orthoglide_pin as og

    flag = tmp_path.parent / f"{tmp_path.name}.paused"
    process = spawn(
        "accuracy", "--example", "contour", "--cut", str(og.shipped_cut_file()),
        "--max-slider-speed", "1.2", "--max-slider-acceleration", "20", "--dt", "0.02",
        "--out", "acc", env=paused_env(flag),
    )  # fmt: skip
    wait_until(
        lambda: flag.exists() or process.poll() is not None,
        TIMEOUT,
        "the accuracy to have written its files",
    )
    assert process.poll() is None, "the command ended before it could be interrupted"
    process.send_signal(signal.SIGINT)
    ended(process, 130, "orthoglide: interrupted\n")
    assert list(tmp_path.iterdir()) == []  # no output, no temporary directory
