"""Fixtures of the controller layer's tests: the exported configuration run in LinuxCNC."""

from __future__ import annotations

import pytest
from controller._session import DESIGNS, run_design
from controller._support import require


@pytest.fixture(scope="session")
def run(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Each design's configuration run in LinuxCNC, both routes, once per test run."""
    linuxcnc = require("linuxcnc", "halcompile", "halsampler", "halstreamer")["linuxcnc"]
    return {d: run_design(tmp_path_factory.mktemp(d), d, linuxcnc) for d in DESIGNS}
