"""Move-by-move comparison of two readings of a program (built-in reader and ``rs274``).

Two readers agree when they give the same number of moves and, move by move,
the same line and kind, start and end points and arc centres within a length
tolerance, the same plane normal and signed turn count, the same feed and the
same dwell. The default tolerance is ``rs274``'s printed precision: 4 decimals
of an inch, for up to three rounded terms (position, work offset, tool length).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

import numpy as np

from orthoglide_pin._validation import instance_of, integer, positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.program.moves import FloatArray, Move

#: Default length tolerance [m]: three half-units of 4 decimals of an inch.
PRINTED_TOL: Final[float] = 3 * 0.5e-4 * 0.0254
#: Default dwell tolerance [s]: half a unit of 4 decimals.
DWELL_TOL: Final[float] = 0.5e-4
#: Default relative feed tolerance, and its absolute floor [m/s] (half a unit
#: of 4 decimals of an inch per minute).
FEED_RTOL: Final[float] = 1e-6
FEED_ATOL: Final[float] = 0.5e-4 * 0.0254 / 60.0
#: Normals are unit vectors: their components agree to this.
NORMAL_TOL: Final[float] = 1e-9


def _far(a: FloatArray | None, b: FloatArray | None, tol: float) -> bool:
    """Whether two optional points differ by more than ``tol`` (or only one is given)."""
    if a is None or b is None:
        return (a is None) != (b is None)
    return bool(np.max(np.abs(np.asarray(a) - np.asarray(b))) > tol)


def _mm(p: FloatArray | None) -> str:
    """A point [m] in millimetres for a message."""
    if p is None:
        return "none"
    return "(" + ", ".join(f"{1e3 * v:.4f}" for v in np.asarray(p)) + ") mm"


def _differences(i: int, a: Move, b: Move, tol: float, dwell_tol: float) -> list[str]:
    """What differs between two moves of the same index."""
    where = f"move {i} (line {a.line})"
    out = []
    if (a.line, a.kind) != (b.line, b.kind):
        out.append(f"{where}: {a.kind} of line {a.line} vs {b.kind} of line {b.line}")
        return out
    for name in ("start", "end", "center"):
        pa, pb = getattr(a, name), getattr(b, name)
        if _far(pa, pb, tol):
            out.append(f"{where}: {name} {_mm(pa)} vs {_mm(pb)}")
    if _far(a.normal, b.normal, NORMAL_TOL) or a.turns != b.turns:
        out.append(f"{where}: normal/turns {a.normal}/{a.turns} vs {b.normal}/{b.turns}")
    if (a.feed is None) != (b.feed is None) or (
        a.feed is not None
        and b.feed is not None
        and abs(a.feed - b.feed) > FEED_ATOL + FEED_RTOL * abs(b.feed)
    ):
        out.append(f"{where}: feed {a.feed} vs {b.feed} m/s")
    if abs(a.dwell - b.dwell) > dwell_tol:
        out.append(f"{where}: dwell {a.dwell} vs {b.dwell} s")
    return out


def _moves(name: str, value: object) -> list[Move]:
    """``value`` as a list of moves, or an error naming the argument."""
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidParameterError(name, value, "a sequence of Move records")
    for move in value:
        instance_of(name, move, Move, "a sequence of Move records")
    return list(value)


def compare_moves(
    a: Sequence[Move],
    b: Sequence[Move],
    tol: float = PRINTED_TOL,
    *,
    dwell_tol: float = DWELL_TOL,
    limit: int = 10,
) -> list[str]:
    """Compare two readings of a program move by move.

    Args:
        a: Moves of one reader.
        b: Moves of the other.
        tol: Largest difference of a coordinate of a start, end or centre [m].
        dwell_tol: Largest difference of a dwell [s].
        limit: Most differences listed.

    Returns:
        One line per difference (at most ``limit``), empty when they agree.

    Raises:
        InvalidParameterError: A reading that is not a sequence of moves, or a
            bad tolerance or limit (named).
    """
    a, b = _moves("a", a), _moves("b", b)
    tol = positive_number("tol", tol, "a positive length [m]")
    dwell_tol = positive_number("dwell_tol", dwell_tol, "a positive duration [s]")
    limit = integer("limit", limit, 1)
    out = []
    if len(a) != len(b):
        out.append(f"{len(a)} moves vs {len(b)}")
    for i, (ma, mb) in enumerate(zip(a, b, strict=False)):
        out += _differences(i, ma, mb, tol, dwell_tol)
        if len(out) >= limit:
            break
    return out[:limit]
