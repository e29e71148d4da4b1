"""Milling stability by first-order semi-discretization (Insperger and Stepan).

The regenerative milling model of
:mod:`~orthoglide_pin.machining.regeneration` (the tool's modes driven by
``F(t) = -a H(t) (r(t) - r(t - T))``).

Semi-discretization: the tooth period is cut into ``k`` intervals; on each,
``H`` is replaced by its mean, the delayed ``r(t - T)`` by the straight line
through its values at the interval's ends (the first-order scheme), and the
remaining linear ODE is solved exactly. The map over one period (the
monodromy matrix) is stable when all its eigenvalues lie inside the unit
circle (Insperger and Stepan, Int. J. Numer. Meth. Eng. 55 (2002) 503-518 and
61 (2004) 117-141). Where the teeth leave the cut, the free flight is one
exact step, and only the delayed motion over the cut is kept. The critical
axial depth at a spindle speed is bracketed and narrowed by regula falsi,
every speed at once.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import float_array, integer
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machining.frf import ModalModel
from orthoglide_pin.machining.regeneration import (
    MillingProcess,
    check_model,
    check_process,
    paired,
    speeds_array,
)

FloatArray = NDArray[np.float64]

__all__ = ["critical_depths_sd", "spectral_radius_sd", "stack_models"]

#: Fewest intervals over the cut (first order: on the prototype with the
#: shipped cut file, the lobes within 0.2 % (median over the speeds) of 48 intervals).
STEPS: Final[int] = 12
#: Fewest intervals per period of the highest mode (the delayed motion is a
#: straight line over each interval).
PER_CYCLE: Final[int] = 10
#: Modes whose resonant flexibility ``|u|^2 / (k zeta)`` is at least this share
#: of the largest set the intervals' length [-].
DOMINANT: Final[float] = 0.1
#: A guess's bracket: this factor below and above it [-].
GUESS_FACTOR: Final[float] = 1.6
#: Most widenings of a guess's bracket (each by the factor squared, both ways).
EXPANSIONS: Final[int] = 8
#: Most refinements of the depth bracket (Illinois regula falsi, log scale).
REFINEMENTS: Final[int] = 12
#: Bracket width at which a speed's refinement stops (log of the depth ratio).
TOLERANCE: Final[float] = 3e-3
#: ``|log rho|`` at which a depth tried is the limit (the refinement stops).
ON_BOUNDARY: Final[float] = 3e-4
#: Depths tried first, geometric, to find the lowest unstable one.
COARSE_DEPTHS: Final[int] = 5
#: Terms of the Taylor series of the interval's matrix functions.
_TAYLOR: Final[int] = 8


def _phi_functions(
    stiff: FloatArray, damp: FloatArray, dt: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``exp(A dt)``, ``int_0^dt exp(A (dt - s)) ds`` and the same weighted by ``s / dt``.

    For ``A = [[0, I], [-K, -diag(c)]]`` with ``K = stiff`` (..., n, n) and
    ``c = damp`` (..., n); ``dt`` (...). These are ``dt phi_k(A dt)`` for
    ``k = 0, 1, 2``: a Taylor series of ``Z = A dt / 2^s`` with ``|Z| <= 1/2``
    (Horner, each product with ``Z`` a quarter of a full one), then ``s``
    doublings, ``e^2Z = (e^Z)^2``, ``phi_1(2Z) = phi_1(Z) (e^Z + I) / 2``,
    ``phi_2(2Z) = (phi_1(Z) + (e^Z + I) phi_2(Z)) / 4`` (Skaflestad and Wright,
    Appl. Numer. Math. 59 (2009) 783-799). Matrix products only: batched, fast.
    """
    n = stiff.shape[-1]
    col = np.sum(np.abs(stiff), axis=-2) * dt[..., np.newaxis]
    norm = float(max(np.max(col, initial=0.0), np.max(dt * (1.0 + np.max(damp, axis=-1)))))
    squarings = max(0, math.ceil(math.log2(max(norm, 1e-300) / 0.5)))
    h = (dt / 2.0**squarings)[..., np.newaxis, np.newaxis]
    zk, zc = h * stiff, h[..., 0] * damp  # (..., n, n), (..., n)

    def right(x: FloatArray) -> FloatArray:  # x @ Z
        xa, xb = x[..., :n], x[..., n:]
        return np.concatenate([-(xb @ zk), h * xa - xb * zc[..., np.newaxis, :]], axis=-1)

    def left(x: FloatArray) -> FloatArray:  # Z @ x
        x1, x2 = x[..., :n, :], x[..., n:, :]
        return np.concatenate([h * x2, -(zk @ x1) - zc[..., :, np.newaxis] * x2], axis=-2)

    eye = np.eye(2 * n)
    f2 = np.broadcast_to(eye / math.factorial(_TAYLOR + 2), (*dt.shape, 2 * n, 2 * n))
    for j in range(_TAYLOR + 1, 1, -1):  # Horner: phi_2 = sum Z^i / (i + 2)!
        f2 = right(f2)
        f2 += eye / math.factorial(j)
    f1 = eye + left(f2)
    e = eye + left(f1)
    for _ in range(squarings):
        ei = e + eye
        f2 = 0.25 * (f1 + ei @ f2)
        f1 = 0.5 * (f1 @ ei)
        e = e @ e
    scale = dt[..., np.newaxis, np.newaxis]
    return np.asarray(e), np.asarray(scale * f1), np.asarray(scale * f2)


@dataclass(frozen=True)
class _Modes:
    """Modal models stacked over a batch (padded with motionless modes to one count)."""

    omega: FloatArray  # (b, n) [rad/s]
    damping: FloatArray  # (b, n)
    masses: FloatArray  # (b, n) [kg]
    shapes: FloatArray  # (b, 2, n)

    def take(self, sel: NDArray[np.bool_]) -> _Modes:
        return _Modes(self.omega[sel], self.damping[sel], self.masses[sel], self.shapes[sel])


def stack_models(model: ModalModel | Sequence[ModalModel], count: int) -> _Modes:
    """One model for every item, or one per item (``count`` of them), as arrays."""
    listed = isinstance(model, (list, tuple))
    models = list(model) if listed else [check_model(model)]  # type: ignore[arg-type]
    if not models or not all(isinstance(m, ModalModel) for m in models):
        raise InvalidParameterError("model", model, "a ModalModel or a sequence of them")
    if len(models) not in (1, count):
        raise InvalidParameterError(
            "model", f"{len(models)} models", f"1 or {count} (one per speed)"
        )
    n = max(m.count for m in models)
    arrays = np.zeros((len(models), 5, n))
    for i, m in enumerate(models):
        arrays[i, 0] = m.omega[0]  # padding: motionless copies of the first mode
        arrays[i, 1:3] = np.array([[m.damping[0]], [m.masses[0]]])
        arrays[i, 0, : m.count], arrays[i, 1, : m.count] = m.omega, m.damping
        arrays[i, 2, : m.count], arrays[i, 3:, : m.count] = m.masses, m.shapes
    arrays = np.broadcast_to(arrays, (count, 5, n))
    return _Modes(arrays[:, 0], arrays[:, 1], arrays[:, 2], arrays[:, 3:])


def steps_for(
    modes: _Modes, process: MillingProcess, omega: FloatArray, steps: int
) -> NDArray[np.intp]:
    """Intervals over the cut at each speed, a multiple of 4.

    At least ``steps``, and :data:`PER_CYCLE` per period of the highest
    dominant mode (its resonant flexibility at least :data:`DOMINANT` of the largest).
    """
    cut = process.cut_fraction * 2.0 * math.pi / (process.teeth * omega)
    peak = np.sum(modes.shapes**2, axis=1) / (modes.masses * modes.omega**2 * modes.damping)
    dominant = peak >= DOMINANT * np.max(peak, axis=1, keepdims=True)
    top = np.max(np.where(dominant, modes.omega, 0.0), axis=1) / (2.0 * math.pi)
    need = np.ceil(PER_CYCLE * top * cut / 4.0) * 4
    return np.asarray(np.maximum(need, steps).astype(np.intp))


def spectral_radius_sd(
    model: ModalModel | Sequence[ModalModel],
    process: MillingProcess,
    speeds: ArrayLike,
    depths: ArrayLike,
    steps: int = STEPS,
) -> FloatArray:
    """The largest modulus of the Floquet multipliers per (speed, depth) pair (> 1: chatter).

    Args:
        model: The tip's modes, x along the feed; or one model per pair.
        process: Teeth, cutting coefficients, immersion.
        speeds: Spindle speeds [rad/s], shape (b,).
        depths: Axial depths [m], shape (b,) (paired with ``speeds``).
        steps: Fewest intervals over the cut (more where the modes' periods are
            short against it, :func:`steps_for`).

    Returns:
        The spectral radius of the monodromy matrix, shape (b,).
    """
    check_process(process)
    omega = speeds_array("speeds", speeds)
    depth = paired("depths", depths, omega.size)
    modes = stack_models(model, omega.size)
    k = steps_for(modes, process, omega, integer("steps", steps, 2, 10_000))
    out = np.empty(omega.shape)
    for kk in np.unique(k):
        sel = k == kk
        out[sel] = _radius(modes.take(sel), process, omega[sel], depth[sel], int(kk))
    return out


def _radius(
    modes: _Modes, process: MillingProcess, omega: FloatArray, depth: FloatArray, steps: int
) -> FloatArray:
    b, n = modes.omega.shape
    u = modes.shapes  # (b, 2, n)
    # the delayed tip motion only matters within the span of U: keep its coordinates there
    basis, sing, _ = np.linalg.svd(np.concatenate(list(u), axis=1), full_matrices=False)
    basis = basis[:, sing > 1e-12 * sing[0]]  # (2, p)
    p = basis.shape[1]
    full = process.cut_fraction >= 1.0
    minv_ut = np.swapaxes(u, 1, 2) / modes.masses[:, :, np.newaxis]  # (b, n, 2)
    w = minv_ut[:, np.newaxis] @ process.interval_means(steps)  # (b, k, n, 2)
    stiff = np.zeros((b, steps + 1, n, n))  # the last interval: free flight
    idx = np.arange(n)
    stiff[:, :, idx, idx] = (modes.omega**2)[:, np.newaxis]
    stiff[:, :steps] += depth[:, None, None, None] * (w @ u[:, np.newaxis])
    damp = np.broadcast_to((2.0 * modes.damping * modes.omega)[:, np.newaxis], (b, steps + 1, n))
    period = 2.0 * math.pi / (process.teeth * omega)
    dt = np.empty((b, steps + 1))
    dt[:, :steps] = (process.cut_fraction * period / steps)[:, None]
    dt[:, steps] = np.maximum((1.0 - process.cut_fraction) * period, 0.0)  # free flight
    p_mat, f0, f1 = _phi_functions(stiff[:, :steps], damp[:, :steps], dt[:, :steps])
    free = _phi_functions(stiff[:, steps], damp[:, steps], dt[:, steps])[0]  # no cut
    bd = depth[:, None, None, None] * (w @ basis)  # (b, k, n, p)
    e_old = (f0 - f1)[:, :, :, n:] @ bd  # on r at the interval's start, T ago
    e_new = f1[:, :, :, n:] @ bd  # on r at its end, T ago
    to_s = basis.T @ u  # (b, p, n): delayed coordinates of the modal displacements
    nodes = steps if full else steps + 1  # delayed values kept in the state
    size = 2 * n + p * nodes
    eye = np.eye(size)
    y = np.broadcast_to(eye[: 2 * n], (b, 2 * n, size)).copy()
    old = [
        np.broadcast_to(eye[2 * n + p * j : 2 * n + p * (j + 1)], (b, p, size))
        for j in range(nodes)
    ]
    if full:  # the last node of the previous period is this period's start
        old.append(to_s @ y[:, :n])
    new = []
    for i in range(steps):
        new.append(to_s @ y[:, :n])
        y = p_mat[:, i] @ y + e_old[:, i] @ old[i] + e_new[:, i] @ old[i + 1]
    if not full:
        new.append(to_s @ y[:, :n])
        y = free @ y
    mono = np.concatenate([y, *new], axis=1)
    return np.asarray(np.max(np.abs(np.linalg.eigvals(mono)), axis=-1))


def critical_depths_sd(
    model: ModalModel | Sequence[ModalModel],
    process: MillingProcess,
    speeds: ArrayLike,
    depth_range: tuple[float, float] = (1e-5, 0.05),
    steps: int = STEPS,
    guess: ArrayLike | None = None,
) -> FloatArray:
    """The lowest axial depth [m] at which the cut chatters, at each spindle speed.

    The limit is bracketed first: without ``guess``, by a few geometric depths
    over ``depth_range`` (the lowest unstable one and the stable one below
    it); with one (e.g. the zero-order limit), by the depths a factor
    :data:`GUESS_FACTOR` either side of it, widened until they bracket. Regula
    falsi (Illinois) on ``log rho`` against ``log depth`` then narrows every
    bracket at once.

    Args:
        model: The tip's modes, x along the feed; or one model per speed.
        process: Teeth, cutting coefficients, immersion.
        speeds: Spindle speeds [rad/s], shape (s,).
        depth_range: Depths searched [m]; a speed stable up to the top gets ``inf``,
            one unstable at the bottom gets the bottom.
        steps: Fewest intervals over the cut.
        guess: An estimate of the limit at each speed [m], shape (s,) (``inf``:
            none), or ``None``.

    Returns:
        The critical depth at each speed [m], shape (s,).
    """
    check_process(process)
    omega = speeds_array("speeds", speeds)
    rng = float_array(depth_range) if not isinstance(depth_range, (str, dict)) else np.empty(0)
    if rng.shape != (2,) or not (0.0 < rng[0] < rng[1] < math.inf):
        raise InvalidParameterError(
            "depth_range", depth_range, "(low, high) with 0 < low < high [m]"
        )
    lo_d, hi_d = float(rng[0]), float(rng[1])
    s = omega.size
    stack_models(model, s)  # one model, or one per speed
    models = [model] if isinstance(model, ModalModel) else list(model)
    steps = integer("steps", steps, 2, 10_000)
    bottom, top = math.log(lo_d), math.log(hi_d)

    def log_rho(idx: NDArray[np.intp], x: FloatArray) -> FloatArray:
        some = models if len(models) == 1 else [models[i] for i in idx]
        return np.log(spectral_radius_sd(some, process, omega[idx], np.exp(x), steps))

    if guess is None:
        x_lo, x_hi, f_lo, f_hi = _grid_bracket(log_rho, s, bottom, top)
    else:
        g = (
            np.atleast_1d(float_array(guess))
            if not isinstance(guess, (str, dict))
            else np.empty(0)
        )
        if g.ndim != 1 or g.size not in (1, s) or np.any(np.isnan(g) | (g <= 0.0)):
            raise InvalidParameterError("guess", guess, f"1 or {s} depths > 0 [m] (inf: none)")
        x_lo, x_hi, f_lo, f_hi = _guess_bracket(log_rho, g, s, bottom, top)
    active = np.flatnonzero((f_lo <= 0.0) & (f_hi > 0.0))
    side = np.zeros(s, dtype=np.intp)  # Illinois: the end kept twice in a row is halved
    for _ in range(REFINEMENTS):
        if active.size == 0:
            break
        lo, hi, flo, fhi = x_lo[active], x_hi[active], f_lo[active], f_hi[active]
        x = hi - fhi * (hi - lo) / (fhi - flo)  # regula falsi on log rho against log depth
        x = np.clip(x, lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo))
        f = log_rho(active, x)
        bad = f > 0.0
        x_hi[active] = np.where(bad, x, hi)
        f_hi[active] = np.where(bad, f, np.where(side[active] == -1, 0.5 * fhi, fhi))
        x_lo[active] = np.where(bad, lo, x)
        f_lo[active] = np.where(bad, np.where(side[active] == 1, 0.5 * flo, flo), f)
        side[active] = np.where(bad, 1, -1)
        active = active[((x_hi[active] - x_lo[active]) > TOLERANCE) & (np.abs(f) > ON_BOUNDARY)]
    span = np.where(f_hi != f_lo, f_hi - f_lo, 1.0)
    out = np.clip(np.exp(x_lo - f_lo * (x_hi - x_lo) / span), np.exp(x_lo), np.exp(x_hi))
    out = np.where(f_lo > 0.0, lo_d, out)  # unstable at the bottom
    return np.asarray(np.where(f_hi <= 0.0, math.inf, out))  # stable at the top


_Rho = Callable[[NDArray[np.intp], FloatArray], FloatArray]
_Bracket = tuple[FloatArray, FloatArray, FloatArray, FloatArray]


def _grid_bracket(log_rho: _Rho, s: int, bottom: float, top: float) -> _Bracket:
    """``(x_lo, x_hi, f_lo, f_hi)`` from geometric depths (log) over the range."""
    log = np.linspace(bottom, top, COARSE_DEPTHS)
    idx = np.repeat(np.arange(s), log.size)
    f_grid = log_rho(idx, np.tile(log, s)).reshape(s, log.size)
    unstable = f_grid > 0.0
    first = np.where(np.any(unstable, axis=1), np.argmax(unstable, axis=1), log.size)
    i_hi, i_lo = np.minimum(first, log.size - 1), np.maximum(first - 1, 0)
    rows = np.arange(s)
    return log[i_lo], log[i_hi], f_grid[rows, i_lo], f_grid[rows, i_hi]


def _guess_bracket(
    log_rho: _Rho, guess: FloatArray, s: int, bottom: float, top: float
) -> _Bracket:
    """``(x_lo, x_hi, f_lo, f_hi)`` around a guess, widened until it brackets."""
    g = np.broadcast_to(guess, (s,))
    centre = np.clip(np.log(np.where(np.isfinite(g) & (g > 0.0), g, math.exp(top))), bottom, top)
    width = math.log(GUESS_FACTOR)
    x_lo, x_hi = np.maximum(centre - width, bottom), np.minimum(centre + width, top)
    both = log_rho(np.tile(np.arange(s), 2), np.concatenate([x_lo, x_hi]))
    f_lo, f_hi = both[:s].copy(), both[s:].copy()
    for _ in range(EXPANSIONS):
        down = np.flatnonzero((f_lo > 0.0) & (x_lo > bottom))  # unstable below: go lower
        up = np.flatnonzero((f_hi <= 0.0) & (x_hi < top))  # stable above: go higher
        if down.size + up.size == 0:
            break
        x_hi[down], f_hi[down] = x_lo[down], f_lo[down]
        x_lo[down] = np.maximum(x_lo[down] - 2.0 * width, bottom)
        x_lo[up], f_lo[up] = x_hi[up], f_hi[up]
        x_hi[up] = np.minimum(x_hi[up] + 2.0 * width, top)
        f = log_rho(np.concatenate([down, up]), np.concatenate([x_lo[down], x_hi[up]]))
        f_lo[down], f_hi[up] = f[: down.size], f[down.size :]
    return x_lo, x_hi, f_lo, f_hi
