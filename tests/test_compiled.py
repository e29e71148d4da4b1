"""numba, optional: the one way the package compiles a loop, and its fallback flag."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from orthoglide_pin import _compiled
from orthoglide_pin.dynamics import forms_compiled
from orthoglide_pin.planning import reach_compiled


def test_available_says_whether_numba_is_installed() -> None:
    installed = importlib.util.find_spec("numba") is not None
    assert _compiled.AVAILABLE is installed
    assert reach_compiled.AVAILABLE is installed and forms_compiled.AVAILABLE is installed


def _shares(x: np.ndarray) -> np.ndarray:
    out = np.empty(x.size)
    total = 0.0
    for k in range(x.size):
        total += x[k]
    for k in range(x.size):
        out[k] = x[k] / total
    return out


@pytest.mark.skipif(not _compiled.AVAILABLE, reason="numba is not installed (the [plan] extra)")
@pytest.mark.parametrize("inline", [False, True])
def test_a_compiled_loop_gives_numpy_s_numbers_and_division_by_zero(inline: bool) -> None:
    shares = _compiled.jit(_shares, inline=inline)
    x = np.array([1.0, 2.0, 5.0])
    np.testing.assert_array_equal(shares(x), x / x.sum())
    assert shares(x)[2] == 0.625
    with np.errstate(divide="ignore", invalid="ignore"):
        zero = shares(np.zeros(2))  # numpy's error model: nan, no exception
    assert np.isnan(zero).all()
