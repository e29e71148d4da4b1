"""The transmission criterion of a machine: bounds on its velocity transmission factors.

A machine is designed for a prescribed cube and for bounds ``psi_min < 1 <
psi_max`` on its velocity transmission factors (the singular values of ``J``)
over that cube (paper, section 3.4). The bounds are part of the machine, beside
its cube (:attr:`~orthoglide_pin.machine.params.OrthoglideParams.psi_min`,
``psi_max``), and of its design file, so that every command judges a machine by
the criterion it was designed for (``orthoglide certify``, ``summary``,
``sweep`` and ``report``; their ``--psi MIN MAX`` overrides it).

**One tolerance rule.** The criterion holds on a set of points when every
factor lies in ``[psi_min - tol, psi_max + tol]``, ``tol`` =
:data:`CRITERION_TOL` (1e-4) unless told otherwise. The design method puts the
reference points Q1 and Q2 exactly on the bounds, so a design's own cube has no
margin at all: without a tolerance its criterion could be neither proven nor
refuted in floating point. The same rule serves the proof over the continuum
(:func:`~orthoglide_pin.kinetostatics.certify.certify_cube`, whose ``tol`` is
this tolerance) and every check on a grid (the design's, ``summary``'s,
``report``'s and the sweep's), so they decide the same question.

**The prototype.** The paper's prototype is designed for [0.5, 2]
(:data:`PAPER_BOUNDS`) on a 200 mm cube, which the design method meets with
legs of 310.58 mm; the paper rounds them to 310 mm, and with 310 mm the factors
over that cube lie in [0.4989, 2.0090] (both extremes at the cube's corner Q2).
:func:`~orthoglide_pin.machine.params.prototype` keeps the paper's 310 mm and its
criterion [0.5, 2], which its cube therefore does not meet.
"""

from __future__ import annotations

import math
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.exceptions import InvalidParameterError

#: The paper's bounds on the transmission factors (section 4): the prototype's criterion.
PAPER_BOUNDS: Final = (0.5, 2.0)
#: The tolerance of the criterion (see the module): factors within this of the bounds pass.
CRITERION_TOL: Final[float] = 1e-4
#: The machine parameters of the criterion, lower bound first.
CRITERION_FIELDS: Final = ("psi_min", "psi_max")
#: What each bound must be.
ALLOWED: Final = {
    "psi_min": "a lower bound in (0, 1) (the factors are 1 at home)",
    "psi_max": "an upper bound > 1 (the factors are 1 at home)",
}


def check_bounds(
    psi_min: Any, psi_max: Any, names: tuple[str, str] = CRITERION_FIELDS
) -> tuple[float, float]:
    """The bounds of a criterion as floats, checked: finite, ``0 < psi_min < 1 < psi_max``.

    Args:
        psi_min: Lower bound on the transmission factors [-].
        psi_max: Upper bound [-].
        names: How to name them in an error (e.g. ``("--psi MIN", "--psi MAX")``).

    Returns:
        ``(psi_min, psi_max)``.

    Raises:
        InvalidParameterError: Naming the bad bound and what is allowed.
    """
    values = []
    for key, name, value in zip(CRITERION_FIELDS, names, (psi_min, psi_max), strict=True):
        try:
            number = math.nan if isinstance(value, bool) else float(value)
        except (TypeError, ValueError):
            number = math.nan
        ok = 0.0 < number < 1.0 if key == "psi_min" else 1.0 < number < math.inf
        if not ok:  # NaN fails both
            raise InvalidParameterError(name, value, ALLOWED[key])
        values.append(number)
    return values[0], values[1]


def within(
    lowest: ArrayLike,
    highest: ArrayLike,
    psi_min: float,
    psi_max: float,
    tol: float = CRITERION_TOL,
) -> NDArray[np.bool_]:
    """Whether factors from ``lowest`` to ``highest`` meet the criterion (the one rule).

    Args:
        lowest: Smallest factor of each point, any shape (NaN: out of reach).
        highest: Largest factor of each point, the same shape (``inf`` or NaN:
            singular or out of reach, which never meets it).
        psi_min: Lower bound of the criterion.
        psi_max: Upper bound.
        tol: Tolerance of the rule (:data:`CRITERION_TOL`).

    Returns:
        ``psi_min - tol <= lowest`` and ``highest <= psi_max + tol``, per point.
    """
    lo = np.asarray(lowest, dtype=np.float64)
    hi = np.asarray(highest, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.asarray((lo >= psi_min - tol) & (hi <= psi_max + tol), dtype=np.bool_)


def describe(psi_min: float, psi_max: float, tol: float = CRITERION_TOL) -> str:
    """The criterion in words: ``factors in [0.5, 2] (within 0.0001)``."""
    return f"factors in [{psi_min:g}, {psi_max:g}] (within {tol:g})"


__all__ = [
    "ALLOWED",
    "CRITERION_FIELDS",
    "CRITERION_TOL",
    "PAPER_BOUNDS",
    "check_bounds",
    "describe",
    "within",
]
