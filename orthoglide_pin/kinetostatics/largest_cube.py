"""The largest certified cube: bisection on the side of nested cubes.

Cubes of one centre are nested, so "every point has its transmission factors
within the bounds" can only be lost as the side grows: a bisection on the side,
each step a verdict-only :func:`~orthoglide_pin.kinetostatics.certify.certify_cube`,
finds the largest certified side to a given resolution. The sweep's
``design_cube_side`` is this side around the design method's cube
(:mod:`orthoglide_pin.sweep.metrics`).
"""

from __future__ import annotations

from typing import Final

from numpy.typing import ArrayLike

from orthoglide_pin._validation import finite_vector, positive_length
from orthoglide_pin.kinetostatics.certify import certify_cube

#: Default resolution of :func:`largest_certified_side` [m] (0.1 mm).
SIDE_RESOLUTION: Final[float] = 1e-4


def largest_certified_side(
    leg_length: float,
    centre: ArrayLike,
    psi_min: float,
    psi_max: float,
    *,
    guess: float,
    resolution: float = SIDE_RESOLUTION,
) -> float:
    """The largest cube of this centre where the bounds are certified: its side.

    The cubes ``centre -/+ side / 2`` are nested, so certification is monotonic
    in the side: bisection, each step a verdict-only :func:`certify_cube`; an
    undecided or singular cube counts as not certified. The bracket starts at
    ``guess -/+ resolution / 2``, so a good guess (the design method's cube,
    centred between Q1 and Q2) costs two certifications.

    Args:
        leg_length: Leg length ``L`` [m].
        centre: Centre of the cubes [m], shape (3,).
        psi_min: Lower bound on the transmission factors.
        psi_max: Upper bound.
        guess: A side near the answer [m], positive.
        resolution: Width of the final bracket [m].

    Returns:
        A certified side [m] within ``resolution`` of the largest one; 0 if no
        cube of side ``resolution / 2`` or more is certified.

    Raises:
        InvalidParameterError: A bad argument.
    """
    res = positive_length("resolution", resolution)
    g = positive_length("guess", guess)
    c = finite_vector("centre", centre, 3, "[m]")

    def ok(side: float) -> bool:
        cube = certify_cube(leg_length, c - side / 2, side, psi_min, psi_max, refine=False)
        return cube.certified

    lo, hi = max(g - res / 2, res / 2), g + res / 2
    if ok(lo):
        step = res
        while ok(hi):  # the guess was short: widen the bracket
            lo, hi, step = hi, hi + step, 2 * step
    else:
        lo, hi = 0.0, lo
    while hi - lo > res:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


__all__ = ["SIDE_RESOLUTION", "largest_certified_side"]
