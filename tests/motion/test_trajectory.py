"""Tests of the sampled trajectories (orthoglide_pin.motion.trajectory)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.profiles import MotionLimits
from orthoglide_pin.motion.segments import circle_move, dwell, line_move, polygon_moves
from orthoglide_pin.motion.trajectory import DEFAULT_DT, build_trajectory

#: The prototype's sizing figures (paper, section 4) and the cycle's jerk.
V, A, J = 1.2, 20.0, 1000.0
LIMITS = MotionLimits(V, A, J)
#: Rounding of exact identities.
EXACT_TOL = 1e-12
#: Sampling period of the finite-difference checks [s].
FINE_DT = 1e-5
#: Rounding of a finite difference over 2 FINE_DT of values ~1.
FD_ROUNDING = 1e-8
#: Square side [m], circle radius [m], rest between moves [s].
SIDE, RADIUS, REST = 0.1, 0.04, 0.02


def contour() -> list:
    """A square with a circle inscribed, joined by a straight move."""
    square = np.array([[0, 0, 0], [SIDE, 0, 0], [SIDE, SIDE, 0], [0, SIDE, 0]])
    center = np.array([SIDE / 2, SIDE / 2, 0.0])
    circle = circle_move(center, [0, 0, 1], RADIUS, LIMITS.scaled(0.6, 12.0))
    return [
        *polygon_moves(square, LIMITS, label="square"),
        line_move(square[0], circle.start, LIMITS, label="to circle"),
        circle,
    ]


def test_uniform_sampling_covers_the_whole_time() -> None:
    segments = contour()
    traj = build_trajectory(segments, dwell_time=REST)
    T = math.fsum(s.duration for s in segments) + REST * (len(segments) - 1)
    assert traj.duration == pytest.approx(T, rel=EXACT_TOL)
    assert traj.dt == DEFAULT_DT
    np.testing.assert_allclose(np.diff(traj.t), DEFAULT_DT, rtol=1e-9)
    assert traj.t[0] == 0.0
    assert traj.t[-2] < traj.duration <= traj.t[-1]
    assert len(traj) == math.ceil(T / DEFAULT_DT) + 1
    assert traj.p.shape == traj.v.shape == traj.a.shape == traj.j.shape == (len(traj), 3)
    # the end: at rest at the last segment's end
    np.testing.assert_allclose(traj.p[-1], segments[-1].end, atol=EXACT_TOL)
    np.testing.assert_array_equal(traj.v[-1], 0.0)


def test_segments_and_dwells_are_labelled_in_order() -> None:
    segments = contour()
    traj = build_trajectory(segments, dwell_time=REST)
    names = [s.label for s in segments]
    assert traj.labels[0::2] == tuple(names)
    assert set(traj.labels[1::2]) == {"dwell"}
    assert np.all(np.diff(traj.segment) >= 0)
    starts = traj.segment_times[traj.segment]
    assert np.all(starts <= traj.t + EXACT_TOL)
    rest = traj.where("dwell")
    assert rest.sum() == pytest.approx(REST / DEFAULT_DT * (len(segments) - 1), abs=len(segments))
    np.testing.assert_array_equal(traj.v[rest], 0.0)
    np.testing.assert_array_equal(traj.a[rest], 0.0)
    on_circle = traj.p[traj.where("circle")]
    center = np.array([SIDE / 2, SIDE / 2, 0.0])
    np.testing.assert_allclose(np.linalg.norm(on_circle - center, axis=1), RADIUS, rtol=1e-12)
    assert build_trajectory(segments).labels == tuple(names)  # no dwell asked


def test_samples_are_derivatives_of_each_other() -> None:
    traj = build_trajectory(contour(), dt=FINE_DT, dwell_time=REST)
    h = FINE_DT
    a_top, j_top = np.abs(traj.a).max(), np.abs(traj.j).max()
    fd_v = (traj.p[2:] - traj.p[:-2]) / (2 * h)
    fd_a = (traj.v[2:] - traj.v[:-2]) / (2 * h)
    # Lipschitz bounds across phases, segments and dwells alike
    assert np.abs(fd_v - traj.v[1:-1]).max() <= a_top * h / 2 + FD_ROUNDING
    assert np.abs(fd_a - traj.a[1:-1]).max() <= j_top * h / 2 + FD_ROUNDING
    # the path is continuous: no jump between consecutive samples
    step = np.linalg.norm(np.diff(traj.p, axis=0), axis=1)
    assert step.max() <= V * h * (1 + 1e-9)
    # the length run is the sum of the edges, the joining move and the circle
    length = step.sum()
    joining = np.hypot(SIDE / 2 + RADIUS - 0.0, SIDE / 2)
    assert length == pytest.approx(4 * SIDE + joining + 2 * math.pi * RADIUS, rel=1e-6)


def test_bounds_and_trapezoid_variant() -> None:
    for limits in (LIMITS, MotionLimits(V, A)):
        segs = [
            line_move([0, 0, 0], [0.2, 0, 0], limits),
            line_move([0.2, 0, 0], [0.2, 0.2, 0.2], limits),
        ]
        traj = build_trajectory(segs, dt=1e-4)
        assert traj.speed.max() == pytest.approx(V, rel=EXACT_TOL)
        assert np.linalg.norm(traj.a, axis=1).max() == pytest.approx(A, rel=EXACT_TOL)
        # stop-to-stop: the velocity vanishes at the junction (next sample within dt)
        junction = np.searchsorted(traj.t, traj.segment_times[1])
        assert 0.0 < traj.t[junction] - traj.segment_times[1] < traj.dt
        assert traj.speed[junction] <= A * traj.dt
    assert np.abs(traj.j).max() == 0.0  # the trapezoid reports no jerk


def test_one_dwell_alone() -> None:
    traj = build_trajectory([dwell([0.0, 0.01, 0.02], 0.0105)])
    assert len(traj) == 12
    np.testing.assert_array_equal(traj.p, np.tile([0.0, 0.01, 0.02], (12, 1)))


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"segments": []}, "segments"),
        ({"dt": 0.0}, "dt"),
        ({"dt": math.nan}, "dt"),
        ({"dt": 1e-12}, "dt"),
        ({"dwell_time": -0.1}, "dwell_time"),
        (
            {"segments": [line_move([0, 0, 0], [0.1, 0, 0], LIMITS)] * 2},
            "segments[1].start",
        ),
    ],
)
def test_bad_input_names_the_value(kwargs: dict, name: str) -> None:
    args = {"segments": contour(), **kwargs}
    with pytest.raises(InvalidParameterError) as info:
        build_trajectory(args.pop("segments"), **args)
    assert info.value.name == name


def test_unknown_label() -> None:
    traj = build_trajectory(contour())
    with pytest.raises(InvalidParameterError, match="square 1"):
        traj.where("triangle")
