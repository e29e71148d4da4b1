"""Milling stability by simulating the delayed equations in time: growth or decay.

An independent check of :mod:`~orthoglide_pin.machining.stability_sd`: the
same regenerative model (the tool's modes driven by ``F(t) = -a H(t) (r(t) -
r(t - T))``, with the exact tooth-by-tooth directional factors, each tooth
entering and leaving the cut) integrated with the classical fourth-order
Runge-Kutta scheme at a fixed step, an integer number of steps per tooth
period so that the delayed motion is read from the stored history (at the
half steps, halfway between two stored values). The cut is linear (the tool
never leaves the cut for good; the static chip does not enter, it only shifts
the motion): from a small initial displacement the vibration decays below the
stability limit and grows above it. The growth per tooth period is the slope
of the logarithm of each period's largest tip motion over the second half of
the run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import integer
from orthoglide_pin.machining.frf import ModalModel
from orthoglide_pin.machining.regeneration import (
    MillingProcess,
    check_model,
    check_process,
    paired,
    speeds_array,
)

FloatArray = NDArray[np.float64]

__all__ = ["ChatterSimulation", "simulate_chatter"]

#: Fewest integration steps per period of the highest mode.
STEPS_PER_CYCLE: Final[int] = 40
#: Fewest steps per tooth period.
MIN_STEPS: Final[int] = 64
#: Tooth periods simulated by default.
PERIODS: Final[int] = 120


@dataclass(frozen=True)
class ChatterSimulation:
    """Growth or decay of the vibration at (speed, depth) points.

    Attributes:
        speeds: Spindle speeds [rad/s], shape (b,).
        depths: Axial depths [m], shape (b,).
        growth: The vibration's growth per tooth period (> 1: chatter), shape (b,).
        amplitude: Each tooth period's largest tip motion [m], shape (b, periods).
        steps: Integration steps per tooth period.
    """

    speeds: FloatArray
    depths: FloatArray
    growth: FloatArray
    amplitude: FloatArray
    steps: int

    @property
    def grows(self) -> NDArray[np.bool_]:
        """Whether the vibration grows (chatter) at each point, shape (b,)."""
        return np.asarray(self.growth > 1.0)


def simulate_chatter(
    model: ModalModel,
    process: MillingProcess,
    speeds: ArrayLike,
    depths: ArrayLike,
    periods: int = PERIODS,
) -> ChatterSimulation:
    """Integrate the delayed equations at (speed, depth) pairs (see the module).

    Args:
        model: The tip's modes, x along the feed.
        process: Teeth, cutting coefficients, immersion.
        speeds: Spindle speeds [rad/s], shape (b,).
        depths: Axial depths [m], shape (b,) (paired with ``speeds``).
        periods: Tooth periods simulated (at least 20).

    Returns:
        The growth per tooth period and the amplitudes.
    """
    check_model(model)
    check_process(process)
    omega = speeds_array("speeds", speeds)
    depth = paired("depths", depths, omega.size)
    count = integer("periods", periods, 20, 100_000)
    n, b = model.count, omega.size
    period = 2.0 * math.pi / (process.teeth * omega)
    cycles = float(np.max(model.frequencies * np.max(period)))
    steps = max(MIN_STEPS, 2 * math.ceil(STEPS_PER_CYCLE * cycles / 2))
    dt = period / steps
    pitch = 2.0 * math.pi / process.teeth
    h_half = process.directional(pitch * np.arange(2 * steps + 1) / (2 * steps))  # (2k+1, 2, 2)
    u = model.shapes
    force = (u.T / model.masses[:, np.newaxis]) @ h_half  # (2k+1, n, 2) modal accel per r
    w2, c2 = model.omega**2, 2.0 * model.damping * model.omega
    scale = depth[:, np.newaxis, np.newaxis]

    def rate(y: FloatArray, delayed: FloatArray, half: int) -> FloatArray:
        q, v = y[:, :n], y[:, n:]
        r = q @ u.T  # (b, 2)
        acc = -w2 * q - c2 * v - np.einsum("bnk,bk->bn", scale * force[half], r - delayed)
        return np.concatenate([v, acc], axis=1)

    y = np.zeros((b, 2 * n))
    y[:, :n] = 1e-6 * (u[0] + 0.5 * u[1]) / np.maximum(np.sum(u**2, axis=0), 1e-300)
    prev = np.zeros((steps + 1, b, 2))  # r over the last tooth period (none before: rest)
    cur = np.empty_like(prev)
    amp = np.zeros((b, count))
    h = dt[:, np.newaxis]
    for p in range(count):
        cur[0] = y[:, :n] @ u.T
        for i in range(steps):
            old0, old1 = prev[i], prev[i + 1]  # r at t - T and t + dt - T
            mid = 0.5 * (old0 + old1)
            k1 = rate(y, old0, 2 * i)
            k2 = rate(y + 0.5 * h * k1, mid, 2 * i + 1)
            k3 = rate(y + 0.5 * h * k2, mid, 2 * i + 1)
            k4 = rate(y + h * k3, old1, 2 * i + 2)
            y = y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
            cur[i + 1] = y[:, :n] @ u.T
        amp[:, p] = np.max(np.linalg.norm(cur, axis=2), axis=0)
        prev, cur = cur, prev
    half = count // 2
    logs = np.log(np.maximum(amp[:, half:], 1e-300))
    x = np.arange(logs.shape[1]) - 0.5 * (logs.shape[1] - 1)
    slope = logs @ x / float(x @ x)
    return ChatterSimulation(omega, depth, np.exp(slope), amp, steps)
