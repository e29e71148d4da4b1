"""The path forms in one compiled loop: the array route's numbers and errors."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CUBE_CORNER, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.dynamics import forms_compiled as fc
from orthoglide_pin.dynamics import path_forms as pf
from orthoglide_pin.dynamics.leg_harmonics import leg_harmonics

#: Compiled forms against the array route, relative to each row's size (the
#: expansion's sums are taken in another order) and absolute [N, m, 1/m].
ROUNDING_RTOL, ROUNDING = 1e-13, 1e-12
FIELDS = ("q", "dq", "ddq", "a", "b", "c")

needs_numba = pytest.mark.skipif(not fc.AVAILABLE, reason="numba is not installed")


def _both(
    monkeypatch: pytest.MonkeyPatch, *args: object, **kwargs: object
) -> tuple[pf.PathForms, pf.PathForms]:
    """``path_forms`` compiled, then by the arrays."""
    compiled = pf.path_forms(*args, **kwargs)  # type: ignore[arg-type]
    with monkeypatch.context() as m:
        m.setattr(pf, "COMPILED", False)
        arrays = pf.path_forms(*args, **kwargs)  # type: ignore[arg-type]
    return compiled, arrays


def _path(dyn: og.ClosedLoopDynamics, n: int, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    cube = dyn.closed_loop.params.workspace
    p = cube.q1 + cube.side * rng.random((n, 3))
    t = rng.standard_normal((n, 3))
    return p, t / np.linalg.norm(t, axis=1, keepdims=True), 50.0 * rng.standard_normal((n, 3))


@needs_numba
@pytest.mark.parametrize("leg_length", [None, 0.35])
@pytest.mark.parametrize("wrench", [None, (40.0, -25.0, 60.0, 2.0, -1.0, 3.0), "per point"])
def test_compiled_forms_are_the_array_forms(
    monkeypatch: pytest.MonkeyPatch, leg_length: float | None, wrench: object
) -> None:
    params = og.prototype() if leg_length is None else og.prototype().replace(leg_length=0.35)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    path = _path(dyn, 300, seed=41)
    if wrench == "per point":
        wrench = np.random.default_rng(41).uniform(-80.0, 80.0, (300, 6))
    compiled, arrays = _both(monkeypatch, dyn, *path, gravity=(1.5, -2.0, 9.6), wrench=wrench)
    for name in FIELDS:
        mine, theirs = getattr(compiled, name), getattr(arrays, name)
        size = np.linalg.norm(theirs, axis=1, keepdims=True)
        assert np.all(np.abs(mine - theirs) <= ROUNDING + ROUNDING_RTOL * size), name


@needs_numba
def test_a_point_near_a_check_takes_the_array_route(
    dyn: og.ClosedLoopDynamics, monkeypatch: pytest.MonkeyPatch
) -> None:
    face = np.array([CUBE_CORNER, 0.0, 0.0])  # slider 1 at its lower limit
    expansion = leg_harmonics(dyn)
    assert expansion is not None
    params = dyn.closed_loop.params
    limits = (dyn.leg_length, params.slider_lower, params.slider_upper, pf.PATH_LIMIT_TOL)

    def compiled(points: np.ndarray) -> np.ndarray | None:
        n = points.shape[0]
        t, k = np.tile([1.0, 0.0, 0.0], (n, 1)), np.zeros((n, 3))
        coef = expansion.coefficients(dyn.gravity_vector(None))
        args = (points, t, k, np.zeros((n, 3)), coef, expansion.harmonics, pf._LEGS)
        return fc.forms_compiled(*args, (*limits, 1e-9, 1e-9))

    inside = np.array([face + np.array([1e-3, 0.0, 0.0]), np.zeros(3)])
    assert compiled(inside) is not None
    # beyond the limit by less than the tolerance, but past half of it: the arrays decide
    near = face - [0.8 * pf.PATH_LIMIT_TOL, 0.0, 0.0]
    assert compiled(np.vstack([inside, near])) is None
    assert compiled(np.vstack([np.tile(inside, (150, 1)), near])) is None  # in a later chunk
    got, want = _both(monkeypatch, dyn, [near], [[1.0, 0.0, 0.0]], np.zeros((1, 3)))
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    # out of reach, and beyond the limit: the array route's errors, with the compiled loop on
    far = np.array([0.0, PROTOTYPE_LEG, PROTOTYPE_LEG])
    beyond = face - [1e-7, 0.0, 0.0]
    for bad, match in ((far, "to slider axis"), (beyond, "outside the limits")):
        assert compiled(np.vstack([inside, bad])) is None
        with pytest.raises(og.UnreachablePointError, match=match):
            pf.path_forms(
                dyn, np.vstack([inside, bad]), np.tile([1.0, 0, 0], (3, 1)), np.zeros((3, 3))
            )


def test_without_numba_the_compiled_forms_say_so(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(fc, "AVAILABLE", False)
    empty = np.zeros((0, 3))
    with pytest.raises(RuntimeError, match="numba"):
        fc.forms_compiled(
            empty,
            empty,
            empty,
            empty,
            empty,
            empty.astype(np.intp),
            empty.astype(np.intp),
            (1.0,) * 6,
        )  # type: ignore[arg-type]
