"""A section sampled in batches: the same samples as piece by piece.

Bit for bit in arrays; to rounding when the blends are sampled compiled (numba).
"""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.planning import sample_batch as sb
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.path import build_path, sample_section
from orthoglide_pin.planning.sample_batch import sample_batch

#: Lines, helices and arcs of two radii blended, a rapid, an exact stop, short blended blocks.
PROGRAM = (
    "G21 G90 G64 P0.02\nG1 X10 F6000\nG3 X20 Y0 R5\nG1 X30 Y5 Z2\nG2 X40 Y5 I5 J0 Z4\n"
    "G1 X45 Y-3\nG0 X0 Y0 Z0\nG61 G1 X3\nG64 P0.01\n"
    + "".join(
        f"G1 X{3 + 0.2 * k:.3f} Y{0.05 * (k % 3):.3f} Z{0.01 * k:.3f}\n" for k in range(1, 40)
    )
)
#: The compiled blends against piece by piece: arc length [m], points [m],
#: unit tangents [-] and curvature vectors [1/m] (up to 2e4 here), absolute and
#: relative to each row's size (a component much smaller than its vector keeps
#: the vector's rounding).
ROUNDING, ROUNDING_RTOL = 1e-12, 1e-13


def _close(mine: np.ndarray, theirs: np.ndarray, name: str = "") -> None:
    """``mine`` equals ``theirs`` to rounding, row by row."""
    size = np.abs(theirs) if theirs.ndim == 1 else np.linalg.norm(theirs, axis=-1)[..., None]
    excess = np.abs(mine - theirs) - (ROUNDING + ROUNDING_RTOL * size)
    assert excess.max(initial=0.0) <= 0.0, f"{name}: {np.abs(mine - theirs).max()}"


@pytest.mark.parametrize(("refine", "compiled"), [(1, False), (10, False), (10, True)])
def test_batches_give_the_samples_of_piece_by_piece(
    refine: int, compiled: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    if compiled and not sb.AVAILABLE:
        pytest.skip("numba is not installed")
    monkeypatch.setattr(sb, "AVAILABLE", compiled)
    path = build_path(read_program(PROGRAM))
    kinds = set()
    for sec in path.sections:
        if not sec.pieces:
            continue
        kinds |= {(p.is_blend, p.is_arc) for p in sec.pieces}
        one, many = (
            sample_section(sec, 2e-3, refine=refine),
            sample_batch(sec, 2e-3, refine=refine),
        )
        np.testing.assert_array_equal(many.piece, one.piece)
        for name in ("s", "p", "dp", "ddp"):
            mine, theirs = getattr(many, name), getattr(one, name)
            if compiled:
                _close(mine, theirs, name)
            else:
                np.testing.assert_array_equal(mine, theirs, err_msg=name)
    assert kinds == {(False, False), (False, True), (True, False)}  # lines, arcs, blends


def test_without_numba_the_compiled_sampling_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    from orthoglide_pin.planning import sample_compiled

    monkeypatch.setattr(sample_compiled, "AVAILABLE", False)
    with pytest.raises(RuntimeError, match="numba"):
        sample_compiled.blends_compiled(*(np.zeros(0) for _ in range(6)))  # type: ignore[arg-type]


def test_sections_sampled_together_are_sampled_as_each() -> None:
    moving = [sec for sec in build_path(read_program(PROGRAM)).sections if sec.pieces]
    assert len(moving) >= 3
    for mine, sec in zip(sb.sample_sections(moving, 2e-3, refine=10), moving, strict=True):
        alone = sample_batch(sec, 2e-3, refine=10)
        for name in ("s", "p", "dp", "ddp", "piece"):
            np.testing.assert_array_equal(getattr(mine, name), getattr(alone, name), err_msg=name)


@pytest.mark.parametrize("compiled", [False, True])
def test_pieces_evaluated_together_are_evaluated_as_each(
    compiled: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    if compiled and not sb.AVAILABLE:
        pytest.skip("numba is not installed")
    monkeypatch.setattr(sb, "AVAILABLE", compiled)
    pieces = [p for sec in build_path(read_program(PROGRAM)).sections for p in sec.pieces]
    rng = np.random.default_rng(7)
    which = rng.integers(0, len(pieces), 400).astype(np.intp)
    lengths = np.array([p.length for p in pieces])
    local = rng.uniform(0.0, 1.0, which.size) * lengths[which]
    local[:3] = 0.0
    local[3:6] = lengths[which[3:6]]  # the ends, exactly
    mine = sb.evaluate_pieces(pieces, which, local)
    for k, piece in enumerate(pieces):
        sel = which == k
        if not sel.any():
            continue
        for got, want in zip(mine, piece.evaluate(local[sel]), strict=True):
            _close(got[sel], want)
    empty = sb.evaluate_pieces(pieces, np.zeros(0, dtype=np.intp), np.zeros(0))
    assert all(e.shape == (0, 3) for e in empty)


def test_compiled_blends_sampled_in_order_or_not_agree() -> None:
    """The compiled inversion warm-starts on samples in order, starts afresh on the others."""
    if not sb.AVAILABLE:
        pytest.skip("numba is not installed")
    pieces = [p for sec in build_path(read_program(PROGRAM)).sections for p in sec.pieces]
    curves = [p for p in pieces if p.is_blend]
    which = np.repeat(np.arange(len(curves), dtype=np.intp), 200)
    lengths = np.array([c.length for c in curves])
    local = np.tile(np.linspace(0.0, 1.0, 200), len(curves)) * lengths[which]
    forward = sb._blends(curves, local, which)  # type: ignore[arg-type]
    order = np.random.default_rng(3).permutation(which.size)
    shuffled = sb._blends(curves, local[order], which[order])  # type: ignore[arg-type]
    for mine, theirs in zip(shuffled, forward, strict=True):
        _close(mine, theirs[order])
