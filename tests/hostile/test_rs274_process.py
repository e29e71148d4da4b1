"""LinuxCNC's ``rs274`` run by the package ends with its caller (skipped without rs274).

A program that loops forever keeps ``rs274`` printing; when the Python process
that runs it is killed (``SIGKILL``: no cleanup), the kernel kills ``rs274``
too; when it is interrupted (``SIGINT``), ``rs274`` is stopped and its
temporary directory removed.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from hostile._support import TIMEOUT, first_line, wait_until

#: A program that never ends, and the script that reads it through rs274.
SCRIPT = """
import orthoglide_pin as og
print("ready", flush=True)
og.read_rs274_text("G21\\no1 while [1]\\nG0 X1\\nG0 X0\\no1 endwhile\\nM2\\n", timeout=600)
"""


def _rs274_in_group(pgid: int) -> list[int]:
    """Processes named rs274 of the group ``pgid`` still running."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            name, rest = (entry / "stat").read_text().rsplit(")", 1)
        except OSError:
            continue
        fields = rest.split()
        if name.endswith("(rs274") and int(fields[2]) == pgid and fields[0] != "Z":
            found.append(int(entry.name))
    return found


@pytest.fixture
def reader(tmp_path: Path) -> subprocess.Popen[str]:
    if shutil.which("rs274") is None:
        if os.environ.get("ORTHOGLIDE_REQUIRE_LINUXCNC") == "1":
            pytest.fail("rs274 not found, and ORTHOGLIDE_REQUIRE_LINUXCNC=1 requires it")
        pytest.skip("rs274 not found on PATH (Debian: apt-get install linuxcnc-uspace)")
    env = {**os.environ, "TMPDIR": str(tmp_path)}
    process = subprocess.Popen(
        [sys.executable, "-c", SCRIPT],
        stdout=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,
    )
    assert first_line(process) == "ready\n"
    wait_until(lambda: bool(_rs274_in_group(process.pid)), TIMEOUT, "rs274 to start")
    yield process
    if process.poll() is None:  # pragma: no cover - only when the test failed
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()


def test_killed_caller_takes_rs274_along(reader: subprocess.Popen[str]) -> None:
    os.kill(reader.pid, signal.SIGKILL)  # the caller only: rs274 is not signalled
    reader.wait(TIMEOUT)
    wait_until(lambda: not _rs274_in_group(reader.pid), 10.0, "rs274 to end")


def test_interrupted_caller_stops_rs274_and_cleans_up(
    reader: subprocess.Popen[str], tmp_path: Path
) -> None:
    os.kill(reader.pid, signal.SIGINT)
    assert reader.wait(TIMEOUT) != 0
    wait_until(lambda: not _rs274_in_group(reader.pid), 10.0, "rs274 to end")
    assert not list(tmp_path.glob("orthoglide-rs274-*"))
