"""Measurement planning: the poses that condition the identification best.

The identification's covariance is ``sigma^2 (A^T A)^-1`` with ``A`` the
stacked identification Jacobian (:func:`~orthoglide_pin.calibration.identification.
stacked_jacobian`). A **D-optimal** plan of ``N`` poses maximises
``log det(A^T A)`` in the physically scaled parameters
(:func:`~orthoglide_pin.calibration.identification.parameter_scales`), which shrinks
the volume of the confidence ellipsoid of all 18 parameters at once.

The candidates are a regular grid over the machine's cube (every one within
the slider limits, since the limits cover the cube). The plan is built
greedily, each pose adding the most to the log-determinant
(``log det(M + A_c^T A_c) = log det M + log det(I_3 + A_c M^-1 A_c^T)``, so every
candidate is scored at once), then improved by Fedorov exchanges (a chosen
pose swapped for the candidate that raises the criterion most) until no swap
helps. Poses are distinct.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import integer, number_in, optional_callable
from orthoglide_pin.calibration.identification import MIN_POSES, parameter_scales, stacked_jacobian
from orthoglide_pin.calibration.model import GeometricModel
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Default candidate grid: points per edge of the cube.
GRID: Final[int] = 9
#: Regularisation of the greedy start, relative to the mean information.
RIDGE: Final[float] = 1e-9
#: Most passes of Fedorov exchanges.
MAX_PASSES: Final[int] = 20
#: Default tracker noise per axis [m].
DEFAULT_NOISE: Final[float] = 5e-6
#: Range of the tracker noise per axis [m]: 1 nm to 10 mm.
MIN_NOISE: Final[float] = 1e-9
MAX_NOISE: Final[float] = 1e-2


@dataclass(frozen=True)
class MeasurementPlan:
    """Poses to measure, and what they will determine.

    Attributes:
        points: Tool targets [m], shape (N, 3).
        q: Slider values to command (the drawing's inverse kinematics) [m],
            shape (N, 3).
        expected_std: Standard deviation of each parameter to expect for the
            tracker noise [m or rad], shape (18,).
        noise: The tracker noise per axis assumed [m].
        log_det: The D-criterion, ``log det(A^T A)`` in scaled parameters.
    """

    points: FloatArray
    q: FloatArray
    expected_std: FloatArray
    noise: float
    log_det: float


def candidate_points(params: OrthoglideParams, grid: int = GRID) -> FloatArray:
    """A regular grid of ``grid^3`` points over the machine's cube [m], (grid^3, 3)."""
    cube = params.workspace
    axis = np.linspace(0.0, cube.side, grid)
    mesh = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    return np.asarray(cube.corner) + mesh


def information(model: GeometricModel, q: FloatArray) -> FloatArray:
    """``A^T A`` of poses in the scaled parameters, shape (18, 18)."""
    a = stacked_jacobian(model, q) * parameter_scales(model.mean_length)
    out: FloatArray = a.T @ a
    return out


def expected_std(model: GeometricModel, q: FloatArray, noise: float) -> FloatArray:
    """Parameter standard deviations for poses ``q`` and a tracker noise [m, rad]."""
    info = information(model, q)
    scales = parameter_scales(model.mean_length)
    cov = noise**2 * scales[:, None] * np.linalg.pinv(info) * scales[None, :]
    out: FloatArray = np.sqrt(np.maximum(np.diag(cov), 0.0))
    return out


def _log_det(info: FloatArray) -> float:
    sign, value = np.linalg.slogdet(info)
    return float(value) if sign > 0 else -math.inf


def plan_poses(
    params: OrthoglideParams,
    count: int,
    *,
    noise: float = DEFAULT_NOISE,
    grid: int = GRID,
    progress: Callable[[int, int], None] | None = None,
) -> MeasurementPlan:
    """A D-optimal set of ``count`` poses in the machine's cube.

    Args:
        params: The machine (its leg length and cube).
        count: Number of poses, at least :data:`MIN_POSES`, at most ``grid^3``.
        noise: Tracker noise per axis [m], in ``[MIN_NOISE, MAX_NOISE]``, for the
            expected deviations.
        grid: Candidate points per edge of the cube.
        progress: Called with (poses chosen, ``count``) as they are, or ``None``.

    Returns:
        The plan: targets, slider values, expected deviations.

    Raises:
        InvalidParameterError: A bad ``count``, ``noise`` or ``grid``.
    """
    params = as_params(params)
    grid = integer("grid", grid, 2, 41)
    cand = candidate_points(params, grid)
    if (
        isinstance(count, bool)
        or not isinstance(count, int)
        or not MIN_POSES <= count <= len(cand)
    ):
        raise InvalidParameterError(
            "count", count, f"an integer from {MIN_POSES} to {len(cand)} (the candidates)"
        )
    sigma = number_in("noise", noise, MIN_NOISE, MAX_NOISE, "[m]")
    progress = optional_callable("progress", progress, "a function of (done, total), or None")
    nominal = GeometricModel.nominal(params.leg_length)
    q_cand = nominal.inverse_kinematics(cand)
    blocks = (stacked_jacobian(nominal, q_cand) * parameter_scales(params.leg_length)).reshape(
        len(cand), 3, -1
    )
    n_par = blocks.shape[2]
    ridge = RIDGE * float(np.einsum("cij,cij->", blocks, blocks)) / len(cand)
    info = ridge * np.eye(n_par)
    chosen: list[int] = []
    free = np.ones(len(cand), dtype=bool)
    for _ in range(count):
        gain = _gains(blocks, np.asarray(np.linalg.inv(info), dtype=np.float64))
        gain[~free] = -math.inf
        best = int(np.argmax(gain))
        chosen.append(best)
        free[best] = False
        info += blocks[best].T @ blocks[best]
        if progress is not None:
            progress(len(chosen), count)
    info -= ridge * np.eye(n_par)
    for _ in range(MAX_PASSES):
        improved = False
        for slot, old in enumerate(chosen):
            without = info - blocks[old].T @ blocks[old]
            inv = np.linalg.pinv(without)
            gain = _gains(blocks, inv)
            gain[~free] = -math.inf
            best = int(np.argmax(gain))
            here = float(np.linalg.det(np.eye(3) + blocks[old] @ inv @ blocks[old].T))
            if gain[best] > math.log(max(here, 1e-300)) + 1e-12:
                free[old], free[best] = True, False
                chosen[slot] = best
                info = without + blocks[best].T @ blocks[best]
                improved = True
        if not improved:
            break
    rows = np.array(chosen)
    return MeasurementPlan(
        points=cand[rows],
        q=q_cand[rows],
        expected_std=expected_std(nominal, q_cand[rows], sigma),
        noise=sigma,
        log_det=_log_det(info),
    )


def _gains(blocks: FloatArray, inv: FloatArray) -> FloatArray:
    """``log det(I_3 + A_c M^-1 A_c^T)`` for every candidate, shape (C,)."""
    inner = np.einsum("cij,jk,clk->cil", blocks, inv, blocks)
    sign, value = np.linalg.slogdet(np.eye(3) + inner)
    out: FloatArray = np.where(sign > 0, value, -math.inf)
    return out
