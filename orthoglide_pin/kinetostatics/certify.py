"""Certified workspace: the transmission bounds proven over the whole cube, not on a grid.

:func:`certify` decides whether every point of a cube (the continuum) meets a
criterion ``[psi_min, psi_max]`` on its three transmission factors, with the
package's one tolerance rule (:mod:`~orthoglide_pin.machine.criterion`): every
factor within ``[psi_min - tol, psi_max + tol]``, ``tol`` = 1e-4 by default. A
design's own cube reaches its bounds exactly at Q1 and Q2, so it can be proven
only with a tolerance; ``orthoglide design`` and ``orthoglide certify`` prove the
same statement. The search is a branch and bound on boxes:

* each box gets certified bounds of its smallest and largest factor
  (:func:`~orthoglide_pin.kinetostatics.interval_jacobian.factor_bounds_on_box`:
  interval enclosure of ``J^-1`` with arb balls and Weyl's inequality around
  the floating-point SVD at the box centre, batched with numpy);
* its centre and corners are evaluated in ordinary floating point with the
  closed form (:func:`~orthoglide_pin.kinetostatics.transmission.transmission_factors`):
  the extreme factors attained so far, and any point whose factors leave
  ``[psi_min - tol, psi_max + tol]`` by more than rounding (``BOUND_RTOL``),
  the counterexample;
* a box is done when its bounds are within ``tol`` of the attained extremes
  (the enclosure) and it is proven inside the widened bounds (or a
  counterexample is already known); otherwise it is split in eight, down to
  ``max_depth`` or until the box budget is spent;
* a cube on the main diagonal (equal corner coordinates, as every design's
  cube) keeps one box of each orbit of the axis permutations, which leave the
  factors unchanged: up to six times fewer boxes.

The certified enclosure ``[lo, hi]`` is the smallest lower bound and the
largest upper bound of the final boxes: every factor of every point of the
cube lies in it, and, when :attr:`Certification.tight`, ``lo`` and ``hi`` are
within ``tol`` of factors attained at actual points. A box whose enclosure
meets a singular surface (serial: a leg orthogonal to its slider or out of
reach; parallel: coplanar legs) has infinite bounds; if it cannot be resolved
by subdivision the certification fails with that reason.

Outcomes (:attr:`Certification.status`), which follow from the enclosure alone:
``"certified"`` (every box proven inside the widened bounds: the certified
margin is ``>= 0``; an enclosure that could not be refined to ``tol`` within the
budget only makes it not :attr:`~Certification.tight`), ``"violated"``
(counterexample), ``"singular"`` (a box that may meet a singular surface was
left), ``"undecided"`` (a box neither proven inside nor refuted was left: a
bound is reached within the resolution of the boxes, or the budget ran out).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    finite_vector,
    flag,
    integer,
    positive_length,
    positive_number,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import legs_from_etas, radicands
from orthoglide_pin.kinetostatics.certification import Certification, Leaf, verdict
from orthoglide_pin.kinetostatics.interval_jacobian import factor_bounds_on_box
from orthoglide_pin.kinetostatics.transmission import transmission_factors
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.criterion import CRITERION_TOL, PAPER_BOUNDS
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Default tolerance: of the criterion (its bounds widened by it) and of the enclosure
#: (``lo`` and ``hi`` within it of attained factors); the package's one rule.
CERTIFY_TOL: Final[float] = CRITERION_TOL
#: Relative slack before a floating-point factor counts as a violation (rounding).
BOUND_RTOL: Final[float] = 1e-9
#: Default number of halvings of the cube side (boxes of side ``2^-24`` of the cube).
MAX_DEPTH: Final[int] = 24
#: Default budget of boxes.
MAX_BOXES: Final[int] = 400_000
#: Largest budget of boxes accepted (about 0.5 ms each: some 40 minutes).
BOX_BUDGET_CAP: Final[int] = 5_000_000
#: Most halvings accepted: a box below ``2^-52`` of the side is below a float's resolution.
DEPTH_CAP: Final[int] = 52
_CORNERS: Final = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)], dtype=np.float64)


def _centre_svd(lo: FloatArray, hi: FloatArray, L: float) -> tuple[FloatArray, ...]:
    """Float SVD of ``J^-1`` at the box centres: ``U`` (n, 3, 3), ``s`` (n, 3), ``V^T``."""
    c = 0.5 * (lo + hi)
    with np.errstate(all="ignore"):
        eta = np.sqrt(radicands(c, L))
        m = legs_from_etas(c, eta) / eta[..., np.newaxis]
    bad = ~np.isfinite(m).all(axis=(1, 2))
    m[bad] = np.eye(3)  # no finite reference: any matrix keeps the bounds valid
    u, s, vt = np.linalg.svd(m)
    return u, s, vt


@dataclass
class _Search:
    """Running state of the branch and bound."""

    L: float
    lo_bound: float
    hi_bound: float
    tol: float
    refine: bool
    att_min: float = math.inf
    att_max: float = -math.inf
    att_min_at: FloatArray | None = None
    att_max_at: FloatArray | None = None
    worst: float = 0.0  # size of the worst violation found
    counter: FloatArray | None = None
    counter_factors: FloatArray | None = None

    def sample(self, lo: FloatArray, hi: FloatArray, cube: tuple[FloatArray, FloatArray]) -> None:
        """Evaluate the box centres and corners (clipped to ``cube``) in floating point."""
        pts = np.concatenate(
            [0.5 * (lo + hi), (lo[:, None, :] + _CORNERS * (hi - lo)[:, None, :]).reshape(-1, 3)]
        )
        np.clip(pts, cube[0], cube[1], out=pts)
        f = transmission_factors(pts, self.L, check=False)
        finite = np.isfinite(f).all(axis=1)
        if finite.any():
            ok = np.flatnonzero(finite)
            i, j = ok[np.argmin(f[ok, 0])], ok[np.argmax(f[ok, 2])]
            if f[i, 0] < self.att_min:
                self.att_min, self.att_min_at = float(f[i, 0]), pts[i].copy()
            if f[j, 2] > self.att_max:
                self.att_max, self.att_max_at = float(f[j, 2]), pts[j].copy()
        # violation size: inf for a point out of reach or singular
        with np.errstate(invalid="ignore"):
            over = np.maximum(self.lo_bound - f[:, 0], f[:, 2] - self.hi_bound)
        over = np.where(finite, over, math.inf)
        k = int(np.argmax(over))
        slack = BOUND_RTOL * self.hi_bound
        if over[k] > slack and over[k] > self.worst:
            self.worst, self.counter, self.counter_factors = float(over[k]), pts[k], f[k]
            if not np.isfinite(f[k]).all():
                self.att_min, self.att_max = 0.0, math.inf

    def done(self, lower: float, upper: float) -> tuple[bool, bool]:
        """(enclosure tight on the box, verdict settled on the box)."""
        tight = lower >= self.att_min - self.tol and upper <= self.att_max + self.tol
        inside = lower >= self.lo_bound and upper <= self.hi_bound
        return tight or not self.refine, inside or self.counter is not None


def _check_bounds(psi_min: Any, psi_max: Any) -> tuple[float, float]:
    lo = positive_number("psi_min", psi_min, "a positive lower bound below psi_max")
    hi = positive_number("psi_max", psi_max, "a finite upper bound above psi_min")
    if not lo < hi:
        raise InvalidParameterError("psi_min", psi_min, f"a lower bound below psi_max = {hi:g}")
    return lo, hi


def certify_cube(
    leg_length: float,
    corner: ArrayLike,
    side: float,
    psi_min: float = PAPER_BOUNDS[0],
    psi_max: float = PAPER_BOUNDS[1],
    *,
    tol: float = CERTIFY_TOL,
    refine: bool = True,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
) -> Certification:
    """Prove, or refute, the criterion ``[psi_min, psi_max]`` (within ``tol``) over a cube.

    Args:
        leg_length: Leg length ``L`` [m].
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        psi_min: Lower bound of the criterion on the transmission factors.
        psi_max: Upper bound, above ``psi_min``.
        tol: Tolerance (positive): the bounds proven are ``[psi_min - tol,
            psi_max + tol]`` (the package's rule), and the enclosure is refined
            to within ``tol`` of attained factors.
        refine: Refine the enclosure to ``tol``; if False, only the verdict is
            sought and the search stops at the first counterexample (faster).
        max_depth: Number of halvings of the cube side allowed, at most :data:`DEPTH_CAP`.
        max_boxes: Budget of boxes, at most :data:`BOX_BUDGET_CAP`.

    Returns:
        The verdict, the enclosure and, on failure, a counterexample.

    Raises:
        InvalidParameterError: A bad length, corner, side, bound or count.
    """
    start = time.perf_counter()
    L = positive_length("leg_length", leg_length)
    q1 = finite_vector("corner", corner, 3, "[m]")
    lw = positive_length("side", side)
    lo_b, hi_b = _check_bounds(psi_min, psi_max)
    tol = positive_number("tol", tol, "a positive tolerance")
    depth_cap = integer("max_depth", max_depth, 1, DEPTH_CAP)
    budget = integer("max_boxes", max_boxes, 1, BOX_BUDGET_CAP)
    # the cube, rounded outwards
    top = np.nextafter(q1 + lw, math.inf)
    search = _Search(L, lo_b - tol, hi_b + tol, tol, flag("refine", refine))
    lo, hi = q1[np.newaxis].copy(), top[np.newaxis].copy()
    symmetric = bool(q1[0] == q1[1] == q1[2])
    enc_lo, enc_hi = math.inf, -math.inf
    boxes = depth = 0
    left: list[Leaf] = []  # leaves not done: unsettled, or settled but not tight
    while lo.shape[0]:
        boxes += lo.shape[0]
        search.sample(lo, hi, (q1, q1 + lw))
        if not refine and search.counter is not None:
            enc_lo, enc_hi = 0.0, math.inf  # not computed
            break
        u, s, vt = _centre_svd(lo, hi, L)
        keep = np.zeros(lo.shape[0], dtype=bool)
        for n in range(lo.shape[0]):
            b = factor_bounds_on_box(lo[n], hi[n], L, u[n], s[n], vt[n])
            tight, settled = search.done(b.lower, b.upper)
            if tight and settled:
                enc_lo, enc_hi = min(enc_lo, b.lower), max(enc_hi, b.upper)
            elif depth >= depth_cap or boxes >= budget:
                enc_lo, enc_hi = min(enc_lo, b.lower), max(enc_hi, b.upper)
                left.append(Leaf(b.singular, b.leg, 0.5 * (lo[n] + hi[n]), settled))
            else:
                keep[n] = True
        lo, hi = _split(lo[keep], hi[keep])
        if symmetric:
            lo, hi = _canonical(lo, hi)
        depth += int(lo.shape[0] > 0)
    found = (search.counter, search.counter_factors)
    enclosure = (enc_lo, enc_hi)
    status, reason = verdict((lo_b, hi_b), tol, found, left, enclosure, boxes >= budget)
    att_at = [search.att_min_at, search.att_max_at]
    return Certification(
        certified=status == "certified",
        status=status,
        reason=reason,
        leg_length=L,
        corner=q1,
        side=lw,
        psi_min=lo_b,
        psi_max=hi_b,
        factor_bounds=(float(enc_lo), float(enc_hi)),
        attained=(search.att_min, search.att_max),
        attained_at=np.array([np.full(3, np.nan) if a is None else a for a in att_at]),
        counterexample=search.counter,
        counterexample_factors=search.counter_factors,
        tolerance=tol,
        tight=bool(enc_lo >= search.att_min - tol and enc_hi <= search.att_max + tol),
        boxes=boxes,
        depth=depth,
        seconds=time.perf_counter() - start,
    )


def _canonical(lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """One box of each orbit of the axis permutations (cube on the main diagonal).

    The factors are invariant under any permutation ``P`` of the axes
    (``J(P p) = P J(p) P^T``), and a cube with equal corner coordinates is too,
    with its octree boxes (the same floats on every axis): a box is certified
    exactly when its permuted images are. Each box is permuted so that its
    centre's coordinates descend, and duplicates are dropped.
    """
    order = np.argsort(-(lo + hi), axis=1, kind="stable")
    lo_c = np.take_along_axis(lo, order, axis=1)
    hi_c = np.take_along_axis(hi, order, axis=1)
    _, first = np.unique(np.hstack([lo_c, hi_c]), axis=0, return_index=True)
    first.sort()
    return lo_c[first], hi_c[first]


def _split(lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The eight children of each box; they cover it exactly (shared float midpoints)."""
    mid = 0.5 * (lo + hi)
    lo8 = np.where(_CORNERS[None] > 0, mid[:, None, :], lo[:, None, :]).reshape(-1, 3)
    hi8 = np.where(_CORNERS[None] > 0, hi[:, None, :], mid[:, None, :]).reshape(-1, 3)
    return lo8, hi8


def certify(
    params: OrthoglideParams,
    corner: ArrayLike | None = None,
    side: float | None = None,
    psi_min: float | None = None,
    psi_max: float | None = None,
    **options: Any,
) -> Certification:
    """Certify a machine's criterion over a cube (see the module).

    Args:
        params: The machine (its leg length, and by default its cube and criterion).
        corner: Lowest corner of the cube [m], shape (3,); default: the
            machine's prescribed cube (``params.workspace_corner``).
        side: Side of the cube [m]; default: ``params.workspace_side``.
        psi_min: Lower bound on the transmission factors; default: the
            machine's criterion, ``params.psi_min``.
        psi_max: Upper bound; default: ``params.psi_max``.
        **options: ``tol``, ``refine``, ``max_depth``, ``max_boxes`` of
            :func:`certify_cube`.

    Returns:
        The :class:`Certification`.

    Raises:
        InvalidParameterError: A bad argument.
    """
    params = as_params(params)
    if corner is None or side is None:
        cube = params.workspace
        corner = cube.q1 if corner is None else corner
        side = cube.side if side is None else side
    psi_min = params.psi_min if psi_min is None else psi_min
    psi_max = params.psi_max if psi_max is None else psi_max
    return certify_cube(params.leg_length, corner, side, psi_min, psi_max, **options)


__all__ = [
    "BOUND_RTOL",
    "BOX_BUDGET_CAP",
    "CERTIFY_TOL",
    "DEPTH_CAP",
    "MAX_BOXES",
    "MAX_DEPTH",
    "PAPER_BOUNDS",
    "Certification",
    "certify",
    "certify_cube",
]
