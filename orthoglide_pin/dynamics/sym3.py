"""Smallest and largest eigenvalues of batches of symmetric 3 x 3 matrices.

:func:`extreme_eigenvalues` gives them to rounding for any spectrum, repeated
eigenvalues included, about three times as fast as ``numpy.linalg.eigvalsh``
on the small stacks of the worst-case requirements
(:meth:`orthoglide_pin.dynamics.motion_forms.MotionForm.bounds`):

1. The trigonometric closed form (``A = q I + p B``, ``r = det(B) / 2``,
   eigenvalues ``q + 2 p cos(acos(r) / 3 + 2 k pi / 3)``) gives the eigenvalue
   that is isolated: the largest when ``r >= 0``, the smallest otherwise.
   Its distance to the other two is at least ``sqrt(3) p``, so it is accurate
   (the closed form loses digits only on the two that come close).
2. Its eigenvector is the largest cross product of two rows of ``A - mu I``;
   the Rayleigh quotient of that vector gives the isolated eigenvalue again,
   to rounding.
3. On an orthonormal basis of the complement of that vector (Duff et al.,
   "Building an orthonormal basis, revisited", JCGT 2017), ``A`` is a
   symmetric 2 x 2 matrix, whose eigenvalues ``m +- hypot(d, b)`` are stable.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def extreme_eigenvalues(matrices: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Smallest and largest eigenvalue of each symmetric matrix.

    Args:
        matrices: Symmetric matrices, shape (..., 3, 3) (the upper triangle is read).

    Returns:
        ``(lambda_min, lambda_max)``, each of shape (...).
    """
    h = np.asarray(matrices, dtype=np.float64)
    a11, a22, a33 = h[..., 0, 0], h[..., 1, 1], h[..., 2, 2]
    a12, a13, a23 = h[..., 0, 1], h[..., 0, 2], h[..., 1, 2]
    q = (a11 + a22 + a33) / 3.0
    b11, b22, b33 = a11 - q, a22 - q, a33 - q
    off = a12 * a12 + a13 * a13 + a23 * a23
    p = np.sqrt((b11 * b11 + b22 * b22 + b33 * b33 + 2.0 * off) / 6.0)
    det = (
        b11 * (b22 * b33 - a23 * a23)
        - a12 * (a12 * b33 - a23 * a13)
        + a13 * (a12 * a23 - b22 * a13)
    )
    p3 = 2.0 * p * p * p
    r = np.clip(det / np.where(p3 > 0.0, p3, 1.0), -1.0, 1.0)
    phi = np.arccos(r) / 3.0
    iso = q + 2.0 * p * np.cos(np.where(r >= 0.0, phi, phi + 2.0 * np.pi / 3.0))
    # its eigenvector: the largest cross product of two rows of A - iso I
    d1, d2, d3 = a11 - iso, a22 - iso, a33 - iso
    x = (a12 * a23 - a13 * d2, a13 * a12 - d1 * a23, d1 * d2 - a12 * a12)
    y = (a12 * d3 - a13 * a23, a13 * a13 - d1 * d3, d1 * a23 - a12 * a13)
    z = (d2 * d3 - a23 * a23, a23 * a13 - a12 * d3, a12 * a23 - d2 * a13)
    nx, ny, nz = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] for v in (x, y, z))
    use_y = ny > nx
    e = [np.where(use_y, yi, xi) for xi, yi in zip(x, y, strict=True)]
    ne = np.where(use_y, ny, nx)
    use_z = nz > ne
    e = [np.where(use_z, zi, ei) for ei, zi in zip(e, z, strict=True)]
    ne = np.where(use_z, nz, ne)
    good = ne > 0.0  # else A = iso I: any vector will do
    inv = 1.0 / np.sqrt(np.where(good, ne, 1.0))
    e1 = np.where(good, e[0] * inv, 1.0)
    e2 = np.where(good, e[1] * inv, 0.0)
    e3 = np.where(good, e[2] * inv, 0.0)
    # an orthonormal basis (u, w) of the plane orthogonal to e
    sign = np.copysign(1.0, e3)
    c = -1.0 / (sign + e3)
    s = e1 * e2 * c
    u = (1.0 + sign * e1 * e1 * c, sign * s, -sign * e1)
    w = (s, sign + e2 * e2 * c, -e2)

    def form(v: tuple[FloatArray, ...], t: tuple[FloatArray, ...]) -> FloatArray:
        """``v^T A t``."""
        return np.asarray(
            a11 * v[0] * t[0]
            + a22 * v[1] * t[1]
            + a33 * v[2] * t[2]
            + a12 * (v[0] * t[1] + v[1] * t[0])
            + a13 * (v[0] * t[2] + v[2] * t[0])
            + a23 * (v[1] * t[2] + v[2] * t[1])
        )

    ev = (e1, e2, e3)
    mu = form(ev, ev)
    buu, bww, buw = form(u, u), form(w, w), form(u, w)
    mid, half = 0.5 * (buu + bww), np.hypot(0.5 * (buu - bww), buw)
    return np.minimum(mu, mid - half), np.maximum(mu, mid + half)
