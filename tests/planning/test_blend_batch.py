"""Corners of two lines blended together: the blends of one by one, to rounding."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from orthoglide_pin.planning import blend_batch
from orthoglide_pin.planning.blend import corner_blend
from orthoglide_pin.planning.blend_batch import corner_blends
from orthoglide_pin.planning.geometry import arc_piece, line_piece

#: Trims, misses and control points [m], arc lengths of the curves [m], absolute.
ROUNDING = 1e-15


def _lines(seed: int, count: int) -> list:
    """A polyline of short and long lines turning by small, large and reversing angles."""
    rng = np.random.default_rng(seed)
    points = [np.zeros(3)]
    for k in range(count):
        length = rng.choice([1e-4, 5e-4, 5e-3, 3e-2]) * rng.uniform(0.5, 1.5)
        back = k % 7 == 0 and k > 0  # every seventh line turns back (no blend)
        direction = -np.sign(points[-1] - points[-2] + 1e-9) if back else rng.normal(size=3)
        points.append(points[-1] + length * direction / np.linalg.norm(direction))
    return [line_piece(k, a, b, 0.05) for k, (a, b) in enumerate(itertools.pairwise(points))]


@pytest.mark.parametrize("chunk", [4096, 7])
def test_the_corners_of_lines_together_are_those_one_by_one(
    chunk: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(blend_batch, "CHUNK", chunk)  # 7: in chunks, across them
    pieces = _lines(5, 120)
    arc = arc_piece(200, pieces[-1].origin + pieces[-1].length * pieces[-1].u,
                    pieces[-1].origin, (0, 1, 2), 1.0, 0.0, None, 0.0)  # fmt: skip
    corners = [(a, b, tol) for a, b in itertools.pairwise(pieces) for tol in (1e-5, 1e-4, 0.0)]
    corners.append((pieces[-1], arc, 1e-5))  # an arc: blended one by one
    together = corner_blends(corners)
    kinds = set()
    for (a, b, tol), mine in zip(corners, together, strict=True):
        theirs = corner_blend(a, b, tol)
        assert (mine is None) == (theirs is None)
        if mine is None or theirs is None:
            kinds.add("none")
            continue
        kinds.add("equal" if mine.trim_in == mine.trim_out else "capped")
        np.testing.assert_allclose(
            [mine.trim_in, mine.trim_out, mine.miss, mine.piece.length],
            [theirs.trim_in, theirs.trim_out, theirs.miss, theirs.piece.length],
            rtol=0.0,
            atol=ROUNDING,
        )
        np.testing.assert_allclose(
            mine.piece.curve.control, theirs.piece.curve.control, atol=ROUNDING
        )
        np.testing.assert_allclose(mine.piece.curve._cum, theirs.piece.curve._cum, atol=ROUNDING)
        assert mine.piece.feed == theirs.piece.feed and mine.piece.block == theirs.piece.block
    assert kinds == {"none", "equal", "capped"}


@pytest.mark.skipif(not blend_batch.AVAILABLE, reason="numba is not installed (the [plan] extra)")
def test_the_compiled_arc_length_tables_are_the_array_ones() -> None:
    rng = np.random.default_rng(3)
    control = np.cumsum(rng.normal(scale=1e-4, size=(50, 6, 3)), axis=1)  # 0.1 mm polygons
    coef = np.einsum("ij,mjc->mic", blend_batch._TO_POWER, control - control[:, :1])
    compiled = blend_batch.arc_tables(coef, compiled=True)
    arrays = blend_batch.arc_tables(coef, compiled=False)
    assert compiled.shape == (50, blend_batch.SUBDIVISIONS + 1)
    assert np.all(np.diff(compiled, axis=1) > 0.0)
    np.testing.assert_allclose(compiled, arrays, rtol=0.0, atol=ROUNDING)
