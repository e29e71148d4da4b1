"""Shared pieces of the hostile-input suite: the real console script in a subprocess.

Every subprocess has a timeout and runs in its own session; whatever is still
alive of its process group when a test ends is killed, so no test hangs or
leaks a process.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from hostile._support import ORTHOGLIDE, TIMEOUT, group_alive


@pytest.fixture
def spawn(tmp_path: Path) -> Iterator[Callable[..., subprocess.Popen[str]]]:
    """Start ``orthoglide ARGS`` in ``tmp_path``, in a new session; killed at the end."""
    started: list[subprocess.Popen[str]] = []

    def start(
        *args: str, cwd: Path = tmp_path, env: dict[str, str] | None = None
    ) -> subprocess.Popen[str]:
        process = subprocess.Popen(
            [ORTHOGLIDE, *args],
            cwd=cwd,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
        started.append(process)
        return process

    yield start
    for process in started:
        if process.poll() is None or group_alive(process.pid):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(process.pid, signal.SIGKILL)
        process.communicate(timeout=TIMEOUT)


@pytest.fixture
def cli(tmp_path: Path) -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run ``orthoglide ARGS`` in ``tmp_path`` to the end (with a timeout)."""

    def run(*args: str, cwd: Path = tmp_path) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [ORTHOGLIDE, *args],
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
            check=False,
        )

    return run
