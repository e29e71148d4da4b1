"""Shared by the controller layer's tests: LinuxCNC's tools where they are installed.

The tests in LinuxCNC need ``halcompile`` (Debian ``linuxcnc-uspace-dev``) and
``linuxcnc`` (``linuxcnc-uspace``), installed by ``.ci/install-linuxcnc``.
Where they are missing they are skipped with the reason, unless
``ORTHOGLIDE_REQUIRE_LINUXCNC=1`` (as for the ``rs274`` tests of the program
layer) turns the skip into a failure.
"""

from __future__ import annotations

import ctypes
import os
import pwd
import shutil
import signal
import subprocess
from pathlib import Path

import pytest

#: Environment variable that makes a missing LinuxCNC a failure (shared with tests/program).
REQUIRE_ENV = "ORTHOGLIDE_REQUIRE_LINUXCNC"


def require(*tools: str) -> dict[str, str]:
    """Paths of LinuxCNC's ``tools``, or skip (fail with ``ORTHOGLIDE_REQUIRE_LINUXCNC=1``)."""
    found = {t: shutil.which(t) for t in tools}
    missing = [t for t, p in found.items() if p is None]
    if not missing:
        return {t: str(p) for t, p in found.items()}
    unavailable(
        f"{', '.join(missing)} not found on PATH (Debian: apt-get install linuxcnc-uspace "
        "linuxcnc-uspace-dev, or .ci/install-linuxcnc)"
    )
    raise AssertionError("unreachable")


def unavailable(message: str) -> None:
    """Skip the test for ``message`` (fail with ``ORTHOGLIDE_REQUIRE_LINUXCNC=1``)."""
    if os.environ.get(REQUIRE_ENV) == "1":
        pytest.fail(f"{message}, and {REQUIRE_ENV}=1 requires the LinuxCNC tests")
    pytest.skip(f"{message}: LinuxCNC tests skipped (set {REQUIRE_ENV}=1 to fail instead)")


def ordinary_uid() -> int:
    """An ordinary user's id: LinuxCNC refuses to run as root without one (``RTAPI_UID``)."""
    users = [u for u in pwd.getpwall() if 1000 <= u.pw_uid < 60000]
    return users[0].pw_uid if users else 65534


def rtapi_env(sockets: Path, **extra: str) -> dict[str, str]:
    """The environment of a LinuxCNC run; as root, an ordinary user and a socket in ``sockets``."""
    env = dict(os.environ, **extra)
    if os.geteuid() == 0:  # LinuxCNC refuses root without an ordinary user to run as
        env.update(RTAPI_UID=str(ordinary_uid()), RTAPI_FIFO_PATH=str(sockets / "rtapi_fifo"))
    return env


def run_session(args: list[str], folder: Path, env: dict[str, str], timeout: float) -> None:
    """Run ``args`` in ``folder`` in a session of its own, its output in ``log.txt``.

    The whole session (LinuxCNC's rtapi_app, halcmd, the display...) is
    killed at the end, even when the run fails or times out.
    """
    proc = None
    try:
        with open(folder / "log.txt", "w") as log:
            proc = subprocess.Popen(
                args,
                cwd=folder,
                env=env,
                stdout=log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
            proc.wait(timeout=timeout)
    finally:
        if proc is not None and proc.poll() is None:
            for sig in (signal.SIGTERM, signal.SIGKILL):
                try:
                    os.killpg(proc.pid, sig)
                    proc.wait(timeout=10)
                    break
                except (ProcessLookupError, subprocess.TimeoutExpired):
                    continue


def halcompile(comp: Path, *, install: bool = False) -> str:
    """Build ``comp`` with ``halcompile`` in its folder (``install``: into LinuxCNC's modules)."""
    tool = require("halcompile")["halcompile"]
    option = "--install" if install else "--compile"
    done = subprocess.run(
        [tool, option, comp.name], cwd=comp.parent, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


class Pose(ctypes.Structure):
    """LinuxCNC's ``EmcPose``: ``tran`` (x, y, z) then a, b, c, u, v, w [mm, deg]."""

    _fields_ = [(n, ctypes.c_double) for n in ("x", "y", "z", "a", "b", "c", "u", "v", "w")]
