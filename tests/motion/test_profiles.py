"""Tests of the one-dimensional motion laws (orthoglide_pin.motion.profiles)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.profiles import MotionLimits, s_curve_profile, trapezoidal_profile

#: The prototype's sizing figures (paper, section 4) and the cycle's jerk.
V, A, J = 1.2, 20.0, 1000.0
#: Rounding of closed-form durations, positions and bounds (relative).
EXACT_TOL = 1e-12
#: Step of the central finite differences [s].
FD_STEP = 1e-6
#: Rounding of a finite difference of values of size ~1 over 2 FD_STEP.
FD_ROUNDING = 1e-8
#: Random times per law, and the dense grid for the bounds.
N_RANDOM = 2000
N_DENSE = 200_001

# Each law with its independent closed-form duration; ids say which bounds are reached.
LAWS = {
    "trapezoid": (trapezoidal_profile(0.2, V, A), 0.2 / V + V / A),
    "triangle": (trapezoidal_profile(0.05, V, A), 2.0 * math.sqrt(0.05 / A)),
    "s-curve full": (s_curve_profile(0.2, V, A, J), 0.2 / V + V / A + A / J),
    "s-curve a only": (
        s_curve_profile(0.05, V, A, J),
        A / J + math.sqrt((A / J) ** 2 + 4.0 * 0.05 / A),
    ),
    "s-curve neither": (s_curve_profile(0.01, V, A, J), 4.0 * (0.01 / (2.0 * J)) ** (1 / 3)),
    "s-curve v only": (s_curve_profile(0.4, V, A, 100.0), 0.4 / V + 2.0 * math.sqrt(V / 100.0)),
}
REACHED = {  # (v_max reached, a_max reached)
    "trapezoid": (True, True),
    "triangle": (False, True),
    "s-curve full": (True, True),
    "s-curve a only": (False, True),
    "s-curve neither": (False, False),
    "s-curve v only": (True, False),
}


@pytest.fixture(params=sorted(LAWS))
def law(request: pytest.FixtureRequest) -> tuple[str, og.MotionProfile, float]:
    name = request.param
    return name, *LAWS[name]


def random_times(profile: og.MotionProfile, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(FD_STEP, profile.duration - FD_STEP, N_RANDOM)


def test_duration_matches_the_closed_forms(law: tuple[str, og.MotionProfile, float]) -> None:
    name, profile, expected = law
    assert profile.duration == pytest.approx(expected, rel=EXACT_TOL)
    v_reached, a_reached = REACHED[name]
    assert (profile.peak_velocity == pytest.approx(V, rel=EXACT_TOL)) is v_reached
    assert (profile.peak_acceleration == pytest.approx(A, rel=EXACT_TOL)) is a_reached
    assert profile.peak_velocity <= V * (1 + EXACT_TOL)
    assert profile.peak_acceleration <= A * (1 + EXACT_TOL)
    assert profile.kind == ("trapezoidal" if name in ("trapezoid", "triangle") else "s-curve")


def test_ends_at_rest_at_the_distance(law: tuple[str, og.MotionProfile, float]) -> None:
    _, profile, _ = law
    T, D = profile.duration, profile.distance
    start, end = profile.sample([0.0, T, T + 1.0, -1.0]), profile.sample(T * (1 - 1e-12))
    np.testing.assert_allclose(start.s, [0.0, D, D, 0.0], atol=EXACT_TOL * D)
    np.testing.assert_array_equal(start.v, 0.0)
    assert float(end.s) == pytest.approx(D, rel=EXACT_TOL)
    assert abs(float(end.v)) < 1e-9
    # the peak velocity is reached at mid-course
    mid = profile.sample(T / 2)
    assert float(mid.v) == pytest.approx(profile.peak_velocity, rel=EXACT_TOL)
    assert float(mid.s) == pytest.approx(D / 2, rel=EXACT_TOL)


def test_velocity_and_acceleration_are_the_derivatives(
    law: tuple[str, og.MotionProfile, float],
) -> None:
    name, profile, _ = law
    t, h = random_times(profile, seed=1), FD_STEP
    now, ahead, behind = profile.sample(t), profile.sample(t + h), profile.sample(t - h)
    # v is A-Lipschitz: |central difference - v| <= A h / 2
    fd_v = (ahead.s - behind.s) / (2 * h)
    assert np.max(np.abs(fd_v - now.v)) <= A * h / 2 + FD_ROUNDING
    if name.startswith("s-curve"):  # a is J-Lipschitz, and the jerk is exact inside phases
        jerk = profile.jerk
        fd_a = (ahead.v - behind.v) / (2 * h)
        assert np.max(np.abs(fd_a - now.a)) <= jerk * h / 2 + FD_ROUNDING
        fd_j = (ahead.a - behind.a) / (2 * h)
        assert np.max(np.abs(fd_j)) <= jerk * (1 + 1e-6)
        smooth = np.abs(fd_j - now.j) < 1e-6 * jerk  # all but samples within h of a switch
        assert smooth.mean() > 0.99
    else:  # constant acceleration between the switches
        fd_a = (ahead.v - behind.v) / (2 * h)
        inside = np.abs(fd_a - now.a) < 1e-6 * A
        assert inside.mean() > 0.99
        np.testing.assert_array_equal(now.j, 0.0)


def test_integrals_give_back_velocity_and_position(
    law: tuple[str, og.MotionProfile, float],
) -> None:
    _, profile, _ = law
    t = np.linspace(0.0, profile.duration, N_DENSE)
    sample, dt = profile.sample(t), t[1] - t[0]
    s = np.concatenate(([0.0], np.cumsum((sample.v[1:] + sample.v[:-1]) / 2 * dt)))
    v = np.concatenate(([0.0], np.cumsum((sample.a[1:] + sample.a[:-1]) / 2 * dt)))
    # trapezoidal rule: error <= T max|a'| dt^2 / 12 for s; steps in a cost <= A dt per switch
    assert np.max(np.abs(s - sample.s)) < profile.duration * J * dt**2 + 4 * A * dt**2
    assert np.max(np.abs(v - sample.v)) < 4 * A * dt


def test_bounds_hold_on_a_dense_grid(law: tuple[str, og.MotionProfile, float]) -> None:
    _, profile, _ = law
    sample = profile.sample(np.linspace(-0.01, profile.duration + 0.01, N_DENSE))
    assert sample.v.min() >= 0.0  # monotonic: the axis never goes back
    assert np.diff(sample.s).min() >= -EXACT_TOL * profile.distance
    assert sample.v.max() <= profile.v_max * (1 + EXACT_TOL)
    assert np.abs(sample.a).max() <= profile.a_max * (1 + EXACT_TOL)
    if profile.kind == "s-curve":
        assert np.abs(sample.j).max() <= profile.jerk
    assert sample.v.max() == pytest.approx(profile.peak_velocity, rel=1e-6)


def test_profiles_are_symmetric(law: tuple[str, og.MotionProfile, float]) -> None:
    _, profile, _ = law
    t = random_times(profile, seed=2)
    fwd, back = profile.sample(t), profile.sample(profile.duration - t)
    D = profile.distance
    np.testing.assert_allclose(fwd.s + back.s, D, rtol=0, atol=EXACT_TOL * 10 * D)
    np.testing.assert_allclose(fwd.v, back.v, rtol=0, atol=EXACT_TOL * 10 * V)
    np.testing.assert_allclose(fwd.a, -back.a, rtol=0, atol=EXACT_TOL * 10 * A)


def test_huge_jerk_tends_to_the_trapezoid() -> None:
    # full case: the S-curve lasts exactly a_max / J longer than the trapezoid
    for jerk in (1e3, 1e5, 1e8):
        extra = s_curve_profile(0.2, V, A, jerk).duration - trapezoidal_profile(0.2, V, A).duration
        assert extra == pytest.approx(A / jerk, rel=1e-9)
    s_curve, trapezoid = s_curve_profile(0.2, V, A, 1e8), trapezoidal_profile(0.2, V, A)
    t = np.linspace(0.0, trapezoid.duration, 1001)
    assert np.max(np.abs(s_curve.sample(t).s - trapezoid.sample(t).s)) < V * A / 1e8


def test_zero_distance_is_an_empty_law() -> None:
    for profile in (trapezoidal_profile(0.0, V, A), s_curve_profile(0.0, V, A, J)):
        assert profile.duration == 0.0
        sample = profile.sample([-1.0, 0.0, 1.0])
        for values in sample:
            np.testing.assert_array_equal(values, 0.0)


def test_limits_pick_the_law_and_keep_the_shape() -> None:
    assert MotionLimits(V, A).profile(0.2).kind == "trapezoidal"
    profile = MotionLimits(V, A, J).profile(0.2)
    assert profile.kind == "s-curve"
    assert profile.jerk == J
    assert MotionLimits(V, A, J).scaled(v_max=0.5).profile(0.2).peak_velocity == 0.5
    sample = profile.sample(np.zeros((2, 5)))
    assert all(values.shape == (2, 5) for values in sample)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: trapezoidal_profile(-0.1, V, A), "distance"),
        (lambda: trapezoidal_profile(math.nan, V, A), "distance"),
        (lambda: trapezoidal_profile(0.1, 0.0, A), "v_max"),
        (lambda: trapezoidal_profile(0.1, V, -1.0), "a_max"),
        (lambda: trapezoidal_profile(0.1, True, A), "v_max"),
        (lambda: s_curve_profile(0.1, V, A, 0.0), "jerk"),
        (lambda: s_curve_profile(0.1, V, A, math.inf), "jerk"),
        (lambda: MotionLimits("fast", A), "v_max"),
        (lambda: MotionLimits(V, A, -5.0), "jerk"),
        (lambda: trapezoidal_profile(0.1, V, A).sample([0.0, math.nan]), "t"),
        (lambda: trapezoidal_profile(0.1, V, A).sample("soon"), "t"),
    ],
)
def test_bad_input_names_the_value(call: object, name: str) -> None:
    with pytest.raises(InvalidParameterError) as info:
        call()  # type: ignore[operator]
    assert info.value.name == name
    assert "expected" in str(info.value)
