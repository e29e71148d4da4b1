"""Rigorous bounds of the transmission factors over a box of tool points (arb balls).

The transmission factors are the singular values of ``J``, the inverses of the
singular values of ``M = J^-1`` (paper eq. 2: ones on the diagonal, ``M_ij =
p_j / eta_i`` off it, ``eta_i = sqrt(L^2 - p_j^2 - p_k^2)``). ``M`` is a simple
function of the point, so it is the matrix bounded here. For a box ``X`` of
points:

1. the floating-point SVD of ``M`` at the box centre, ``M(c) ~ U diag(s) V^T``
   (``s`` descending), gives the reference;
2. with ``M(X)``, an interval enclosure of ``M`` over the whole box, the interval
   matrix ``R = U^T M(X) V - diag(s)`` holds ``U^T M(p) V - diag(s)`` for every
   ``p`` in the box, so ``||U^T M(p) V - diag(s)||_2 <= ||R||_F <= delta``;
3. Weyl's inequality ``|sigma_k(A) - sigma_k(B)| <= ||A - B||_2`` then gives
   ``|sigma_k(U^T M(p) V) - s_k| <= delta``;
4. ``U`` and ``V`` are only nearly orthogonal (rounding): with ``e_U >=
   ||U^T U - I||_F``, ``sigma(U)^2`` lies in ``[1 - e_U, 1 + e_U]``, and
   ``sigma_k(X A Y)`` is between ``sigma_min(X) sigma_min(Y) sigma_k(A)`` and
   ``||X|| ||Y|| sigma_k(A)``, so ``sigma_k(M(p))`` is bounded by
   ``(s_k -/+ delta) / sqrt((1 +/- e_U)(1 +/- e_V))``.

Hence, over the box, ``sigma_min(J) >= 1 / (s_0 + delta)...`` and ``sigma_max(J)
<= 1 / (s_2 - delta)...`` (:func:`factor_bounds_on_box`). Every quantity of
steps 2-4 is computed with outward rounding; the float SVD only chooses the
reference and never enters the proof. ``delta`` shrinks linearly with the box
size, so subdivision tightens the bounds (:mod:`~orthoglide_pin.kinetostatics.certify`).

Library: `python-flint <https://python-flint.readthedocs.io>`_'s ``arb``
balls (FLINT/Arb: midpoint-radius arithmetic with rigorous outward rounding of
every operation, square roots and 3 x 3 matrix products included), chosen over
Codac because it is a self-contained maintained wheel on PyPI with exactly the
operations needed here (scalar and small-matrix ball arithmetic), while Codac
brings a constraint-programming framework that this proof does not use.

Singular surfaces: a box where ``L^2 - p_j^2 - p_k^2`` may vanish (leg ``i``
orthogonal to its slider, or out of reach) has no finite enclosure of ``M``; a
box where ``s_2 - delta <= 0`` may hold a parallel singularity (``M`` singular,
three coplanar legs). Both give infinite bounds and a reason
(:class:`BoxBounds`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from flint import arb, arb_mat
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Reason of a box whose enclosure may meet the serial singular surface of a leg.
SERIAL: Final[str] = "serial"
#: Reason of a box whose enclosure may meet the parallel singular surface.
PARALLEL: Final[str] = "parallel"
_IDENTITY: Final = arb_mat([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


@dataclass(frozen=True)
class BoxBounds:
    """Certified bounds of the transmission factors over one box.

    Attributes:
        lower: A lower bound of the smallest factor over the box (0 if none).
        upper: An upper bound of the largest factor over the box (``inf`` if none).
        singular: ``""`` for a regular box, :data:`SERIAL` or :data:`PARALLEL`
            when the enclosure may meet that singular surface.
        leg: The leg (1-3) of a serial singularity, else 0.
    """

    lower: float
    upper: float
    singular: str = ""
    leg: int = 0


def down(x: arb) -> float:
    """A float ``<=`` every real number of the ball ``x`` (``-inf`` if not finite)."""
    if not x.is_finite():
        return -math.inf
    lo = x.lower()  # a ball around the exact lower endpoint
    value = float(lo.mid()) - 2.0 * float(lo.rad())
    return math.nextafter(value, -math.inf)


def up(x: arb) -> float:
    """A float ``>=`` every real number of the ball ``x`` (``inf`` if not finite)."""
    if not x.is_finite():
        return math.inf
    hi = x.upper()
    value = float(hi.mid()) + 2.0 * float(hi.rad())
    return math.nextafter(value, math.inf)


def _span(a: float, b: float) -> arb:
    """The ball enclosing the real interval ``[a, b]`` (floats, ``a <= b``)."""
    return arb(a).union(arb(b))


def _square_span(a: float, b: float) -> arb:
    """A ball enclosing ``{t^2 : a <= t <= b}``, tight even when ``a < 0 < b``."""
    hi = max(abs(a), abs(b))
    lo = 0.0 if a <= 0.0 <= b else min(abs(a), abs(b))
    return (arb(lo) * lo).union(arb(hi) * hi)


def inverse_jacobian_enclosure(lo: FloatArray, hi: FloatArray, leg_length: float) -> arb_mat | int:
    """Interval enclosure of ``M = J^-1`` over the box ``[lo, hi]``.

    Args:
        lo: Lowest corner of the box [m], shape (3,).
        hi: Highest corner [m], shape (3,).
        leg_length: Leg length ``L`` [m].

    Returns:
        The 3 x 3 ball matrix, dimensionless; or the leg (1-3) whose
        ``L^2 - p_j^2 - p_k^2`` is not certified positive over the box (serial
        singularity or out of reach).
    """
    a, b = [float(v) for v in lo], [float(v) for v in hi]
    p = [_span(a[i], b[i]) for i in range(3)]
    sq = [_square_span(a[i], b[i]) for i in range(3)]
    LL = arb(leg_length) * leg_length
    inv_eta = []
    for i, j, k in _CYCLIC:
        rad = LL - sq[j] - sq[k]
        if not rad > 0:  # arb comparison: True only if certain
            return i + 1
        inv_eta.append(rad.rsqrt())
    return arb_mat(
        [
            [1, p[1] * inv_eta[0], p[2] * inv_eta[0]],
            [p[0] * inv_eta[1], 1, p[2] * inv_eta[1]],
            [p[0] * inv_eta[2], p[1] * inv_eta[2], 1],
        ]
    )


def _frobenius(m: arb_mat) -> arb:
    """An enclosure of ``sqrt(sum |m_ij|^2)`` (upper bound valid for every member)."""
    total: arb = (m.transpose() * m).trace()  # sum of squares, as balls (in C)
    return total.nonnegative_part().sqrt()


def _orthogonality_defect(u: arb_mat) -> arb:
    """``||U^T U - I||_F``, bounds ``|sigma(U)^2 - 1|``."""
    return _frobenius(u.transpose() * u - _IDENTITY)


def factor_bounds_on_box(
    lo: FloatArray,
    hi: FloatArray,
    leg_length: float,
    u: FloatArray,
    s: FloatArray,
    vt: FloatArray,
) -> BoxBounds:
    """Certified bounds of the smallest and largest transmission factor over a box.

    Args:
        lo: Lowest corner of the box [m], shape (3,).
        hi: Highest corner [m], shape (3,).
        leg_length: Leg length ``L`` [m].
        u: Left singular vectors of ``J^-1`` at (or near) the box centre, shape
            (3, 3), as columns; any matrix is valid, a good one gives tight bounds.
        s: The singular values, descending, shape (3,).
        vt: Right singular vectors as rows, shape (3, 3).

    Returns:
        The bounds (see the module); :attr:`BoxBounds.singular` says why they
        are infinite, if they are.
    """
    m = inverse_jacobian_enclosure(lo, hi, leg_length)
    if isinstance(m, int):
        return BoxBounds(0.0, math.inf, SERIAL, m)
    ua, va = arb_mat(u.tolist()), arb_mat(vt.T.tolist())
    sa = arb_mat([[float(s[0]), 0, 0], [0, float(s[1]), 0], [0, 0, float(s[2])]])
    a = ua * sa * va.transpose()  # a matrix near M(c), kept unrotated (no wrapping)
    delta = _frobenius(m - a)  # >= ||M(p) - A||_2 for every p of the box
    residual = _frobenius(ua.transpose() * a * va - sa)  # rounding only, ~1e-16
    e_u, e_v = _orthogonality_defect(ua), _orthogonality_defect(va)
    shrink = ((1 - e_u) * (1 - e_v)).sqrt()  # <= sigma_min(U) sigma_min(V)
    grow = ((1 + e_u) * (1 + e_v)).sqrt()  # >= ||U|| ||V||
    sigma_max_m = (arb(float(s[0])) + residual) / shrink + delta
    sigma_min_m = (arb(float(s[2])) - residual) / grow - delta
    lower = 1.0 / sigma_max_m
    lower_f = max(down(lower), 0.0) if sigma_max_m > 0 else 0.0
    if not sigma_min_m > 0:
        return BoxBounds(lower_f, math.inf, PARALLEL, 0)
    return BoxBounds(lower_f, up(1.0 / sigma_min_m))


__all__ = [
    "PARALLEL",
    "SERIAL",
    "BoxBounds",
    "down",
    "factor_bounds_on_box",
    "inverse_jacobian_enclosure",
    "up",
]
