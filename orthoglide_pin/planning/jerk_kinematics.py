"""The slider jerk along a path: its path derivatives and the chain rule.

Along the path the slider jerk is, with ``dq, ddq, dddq`` the first three
derivatives of the slider positions in arc length and ``s', s'', s'''`` the
path speed, acceleration and jerk in time,

    q''' = dq s''' + 3 ddq s' s'' + dddq s'^3,

where ``dddq`` is the derivative of ``ddq`` (exact, from the path forms) by
second-order differences within each piece of the verification grid
(:func:`third_derivative`). :class:`Kinematics` holds these derivatives on a
section's verification grid for the jerk-limited re-timing
(:mod:`~orthoglide_pin.planning.jerk`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.calibrated import CalibratedKinematics, calibrated_forms
from orthoglide_pin.planning.path import Samples

FloatArray = NDArray[np.float64]


def third_derivative(s: FloatArray, ddq: FloatArray, piece: NDArray[np.intp]) -> FloatArray:
    """``dddq = d(ddq)/ds`` by second-order differences within each piece [1/m^2], (m, 3)."""
    out = np.zeros_like(ddq)
    cuts = np.flatnonzero(np.diff(piece) != 0) + 1
    for idx in np.split(np.arange(s.size), cuts):
        if idx.size >= 3:
            out[idx] = np.gradient(ddq[idx], s[idx], axis=0, edge_order=2)
        elif idx.size == 2:
            out[idx] = (ddq[idx[1]] - ddq[idx[0]]) / (s[idx[1]] - s[idx[0]])
    return out


def slider_jerk(
    dq: FloatArray,
    ddq: FloatArray,
    dddq: FloatArray,
    sd: FloatArray,
    sdd: FloatArray,
    sddd: FloatArray,
) -> FloatArray:
    """``q''' = dq s''' + 3 ddq s' s'' + dddq s'^3`` [m/s^3], (m, 3)."""
    return np.asarray(
        dq * sddd[:, None] + 3.0 * ddq * (sd * sdd)[:, None] + dddq * (sd**3)[:, None]
    )


@dataclass(frozen=True)
class Kinematics:
    """The slider motion's path derivatives on a section's verification grid.

    Attributes:
        s: Arc lengths [m], (m,). dq: ``dq/ds`` [-], (m, 3).
        ddq: ``d2q/ds2`` [1/m], (m, 3). dddq: ``d3q/ds3`` [1/m^2], (m, 3).
        feed: The path-speed cap [m/s] (``inf`` on rapid moves), (m,).
    """

    s: FloatArray
    dq: FloatArray
    ddq: FloatArray
    dddq: FloatArray
    feed: FloatArray


def fine_kinematics(
    forms: list[PathForms],
    fines: list[Samples],
    feeds: list[FloatArray],
    calibration: CalibratedKinematics | None = None,
) -> list[Kinematics]:
    """The :class:`Kinematics` of every section's fine samples.

    Args:
        forms: The path forms at each section's fine samples (computed once by the plan).
        fines: The fine samples of each section.
        feeds: The path-speed cap at each fine sample [m/s].
        calibration: A calibration: the sliders' commands of the calibrated machine.
    """
    out = []
    for f, x, feed in zip(forms, fines, feeds, strict=True):
        if calibration is not None:
            f = calibrated_forms(calibration, f, x.p, x.dp, x.ddp)
        out.append(Kinematics(x.s, f.dq, f.ddq, third_derivative(x.s, f.ddq, x.piece), feed))
    return out
