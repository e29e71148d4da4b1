"""The bare wheel: the core install runs the model and the report without the extras.

``pip install orthoglide-pin`` brings what the model needs; the sweep's table
stack (pandas, pyarrow: ``[tables]``), Dask (``[cluster]``) and PyNite (the
frame FEA check, ``[fea]``) are extras. The
wheel is installed in a fresh environment whose dependencies come from this
one, with the extras' modules made unimportable: ``orthoglide report`` must
succeed there, and ``orthoglide sweep`` must fail with one line naming the
extra to install, having written nothing.
"""

from __future__ import annotations

import os
import subprocess
import zipfile
from email.parser import Parser
from pathlib import Path

import pytest
from _wheel import TIMEOUT, fresh_environment, site_packages

pytestmark = pytest.mark.slow

#: Top-level modules of the extras, blocked in the bare environment.
EXTRA_MODULES = ("dask", "distributed", "pandas", "pyarrow", "Pynite")
#: Distributions that must only be required through an extra.
EXTRA_DISTRIBUTIONS = ("dask", "pandas", "pyarrow", "pynitefea")
_BLOCKER = f"""
import sys

BLOCKED = {EXTRA_MODULES!r}


class _BlockExtras:
    @staticmethod
    def find_spec(name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None


sys.meta_path.insert(0, _BlockExtras)
"""


@pytest.fixture(scope="module")
def bare_python(wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    python = fresh_environment(wheel, tmp_path_factory.mktemp("bare") / "env")
    fresh = site_packages(python)
    (fresh / "zzz_block_extras.py").write_text(_BLOCKER)
    (fresh / "zzz_block_extras.pth").write_text("import zzz_block_extras\n")
    return python


def _orthoglide(python: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    return subprocess.run(
        [str(python), "-m", "orthoglide_pin", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )


def test_the_extras_are_blocked_and_the_package_is_the_wheel(
    bare_python: Path, tmp_path: Path
) -> None:
    script = (
        "import importlib.util, orthoglide_pin\n"
        "print(orthoglide_pin.__file__)\n"
        f"for m in {EXTRA_MODULES!r}:\n"
        "    try:\n"
        "        __import__(m)\n"
        "    except ImportError:\n"
        "        print('blocked', m)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    done = subprocess.run(
        [str(bare_python), "-c", script],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    lines = done.stdout.split("\n")
    assert lines[0].startswith(str(bare_python.parents[1])), done.stderr
    assert [line for line in lines if line.startswith("blocked")] == [
        f"blocked {m}" for m in EXTRA_MODULES
    ]


def test_report_runs_on_the_core_install(bare_python: Path, tmp_path: Path) -> None:
    done = _orthoglide(bare_python, "report", "--out", "rep", "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "rep" / "report.html").is_file()
    assert done.stderr == ""


def test_sweep_says_which_extra_to_install(bare_python: Path, tmp_path: Path) -> None:
    done = _orthoglide(
        bare_python, "sweep", "--leg-length", "0.3:0.32:2", "--out", "sw", cwd=tmp_path
    )
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr.count("\n") == 1
    assert done.stderr.startswith("orthoglide sweep: error: ")
    assert "pip install 'orthoglide-pin[tables]'" in done.stderr
    assert not (tmp_path / "sw").exists()  # nothing written


def test_the_frame_fea_says_which_extra_to_install(bare_python: Path, tmp_path: Path) -> None:
    script = (
        "import orthoglide_pin as og\n"
        "try:\n"
        "    og.frame_compliance([0.0, 0.0, 0.0])\n"
        "except og.MissingExtraError as error:\n"
        "    print(error)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    done = subprocess.run(
        [str(bare_python), "-c", script],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout == (
        "the frame FEA check needs the optional package Pynite, which is not installed: "
        "pip install 'orthoglide-pin[fea]'\n"
    )


def test_the_extras_are_required_only_through_extras(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as zf:
        name = next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA"))
        metadata = Parser().parsestr(zf.read(name).decode())
    requires = metadata.get_all("Requires-Dist") or []
    core = [r for r in requires if "extra ==" not in r]
    for dist in EXTRA_DISTRIBUTIONS:
        assert not [r for r in core if r.lower().startswith(dist)], core
    assert {"tables", "cluster", "fea", "all"} <= set(metadata.get_all("Provides-Extra") or [])
    for dist in ("pin", "yourdfpy", "xacro", "meshcat", "numpy", "PyYAML", "matplotlib"):
        assert any(r.startswith(dist) for r in core), dist
