"""Path forms of the slider forces against the closed-loop inverse dynamics, point by point."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_states

import orthoglide_pin as og
from orthoglide_pin.dynamics.path_dynamics import PathForms, path_forms

#: The forms against one inverse-dynamics call per point (rounding only).
FORM_RTOL = 1e-10
#: Absolute floor of the force comparison [N] and of the slider motion [m/s, m/s^2].
FORCE_ATOL = 1e-9
MOTION_ATOL = 1e-12


def _path_data(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, unit tangents and curvatures normal to them [1/m], shape (n, 3) each."""
    rng = np.random.default_rng(seed)
    p = random_states(n, seed)[0]
    t = rng.standard_normal((n, 3))
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    k = rng.standard_normal((n, 3)) * 40.0
    k -= np.einsum("ni,ni->n", k, t)[:, None] * t
    return p, t, k


def _compare(dyn: og.ClosedLoopDynamics, forms: PathForms, p, t, k, seed, **kw) -> None:
    rng = np.random.default_rng(seed)
    sd = 1.5 * rng.random(p.shape[0])
    sdd = 30.0 * rng.standard_normal(p.shape[0])
    res = dyn.inverse_dynamics(p, t * sd[:, None], t * sdd[:, None] + k * (sd**2)[:, None], **kw)
    np.testing.assert_allclose(forms.forces(sd, sdd), res.forces, rtol=FORM_RTOL, atol=FORCE_ATOL)
    np.testing.assert_allclose(forms.q, res.slider_positions, rtol=0, atol=MOTION_ATOL)
    np.testing.assert_allclose(forms.dq * sd[:, None], res.slider_velocities, atol=MOTION_ATOL)
    qdd = forms.dq * sdd[:, None] + forms.ddq * (sd**2)[:, None]
    np.testing.assert_allclose(qdd, res.slider_accelerations, rtol=FORM_RTOL, atol=1e-10)


def test_forms_equal_the_inverse_dynamics_on_the_prototype(dyn: og.ClosedLoopDynamics) -> None:
    p, t, k = _path_data(60, seed=11)
    forms = path_forms(dyn, p, t, k)
    _compare(dyn, forms, p, t, k, seed=12)
    # the forms are not trivial: speed and curvature both matter on this machine
    assert np.abs(forms.b).max() > 1.0
    assert np.abs(forms.c[:, 2]).min() > 10.0  # gravity on the vertical slider


def test_forms_with_a_wrench_gravity_and_another_design() -> None:
    params = og.prototype().replace(leg_length=0.36)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    p, t, k = _path_data(40, seed=21)
    wrench = np.random.default_rng(22).standard_normal((40, 6)) * 50.0
    gravity = (0.0, 9.81, 0.0)
    forms = path_forms(params, p, t, k, gravity=gravity, wrench=wrench)
    _compare(dyn, forms, p, t, k, seed=23, gravity=gravity, wrench=wrench)


def test_bad_shapes_are_named(dyn: og.ClosedLoopDynamics) -> None:
    p, t, k = _path_data(5, seed=31)
    with pytest.raises(og.InvalidParameterError, match="shapes"):
        path_forms(dyn, p, t[:4], k)
    with pytest.raises(og.InvalidParameterError, match="tangents"):
        path_forms(dyn, p, np.full((5, 3), np.nan), k)
