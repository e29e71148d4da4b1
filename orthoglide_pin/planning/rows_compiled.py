"""The motor-torque rows' affine majorants, compiled with numba: one loop over the points.

Each motor's torque rows (:func:`~orthoglide_pin.planning.limits.rows`) bound
``phi(x) = +-friction(w) - available(w)`` (``w`` the motor speed at the squared
path speed ``x``) by a line in ``x``, tight at the previous pass's speed: three
candidate lines (the tangent, two chords) are raised above ``phi``'s samples
and the lowest there is kept (:func:`~orthoglide_pin.planning.limits._majorant`).
The friction and the available torque are evaluated in numpy at every sample;
:func:`majorants` then raises the lines of both signs point by point, without
the dozen (points, samples) arrays of the array version, and with the same
operations, so that the two agree to rounding
(``tests/planning/test_rows_compiled.py``). Without numba
(:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE` false) the array
version runs.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.planning.reach_compiled import AVAILABLE, jit

FloatArray = NDArray[np.float64]


def _majorants(
    h: FloatArray,
    av: FloatArray,
    h_probe: FloatArray,
    av_probe: FloatArray,
    xs: FloatArray,
    xt: FloatArray,
    step: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """Slopes and intercepts (n, 2) of the majorants of both signs (``+1``, then ``-1``)."""
    n, m = xs.shape
    slopes, cuts = np.zeros((n, 2)), np.zeros((n, 2))
    for i in range(n):
        x_top, x_mid = xs[i, m - 1], min(4.0 * xt[i], xs[i, m - 1])
        for col in range(2):
            sign = 1.0 if col == 0 else -1.0
            p0 = sign * h_probe[i, 0] - av_probe[i, 0]
            p1 = sign * h_probe[i, 1] - av_probe[i, 1]
            p2 = sign * h_probe[i, 2] - av_probe[i, 2]
            p3 = sign * h_probe[i, 3] - av_probe[i, 3]
            zero, top = sign * h[i, 0] - av[i, 0], sign * h[i, m - 1] - av[i, m - 1]
            tangent = (p2 - p0) / (2.0 * step[i])
            chord = (top - zero) / x_top if x_top > 0.0 else 0.0
            middle = (p3 - zero) / x_mid if x_mid > 0.0 else 0.0
            best_slope, best_cut, best_at = 0.0, 0.0, math.inf
            for line in range(3):
                raw = tangent if line == 0 else (chord if line == 1 else middle)
                base = p1 - tangent * xt[i] if line == 0 else zero
                slope = raw if math.isfinite(raw) else 0.0
                high = -math.inf
                for j in range(m):
                    high = max(high, (sign * h[i, j] - av[i, j]) - slope * xs[i, j])
                cut = base + max(high - base, 0.0)
                at = cut + slope * xt[i]
                if at < best_at:
                    best_slope, best_cut, best_at = slope, cut, at
            slopes[i, col], cuts[i, col] = best_slope, best_cut
    return slopes, cuts


if AVAILABLE:
    _majorants = jit(_majorants)


def majorants(
    h: FloatArray,
    av: FloatArray,
    h_probe: FloatArray,
    av_probe: FloatArray,
    xs: FloatArray,
    xt: FloatArray,
    step: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """The majorants of one motor at ``n`` points, compiled (see the module).

    Args:
        h: The friction over ``T_ref`` at the samples ``xs``, (n, S).
        av: The available torque over ``T_ref`` there, (n, S).
        h_probe: The friction at ``xt - step``, ``xt``, ``xt + step`` and
            ``min(4 xt, X)``, (n, 4).
        av_probe: The available torque there, (n, 4).
        xs: Samples of ``[0, X]`` per point, from 0 to ``X`` [(m/s)^2], (n, S).
        xt: Where each line should be tight [(m/s)^2], (n,).
        step: The step of the tangent's central difference [(m/s)^2], (n,).

    Returns:
        Slopes and intercepts, (n, 2) each: the sign ``+1``, then ``-1``.

    Raises:
        RuntimeError: numba is not installed.
    """
    if not AVAILABLE:
        raise RuntimeError("the compiled rows need numba (pip install 'orthoglide-pin[plan]')")
    h, av, h_probe, av_probe, xs, xt, step = (
        np.ascontiguousarray(v, dtype=np.float64) for v in (h, av, h_probe, av_probe, xs, xt, step)
    )
    return _majorants(h, av, h_probe, av_probe, xs, xt, step)
