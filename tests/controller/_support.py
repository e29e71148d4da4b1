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
import shutil
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
