"""The regenerative milling model: what the cut does to the tool, tooth by tooth.

Altintas, Manufacturing Automation, 2nd ed., ch. 3; Insperger and Stepan,
Int. J. Numer. Meth. Eng. 55 (2002) 503-518 and 61 (2004) 117-141: a tooth at
angle ``phi`` (from +y, the normal to the feed x, clockwise) cuts a chip
whose dynamic part is the tip's displacement now minus one tooth period
``T = 2 pi / (N Omega)`` ago, along the tooth's radial
direction ``(sin phi, cos phi)``; the tangential and radial forces
``k_t a h`` and ``k_r a h`` act back on the tool. Summed over the teeth in cut,

    F(t) = -a H(t) (r(t) - r(t - T)),
    H(t) = sum_j g_j [k_t cos phi_j + k_r sin phi_j ; -k_t sin phi_j + k_r cos phi_j]
                     [sin phi_j , cos phi_j],

with ``g_j`` = 1 while tooth ``j`` is between the entry and exit angles, and
the tool's modes (:class:`~orthoglide_pin.machining.frf.ModalModel`) give
``M q'' + C q' + K q = U^T F``, ``r = U q``. The helix is ignored (its
effect on the lobes is small for axial depths below the helix pitch) and the
edge forces do not enter (they do not depend on the chip).

Its three solutions: :mod:`~orthoglide_pin.machining.stability_sd`
(semi-discretization), :mod:`~orthoglide_pin.machining.stability_zoa` (the
zero-order frequency-domain solution) and
:mod:`~orthoglide_pin.machining.stability_td` (time-domain simulation); and
the checks of their arguments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    finite_number,
    float_array,
    instance_of,
    integer,
    number_in,
    positive_number,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machining.frf import ModalModel

FloatArray = NDArray[np.float64]

__all__ = [
    "MAX_SPEEDS",
    "MillingProcess",
    "check_model",
    "check_process",
    "paired",
    "speeds_array",
]

#: Samples of the directional factors within each interval (their mean).
SUB_SAMPLES: Final[int] = 8


@dataclass(frozen=True)
class MillingProcess:
    """What the cut does to the tool (see the module).

    Attributes:
        teeth: Number of teeth ``N``.
        kt: Tangential cutting coefficient [N/m^2].
        kr: Radial cutting coefficient [N/m^2].
        phi_start: Entry angle [rad] (from +y, clockwise).
        phi_exit: Exit angle [rad], above ``phi_start``, at most ``pi``.
    """

    teeth: int
    kt: float
    kr: float
    phi_start: float
    phi_exit: float

    def __post_init__(self) -> None:
        integer("teeth", self.teeth, 1, 100)
        object.__setattr__(self, "kt", positive_number("kt", self.kt))
        object.__setattr__(self, "kr", number_in("kr", self.kr, 0.0, 1e12, "[N/m^2]"))
        s = finite_number("phi_start", self.phi_start, "[rad]")
        e = finite_number("phi_exit", self.phi_exit, "[rad]")
        object.__setattr__(self, "phi_start", s)
        object.__setattr__(self, "phi_exit", e)
        if not (0.0 <= s < e <= math.pi + 1e-12):
            raise InvalidParameterError(
                "immersion",
                (self.phi_start, self.phi_exit),
                "0 <= phi_start < phi_exit <= pi [rad]",
            )

    def directional(self, angles: ArrayLike) -> FloatArray:
        """``H`` [N/m^2] (per unit depth) with tooth 0 at ``angles`` [rad], shape (..., 2, 2)."""
        base = float_array(angles)[..., np.newaxis]
        phi = np.mod(base + 2.0 * math.pi * np.arange(self.teeth) / self.teeth, 2.0 * math.pi)
        g = (phi >= self.phi_start) & (phi <= self.phi_exit)
        s, c = np.sin(phi), np.cos(phi)
        row = np.stack([self.kt * c + self.kr * s, -self.kt * s + self.kr * c], axis=-1)
        out = np.einsum("...j,...ja,...jb->...ab", g.astype(np.float64), row, np.stack([s, c], -1))
        return np.asarray(out)

    def mean_directional(self) -> FloatArray:
        """``H`` averaged over a tooth period [N/m^2], (2, 2) (closed form)."""
        a, b = self.phi_start, self.phi_exit

        def prim(p: float) -> FloatArray:
            s2, c2 = math.sin(2 * p), math.cos(2 * p)
            kt, kr = self.kt, self.kr
            return np.array(
                [
                    [-kt * c2 / 4 + kr * (p / 2 - s2 / 4), kt * (p / 2 + s2 / 4) - kr * c2 / 4],
                    [kt * (-p / 2 + s2 / 4) - kr * c2 / 4, kt * c2 / 4 + kr * (p / 2 + s2 / 4)],
                ]
            )

        return np.asarray(self.teeth / (2.0 * math.pi) * (prim(b) - prim(a)))

    @property
    def cut_fraction(self) -> float:
        """Share of a tooth period with a tooth in cut [-] (1: always one)."""
        return min(1.0, (self.phi_exit - self.phi_start) * self.teeth / (2.0 * math.pi))

    def interval_means(self, steps: int) -> FloatArray:
        """``H`` averaged over each of ``steps`` equal intervals of the cut, (steps, 2, 2).

        The cut starts as tooth 0 enters (at ``phi_start``) and lasts
        :attr:`cut_fraction` of the tooth period.
        """
        steps = integer("steps", steps, 1, 100_000)
        span = self.cut_fraction * 2.0 * math.pi / self.teeth
        frac = np.arange(steps)[:, np.newaxis] + (np.arange(SUB_SAMPLES) + 0.5) / SUB_SAMPLES
        return np.asarray(np.mean(self.directional(self.phi_start + frac * span / steps), axis=1))


#: Most spindle speeds (or speed and depth pairs) of one call.
MAX_SPEEDS: Final[int] = 100_000


def speeds_array(name: str, value: ArrayLike) -> FloatArray:
    """``value`` as a non-empty vector of positive finite spindle speeds [rad/s]."""
    arr = np.atleast_1d(float_array(value)) if not isinstance(value, (str, dict)) else np.empty(0)
    if (
        arr.ndim != 1
        or not 1 <= arr.size <= MAX_SPEEDS
        or not np.all(np.isfinite(arr) & (arr > 0))
    ):
        raise InvalidParameterError(
            name, value, f"1 to {MAX_SPEEDS} positive finite spindle speeds [rad/s]"
        )
    return np.asarray(arr, dtype=np.float64)


def paired(name: str, value: ArrayLike, count: int, low: float = 0.0) -> FloatArray:
    """``value`` as ``count`` finite numbers above ``low`` (one number is repeated)."""
    arr = np.atleast_1d(float_array(value)) if not isinstance(value, (str, dict)) else np.empty(0)
    if arr.ndim != 1 or arr.size not in (1, count) or not np.all(np.isfinite(arr) & (arr > low)):
        raise InvalidParameterError(name, value, f"1 or {count} finite numbers above {low:g}")
    return np.asarray(np.broadcast_to(arr, (count,)), dtype=np.float64)


def check_process(process: object) -> MillingProcess:
    """``process`` itself if it is a :class:`MillingProcess`."""
    return instance_of("process", process, MillingProcess, "a MillingProcess")


def check_model(model: object) -> ModalModel:
    """``model`` itself if it is a :class:`~orthoglide_pin.machining.frf.ModalModel`."""
    return instance_of("model", model, ModalModel, "a ModalModel")
