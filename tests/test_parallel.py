"""The units of work of the parallel run (``tests/_parallel.py``) name what exists."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("xdist")
from _parallel import LONGEST, SHARED, work_unit  # after the skip: it needs pytest-xdist

ROOT = Path(__file__).resolve().parents[1]


def test_every_named_module_exists() -> None:
    """A renamed module would silently leave its group, or lose its early start."""
    groups = set(SHARED.values())
    assert all((ROOT / module).is_file() for module in SHARED)
    assert all(unit in groups or (ROOT / unit).is_file() for unit in LONGEST)
    assert len(set(LONGEST)) == len(LONGEST)


def test_modules_that_share_a_session_fixture_are_one_unit() -> None:
    assert work_unit("tests/test_docs.py::test_the_build_is_strict_and_clean") == work_unit(
        "tests/test_notebooks.py::test_every_notebook_runs[01_kinematics_isotropy.ipynb]"
    )
    assert work_unit("tests/test_wheel.py::t") == work_unit("tests/test_bare_install.py::t")
    # one LinuxCNC at a time on a machine
    assert work_unit("tests/controller/test_stream.py::t") == work_unit(
        "tests/controller/test_configuration.py::t"
    )
    assert work_unit("tests/sweep/test_pool.py::t[a::b]") == "tests/sweep/test_pool.py"
