"""Velocity transmission factors (singular values of ``J``) in closed form, block-wise.

The rows of ``M = J^-1`` are ``u_i / eta_i`` (leg vectors, ``|u_i| = L``), so
``N = M M^T`` has ``N_ii = L^2 / eta_i^2`` and, for ``i != j`` (``k`` the third
index), ``N_ij = p_j / eta_i + p_i / eta_j + p_k^2 / (eta_i eta_j)``. Its
eigenvalues are ``1 / sigma^2`` for the singular values ``sigma`` of ``J``.

Eigenvalues of the symmetric 3 x 3 ``N`` by the trigonometric method on the
deviatoric part ``B = N - q I`` (``q = tr N / 3``): with ``p = |B|_F^2 / 6``
and ``r = det(B) / (2 p^(3/2)) = cos(3 theta)``, the two largest are
``q + 2 sqrt(p) cos(theta)`` and ``q + sqrt(p) (sqrt(3) sin(theta) - cos(theta))``.
The smallest comes from the determinant, ``lambda_3 = det(N) / (lambda_1 lambda_2)``
with ``sqrt(det N) = |det J^-1| = |det(u_1, u_2, u_3)| / (eta_1 eta_2 eta_3)``,
which keeps its relative accuracy near singularities.

The angle loses accuracy when two eigenvalues nearly coincide
(``sin(3 theta) -> 0``; the whole main diagonal, and the isotropic point): the
error of the method is about ``10 eps q / sin(3 theta)``. Points with
``sin(3 theta) lambda_2 < REFINE_TOL q`` are recomputed with LAPACK's
``eigvalsh`` (an expected error below ``1e-10``, relative); on a regular grid
that is a handful of points. Everything runs on preallocated blocks of
structure-of-arrays rows, so memory stays flat whatever the batch.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import flag, integer, output_array, points_array, positive_length
from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import (
    PARALLEL_TOL,
    SERIAL_TOL,
    etas,
    unit_leg_determinant,
)

FloatArray = NDArray[np.float64]

#: Points per block of the kernel (4 MB of scratch rows).
BLOCK: Final[int] = 16384
#: Nearly repeated eigenvalues: ``sin(3 theta) lambda_2 < REFINE_TOL q`` goes to
#: LAPACK (``eigvalsh`` of ``N``) instead of the trigonometric formula.
REFINE_TOL: Final[float] = 1e-5
#: Rows of scratch used by :func:`_kernel`.
SCRATCH_ROWS: Final[int] = 32
_SQRT3: Final[float] = math.sqrt(3.0)
_TINY: Final[float] = float(np.finfo(np.float64).tiny)
#: Taylor coefficients of ``(cos(theta) - 1)`` in ``theta^2``, highest first; the
#: first term left out is below ``4e-16`` for ``theta <= pi/3``.
_COS_TAYLOR: Final = tuple((-1) ** k / math.factorial(2 * k) for k in range(8, 0, -1))


def _kernel(b: FloatArray, L: float, out_t: FloatArray, check: bool) -> tuple[float, float]:
    """Transmission factors of the ``m`` points held in ``b[0:3]``.

    Args:
        b: Scratch ``(SCRATCH_ROWS, m)``; rows 0-2 hold ``x, y, z`` [m] on entry.
        L: Leg length [m].
        out_t: Output, ``(3, m)`` (a transposed view is fine), ascending factors.
        check: Compute the two minima below (else ``inf`` is returned).

    Returns:
        ``(min eta [m], min |det(u_1, u_2, u_3)| / L^3)`` over the block, NaN if
        a point is out of reach.
    """
    P5, T5, E, IE5 = b[0:5], b[5:10], b[10:13], b[13:18]
    D, F, X = b[18:21], b[21:24], b[24:27]
    q, p2, t, u, sp = b[27], b[28], b[29], b[30], b[31]
    np.copyto(P5[3:5], P5[0:2])  # x, y, z, x, y: cyclic index windows
    np.multiply(P5[0:3], P5[0:3], out=T5[0:3])
    np.copyto(T5[3:5], T5[0:2])
    np.add(T5[1:4], T5[2:5], out=E)
    np.subtract(L * L, E, out=E)
    np.sqrt(E, out=E)  # eta_i, NaN out of reach
    np.divide(1.0, E, out=IE5[0:3])
    np.copyto(IE5[3:5], IE5[0:2])
    np.multiply(IE5[0:3], L, out=D)
    np.multiply(D, D, out=D)  # N_ii
    # O_k = N_ij with (i, j) = (k + 1, k + 2): p_j / eta_i + p_i / eta_j + p_k^2 / (eta_i eta_j)
    np.multiply(P5[2:5], IE5[1:4], out=F)
    np.multiply(P5[1:4], IE5[2:5], out=X)
    np.add(F, X, out=F)
    np.multiply(IE5[1:4], IE5[2:5], out=X)
    np.multiply(X, T5[0:3], out=X)
    np.add(F, X, out=F)
    # det(u_1, u_2, u_3) = e1 (e2 e3 - y z) + x (y (z - e3) + z (y - e2)), into u
    x, y, z = P5[0], P5[1], P5[2]
    np.multiply(E[1], E[2], out=u)
    np.multiply(y, z, out=t)
    np.subtract(u, t, out=u)
    np.multiply(u, E[0], out=u)
    np.subtract(z, E[2], out=t)
    np.multiply(t, y, out=t)
    np.subtract(y, E[1], out=X[0])
    np.multiply(X[0], z, out=X[0])
    np.add(t, X[0], out=t)
    np.multiply(t, x, out=t)
    np.add(u, t, out=u)
    eta_min = det_min = math.inf
    if check:
        eta_min = float(np.min(E))
        det_min = float(np.min(np.abs(u))) / L**3
    # |det J| = eta_1 eta_2 eta_3 / |det(u)|, kept in u
    np.multiply(E[0], E[1], out=t)
    np.multiply(t, E[2], out=t)
    np.abs(u, out=u)
    np.divide(t, u, out=u)
    # deviatoric part B = N - q I (diagonal in D), p and det(B)
    np.add(D[0], D[1], out=q)
    np.add(q, D[2], out=q)
    np.multiply(q, 1.0 / 3.0, out=q)
    np.subtract(D, q, out=D)
    np.multiply(D, D, out=X)
    np.add(X[0], X[1], out=p2)
    np.add(p2, X[2], out=p2)
    np.multiply(F, F, out=X)
    np.add(X[0], X[1], out=t)
    np.add(t, X[2], out=t)
    np.multiply(t, 2.0, out=t)
    np.add(p2, t, out=p2)
    np.multiply(p2, 1.0 / 6.0, out=p2)
    det = IE5[0]  # 1/eta no longer needed
    np.multiply(D[0], D[1], out=det)
    np.multiply(det, D[2], out=det)
    np.multiply(F[0], F[1], out=t)
    np.multiply(t, F[2], out=t)
    np.multiply(t, 2.0, out=t)
    np.add(det, t, out=det)
    np.multiply(X, D, out=X)  # B_kk O_k^2
    np.subtract(det, X[0], out=det)
    np.subtract(det, X[1], out=det)
    np.subtract(det, X[2], out=det)
    # r = det(B) / (2 p^(3/2)) = cos(3 theta), theta in [0, pi/3]
    np.sqrt(p2, out=sp)
    np.multiply(p2, sp, out=t)
    np.multiply(t, 2.0, out=t)
    np.maximum(t, _TINY, out=t)
    r, w, c, s = IE5[1], IE5[2], X[0], X[1]
    np.divide(det, t, out=r)
    np.clip(r, -1.0, 1.0, out=r)
    np.multiply(r, r, out=w)
    np.subtract(1.0, w, out=w)
    np.sqrt(w, out=w)  # sin(3 theta)
    np.arccos(r, out=s)
    np.multiply(s, 1.0 / 3.0, out=s)
    np.multiply(s, s, out=s)  # theta^2 <= (pi/3)^2: Taylor series of cos(theta)
    np.multiply(s, _COS_TAYLOR[0], out=c)
    for coef in _COS_TAYLOR[1:]:
        np.add(c, coef, out=c)
        np.multiply(c, s, out=c)
    np.add(c, 1.0, out=c)
    np.multiply(c, c, out=s)
    np.subtract(1.0, s, out=s)
    np.sqrt(s, out=s)
    l1, l2 = X[2], p2
    np.multiply(sp, c, out=l1)
    np.multiply(l1, 2.0, out=l1)
    np.add(l1, q, out=l1)
    np.multiply(s, _SQRT3, out=l2)
    np.subtract(l2, c, out=l2)
    np.multiply(l2, sp, out=l2)
    np.add(l2, q, out=l2)
    # sigma = 1 / sqrt(lambda), ascending; sigma_3 = |det J| / (sigma_1 sigma_2)
    np.sqrt(l1, out=l1)
    np.divide(1.0, l1, out=l1)
    np.copyto(out_t[0], l1)
    np.sqrt(l2, out=c)
    np.divide(1.0, c, out=c)
    np.copyto(out_t[1], c)
    np.multiply(l1, c, out=c)
    np.divide(u, c, out=out_t[2])
    # nearly repeated eigenvalues: LAPACK on N
    np.multiply(w, l2, out=w)
    np.multiply(q, REFINE_TOL, out=t)
    flagged = np.flatnonzero(w < t)
    if flagged.size:
        n = np.empty((flagged.size, 3, 3))
        for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
            n[:, i, i] = D[i, flagged] + q[flagged]
            n[:, j, k] = n[:, k, j] = F[i, flagged]
        lam = np.maximum(np.linalg.eigvalsh(n), 0.0)  # ascending: descending factors
        out_t[:, flagged] = 1.0 / np.sqrt(lam.T[::-1])
    return eta_min, det_min


def _raise_first_bad(points: FloatArray, L: float) -> None:
    """Raise the error of the first unreachable or singular point of ``points`` (m, 3)."""
    eta = etas(points, L, serial=True)  # unreachable or serial: raises
    det = np.abs(unit_leg_determinant(points, eta, L))
    idx = int(np.argmin(det))
    why = f"coplanar legs (|det of unit leg directions| = {det[idx]:.3g} < {PARALLEL_TOL:g})"
    raise SingularConfigurationError(points[idx], None, "parallel", why)


def factors_into(
    b: FloatArray, m: int, L: float, out: FloatArray, *, check: bool
) -> tuple[float, float]:
    """Run the kernel on the ``m`` points already in ``b[0:3, :m]``; see :func:`_kernel`.

    Args:
        b: Scratch, shape ``(SCRATCH_ROWS, >= m)``.
        m: Number of points in the block.
        L: Leg length [m].
        out: Output ``(m, 3)``, ascending factors.
        check: Raise for the first unreachable or singular point.

    Returns:
        The kernel's ``(min eta [m], min |det of unit leg directions|)``.
    """
    with np.errstate(all="ignore"):
        eta_min, det_min = _kernel(b[:, :m], L, out.T, check)
    if check and not (eta_min > SERIAL_TOL * L and det_min >= PARALLEL_TOL):
        _raise_first_bad(b[0:3, :m].T.copy(), L)
    return eta_min, det_min


def scratch(n: int, block: int = BLOCK) -> FloatArray:
    """Scratch rows for blocks of at most ``min(n, block)`` points."""
    return np.empty((SCRATCH_ROWS, max(1, min(n, block))))


def transmission_factors(
    points: ArrayLike,
    leg_length: float,
    *,
    check: bool = True,
    out: FloatArray | None = None,
    block: int = BLOCK,
) -> FloatArray:
    """Velocity transmission factors: the singular values of ``J``, ascending.

    Closed form (see the module). Against LAPACK's SVD of ``J``, the relative
    difference stays below ``1e-10`` where ``J`` is well conditioned (as in the
    prescribed cube, nearly repeated factors included) and grows like
    ``eps cond(J)^2`` towards singularities (about ``1e-9`` at a condition
    number of ``5e3``).

    Args:
        points: Tool points ``P`` [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        check: If True, raise for unreachable or singular points; if False,
            such points give NaN (out of reach or exactly serial) or ``inf``
            (exactly parallel) factors, for maps.
        out: Optional C-contiguous float64 output, shape of ``points``.
        block: Points per block.

    Returns:
        ``sigma_1 <= sigma_2 <= sigma_3``, shape ``(..., 3)``, dimensionless
        ([m/s] of tool per [m/s] of slider); all 1 at home.

    Raises:
        InvalidParameterError: Bad points, leg length or ``out``.
        UnreachablePointError: First point out of reach (``check``).
        SingularConfigurationError: First point with ``eta_i <= SERIAL_TOL L``
            or ``|det(u_1, u_2, u_3)| < PARALLEL_TOL`` (``check``).
    """
    p, L = (
        points_array(points, "points"),
        positive_length("leg_length", leg_length),
    )
    block, check = integer("block", block), flag("check", check)
    result = output_array(out, "out", p.shape)
    pf, of = p.reshape(-1, 3), result.reshape(-1, 3)
    n = pf.shape[0]
    buf = scratch(n, block)
    size = buf.shape[1]
    for start in range(0, n, size):
        stop = min(start + size, n)
        np.copyto(buf[0:3, : stop - start], pf[start:stop].T)
        factors_into(buf, stop - start, L, of[start:stop], check=check)
    return result
