from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.dynamics.sym3 import extreme_eigenvalues

#: Against LAPACK, relative to the largest |eigenvalue|: a few roundings.
EIG_RTOL = 1e-14
N = 2000


def _rotated(spectra: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    rot, _ = np.linalg.qr(rng.normal(size=(spectra.shape[0], 3, 3)))
    return np.einsum("nij,nj,nkj->nik", rot, spectra, rot)


def _spectra(kind: str, rng: np.random.Generator) -> np.ndarray:
    ones = np.ones(N)
    if kind == "random":
        return rng.normal(size=(N, 3))
    if kind == "double largest":
        return np.column_stack([ones, ones, -2.0 * ones])
    if kind == "double smallest":
        return np.column_stack([3.0 * ones, -ones, -ones])
    if kind == "nearly double":
        return np.column_stack([ones, ones + 1e-9 * rng.random(N), -0.5 * ones])
    if kind == "triple":
        return 2.0 * np.column_stack([ones, ones, ones])
    if kind == "nearly scalar":
        return 1e6 + np.column_stack([rng.random(N), rng.random(N), 0.0 * ones])
    return np.column_stack([rng.normal(size=N), 0.0 * ones, 0.0 * ones])  # rank 1


@pytest.mark.parametrize(
    "kind",
    [
        "random",
        "double largest",
        "double smallest",
        "nearly double",
        "triple",
        "nearly scalar",
        "rank one",
    ],
)
def test_extreme_eigenvalues_match_lapack(kind: str) -> None:
    rng = np.random.default_rng(7)
    a = _rotated(_spectra(kind, rng), rng)
    a = 0.5 * (a + a.transpose(0, 2, 1))
    lo, hi = extreme_eigenvalues(a)
    ref = np.linalg.eigvalsh(a)
    scale = np.abs(ref).max(axis=1)
    assert np.all(np.abs(lo - ref[:, 0]) <= EIG_RTOL * scale)
    assert np.all(np.abs(hi - ref[:, -1]) <= EIG_RTOL * scale)


def test_exact_matrices_and_shapes() -> None:
    diag = np.diag([1.0, 5.0, 5.0])
    lo, hi = extreme_eigenvalues(np.stack([diag, np.zeros((3, 3)), -diag]).reshape(3, 1, 3, 3))
    assert lo.shape == hi.shape == (3, 1)
    np.testing.assert_array_equal(lo[:, 0], [1.0, 0.0, -5.0])
    np.testing.assert_array_equal(hi[:, 0], [5.0, 0.0, -1.0])
