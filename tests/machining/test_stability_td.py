"""Semi-discretization against a time-domain simulation of the delayed equations.

On the single-degree-of-freedom benchmark (see test_stability_sd), at speeds
on the Hopf and flip lobes, the simulated vibration (fourth-order Runge-Kutta,
tooth by tooth) decays 10 % below the semi-discretization's limit and grows
10 % above it; its growth per tooth period matches the monodromy matrix's
spectral radius.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.machining.frf import ModalModel
from orthoglide_pin.machining.regeneration import MillingProcess
from orthoglide_pin.machining.stability_sd import critical_depths_sd, spectral_radius_sd
from orthoglide_pin.machining.stability_td import simulate_chatter

RPM = 2.0 * math.pi / 60.0
BENCHMARK = ModalModel(
    np.array([922.0]), np.array([0.011]), np.array([0.03993]), np.array([[1.0], [0.0]])
)
#: Depths tried around the limit [-].
BELOW, ABOVE = 0.9, 1.1
#: The simulated growth per tooth period against the spectral radius, absolute.
GROWTH_TOL = 0.03
#: Tooth periods simulated.
PERIODS = 80


@pytest.mark.parametrize("immersion", [0.05, 1.0])
def test_decays_below_and_grows_above_the_limit(immersion: float) -> None:
    process = MillingProcess(2, 6e8, 2e8, math.acos(2.0 * immersion - 1.0), math.pi)
    speeds = np.array([10000.0, 18000.0]) * RPM  # a Hopf lobe, and the flip lobe at 0.05
    limit = critical_depths_sd(BENCHMARK, process, speeds, steps=24)
    w = np.repeat(speeds, 2)
    depths = np.ravel(np.outer(limit, [BELOW, ABOVE]))
    sim = simulate_chatter(BENCHMARK, process, w, depths, periods=PERIODS)
    assert sim.grows.tolist() == [False, True, False, True]
    rho = spectral_radius_sd(BENCHMARK, process, w, depths, steps=24)
    assert np.allclose(sim.growth, rho, atol=GROWTH_TOL)
