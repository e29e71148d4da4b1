"""Tests of the closed-form kinematics (orthoglide_pin.kinematics.closed_form)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from orthoglide_pin.exceptions import (
    InvalidParameterError,
    NoAssemblyError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.kinematics.closed_form import (
    PARALLEL_TOL,
    SERIAL_TOL,
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_vectors,
    slider_range_over_cube,
)

# Paper prototype (section 4): leg length, prescribed cube (Q1 corner, side).
L = 0.31
CORNER = -L / math.sqrt(18.0)
SIDE = 0.2
SEED = 20240611

ROUND_TRIP_TOL = 1e-12  # [m]
EXACT_TOL = 1e-13  # closed-form identities, dimensionless or [m]
FD_STEP = 1e-6  # [m]
FD_TOL = 1e-8  # central differences: O(h^2) + O(eps / h)
SVD_TOL = 1e-12
INVERSE_TOL = 1e-12  # J @ J^-1 = I, and against np.linalg.inv
DK_RESIDUAL_TOL = 1e-12  # [m], sphere equations of both assembly modes
BATCH_TOL = 1e-15  # batched vs per-point evaluation
MIN_LEG_EFFECT = 1e-4  # [m], 0.31 m -> 0.35 m moves every slider by more than this
GRID_TOL = 1e-12  # [m], exact cube range vs brute force on grids holding the extremes
STROKE_TOL = 5e-6  # [m], on the slider extremes quoted to 0.01 mm
PAPER_STROKE_TOL = 1e-4  # [m], the paper's stroke 257 mm


def cube_points(n: int, seed: int = SEED) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return CORNER + SIDE * rng.random((n, 3))


def ik_reference(p: np.ndarray, leg: float = L) -> np.ndarray:
    """Per-point IK written independently from the formula of the paper."""
    x, y, z = p
    return np.array(
        [
            x + leg - math.sqrt(leg**2 - y**2 - z**2),
            y + leg - math.sqrt(leg**2 - z**2 - x**2),
            z + leg - math.sqrt(leg**2 - x**2 - y**2),
        ]
    )


def sphere_residuals(p: np.ndarray, q: np.ndarray, leg: float = L) -> np.ndarray:
    """||P - (q_i - L) e_i|| - L for each leg, shape (..., 3)."""
    legs = np.repeat(p[..., None, :], 3, axis=-2)
    for i in range(3):
        legs[..., i, i] -= q[..., i] - leg
    return np.asarray(np.linalg.norm(legs, axis=-1) - leg)


# --- inverse / direct kinematics ------------------------------------------------


def test_round_trip_in_prototype_cube() -> None:
    points = cube_points(10_000)
    q = inverse_kinematics(points, L)
    back = direct_kinematics(q, L)
    assert back.shape == points.shape
    assert np.max(np.abs(back - points)) <= ROUND_TRIP_TOL
    assert np.max(np.abs(sphere_residuals(points, q))) <= EXACT_TOL


def test_ik_matches_reference_formula() -> None:
    points = cube_points(50)
    q = inverse_kinematics(points, L)
    expected = np.array([ik_reference(p) for p in points])
    np.testing.assert_allclose(q, expected, rtol=0, atol=EXACT_TOL)


def test_home() -> None:
    home = np.zeros(3)
    np.testing.assert_array_equal(inverse_kinematics(home, L), np.zeros(3))
    np.testing.assert_allclose(jacobian(home, L), np.eye(3), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(inverse_jacobian(home, L), np.eye(3), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(leg_vectors(home, L), L * np.eye(3), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(direct_kinematics(home, L), home, rtol=0, atol=EXACT_TOL)


def test_direct_kinematics_both_branches() -> None:
    both = direct_kinematics(np.zeros(3), L, branch="all")
    assert both.shape == (2, 3)
    np.testing.assert_allclose(both[0], np.zeros(3), atol=EXACT_TOL)
    np.testing.assert_allclose(both[1], -(2 * L / 3) * np.ones(3), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(
        direct_kinematics(np.zeros(3), L, branch="other"), both[1], rtol=0, atol=0
    )

    q = inverse_kinematics(cube_points(500), L)
    both = direct_kinematics(q, L, branch="all")
    assert both.shape == (500, 2, 3)
    for b in range(2):
        assert np.max(np.abs(sphere_residuals(both[:, b], q))) <= DK_RESIDUAL_TOL
    # the two assembly modes are distinct points inside the cube
    assert np.min(np.linalg.norm(both[:, 0] - both[:, 1], axis=-1)) > 0.1
    np.testing.assert_array_equal(direct_kinematics(q, L), both[:, 0])


def test_longer_leg_changes_slider_values() -> None:
    point = np.array([0.05, 0.02, -0.03])
    q_short = inverse_kinematics(point, L)
    q_long = inverse_kinematics(point, 0.35)
    np.testing.assert_allclose(q_long, ik_reference(point, 0.35), rtol=0, atol=EXACT_TOL)
    assert np.all(np.abs(q_long - q_short) > MIN_LEG_EFFECT)
    # a longer leg leans less: each slider sits closer to p_i
    assert np.all(np.abs(q_long - point) < np.abs(q_short - point))


def test_leg_vectors_have_leg_length_and_close_the_loops() -> None:
    points = cube_points(200)
    legs = leg_vectors(points, L)
    np.testing.assert_allclose(np.linalg.norm(legs, axis=-1), L, rtol=0, atol=EXACT_TOL)
    q = inverse_kinematics(points, L)
    for i in range(3):  # P - B_i with B_i = (q_i - L) e_i
        expected = points.copy()
        expected[:, i] -= q[:, i] - L
        np.testing.assert_allclose(legs[:, i], expected, rtol=0, atol=EXACT_TOL)


# --- Jacobians ----------------------------------------------------------------------


def test_jacobians_against_finite_differences() -> None:
    points = cube_points(200, seed=SEED + 1)
    j_inv = inverse_jacobian(points, L)
    j = jacobian(points, L)
    eye = np.broadcast_to(np.eye(3), j.shape)
    np.testing.assert_allclose(j @ j_inv, eye, rtol=0, atol=INVERSE_TOL)
    np.testing.assert_allclose(j_inv @ j, eye, rtol=0, atol=INVERSE_TOL)
    q = inverse_kinematics(points, L)
    for c in range(3):
        step = np.zeros(3)
        step[c] = FD_STEP
        # dq/dp_c: column c of J^-1
        dq = (inverse_kinematics(points + step, L) - inverse_kinematics(points - step, L)) / (
            2 * FD_STEP
        )
        np.testing.assert_allclose(j_inv[:, :, c], dq, rtol=0, atol=FD_TOL)
        # dP/dq_c: column c of J, through the direct kinematics
        dp = (direct_kinematics(q + step, L) - direct_kinematics(q - step, L)) / (2 * FD_STEP)
        np.testing.assert_allclose(j[:, :, c], dp, rtol=0, atol=FD_TOL)


def test_jacobian_matches_numpy_inverse() -> None:
    points = cube_points(1000, seed=SEED + 2)
    np.testing.assert_allclose(
        jacobian(points, L), np.linalg.inv(inverse_jacobian(points, L)), rtol=0, atol=INVERSE_TOL
    )


def test_isotropy_along_the_diagonal() -> None:
    for t in np.linspace(-L / math.sqrt(18.0), L / math.sqrt(6.0), 21):
        s = math.sqrt(L**2 - 2 * t**2)
        expected = np.sort([1 / (1 + 2 * t / s), 1 / (1 - t / s), 1 / (1 - t / s)])
        sv = np.sort(np.linalg.svd(jacobian(np.full(3, t), L), compute_uv=False))
        np.testing.assert_allclose(sv, expected, rtol=0, atol=SVD_TOL)
    q1 = np.linalg.svd(jacobian(np.full(3, -L / math.sqrt(18.0)), L), compute_uv=False)
    q2 = np.linalg.svd(jacobian(np.full(3, L / math.sqrt(6.0)), L), compute_uv=False)
    assert q1.max() == pytest.approx(2.0, abs=SVD_TOL)
    assert q2.min() == pytest.approx(0.5, abs=SVD_TOL)
    # Q2 also reaches the upper bound: both factors 2 and 0.5 there
    assert q2.max() == pytest.approx(2.0, abs=SVD_TOL)


def test_ik_and_jacobian_equals_separate_functions() -> None:
    n = 40_000  # spans several internal blocks
    points = cube_points(n, seed=SEED + 3)
    q, j = ik_and_jacobian(points, L)
    assert q.shape == (n, 3) and j.shape == (n, 3, 3)
    np.testing.assert_allclose(q, inverse_kinematics(points, L), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(j, jacobian(points, L), rtol=0, atol=EXACT_TOL)
    np.testing.assert_allclose(
        j, np.linalg.inv(inverse_jacobian(points, L)), rtol=0, atol=INVERSE_TOL
    )
    out_q, out_j = np.empty((n, 3)), np.empty((n, 3, 3))
    rq, rj = ik_and_jacobian(points, L, out_q=out_q, out_J=out_j)
    assert rq is out_q and rj is out_j
    np.testing.assert_array_equal(out_j, j)
    aliased = points.copy()
    ik_and_jacobian(aliased, L, out_q=aliased)  # q may overwrite the points
    np.testing.assert_array_equal(aliased, q)


def test_ik_and_jacobian_rejects_bad_outputs() -> None:
    points = cube_points(10)
    with pytest.raises(InvalidParameterError):
        ik_and_jacobian(points, L, out_q=np.empty((10, 4)))
    with pytest.raises(InvalidParameterError):
        ik_and_jacobian(points, L, out_J=np.empty((10, 3, 3), dtype=np.float32))
    with pytest.raises(InvalidParameterError):
        ik_and_jacobian(points, L, out_J=np.empty((10, 3, 6))[:, :, ::2])


# --- shapes ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "func",
    [inverse_kinematics, direct_kinematics, inverse_jacobian, jacobian, leg_vectors],
)
def test_vectorised_shapes_match_per_point_loop(func: Callable[..., np.ndarray]) -> None:
    grid = cube_points(12, seed=SEED + 4).reshape(3, 4, 3)
    if func is direct_kinematics:
        grid = inverse_kinematics(grid, L)
    batched = func(grid, L)
    tail = batched.shape[2:]
    assert batched.shape[:2] == (3, 4)
    assert func(grid.reshape(12, 3), L).shape == (12, *tail)
    for idx in np.ndindex(3, 4):
        single = func(grid[idx], L)
        assert single.shape == tail
        np.testing.assert_allclose(batched[idx], single, rtol=0, atol=BATCH_TOL)


def test_vectorised_shapes_fused_and_all_branches() -> None:
    grid = cube_points(12, seed=SEED + 5).reshape(3, 4, 3)
    q, j = ik_and_jacobian(grid, L)
    assert q.shape == (3, 4, 3) and j.shape == (3, 4, 3, 3)
    q0, j0 = ik_and_jacobian(grid[1, 2], L)
    assert q0.shape == (3,) and j0.shape == (3, 3)
    np.testing.assert_allclose(j[1, 2], j0, rtol=0, atol=BATCH_TOL)
    both = direct_kinematics(q, L, branch="all")
    assert both.shape == (3, 4, 2, 3)
    np.testing.assert_allclose(both[1, 2], direct_kinematics(q[1, 2], L, branch="all"))


# --- errors -----------------------------------------------------------------------


def test_unreachable_point() -> None:
    with pytest.raises(UnreachablePointError) as info:
        inverse_kinematics([0.0, 0.4, 0.0], L)
    assert info.value.leg == 1
    np.testing.assert_array_equal(info.value.point, [0.0, 0.4, 0.0])
    assert "(0, 0.4, 0)" in str(info.value)
    for func in (inverse_jacobian, jacobian, leg_vectors):
        with pytest.raises(UnreachablePointError):
            func([0.0, 0.4, 0.0], L)
    with pytest.raises(UnreachablePointError) as info:
        ik_and_jacobian([[0.0, 0.0, 0.0], [0.0, 0.0, 0.35]], L)
    assert info.value.leg == 1
    np.testing.assert_array_equal(info.value.point, [0.0, 0.0, 0.35])


def test_first_unreachable_point_of_a_batch_and_nan_maps() -> None:
    points = np.array([[0.01, 0.0, 0.0], [0.0, 0.0, 0.0], [0.3, 0.2, 0.0], [0.0, 0.4, 0.0]])
    with pytest.raises(UnreachablePointError) as info:
        inverse_kinematics(points, L)
    np.testing.assert_array_equal(info.value.point, points[2])
    assert info.value.leg == 3  # x^2 + y^2 = 0.13 > L^2 only for leg 3
    q = inverse_kinematics(points, L, check=False)
    assert np.isnan(q[2, 2]) and np.isfinite(q[2, :2]).all()
    assert np.isnan(q[3, [0, 2]]).all() and np.isfinite(q[3, 1])
    np.testing.assert_allclose(q[:2], inverse_kinematics(points[:2], L), rtol=0, atol=0)


def test_fused_path_reports_the_first_bad_point_of_a_later_block() -> None:
    points = cube_points(40_000, seed=SEED + 6)
    points[30_000] = [0.0, 0.0, 0.35]  # third block, out of reach of legs 1 and 2
    points[35_000] = [np.inf, 0.0, 0.0]
    with pytest.raises(UnreachablePointError) as info:
        ik_and_jacobian(points, L)
    np.testing.assert_array_equal(info.value.point, [0.0, 0.0, 0.35])
    points[30_000] = 0.0
    with pytest.raises(InvalidParameterError):
        ik_and_jacobian(points, L)


def test_unreachable_leg_wins_over_serial_leg_of_the_same_point() -> None:
    # leg 1: y^2 + z^2 = L^2 (serial); leg 2: z^2 + x^2 > L^2 (unreachable)
    with pytest.raises(UnreachablePointError) as info:
        inverse_kinematics([4.0, 0.0, 5.0], 5.0)
    assert info.value.leg == 2


def test_serial_singularity() -> None:
    with pytest.raises(SingularConfigurationError) as info:
        inverse_kinematics([0.0, L, 0.0], L)
    assert info.value.leg == 1 and info.value.kind == "serial"
    with pytest.raises(SingularConfigurationError) as info:
        inverse_jacobian([0.0, 0.0, L], L)
    assert info.value.leg == 1 and info.value.kind == "serial"
    with pytest.raises(SingularConfigurationError) as info:  # x^2 + y^2 = 5^2 exactly
        inverse_kinematics([3.0, 4.0, 0.5], 5.0)
    assert info.value.leg == 3 and info.value.kind == "serial"
    # within SERIAL_TOL of the singularity
    eps = (SERIAL_TOL * L) ** 2 / 4
    with pytest.raises(SingularConfigurationError):
        inverse_kinematics([0.0, math.sqrt(L**2 - eps), 0.0], L)
    # without checks the value is still defined there
    np.testing.assert_allclose(
        inverse_kinematics([0.0, L, 0.0], L, check=False), [L, L, L], rtol=0, atol=EXACT_TOL
    )


def test_parallel_singularity() -> None:
    # On the diagonal at t = L / sqrt(3) the three legs coincide: det = 0.
    t = L / math.sqrt(3.0)
    with pytest.raises(SingularConfigurationError) as info:
        jacobian(np.full(3, t), L)
    assert info.value.kind == "parallel" and info.value.leg is None
    assert PARALLEL_TOL == SERIAL_TOL == 1e-9  # documented values
    # J^-1 stays finite there but is singular (eigenvalue 1 - t/s = 0)
    j_inv = inverse_jacobian(np.full(3, t), L)
    assert abs(np.linalg.det(j_inv)) < EXACT_TOL
    # the fused path applies the same tolerance, reporting the first bad point
    batch = np.array([[0.0, 0.0, 0.0], [t, t, t], [0.0, L, 0.0]])
    with pytest.raises(SingularConfigurationError) as info:
        ik_and_jacobian(batch, L)
    assert info.value.kind == "parallel"
    np.testing.assert_array_equal(info.value.point, batch[1])
    with pytest.raises(SingularConfigurationError) as info:  # legs 1 and 2 coincide
        ik_and_jacobian(batch[[0, 2]], L)
    np.testing.assert_array_equal(info.value.point, [0.0, L, 0.0])


def test_jacobian_at_a_serial_singularity() -> None:
    # leg 3 orthogonal to its slider (x^2 + y^2 = L^2), legs not coplanar:
    # J is finite, its column 3 vanishes (slider 3 cannot move the tool)
    point, leg = np.array([3.0, 4.0, 0.5]), 5.0
    j = jacobian(point, leg)
    np.testing.assert_allclose(j[:, 2], 0.0, rtol=0, atol=EXACT_TOL)
    assert np.linalg.matrix_rank(j) == 2
    np.testing.assert_array_equal(ik_and_jacobian(point, leg)[1], j)
    with pytest.raises(SingularConfigurationError):
        inverse_jacobian(point, leg)


def test_invalid_inputs() -> None:
    for func in (inverse_kinematics, inverse_jacobian, jacobian, leg_vectors, ik_and_jacobian):
        with pytest.raises(InvalidParameterError) as info:
            func([0.0, float("nan"), 0.0], L)
        assert "finite" in str(info.value)
        with pytest.raises(InvalidParameterError) as info:
            func(np.zeros((2, 4)), L)
        assert "(..., 3)" in str(info.value) and "(2, 4)" in str(info.value)
        bad_legs: tuple[Any, ...] = (0.0, -0.31, float("inf"), float("nan"), "abc", True)
        for bad_leg in bad_legs:
            with pytest.raises(InvalidParameterError):
                func(np.zeros(3), bad_leg)
    with pytest.raises(InvalidParameterError):
        inverse_kinematics(0.0, L)
    with pytest.raises(InvalidParameterError):
        direct_kinematics([0.0, np.inf, 0.0], L)
    with pytest.raises(InvalidParameterError) as info:
        direct_kinematics(np.zeros(3), L, branch="upper")
    assert "'working'" in str(info.value) and "'all'" in str(info.value)


def test_no_assembly() -> None:
    # sliders 0.5 m back: the three spheres (centres 0.81 m from O) cannot meet
    with pytest.raises(NoAssemblyError) as info:
        direct_kinematics([-0.5, -0.5, -0.5], L)
    np.testing.assert_array_equal(info.value.q, [-0.5, -0.5, -0.5])
    with pytest.raises(NoAssemblyError) as info:
        direct_kinematics([[0.0, 0.0, 0.0], [-0.5, -0.5, -0.5]], L, branch="all")
    np.testing.assert_array_equal(info.value.q, [-0.5, -0.5, -0.5])
    # q_i = L puts B_i at the origin: the closed form is undefined there
    with pytest.raises(NoAssemblyError) as info:
        direct_kinematics([0.0, L, 0.0], L)
    assert info.value.leg == 2


# --- slider range over a cube ---------------------------------------------------


def face_grid_range(corner: np.ndarray, side: float, n: int = 81) -> tuple[float, float]:
    """Brute-force IK over a dense grid of the six faces (0 added where inside)."""
    axes = []
    for c in corner:
        ax = np.linspace(c, c + side, n)
        if c < 0.0 < c + side:
            ax = np.union1d(ax, [0.0])
        axes.append(ax)
    lo, hi = float("inf"), float("-inf")
    for fixed in range(3):
        for value in (corner[fixed], corner[fixed] + side):
            grids = [axes[k] if k != fixed else np.array([value]) for k in range(3)]
            pts = np.stack(np.meshgrid(*grids, indexing="ij"), axis=-1).reshape(-1, 3)
            q = inverse_kinematics(pts, L)
            lo, hi = min(lo, q.min()), max(hi, q.max())
    return lo, hi


def test_prototype_slider_stroke() -> None:
    q_min, q_max = slider_range_over_cube(L, (CORNER, CORNER, CORNER), SIDE)
    assert q_min == pytest.approx(-0.07307, abs=STROKE_TOL)
    assert q_max == pytest.approx(0.18419, abs=STROKE_TOL)
    assert q_max - q_min == pytest.approx(0.2573, abs=PAPER_STROKE_TOL)  # paper: 257 mm
    assert SIDE / (q_max - q_min) == pytest.approx(0.78, abs=0.005)  # paper: Lw/stroke
    brute = face_grid_range(np.full(3, CORNER), SIDE)
    assert brute == pytest.approx((q_min, q_max), abs=GRID_TOL)


@pytest.mark.parametrize(
    ("corner", "side"),
    [((-0.1, 0.02, -0.05), 0.12), ((0.03, -0.2, -0.01), 0.08), ((-0.15, -0.12, -0.1), 0.1)],
)
def test_slider_range_asymmetric_cubes(corner: tuple[float, float, float], side: float) -> None:
    q_min, q_max = slider_range_over_cube(L, corner, side)
    assert face_grid_range(np.array(corner), side) == pytest.approx((q_min, q_max), abs=GRID_TOL)
    # interior points never exceed the range
    inner = np.array(corner) + side * np.random.default_rng(SEED).random((5000, 3))
    q = inverse_kinematics(inner, L)
    assert q_min <= q.min() and q.max() <= q_max


def test_slider_range_errors() -> None:
    with pytest.raises(UnreachablePointError):
        slider_range_over_cube(L, (-0.2, -0.2, -0.2), 0.5)
    with pytest.raises(InvalidParameterError):
        slider_range_over_cube(L, (0.0, 0.0), 0.1)
    with pytest.raises(InvalidParameterError):
        slider_range_over_cube(L, (0.0, 0.0, 0.0), -0.1)
    with pytest.raises(InvalidParameterError):
        slider_range_over_cube(-L, (0.0, 0.0, 0.0), 0.1)
