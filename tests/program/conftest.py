"""Fixtures of the program layer's tests: LinuxCNC's ``rs274`` where it is installed.

The tests of the LinuxCNC route need ``rs274`` (Debian package ``linuxcnc-uspace``,
installed by ``.ci/install-linuxcnc``). Where it is missing they are skipped,
unless ``ORTHOGLIDE_REQUIRE_LINUXCNC=1`` turns the skip into a failure.
"""

from __future__ import annotations

import os
import shutil

import pytest
from program._support import CORPUS, CORPUS_PROGRAMS, CORPUS_REFUSED, CORPUS_TOOLS

from orthoglide_pin.program import Move, read_rs274

#: Environment variable that makes a missing ``rs274`` a failure.
REQUIRE_ENV = "ORTHOGLIDE_REQUIRE_LINUXCNC"


@pytest.fixture(scope="session")
def rs274() -> str:
    """Path of LinuxCNC's ``rs274``, or skip (fail with ``ORTHOGLIDE_REQUIRE_LINUXCNC=1``)."""
    path = shutil.which("rs274")
    if path:
        return path
    message = "rs274 not found on PATH (Debian: apt-get install linuxcnc-uspace)"
    if os.environ.get(REQUIRE_ENV) == "1":
        pytest.fail(f"{message}, and {REQUIRE_ENV}=1 requires the LinuxCNC tests")
    pytest.skip(f"{message}: LinuxCNC tests skipped (set {REQUIRE_ENV}=1 to fail instead)")


@pytest.fixture(scope="session")
def corpus(rs274: str) -> dict[str, list[Move]]:
    """Every corpus program LinuxCNC reads, read through ``rs274`` (a few seconds)."""
    names = [n for n in CORPUS_PROGRAMS if n not in CORPUS_REFUSED]
    return {n: read_rs274(CORPUS / n, tools=CORPUS_TOOLS) for n in names}
