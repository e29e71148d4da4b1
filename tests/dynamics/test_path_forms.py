"""Slider forces along a path as forms in the path speed, against the inverse dynamics."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.dynamics import leg_harmonics as lh
from orthoglide_pin.dynamics import path_forms as pf
from orthoglide_pin.dynamics.path_forms import PathForms, path_forms, path_forms_by_rnea

#: Forms against the point-by-point inverse dynamics, relative to each point's
#: force (both are rounding away from the same value).
RTOL = 1e-10
#: Absolute floor of those comparisons [N].
FORCE_ATOL = 1e-9
#: Slider motion against the inverse dynamics' [m/s, m/s^2].
MOTION_ATOL = 1e-12
#: Central differences along the path, step [m], and their O(h^2) error.
FD_STEP = 1e-5
FD_TOL = 1e-7
#: A gravity off the default and a tool wrench (force [N], moment [N.m]).
GRAVITY = (1.5, -2.0, 9.6)
WRENCH = (40.0, -25.0, 60.0, 2.0, -1.0, 3.0)


def _other_design() -> og.ClosedLoopDynamics:
    params = og.prototype().replace(leg_length=0.35, platform_offset=0.035)
    return og.ClosedLoopDynamics(og.ClosedLoopModel(params))


@pytest.fixture(scope="module")
def other() -> og.ClosedLoopDynamics:
    return _other_design()


def _random_path(dyn: og.ClosedLoopDynamics, n: int, seed: int) -> tuple[np.ndarray, ...]:
    """Points of the machine's cube, unit tangents, curvatures up to 1/(5 cm), sd and sdd."""
    rng = np.random.default_rng(seed)
    cube = dyn.closed_loop.params.workspace
    p = cube.q1 + cube.side * (0.02 + 0.96 * rng.random((n, 3)))
    t = rng.standard_normal((n, 3))
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    k = 20.0 * rng.standard_normal((n, 3))
    return p, t, k, rng.uniform(0.0, 1.5, n), rng.uniform(-20.0, 20.0, n)


def _close(got: np.ndarray, expected: np.ndarray) -> None:
    scale = np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.all(np.abs(got - expected) <= RTOL * scale + FORCE_ATOL)


def _against_inverse_dynamics(
    dyn: og.ClosedLoopDynamics, forms: PathForms, path: tuple[np.ndarray, ...], **kwargs: object
) -> None:
    """The forms at (sd, sdd) against the inverse dynamics of the tool and of the sliders."""
    p, t, k, sd, sdd = path
    v, a = t * sd[:, None], t * sdd[:, None] + k * (sd * sd)[:, None]
    ref = dyn.inverse_dynamics(p, v, a, **kwargs)  # type: ignore[arg-type]
    _close(forms.forces(sd, sdd), ref.forces)
    qd, qdd = forms.slider_motion(sd, sdd)
    np.testing.assert_allclose(forms.q, ref.slider_positions, rtol=0, atol=MOTION_ATOL)
    np.testing.assert_allclose(qd, ref.slider_velocities, rtol=0, atol=MOTION_ATOL)
    np.testing.assert_allclose(qdd, ref.slider_accelerations, rtol=0, atol=1e3 * MOTION_ATOL)
    by_sliders = dyn.inverse_dynamics_sliders(forms.q, qd, qdd, **kwargs)  # type: ignore[arg-type]
    _close(forms.forces(sd, sdd), by_sliders.forces)


@pytest.mark.parametrize("design", ["prototype", "other"])
@pytest.mark.parametrize("route", [path_forms, path_forms_by_rnea])
def test_forms_equal_the_inverse_dynamics_point_by_point(
    dyn: og.ClosedLoopDynamics, other: og.ClosedLoopDynamics, design: str, route: object
) -> None:
    machine = dyn if design == "prototype" else other
    path = _random_path(machine, 300, seed=31)
    forms = route(machine, *path[:3], gravity=GRAVITY, wrench=WRENCH)  # type: ignore[operator]
    _against_inverse_dynamics(machine, forms, path, gravity=GRAVITY, wrench=WRENCH)
    # and without them: the model's default gravity, no wrench
    plain = route(machine, *path[:3])  # type: ignore[operator]
    _against_inverse_dynamics(machine, plain, path)
    assert np.abs(forms.c - plain.c).max() > 10.0  # the wrench and the gravity count


def test_a_wrench_per_point_and_blocks_of_points(
    dyn: og.ClosedLoopDynamics, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = _random_path(dyn, 53, seed=32)
    wrench = np.random.default_rng(32).uniform(-80.0, 80.0, (53, 6))
    whole = path_forms(dyn, *path[:3], wrench=wrench)
    monkeypatch.setattr(pf, "BLOCK", 8)  # seven blocks, the last one short
    blocks = path_forms(dyn, *path[:3], wrench=wrench)
    for name in ("q", "dq", "ddq", "a", "b", "c"):
        np.testing.assert_array_equal(getattr(blocks, name), getattr(whole, name))
    _against_inverse_dynamics(dyn, blocks, path, wrench=wrench)


def test_both_routes_agree_on_every_coefficient(other: og.ClosedLoopDynamics) -> None:
    path = _random_path(other, 200, seed=33)
    fast = path_forms(other, *path[:3], gravity=GRAVITY, wrench=WRENCH)
    ref = path_forms_by_rnea(other, *path[:3], gravity=GRAVITY, wrench=WRENCH)
    for name in ("a", "b", "c"):
        _close(getattr(fast, name), getattr(ref, name))
    for name in ("q", "dq", "ddq"):
        np.testing.assert_allclose(getattr(fast, name), getattr(ref, name), atol=1e-12)


def _line(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The cube's diagonal from Q1 to Q2, by arc length."""
    q1 = np.full(3, CUBE_CORNER)
    u = np.ones(3) / np.sqrt(3.0)
    s = np.linspace(0.0, CUBE_SIDE * np.sqrt(3.0), n)
    return s, q1 + s[:, None] * u, np.tile(u, (n, 1)), np.zeros((n, 3))


def _arc(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A circle of radius 60 mm in a tilted plane about the cube's centre, by arc length."""
    centre, r = np.full(3, CUBE_CORNER + CUBE_SIDE / 2), 0.06
    e1 = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    e2 = np.array([1.0, 1.0, -2.0]) / np.sqrt(6.0)
    c, si = np.cos(s / r)[:, None], np.sin(s / r)[:, None]
    return centre + r * (c * e1 + si * e2), -si * e1 + c * e2, -(c * e1 + si * e2) / r


def _trapezoid(s: np.ndarray, v_max: float, a_max: float) -> tuple[np.ndarray, np.ndarray]:
    """Rest-to-rest path speed and acceleration over the length ``s[-1]``."""
    length = s[-1]
    sd = np.sqrt(np.minimum(np.minimum(2 * a_max * s, 2 * a_max * (length - s)), v_max**2))
    sdd = np.where(2 * a_max * s < v_max**2, a_max, 0.0)
    sdd = np.where(2 * a_max * (length - s) < v_max**2, -a_max, sdd)
    return sd, np.where(2 * a_max * s < 2 * a_max * (length - s), sdd, np.minimum(sdd, 0.0))


def test_a_line_from_q1_to_q2(dyn: og.ClosedLoopDynamics) -> None:
    """Q1 and Q2 sit on the slider limits and are accepted; the forms give the trajectory."""
    s, p, t, k = _line(401)
    sd, sdd = _trapezoid(s, 1.2, 20.0)
    forms = path_forms(dyn, p, t, k, wrench=WRENCH)
    _against_inverse_dynamics(dyn, forms, (p, t, k, sd, sdd), wrench=WRENCH)
    np.testing.assert_allclose(forms.ddq[[0, -1]].std(axis=1), 0.0, atol=1e-12)  # symmetric
    # the design's own figures: along the diagonal the three sliders move alike; Q1 is
    # where the transmission factor along it reaches 2 (q' = 1 / (2 sqrt 3)), and towards
    # Q2 it falls to about 0.5 (q' = 1.157)
    assert forms.dq[0] == pytest.approx(np.full(3, 0.5 / np.sqrt(3.0)), rel=1e-9)
    assert forms.dq[-1] == pytest.approx(np.full(3, 1.15727), rel=1e-5)
    # the diagonal is the machine's axis of symmetry: inertia and centripetal terms are
    # alike on the three sliders, whichever leg carries the platform in the cut tree;
    # gravity along e3 is not
    for part in (forms.a, forms.b):
        np.testing.assert_allclose(part - part.mean(axis=1, keepdims=True), 0.0, atol=1e-12)
    assert forms.a[0, 0] == pytest.approx(4.795, abs=1e-3)  # [kg] at Q1
    assert np.abs(np.diff(forms.c[:, [0, 2]], axis=1)).min() > 1.0


def test_an_arc_and_its_derivatives(other: og.ClosedLoopDynamics) -> None:
    s = np.linspace(0.0, 2 * np.pi * 0.06, 181)
    p, t, k = _arc(s)
    sd, sdd = _trapezoid(s, 0.8, 15.0)
    forms = path_forms(other, p, t, k, gravity=GRAVITY)
    _against_inverse_dynamics(other, forms, (p, t, k, sd, sdd), gravity=GRAVITY)
    # dq and ddq against central differences of the slider positions along the arc
    h = FD_STEP
    plus, minus = (path_forms(other, *_arc(s + d)) for d in (h, -h))
    np.testing.assert_allclose(forms.dq, (plus.q - minus.q) / (2 * h), rtol=0, atol=FD_TOL)
    np.testing.assert_allclose(forms.ddq, (plus.dq - minus.dq) / (2 * h), rtol=0, atol=FD_TOL)
    np.testing.assert_allclose(
        forms.ddq, (plus.q - 2 * forms.q + minus.q) / (h * h), rtol=0, atol=1e3 * FD_TOL
    )
    # the centripetal part: b is the force per (m/s)^2 on a circle of radius 60 mm
    assert np.abs(forms.b).max() > np.abs(forms.a).max() / 0.06 * 0.5


def test_at_rest_the_forces_are_the_static_forces(other: og.ClosedLoopDynamics) -> None:
    p, t, k, _, _ = _random_path(other, 100, seed=34)
    forms = path_forms(other, p, t, k, gravity=GRAVITY, wrench=WRENCH)
    static = other.static_forces(p, gravity=GRAVITY, wrench=WRENCH)
    _close(forms.c, static)
    _close(forms.forces(0.0, 0.0), static)
    # and the inertia along the path is the inverse dynamics without gravity at a = p'
    unit = other.inverse_dynamics(p, np.zeros_like(p), t, gravity=(0.0, 0.0, 0.0)).forces
    _close(forms.a, unit)


def test_parameters_are_accepted_and_their_dynamics_kept() -> None:
    params = og.prototype().replace(leg_length=0.35)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    path = _random_path(dyn, 20, seed=35)
    by_params = path_forms(params, *path[:3])
    _close(by_params.forces(path[3], path[4]), path_forms(dyn, *path[:3]).forces(*path[3:]))
    assert pf._dynamics(params) is pf._dynamics(og.prototype().replace(leg_length=0.35))


def test_a_single_point_is_one_row(dyn: og.ClosedLoopDynamics) -> None:
    forms = path_forms(dyn, np.zeros(3), [1.0, 0.0, 0.0], [0.0, 5.0, 0.0])
    assert forms.a.shape == forms.q.shape == (1, 3)
    np.testing.assert_allclose(forms.dq[0], [1.0, 0.0, 0.0], atol=1e-15)  # J = I at home


def test_a_model_the_expansion_does_not_fit_uses_rnea(monkeypatch: pytest.MonkeyPatch) -> None:
    dyn = _other_design()
    monkeypatch.setattr(lh, "VERIFY_TOL", -1.0)  # no expansion passes its check
    assert lh.leg_harmonics(dyn) is None
    path = _random_path(dyn, 40, seed=36)
    forms = path_forms(dyn, *path[:3], wrench=WRENCH)
    _against_inverse_dynamics(dyn, forms, path, wrench=WRENCH)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"points": np.zeros((2, 3)), "tangents": np.zeros((3, 3))}, "shapes"),
        ({"points": [[0.0, 0.0, np.nan]]}, "points"),
        ({"tangents": [[1e4, 0.0, 0.0]]}, "tangents"),
        ({"curvatures": [[0.0, 2e9, 0.0]]}, "curvatures"),
        ({"points": "home"}, "points.shape"),
        ({"gravity": (0.0, 9.81)}, "gravity"),
        ({"wrench": (1.0, 2.0)}, "wrench"),
        ({"model": "prototype"}, "model"),
        ({"model": {"leg_length": 0.31}}, "model"),
    ],
)
def test_bad_input_is_named(dyn: og.ClosedLoopDynamics, kwargs: dict, match: str) -> None:
    args = {"model": dyn, "points": np.zeros((1, 3)), "tangents": [[1.0, 0, 0]]}
    args |= {"curvatures": np.zeros((1, 3))} | kwargs
    with pytest.raises(og.InvalidParameterError, match=match):
        path_forms(**args)


def test_the_machine_is_given_as_every_entry_point_takes_it(dyn: og.ClosedLoopDynamics) -> None:
    # the dynamics, their model, the parameters, or None for the prototype: one answer
    path = (np.zeros((2, 3)), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], np.zeros((2, 3)))
    forms = [path_forms(m, *path) for m in (dyn, dyn.closed_loop, og.prototype(), None)]
    for other in forms[1:]:
        for name in ("a", "b", "c"):
            np.testing.assert_array_equal(getattr(other, name), getattr(forms[0], name))


def test_points_beyond_the_slider_limits_are_refused(dyn: og.ClosedLoopDynamics) -> None:
    # slider 1 is lowest on the cube's face x = Q1_x, at y = z = 0 (the derived limit)
    face = np.array([[CUBE_CORNER, 0.0, 0.0]])
    ends = np.array([np.full(3, CUBE_CORNER), np.full(3, CUBE_CORNER + CUBE_SIDE)])
    path_forms(dyn, np.vstack([face, ends]), np.tile([1.0, 0, 0], (3, 1)), np.zeros((3, 3)))
    # a part program's point 1e-9 m beyond them still counts as inside
    path_forms(dyn, face - [1e-9, 0, 0], [[1.0, 0.0, 0.0]], np.zeros((1, 3)))
    with pytest.raises(og.UnreachablePointError, match="outside the limits") as info:
        path_forms(dyn, face - [1e-7, 0, 0], [[1.0, 0.0, 0.0]], np.zeros((1, 3)))
    assert "check_limits" not in str(info.value)  # no option to name here
    with pytest.raises(og.UnreachablePointError):
        path_forms(dyn, [[0.0, PROTOTYPE_LEG, PROTOTYPE_LEG]], [[1.0, 0, 0]], np.zeros((1, 3)))


def test_bad_path_speeds_are_named(dyn: og.ClosedLoopDynamics) -> None:
    forms = path_forms(dyn, np.zeros((2, 3)), np.tile([1.0, 0, 0], (2, 1)), np.zeros((2, 3)))
    for bad in ([1.0, 2.0, 3.0], np.nan, "fast"):
        with pytest.raises(og.InvalidParameterError, match="s_dot"):
            forms.forces(bad, 0.0)
        with pytest.raises(og.InvalidParameterError, match="s_dot"):
            forms.slider_motion(bad, 0.0)


def test_the_function_is_reached_from_the_package_root() -> None:
    """``path_forms`` shares its module's name: the root exports the function, always."""
    import orthoglide_pin.dynamics.path_forms as module

    assert og.path_forms is path_forms is module.path_forms
    assert og.path_forms is path_forms  # also once the module is imported
    assert og.PathForms is og.dynamics.PathForms is PathForms
