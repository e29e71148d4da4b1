"""The compiled passes against the array version, on the rows the planner builds."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import reachability
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.reach_compiled import AVAILABLE, reach_compiled
from orthoglide_pin.planning.reachability import reach, reach_arrays

from .test_reachability import _problem

#: Squared speeds of the two versions, relative to the largest [-] (the same
#: operations in the same order: they agree to rounding).
X_RTOL = 1e-12

needs_numba = pytest.mark.skipif(not AVAILABLE, reason="numba is not installed")


@pytest.fixture(scope="module")
def problems(dyn: og.ClosedLoopDynamics) -> list[tuple[np.ndarray, ...]]:
    limits = PlanLimits(slider_acceleration=15.0, drive=load_drive(str(example_drive_file())))
    return _problem(dyn, limits)


@needs_numba
def test_the_compiled_passes_give_the_array_versions_speeds(problems) -> None:
    for problem in problems:
        ours, theirs = reach_compiled(*problem), reach_arrays(*problem)
        assert ours is not None and theirs is not None
        np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=X_RTOL * theirs.max())


@needs_numba
def test_from_a_start_speed_and_when_a_stage_is_empty(problems) -> None:
    s, a, b, c, bound = problems[0]
    free = reach_arrays(s, a, b, c, bound)
    assert free is not None
    start = 0.5 * float(free[1])  # inside the first controllable set
    bound = bound.copy()
    bound[0] = start  # as a window's first point
    ours, theirs = reach_compiled(s, a, b, c, bound, start), reach_arrays(s, a, b, c, bound, start)
    assert ours is not None and theirs is not None and ours[0] == start
    np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=X_RTOL * theirs.max())
    assert reach_compiled(s, a, b, c, bound, 1e6) is None  # it cannot brake from there
    c = c.copy()
    c[len(s) // 2] = 1.5  # no speed and no acceleration meet the rows here
    assert reach_compiled(s, a, b, c, bound) is None
    assert reach_arrays(s, a, b, c, bound) is None


def test_without_numba_the_array_version_plans(problems, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(reachability, "AVAILABLE", False)
    monkeypatch.setattr(reachability, "reach_compiled", None)  # never called
    x = reach(*problems[0])
    expected = reach_arrays(*problems[0])
    assert x is not None and expected is not None
    np.testing.assert_array_equal(x, expected)


def test_the_compiled_passes_say_numba_is_missing(
    problems, monkeypatch: pytest.MonkeyPatch
) -> None:
    from orthoglide_pin.planning import reach_compiled as module

    monkeypatch.setattr(module, "AVAILABLE", False)  # as where numba is not installed
    with pytest.raises(RuntimeError, match="numba"):
        reach_compiled(*problems[0])


@needs_numba
def test_without_a_folder_to_cache_in_the_loops_still_compile(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import numba

    from orthoglide_pin.planning import reach_compiled

    real = numba.njit

    def njit(*args: object, cache: bool = False, **options: object) -> object:
        if cache:
            raise RuntimeError("cannot cache function: no locator available")
        return real(*args, **options)

    monkeypatch.setattr(numba, "njit", njit)
    twice = reach_compiled.jit(lambda x: 2.0 * x)
    assert twice(1.5) == 3.0


@needs_numba
def test_passes_taken_again_where_the_rows_changed_are_the_whole_ones(problems) -> None:
    """``ReachAgain``: tightened rows at a few points, the same speeds as planned anew."""
    from orthoglide_pin.planning.reach_compiled import ReachAgain

    s, a, b, c, bound = problems[0]
    again = ReachAgain()
    first = again.reach(s, a, b, c, bound)
    assert first is not None and np.array_equal(first, reach_compiled(s, a, b, c, bound))
    n = s.size
    assert again.reach(s, a, b, c, bound) is not None and again.stages == n  # nothing changed
    for points in ([n // 3], [n // 4, n // 4 + 1, (3 * n) // 4], [1, n - 2]):
        a = a.copy()
        a[points] *= 1.3  # a tighter acceleration there
        ours, whole = again.reach(s, a, b, c, bound), reach_compiled(s, a, b, c, bound)
        assert ours is not None and whole is not None
        assert np.array_equal(ours, whole)
    assert again.stages < 2 * n  # only the changed points were marked
    c = c.copy()
    c[n // 2] = 1.5  # an empty stage: refused, as planned anew
    assert again.reach(s, a, b, c, bound) is None
    assert reach_compiled(s, a, b, c, bound) is None
