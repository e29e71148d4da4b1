"""Shared fixtures: an isolated URDF cache and the prototype's models."""

from __future__ import annotations

import json
import math
import os
import signal
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from _notebooks import NotebookRuns, kernel_spec
from _wheel import build_wheel

import orthoglide_pin as og
from orthoglide_pin.cli import main

#: Prototype leg length [m] (paper, section 4).
PROTOTYPE_LEG = 0.31
#: Prototype cube: lower corner coordinate on each axis [m] and side [m].
CUBE_CORNER = -PROTOTYPE_LEG / math.sqrt(18.0)
CUBE_SIDE = 0.2


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """Under ``--dist loadscope``: the suite's units of work, longest first (``_parallel.py``)."""
    if config.getoption("dist") != "loadscope":
        return None
    from _parallel import ModuleUnits

    return ModuleUnits(config, log)


@pytest.fixture(scope="session", autouse=True)
def _interruptible() -> Iterator[None]:
    """Ctrl-C reaches the tests and the commands they start, however the suite was launched.

    A suite started as a background job of a non-interactive shell inherits
    SIGINT ignored, and so would every process it starts (an ignored signal
    survives exec); the interrupt tests then could not interrupt anything.
    """
    old = signal.getsignal(signal.SIGINT)
    if old == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


@pytest.fixture(scope="session", autouse=True)
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Keep every rendered URDF out of the user's cache."""
    old = os.environ.get(og.machine.description.CACHE_ENV)
    os.environ[og.machine.description.CACHE_ENV] = str(tmp_path_factory.mktemp("urdf-cache"))
    yield
    if old is None:
        os.environ.pop(og.machine.description.CACHE_ENV, None)
    else:
        os.environ[og.machine.description.CACHE_ENV] = old


@pytest.fixture
def no_drawing(monkeypatch: pytest.MonkeyPatch) -> None:
    """A report without its figures, for tests of what else it holds.

    The figures are tested in ``tests/report/test_figures.py``; drawing them is
    most of a small report's time.
    """
    from orthoglide_pin.report import figures as report_figures

    monkeypatch.setattr(report_figures, "figures", lambda *_, **__: {})


@pytest.fixture(scope="session")
def params() -> og.OrthoglideParams:
    return og.prototype()


@pytest.fixture(scope="session")
def model(params: og.OrthoglideParams) -> og.ClosedLoopModel:
    return og.ClosedLoopModel(params)


def cube_points(n: int, seed: int) -> np.ndarray:
    """``n`` seeded random points in the prototype cube [m], shape (n, 3)."""
    rng = np.random.default_rng(seed)
    return CUBE_CORNER + CUBE_SIDE * rng.random((n, 3))


def lapack_factors(points: np.ndarray, leg_length: float) -> np.ndarray:
    """Transmission factors, ascending, from LAPACK's SVD of ``J^-1`` (a second route)."""
    s = np.linalg.svd(og.inverse_jacobian(points, leg_length), compute_uv=False)
    return 1.0 / s  # descending singular values of J^-1: ascending ones of J


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """Run ``orthoglide ARGV`` in-process: exit status, stdout, stderr."""
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict[str, Any]:
    """Run ``orthoglide ARGV --json``, check it succeeds quietly, return its one JSON object."""
    code, out, err = run(capsys, *argv, "--json")
    assert code == 0, err
    assert err == ""
    data = json.loads(out)  # exactly one JSON document on stdout
    assert isinstance(data, dict)
    return data


@pytest.fixture(scope="session")
def dyn(model: og.ClosedLoopModel) -> og.ClosedLoopDynamics:
    return og.ClosedLoopDynamics(model)


def random_states(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points well inside the prototype cube [m], speeds ~1 m/s, accelerations ~20 m/s^2."""
    rng = np.random.default_rng(seed)
    p = CUBE_CORNER + 0.05 * CUBE_SIDE + 0.9 * CUBE_SIDE * rng.random((n, 3))
    return p, rng.standard_normal((n, 3)), 20.0 * rng.standard_normal((n, 3))


def unit_sphere(n: int) -> np.ndarray:
    """``n`` nearly uniform unit vectors (Fibonacci lattice), shape (n, 3)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5**0.5) * k
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


@pytest.fixture(scope="session")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The project's wheel, built once per test session (``tests/_wheel.py``)."""
    return build_wheel(tmp_path_factory.mktemp("src"), tmp_path_factory.mktemp("dist"))


@pytest.fixture(scope="session")
def notebook_runs(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NotebookRuns]:
    """The notebooks, each executed once per test session on request (``tests/_notebooks.py``).

    Skipped where the notebook tools (the ``[test]`` extra) are missing.
    """
    for module in ("nbformat", "nbclient", "ipykernel", "jupyter_client"):
        pytest.importorskip(module)
    with kernel_spec(tmp_path_factory.mktemp("jupyter")) as kernel:
        yield NotebookRuns(kernel, tmp_path_factory)
