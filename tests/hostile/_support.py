"""Helpers of the hostile-input suite: the console script, waits with timeouts, process groups."""

from __future__ import annotations

import os
import selectors
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

#: The ``orthoglide`` console script of this environment.
ORTHOGLIDE = str(Path(sys.executable).with_name("orthoglide"))
#: Longest wait for a command, or for a sign of life from it [s].
TIMEOUT = 180.0


def group_alive(pgid: int) -> bool:
    """Whether any process of the group ``pgid`` is still running (not a zombie)."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            return True
    return False


def wait_until(condition: Callable[[], bool], timeout: float, what: str) -> None:
    """Poll ``condition`` every 50 ms; fail the test after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


def first_line(process: subprocess.Popen[str], timeout: float = TIMEOUT) -> str:
    """The first line the process prints on stdout (fails the test after ``timeout``)."""
    assert process.stdout is not None
    with selectors.DefaultSelector() as sel:
        sel.register(process.stdout, selectors.EVENT_READ)
        if not sel.select(timeout):
            pytest.fail(f"no output within {timeout} s")
    return process.stdout.readline()


def cpu_seconds(pid: int) -> float:
    """CPU time used so far by process ``pid`` [s] (0 once it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
