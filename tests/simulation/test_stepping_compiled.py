"""The compiled servo loop against the Python loop: the same run to the last digit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.simulation import stepping
from orthoglide_pin.simulation import stepping_compiled as sc
from orthoglide_pin.simulation.run import simulate_chunks

pytest.importorskip("mujoco")
pytest.importorskip("toppra")

DRIVE = og.load_drive(str(og.example_drive_file()))
PROGRAM = "G21 G90 G17\nG1 X10 Y5 Z-5 F3000\nG2 X10 Y5 I-5 J0\nG0 X0 Y0 Z0\nM30\n"
WRENCH = (40.0, -25.0, 30.0, 1.5, -0.8, 2.0)
#: Periods per chunk: the energy account's blocks and the progress ticks fall inside chunks.
CHUNK = 400


def _runs(plan: og.Plan, settings: og.ServoSettings, compiled: bool, monkeypatch) -> list:
    monkeypatch.setattr(stepping, "COMPILED", compiled)
    ticks: list[tuple[int, int]] = []
    parts = list(
        simulate_chunks(
            plan, None, DRIVE, settings, chunk=CHUNK, progress=lambda d, t: ticks.append((d, t))
        )
    )
    return [parts, ticks]


@pytest.mark.parametrize(
    ("wrench", "settings"),
    [
        (None, og.ServoSettings()),
        (WRENCH, og.ServoSettings(rate=1000.0, encoder_counts=4096, mass_error=0.1)),
    ],
)
def test_the_compiled_loop_runs_the_python_loop_to_the_last_digit(
    wrench, settings: og.ServoSettings, monkeypatch: pytest.MonkeyPatch
) -> None:
    import mujoco

    if sc.library(mujoco) is None:
        pytest.skip("numba or MuJoCo's C library is missing")
    plan = og.plan_program(
        og.read_program(PROGRAM), None, og.PlanLimits(drive=DRIVE), wrench=wrench
    )
    (fast, fast_ticks), (slow, slow_ticks) = (
        _runs(plan, settings, c, monkeypatch) for c in (True, False)
    )
    assert fast_ticks == slow_ticks and len(fast_ticks) > 50
    assert len(fast) == len(slow) > 2
    for a, b in zip(fast, slow, strict=True):
        for f in dataclasses.fields(a):
            x, y = getattr(a, f.name), getattr(b, f.name)
            if isinstance(x, np.ndarray):
                np.testing.assert_array_equal(x, y, err_msg=f.name)


def test_without_numba_there_is_no_compiled_loop(monkeypatch: pytest.MonkeyPatch) -> None:
    import mujoco

    sc.library.cache_clear()
    monkeypatch.setattr(sc, "AVAILABLE", False)
    try:
        assert sc.library(mujoco) is None
    finally:
        sc.library.cache_clear()
