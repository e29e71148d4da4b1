"""Milling stability by the zero-order frequency-domain solution (Altintas and Budak).

Altintas and Budak (CIRP Annals 44 (1995) 357-362) replace the time-periodic
directional factors ``H(t)`` of :mod:`~orthoglide_pin.machining.stability_sd`
by their mean over a tooth period ``H0``. The cut then chatters at a
frequency ``omega_c`` where ``det(I + a (1 - e^{-i omega_c T}) G(omega_c) H0)
= 0``: for each eigenvalue ``lambda`` of ``G(omega_c) H0`` (``G`` the tip's
receptance, :func:`~orthoglide_pin.machining.frf.frequency_response`) with a
negative real part,

    a_lim = -1 / (2 Re lambda),
    omega_c T = pi - 2 psi + 2 pi j,  psi = pi - arg(lambda) in (-pi/2, pi/2),
    j = 0, 1, 2, ... (the lobes),

and the spindle speed is ``Omega = 2 pi / (N T)``. Sweeping ``omega_c`` over
the modes traces every lobe; the limit at a speed is the lowest lobe there.
It is exact where ``H(t)`` is constant and a good approximation where it varies
little over a tooth period (many teeth in cut); at small radial immersion it
misses the period-doubling lobes that semi-discretization finds.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.machining.frf import ModalModel, frequency_response
from orthoglide_pin.machining.regeneration import (
    MillingProcess,
    check_model,
    check_process,
    speeds_array,
)

FloatArray = NDArray[np.float64]

__all__ = ["critical_depths_zoa"]

#: Chatter frequencies sampled per mode, from 0.5 to 3 times the lowest mode
#: and over the band of every mode (log-spaced) [-].
SAMPLES: Final[int] = 2000
#: Lobes traced (``j`` = 0 .. LOBES - 1).
LOBES: Final[int] = 400


def critical_depths_zoa(
    model: ModalModel, process: MillingProcess, speeds: ArrayLike
) -> FloatArray:
    """The zero-order limiting axial depth [m] at each spindle speed (see the module).

    Args:
        model: The tip's modes, x along the feed.
        process: Teeth, cutting coefficients, immersion.
        speeds: Spindle speeds [rad/s], shape (s,).

    Returns:
        The lowest lobe at each speed [m], shape (s,); ``inf`` where no lobe reaches.
    """
    check_model(model)
    h0 = check_process(process).mean_directional()
    omega = speeds_array("speeds", speeds)
    f_lo, f_hi = 0.3 * float(np.min(model.frequencies)), 3.0 * float(np.max(model.frequencies))
    freq = np.geomspace(f_lo, f_hi, SAMPLES)
    raw = np.linalg.eigvals(frequency_response(model, freq) @ h0)
    lam = _branches(np.asarray(raw, dtype=np.complex128))  # (f, 2)
    w = 2.0 * math.pi * freq[:, np.newaxis]
    neg = lam.real < 0.0
    depth = np.where(neg, -1.0 / (2.0 * np.where(neg, lam.real, -1.0)), np.inf)
    psi = np.mod(math.pi - np.angle(lam) + math.pi, 2.0 * math.pi) - math.pi
    best = np.full(omega.shape, np.inf)
    target = 2.0 * math.pi / (process.teeth * omega)  # the tooth periods asked [s]
    for j in range(LOBES):
        period = (math.pi - 2.0 * psi + 2.0 * math.pi * j) / w  # (f, 2)
        if float(np.max(period)) < float(np.min(target)):
            continue  # these lobes are at higher speeds
        if float(np.min(period)) > float(np.max(target)):
            break  # and these (and all after) at lower ones
        for e in range(lam.shape[1]):
            crossing = _lowest_crossing(period[:, e], depth[:, e], target, float(np.max(best)))
            best = np.minimum(best, crossing)
    return best


def _branches(lam: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """The two eigenvalues (f, 2) ordered so that each column varies continuously."""
    a, b = lam[1:, 0], lam[1:, 1]
    pa, pb = lam[:-1, 0], lam[:-1, 1]
    swap = np.abs(a - pb) + np.abs(b - pa) < np.abs(a - pa) + np.abs(b - pb)
    flip = np.concatenate([[False], np.cumsum(swap) % 2 == 1])
    return np.where(flip[:, np.newaxis], lam[:, ::-1], lam)


def _lowest_crossing(
    period: FloatArray, depth: FloatArray, target: FloatArray, ceiling: float
) -> FloatArray:
    """The lowest depth where the curve (period, depth) passes each target period.

    Segments wholly above ``ceiling`` (the highest limit found so far) are skipped.
    """
    p0, p1, d0, d1 = period[:-1], period[1:], depth[:-1], depth[1:]
    ok = np.isfinite(d0) & np.isfinite(d1) & (p0 != p1) & (np.minimum(d0, d1) < ceiling)
    ok &= (np.maximum(p0, p1) >= target.min()) & (np.minimum(p0, p1) <= target.max())
    p0, p1, d0, d1 = p0[ok], p1[ok], d0[ok], d1[ok]
    if p0.size == 0:
        return np.full(target.shape, np.inf)
    frac = (target[:, np.newaxis] - p0) / (p1 - p0)  # (t, segments)
    inside = (frac >= 0.0) & (frac <= 1.0)
    return np.asarray(np.min(np.where(inside, d0 + frac * (d1 - d0), np.inf), axis=1))
