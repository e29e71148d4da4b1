"""Closed-form kinematics of the ideal Orthoglide (vectorised numpy).

Conventions (design notes, section 2): world frame at the tool point ``P`` of
the isotropic configuration ("home"); slider ``i`` (index ``i - 1`` in arrays)
moves along ``+e_i``, ``q_i = 0`` at home; leg ``i`` joins
``B_i = (q_i - L) e_i`` to ``P`` with ``||P - B_i|| = L``. Working branch:
``q_i = p_i + L - eta_i``, ``eta_i = sqrt(L^2 - p_j^2 - p_k^2) > 0``. Paper eq. 2:
``q_dot = J^-1 p_dot``, row ``i`` of ``J^-1`` = ``(P - B_i)^T / eta_i``;
``p_dot = J q_dot``; ``J = I`` at home. Points and slider values have shape
``(3,)`` or ``(..., 3)`` [m] and results keep the leading shape. Serial
singularity: a leg orthogonal to its slider (``eta_i = 0``); parallel: three
coplanar legs. Every function raises :class:`InvalidParameterError` for
non-finite inputs, a last dimension other than 3 or a non-positive leg length.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    choice,
    first_index,
    flag,
    float_array,
    output_array,
    points_array,
    positive_length,
)
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    NoAssemblyError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.kinematics.slider_limits import (
    SliderLimited,
    leg_and_limits,
    refuse_points_beyond,
    refuse_values_beyond,
)

#: Serial-singularity tolerance, relative to ``L``: a leg with
#: ``eta_i <= SERIAL_TOL * L`` counts as orthogonal to its slider.
SERIAL_TOL: Final[float] = 1e-9
#: Parallel-singularity tolerance on ``|det(u_1, u_2, u_3)|``, the determinant of
#: the unit leg directions (1 at home, 0 when the legs are coplanar).
PARALLEL_TOL: Final[float] = 1e-9

FloatArray = NDArray[np.float64]

_BRANCHES: Final = ("working", "other", "all")
_BLOCK: Final[int] = 16384  # points per block of the fused kernel (2.6 MB scratch)
_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


def radicands(p: FloatArray, L: float) -> FloatArray:
    """``L^2 - p_j^2 - p_k^2`` for each leg ``i``, shape ``(..., 3)`` [m^2]."""
    sq = p * p
    rad = np.empty_like(p)
    for i, j, k in _CYCLIC:
        np.add(sq[..., j], sq[..., k], out=rad[..., i])
    return np.subtract(L * L, rad, out=rad)


def etas(p: FloatArray, L: float, *, serial: bool) -> FloatArray:
    """``eta_i`` [m], ``(..., 3)``; raise for the first unreachable (or serial) point."""
    rad = radicands(p, L)
    eta = np.sqrt(np.maximum(rad, 0.0))
    bad = (rad < 0.0) | (eta <= SERIAL_TOL * L) if serial else rad < 0.0
    if bad.any():
        idx = first_index(bad.any(axis=-1))
        out = rad.reshape(-1, 3)[idx] < 0.0  # unreachable legs come first
        leg = int(np.argmax(out if out.any() else bad.reshape(-1, 3)[idx])) + 1
        point, r = p.reshape(-1, 3)[idx], float(rad.reshape(-1, 3)[idx, leg - 1])
        if r < 0.0:
            why = f"distance {math.sqrt(L * L - r):.6g} m to slider axis {leg} > L = {L:.6g} m"
            raise UnreachablePointError(point, leg, why)
        why = f"the leg is orthogonal to its slider (eta = {math.sqrt(r):.3g} m)"
        raise SingularConfigurationError(point, leg, "serial", why)
    return eta


def legs_from_etas(p: FloatArray, eta: FloatArray) -> FloatArray:
    """Leg vectors ``c_i - b_i`` as rows, shape ``(..., 3, 3)`` [m]."""
    legs = np.repeat(p[..., np.newaxis, :], 3, axis=-2)
    legs[..., [0, 1, 2], [0, 1, 2]] = eta
    return legs


def unit_leg_determinant(p: FloatArray, eta: FloatArray, L: float) -> FloatArray:
    """Determinant of the unit leg directions, shape ``(...)``."""
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    e1, e2, e3 = eta[..., 0], eta[..., 1], eta[..., 2]
    det: FloatArray = e1 * (e2 * e3 - y * z) + x * (y * (z - e3) + z * (y - e2))
    return det / L**3


def inverse_kinematics(
    points: ArrayLike,
    leg_length: float | SliderLimited,
    *,
    check: bool = True,
    check_limits: bool = True,
) -> FloatArray:
    """Slider values of the working branch, ``q_i = p_i + L - eta_i``.

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m], or the machine's parameters (its leg
            length and slider limits, see :mod:`~orthoglide_pin.kinematics.slider_limits`).
        check: If True, raise for unreachable or serially singular points; if
            False, the values of unreachable legs are NaN (for maps).
        check_limits: With the machine's parameters (and ``check``), refuse a
            point whose slider values leave the limits.

    Returns:
        Slider values ``q`` [m], shape of ``points``.

    Raises:
        UnreachablePointError: First point with ``p_j^2 + p_k^2 > L^2``, or
            beyond the machine's slider limits.
        SingularConfigurationError: First point with ``eta_i <= SERIAL_TOL * L``.
    """
    p = points_array(points, "points")
    L, limits = leg_and_limits(leg_length)
    limited = flag("check_limits", check_limits) and limits is not None
    if flag("check", check):
        eta = etas(p, L, serial=True)
    else:
        with np.errstate(invalid="ignore"):
            eta = np.sqrt(radicands(p, L))
    q = p + (L - eta)
    if check and limited and limits is not None:
        refuse_points_beyond(p, q, limits)
    return q


def leg_vectors(points: ArrayLike, leg_length: float) -> FloatArray:
    """Leg vectors ``c_i - b_i = P - B_i`` (norm ``L``), defined at serial singularities.

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].

    Returns:
        Shape ``(..., 3, 3)`` [m]; row ``i`` is the vector of leg ``i``.

    Raises:
        UnreachablePointError: First point out of reach of a leg.
    """
    p, L = (
        points_array(points, "points"),
        positive_length("leg_length", leg_length),
    )
    return legs_from_etas(p, etas(p, L, serial=False))


def inverse_jacobian(
    points: ArrayLike, leg_length: float | SliderLimited, *, check_limits: bool = True
) -> FloatArray:
    """Inverse Jacobian (paper, eq. 2): row ``i`` is ``(c_i - b_i)^T / eta_i``.

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m], or the machine's parameters (its leg
            length and slider limits, see :mod:`~orthoglide_pin.kinematics.slider_limits`).
        check_limits: With the machine's parameters, refuse a point whose
            slider values leave the limits (after reach and singularities).

    Returns:
        ``J^-1``, shape ``(..., 3, 3)``, dimensionless: ones on the diagonal,
        ``p_j / eta_i`` off it.

    Raises:
        UnreachablePointError: First point out of reach of a leg, or beyond
            the machine's slider limits.
        SingularConfigurationError: First serially singular point.
    """
    p = points_array(points, "points")
    L, limits = leg_and_limits(leg_length)
    limited = flag("check_limits", check_limits) and limits is not None
    eta = etas(p, L, serial=True)
    if limited and limits is not None:
        refuse_points_beyond(p, p + (L - eta), limits)
    return legs_from_etas(p, eta) / eta[..., np.newaxis]


def jacobian(
    points: ArrayLike, leg_length: float | SliderLimited, *, check_limits: bool = True
) -> FloatArray:
    """Jacobian ``J = (J^-1)^-1`` in closed form (adjugate over determinant).

    Finite at a serial singularity of leg ``i`` (column ``i`` vanishes).

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m], or the machine's parameters (its leg
            length and slider limits, see :mod:`~orthoglide_pin.kinematics.slider_limits`).
        check_limits: With the machine's parameters, refuse a point whose
            slider values leave the limits (after reach and singularities).

    Returns:
        ``J``, shape ``(..., 3, 3)``, dimensionless.

    Raises:
        UnreachablePointError: First point out of reach of a leg, or beyond
            the machine's slider limits.
        SingularConfigurationError: First point with
            ``|det(u_1, u_2, u_3)| < PARALLEL_TOL`` (``kind="parallel"``).
    """
    p = points_array(points, "points")
    L, limits = leg_and_limits(leg_length)
    limited = flag("check_limits", check_limits) and limits is not None
    q, J = ik_and_jacobian(p, L)
    if limited and limits is not None:
        refuse_points_beyond(p, q, limits)
    return J


def _fused_block(p: FloatArray, L: float, q: FloatArray, Jf: FloatArray, buf: FloatArray) -> float:
    """Fill ``q`` (m, 3) and ``Jf`` (m, 9) for the points ``p`` (m, 3).

    ``buf`` (20, >= m) holds structure-of-arrays rows: P = (x, y, z),
    E = eta, D = beta = p - eta = q - L, G_i = e_j e_k - p_j p_k (diagonal
    cofactors), W_j = p_j f_j with f_j = eta_j / det, T = temporaries. Then
    ``J[j, j] = G_j f_j``, ``J[r, j] = beta_m W_j``. Returns ``max |1 / det|``:
    NaN if a point is not finite or out of reach (every eta enters det), and
    ``|J| <= 2 L^3 |1 / det|``.
    """
    b = buf[:, : p.shape[0]]
    P, E, D, T, G, W = b[0:3], b[3:6], b[6:9], b[9:14], b[14:17], b[17:20]
    np.copyto(P, p.T)
    np.multiply(P, P, out=T[0:3])
    for i, j, k in _CYCLIC:
        np.add(T[j], T[k], out=E[i])
    np.subtract(L * L, E, out=E)
    np.sqrt(E, out=E)  # NaN when unreachable or not finite
    np.subtract(P, E, out=D)
    np.add(D, L, out=q.T)
    for i, j, k in _CYCLIC:
        np.multiply(E[j], E[k], out=G[i])
        np.multiply(P[j], P[k], out=T[i])
    np.subtract(G, T[0:3], out=G)
    det, tmp = T[3], T[4]  # det = e1 G_1 + x (y beta_3 + z beta_2)
    np.multiply(P[1:3], D[2:0:-1], out=T[3:5])  # (y beta_3, z beta_2)
    np.add(det, tmp, out=det)
    np.multiply(det, P[0], out=det)
    np.multiply(E[0], G[0], out=tmp)
    np.add(det, tmp, out=det)
    np.divide(1.0, det, out=det)
    np.multiply(E, det, out=T[0:3])
    np.multiply(P, T[0:3], out=W)
    np.multiply(G, T[0:3], out=Jf[:, 0::4].T)
    # off-diagonal J[r, j] = beta_m W_j (m the third index), two per column
    np.multiply(W[0], D[2:0:-1], out=Jf[:, 3::3].T)  # J[1, 0], J[2, 0]
    np.multiply(W[1], D[2::-2], out=Jf[:, 1::6].T)  # J[0, 1], J[2, 1]
    np.multiply(W[2], D[1::-1], out=Jf[:, 2:6:3].T)  # J[0, 2], J[1, 2]
    np.abs(det, out=tmp)
    return float(np.maximum.reduce(tmp))


def ik_and_jacobian(
    points: ArrayLike,
    leg_length: float,
    *,
    out_q: FloatArray | None = None,
    out_J: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Fused fast path for big batches: ``q`` and ``J`` sharing every intermediate.

    Blocks of 16384 points on reused scratch. One reduction per block is the
    only check: ``|det(u_1, u_2, u_3)| >= PARALLEL_TOL`` (hence finite, and
    ``|J| <= 2 / PARALLEL_TOL``); serial singularities are not reported.

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        out_q: Optional C-contiguous float64 output for ``q``, shape of
            ``points``; it may alias ``points``.
        out_J: Optional C-contiguous float64 output for ``J``, ``(..., 3, 3)``.

    Returns:
        ``(q, J)``: slider values [m] ``(..., 3)`` and Jacobians ``(..., 3, 3)``.

    Raises:
        InvalidParameterError: Bad ``out_q``/``out_J`` (or input, see module).
        UnreachablePointError: First point out of reach of a leg.
        SingularConfigurationError: First point with
            ``|det(u_1, u_2, u_3)| < PARALLEL_TOL`` (``kind="parallel"``).
    """
    p = float_array(points)
    if p.ndim == 0 or p.size == 0 or p.shape[-1] != 3:
        raise InvalidParameterError("points.shape", p.shape, "an array of shape (..., 3)")
    L = positive_length("leg_length", leg_length)
    q, J = output_array(out_q, "out_q", p.shape), output_array(out_J, "out_J", (*p.shape, 3))
    pf, qf, Jf = p.reshape(-1, 3), q.reshape(-1, 3), J.reshape(-1, 9)
    n = pf.shape[0]
    buf = np.empty((20, min(n, _BLOCK)))
    for start in range(0, n, _BLOCK):
        stop = min(start + _BLOCK, n)
        with np.errstate(all="ignore"):
            inv_det = _fused_block(pf[start:stop], L, qf[start:stop], Jf[start:stop], buf)
        if not inv_det * L**3 <= 1.0 / PARALLEL_TOL:  # also catches NaN
            # rows 0-2 of buf: the block input, even if out_q aliases points
            _diagnose(buf[0:3, : stop - start].T.copy(), L)
    return q, J


def _diagnose(block: FloatArray, L: float) -> None:
    """Raise the right error for the first point of ``block`` with a bad result."""
    with np.errstate(all="ignore"):
        rad = radicands(block, L)
        det = np.abs(unit_leg_determinant(block, np.sqrt(np.maximum(rad, 0.0)), L))
    bad = ~np.isfinite(block).all(axis=1) | (rad < 0.0).any(axis=1) | ~(det >= PARALLEL_TOL)
    idx = first_index(bad) if bad.any() else int(np.argmin(det))  # else: rounding at the limit
    etas(points_array(block[idx], "points"), L, serial=False)
    why = f"coplanar legs (|det of unit leg directions| = {det[idx]:.3g} < {PARALLEL_TOL:g})"
    raise SingularConfigurationError(block[idx], None, "parallel", why)


def direct_kinematics(
    q: ArrayLike,
    leg_length: float | SliderLimited,
    *,
    branch: str = "working",
    check_limits: bool = True,
) -> FloatArray:
    """Tool points for given slider values, in closed form.

    The sphere equations give ``p_i = beta_i / 2 + k / beta_i`` where
    ``k = (|P|^2 - L^2) / 2`` solves ``a k^2 + k + c = 0``, with
    ``a = sum 1 / beta_i^2`` and ``c = sum beta_i^2 / 4 - L^2``. The working
    assembly (the one of home, ``q = 0 -> P = 0``) is
    ``k = -(1 + sqrt(1 - 4ac)) / (2a)``; the other root is taken as
    ``c / (a k)`` to avoid cancellation.

    Args:
        q: Slider values [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m], or the machine's parameters (its leg
            length and slider limits, see :mod:`~orthoglide_pin.kinematics.slider_limits`).
        branch: ``"working"``, ``"other"`` or ``"all"``.
        check_limits: With the machine's parameters, refuse slider values
            beyond its limits.

    Returns:
        Tool points [m], shape ``(..., 3)``, or ``(..., 2, 3)`` for ``"all"``
        (working assembly first; both coincide when ``1 - 4ac = 0``).

    Raises:
        InvalidParameterError: Unknown ``branch`` (or input, see module), or
            a slider value beyond the machine's limits (``q1``, ``q2``, ``q3``).
        NoAssemblyError: First ``q`` with some ``q_i = L`` (closed form
            undefined) or without assembly (``1 - 4ac < 0``).
    """
    choice("branch", branch, _BRANCHES)
    qa = points_array(q, "q")
    L, limits = leg_and_limits(leg_length)
    if flag("check_limits", check_limits) and limits is not None:
        refuse_values_beyond(qa, limits)
    beta = qa - L
    if (beta == 0.0).any():
        idx = first_index((beta == 0.0).any(axis=-1))
        leg = int(np.argmax(beta.reshape(-1, 3)[idx] == 0.0)) + 1
        why = f"q_{leg} = L = {L:.6g} m, where the closed-form direct kinematics is undefined"
        raise NoAssemblyError(qa.reshape(-1, 3)[idx], why, leg=leg)
    inv = 1.0 / beta
    a = np.einsum("...i,...i->...", inv, inv)
    c = 0.25 * np.einsum("...i,...i->...", beta, beta) - L * L
    disc = 1.0 - 4.0 * a * c
    if (disc < 0.0).any():
        idx = first_index(disc < 0.0)
        why = f"the leg spheres do not meet (1 - 4ac = {disc.reshape(-1)[idx]:.3g} < 0)"
        raise NoAssemblyError(qa.reshape(-1, 3)[idx], why)
    root = 1.0 + np.sqrt(disc)
    # working root without cancellation (a > 0); other root = c / (a k_working)
    k = np.stack([-root / (2.0 * a), -2.0 * c / root], axis=-1)
    pts = 0.5 * beta[..., np.newaxis, :] + k[..., np.newaxis] * inv[..., np.newaxis, :]
    return pts if branch == "all" else np.ascontiguousarray(pts[..., _BRANCHES.index(branch), :])


def slider_range_over_cube(
    leg_length: float, corner: tuple[float, float, float] | ArrayLike, side: float
) -> tuple[float, float]:
    """Exact range of all slider values over the cube ``[corner, corner + side]``.

    ``q_i`` increases with ``p_i`` and with ``rho_i = sqrt(p_j^2 + p_k^2)``: its
    minimum is at the lowest ``p_i`` and the point of the square face nearest
    to axis ``i``, its maximum at the highest ``p_i`` and the face's farthest
    corner. The cube need not be centred; the range covers the three sliders.

    Args:
        leg_length: Leg length ``L`` [m].
        corner: Lowest corner of the cube [m], shape ``(3,)``.
        side: Side of the cube [m].

    Returns:
        ``(q_min, q_max)`` [m].

    Raises:
        InvalidParameterError: ``corner`` not of shape ``(3,)`` or bad ``side``.
        UnreachablePointError: Some point of the cube is out of reach of a leg.
    """
    L, h = (
        positive_length("leg_length", leg_length),
        positive_length("side", side),
    )
    lo = points_array(corner, "corner")
    if lo.shape != (3,):
        raise InvalidParameterError("corner.shape", lo.shape, "an array of shape (3,)")
    hi = lo + h
    near = np.clip(0.0, lo, hi)  # per axis, the coordinate nearest to 0
    far = np.where(np.abs(hi) >= np.abs(lo), hi, lo)  # and the farthest
    q_min, q_max = math.inf, -math.inf
    for i, j, k in _CYCLIC:
        rho2_min = float(near[j] ** 2 + near[k] ** 2)
        rho2_max = float(far[j] ** 2 + far[k] ** 2)
        if rho2_max > L * L:
            point = np.where(np.arange(3) == i, hi, far)
            why = f"distance {math.sqrt(rho2_max):.6g} m to slider axis {i + 1} > L = {L:.6g} m"
            raise UnreachablePointError(point, i + 1, why)
        q_min = min(q_min, float(lo[i]) + L - math.sqrt(L * L - rho2_min))
        q_max = max(q_max, float(hi[i]) + L - math.sqrt(L * L - rho2_max))
    return q_min, q_max
