"""What a certification says: its status, reason, enclosure and margin.

:func:`~orthoglide_pin.kinetostatics.certify.certify_cube` searches; this module
holds its result (:class:`Certification`) and the verdict, which follows from
the bounds of the boxes the search ends with (:func:`verdict`): a
counterexample makes the criterion ``"violated"``; a box left neither proven
inside the bounds nor refuted makes it ``"singular"`` (it may meet a singular
surface) or ``"undecided"``; otherwise it is ``"certified"``, with a certified
margin ``>= 0``, even when the enclosure could not be refined to its tolerance
within the budget (it is then not :attr:`~Certification.tight`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.kinetostatics.interval_jacobian import SERIAL

FloatArray = NDArray[np.float64]

#: The outcomes of a certification.
STATUSES: Final = ("certified", "violated", "singular", "undecided")


@dataclass(frozen=True)
class Certification:
    """The verdict on a cube and the certified enclosure of its factors.

    Attributes:
        certified: Proven: every point of the cube has its three factors in
            ``[psi_min - tolerance, psi_max + tolerance]`` (the criterion, with
            the package's tolerance rule).
        status: ``"certified"``, ``"violated"``, ``"singular"`` or ``"undecided"``.
        reason: One sentence explaining the status.
        leg_length: Leg length ``L`` [m].
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        psi_min: Lower bound of the criterion.
        psi_max: Upper bound of the criterion.
        factor_bounds: Certified enclosure ``(lo, hi)`` of every factor over the
            cube (``lo`` may be 0 and ``hi`` ``inf`` near singularities).
        attained: Smallest and largest factor evaluated at points of the cube.
        attained_at: Where they were found [m], shape (2, 3).
        counterexample: A point of the cube whose factors violate the bounds
            [m], shape (3,), or None.
        counterexample_factors: Its factors (ascending; NaN out of reach), or None.
        tolerance: Tolerance of the criterion and of the enclosure.
        tight: Whether ``lo`` and ``hi`` are within ``tolerance`` of ``attained``.
        boxes: Number of boxes evaluated.
        depth: Deepest subdivision used (the cube halved ``depth`` times).
        seconds: Wall time [s].
    """

    certified: bool
    status: str
    reason: str
    leg_length: float
    corner: FloatArray
    side: float
    psi_min: float
    psi_max: float
    factor_bounds: tuple[float, float]
    attained: tuple[float, float]
    attained_at: FloatArray
    counterexample: FloatArray | None
    counterexample_factors: FloatArray | None
    tolerance: float
    tight: bool
    boxes: int
    depth: int
    seconds: float

    @property
    def proven_bounds(self) -> tuple[float, float]:
        """The bounds proven: the criterion widened by the tolerance."""
        return self.psi_min - self.tolerance, self.psi_max + self.tolerance

    @property
    def margin(self) -> float:
        """Certified margin: how far the enclosure lies inside :attr:`proven_bounds`.

        ``min(lo - (psi_min - tol), (psi_max + tol) - hi)``: ``>= 0`` exactly
        when every factor of the cube is proven to meet the criterion (the
        status is then ``"certified"``, tight or not).
        """
        lo, hi = self.factor_bounds
        low, high = self.proven_bounds
        return min(lo - low, high - hi)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (SI units; infinite or NaN numbers as None)."""
        out: dict[str, Any] = {}
        for name in self.__dataclass_fields__:
            out[name] = _json(getattr(self, name))
        out["margin"] = _json(self.margin)
        out["proven_bounds"] = _json(self.proven_bounds)
        return out


def _json(value: Any) -> Any:
    """Strict-JSON form: arrays and tuples as lists, non-finite floats as None."""
    if isinstance(value, (np.ndarray, tuple, list)):
        return [_json(v) for v in (value.tolist() if isinstance(value, np.ndarray) else value)]
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    return value


@dataclass(frozen=True)
class Leaf:
    """A box left at the depth or budget limit: where, and whether it is settled."""

    singular: str
    leg: int
    centre: FloatArray
    settled: bool  # proven inside the bounds (or a counterexample is known)


def _mm(p: FloatArray) -> str:
    return "(" + ", ".join(f"{1e3 * v:.3f}" for v in p) + ") mm"


def verdict(
    criterion: tuple[float, float],
    tol: float,
    found: tuple[FloatArray | None, FloatArray | None],
    left: list[Leaf],
    enclosure: tuple[float, float],
    out_of_budget: bool,
) -> tuple[str, str]:
    """Status and reason of a finished search: they follow from the boxes' bounds.

    Args:
        criterion: The bounds ``(psi_min, psi_max)`` of the criterion.
        tol: Its tolerance: the bounds proven are widened by it.
        found: The counterexample and its factors, or ``(None, None)``.
        left: The boxes left at the depth or budget limit.
        enclosure: The certified enclosure ``(lo, hi)`` of the factors.
        out_of_budget: Whether the box budget ran out.

    Returns:
        ``(status, reason)``: a counterexample is ``"violated"``; an unsettled
        box that may meet a singular surface, ``"singular"``; any other
        unsettled box, ``"undecided"``; else ``"certified"``, whether or not the
        enclosure reached its tolerance (a box settled but not refined).
    """
    bounds = f"[{criterion[0]:g}, {criterion[1]:g}]"
    counter, f = found
    if counter is not None:
        what = (
            "is out of reach or singular"
            if f is None or not np.isfinite(f).all()
            else f"has factors [{f[0]:.6g}, {f[1]:.6g}, {f[2]:.6g}]"
        )
        return (
            "violated",
            f"the point {_mm(counter)} {what}, outside {bounds} by more than {tol:g}",
        )
    open_ = [leaf for leaf in left if not leaf.settled]
    singular = sorted(
        (leaf for leaf in open_ if leaf.singular), key=lambda x: x.singular != SERIAL
    )
    if singular:
        leaf = singular[0]
        surface = (
            f"the serial singular surface of leg {leaf.leg} (leg orthogonal to its slider) "
            "or its reach"
            if leaf.singular == SERIAL
            else "the parallel singular surface (coplanar legs)"
        )
        return "singular", f"the box around {_mm(leaf.centre)} may meet {surface}"
    why = "the box budget ran out" if out_of_budget else "the resolution was reached"
    if open_:
        return "undecided", (
            f"{why}: a bound of {bounds} (widened by {tol:g}) is reached within the enclosure"
            f" near {_mm(open_[0].centre)}, neither proven nor violated"
        )
    lo, hi = enclosure
    strictly = criterion[0] <= lo and hi <= criterion[1]
    where = f"inside {bounds}" if strictly else f"within {tol:g} of {bounds}"
    note = "" if not left else f" (the enclosure is not refined to the tolerance: {why})"
    return "certified", f"every factor of the cube lies in [{lo:.6f}, {hi:.6f}], {where}{note}"


__all__ = ["STATUSES", "Certification", "Leaf", "verdict"]
