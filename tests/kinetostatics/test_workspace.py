"""Tests of the workspace maps (orthoglide_pin.kinetostatics.workspace)."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.kinetostatics.transmission import transmission_factors
from orthoglide_pin.kinetostatics.workspace import (
    INDEX_NAMES,
    REACH_MARGIN,
    Grid,
    cube_grid,
    parallel_det_and_gradient,
    slice_grid,
    transmission_factor_map,
    workspace_map,
)

# Paper prototype (section 4): leg length [m], prescribed cube (Q1 corner, side) [m].
L = 0.31
CORNER = -L / math.sqrt(18.0)
SIDE = 0.2
SEED = 20240611

EXACT_TOL = 1e-12
#: Central differences of the parallel determinant: O(h^2) + O(eps / h) [1/m].
FD_STEP = 1e-6
FD_TOL = 1e-7
#: Brute-force sampling of a cylinder: angular step 2*pi/N gives L (1 - cos) error [m].
CYLINDER_TOL = 2e-6
#: First-order parallel distance vs a line search: |error| <= PARALLEL_SLOPE d^2 [1/m].
PARALLEL_SLOPE = 5.0


@pytest.fixture(scope="module")
def params() -> og.OrthoglideParams:
    return og.prototype()


def test_grids() -> None:
    cube = cube_grid([CORNER] * 3, SIDE, 5)
    assert cube.shape == (5, 5, 5)
    assert cube.size == 125
    assert cube.fixed_axis is None
    pts = cube.points()
    np.testing.assert_allclose(pts[0, 0, 0], [CORNER] * 3)
    np.testing.assert_allclose(pts[-1, -1, -1], [CORNER + SIDE] * 3)
    plane = slice_grid("y", 0.05, (-0.1, -0.2), (0.1, 0.2), 11)
    assert plane.shape == (11, 1, 11)
    assert plane.fixed_axis == 1
    np.testing.assert_array_equal(plane.points()[..., 1], 0.05)
    assert plane.points()[..., 2].max() == 0.2
    np.testing.assert_array_equal(plane.point(12), plane.points().reshape(-1, 3)[12])


@pytest.mark.parametrize(
    ("call", "args"),
    [
        (cube_grid, ([0.0, 0.0], 0.1, 5)),
        (cube_grid, ([0.0] * 3, -0.1, 5)),
        (cube_grid, ([0.0] * 3, 0.1, 1)),
        (slice_grid, ("w", 0.0, (0, 0), (1, 1), 5)),
        (slice_grid, ("z", 0.0, (0, 0), (1, -1), 5)),
        (slice_grid, ("z", 0.0, (0, 0, 0), (1, 1, 1), 5)),
        (Grid, ([], [0.0], [0.0])),
        (Grid, ([np.nan], [0.0], [0.0])),
    ],
)
def test_bad_grids(call: object, args: tuple[object, ...]) -> None:
    with pytest.raises(InvalidParameterError):
        call(*args)  # type: ignore[operator]


@pytest.mark.parametrize("shape", [(3, 5, 7), (1, 1, 40), (2, 30, 1), (7, 1, 33)])
@pytest.mark.parametrize("block", [1, 5, 64, 10_000])
def test_blocks_cover_the_grid(shape: tuple[int, int, int], block: int) -> None:
    grid = Grid(*(np.linspace(-0.05, 0.05, n) for n in shape))
    ranges = list(grid.blocks(block))
    assert ranges[0][0] == 0 and ranges[-1][1] == grid.size
    assert all(a[1] == b[0] for a, b in itertools.pairwise(ranges))
    assert all(0 < stop - start <= block for start, stop in ranges)
    expected = transmission_factors(grid.points(), L)
    np.testing.assert_array_equal(transmission_factor_map(grid, L, block=block), expected)


def test_serial_distance_is_the_distance_to_each_cylinder(params: og.OrthoglideParams) -> None:
    grid = cube_grid([-0.1] * 3, 0.25, 3)
    wmap = workspace_map(grid, params)
    # brute force: sample each cylinder p_j^2 + p_k^2 = L^2 finely around the point
    angles = np.linspace(0.0, 2.0 * np.pi, 20_000, endpoint=False)
    points, distances = grid.points().reshape(-1, 3), wmap.serial_distances.reshape(-1, 3)
    for p, dist in zip(points, distances, strict=True):
        for i in range(3):
            j, k = (i + 1) % 3, (i + 2) % 3
            # the nearest cylinder point has the same p_i: search the circle in that plane
            circle = np.zeros((angles.size, 3))
            circle[:, i] = p[i]
            circle[:, j], circle[:, k] = L * np.cos(angles), L * np.sin(angles)
            brute = np.linalg.norm(circle - p, axis=1).min()
            assert dist[i] == pytest.approx(brute, abs=CYLINDER_TOL)
    np.testing.assert_array_equal(wmap.serial_distance, wmap.serial_distances.min(axis=-1))
    np.testing.assert_array_equal(wmap.serial_leg, wmap.serial_distances.argmin(axis=-1) + 1)


def test_parallel_gradient_by_finite_differences() -> None:
    rng = np.random.default_rng(SEED)
    points = CORNER + SIDE * rng.random((50, 3))
    det, grad = parallel_det_and_gradient(points, L)
    fd = np.empty_like(grad)
    for m in range(3):
        step = np.zeros(3)
        step[m] = FD_STEP
        plus = parallel_det_and_gradient(points + step, L)[0]
        minus = parallel_det_and_gradient(points - step, L)[0]
        fd[:, m] = (plus - minus) / (2 * FD_STEP)
    np.testing.assert_allclose(grad, fd, atol=FD_TOL)
    np.testing.assert_allclose(det, np.linalg.det(og.leg_vectors(points, L) / L), rtol=1e-12)


def _first_root(p0: np.ndarray, direction: np.ndarray, reach: float) -> float:
    """Brute force: the first sign change of det along p0 + s d, refined by bisection."""
    s = np.linspace(0.0, reach, 4001)
    det = parallel_det_and_gradient(p0 + s[:, None] * direction, L)[0]
    assert np.isfinite(det).all()  # the line stays within reach of every leg
    change = np.flatnonzero(np.sign(det[1:]) != np.sign(det[:-1]))[0]
    lo, hi = s[change], s[change + 1]
    d_lo = parallel_det_and_gradient((p0 + lo * direction)[None], L)[0][0]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        d_mid = parallel_det_and_gradient((p0 + mid * direction)[None], L)[0][0]
        lo, hi, d_lo = (mid, hi, d_mid) if np.sign(d_mid) == np.sign(d_lo) else (lo, mid, d_lo)
    return 0.5 * (lo + hi)


def _estimate_and_descent(p0: np.ndarray) -> tuple[float, np.ndarray]:
    """First-order distance [m] and the unit direction of decreasing |det|."""
    det, grad = parallel_det_and_gradient(p0[None], L)
    norm = np.linalg.norm(grad[0])
    return abs(det[0]) / norm, -np.sign(det[0]) * grad[0] / norm


@pytest.mark.parametrize("gap", [0.03, 0.01, 0.003])
def test_parallel_distance_towards_a_diagonal_singularity(gap: float) -> None:
    # At (t, t, t), t = -L/sqrt(6), J^-1 = (1 - r) I + r 11^T loses its eigenvalue 1 + 2r:
    # the legs are coplanar. Approach it along the diagonal, from home.
    t_sing = -L / math.sqrt(6.0)
    p0 = np.full(3, t_sing + gap / math.sqrt(3.0))
    estimate, unit = _estimate_and_descent(p0)
    np.testing.assert_allclose(unit, np.full(3, -1 / math.sqrt(3.0)), atol=EXACT_TOL)
    brute = _first_root(p0, unit, 2 * gap)
    assert brute == pytest.approx(gap, rel=1e-9)  # the known singular point
    assert abs(estimate - brute) <= PARALLEL_SLOPE * brute**2  # second order


@pytest.mark.parametrize("gap", [0.03, 0.01, 0.003])
def test_parallel_distance_at_the_double_root(gap: float) -> None:
    # At t = L/sqrt(3) the three legs are parallel (J^-1 = 11^T, rank 1): det has a
    # double root there, so the first-order estimate is half the distance (documented).
    p0 = np.full(3, L / math.sqrt(3.0) - gap / math.sqrt(3.0))
    estimate, unit = _estimate_and_descent(p0)
    np.testing.assert_allclose(unit, np.full(3, 1 / math.sqrt(3.0)), atol=EXACT_TOL)
    assert abs(estimate / gap - 0.5) <= PARALLEL_SLOPE * gap


def test_parallel_distance_off_the_diagonal(params: og.OrthoglideParams) -> None:
    # The sheet of coplanar legs through (t, t, t), t = -L/sqrt(6), crosses z = -0.1 m;
    # keep away from the serial cylinders, where det is not smooth (eta_i -> 0).
    grid = slice_grid("z", -0.1, (-0.3, -0.3), (0.3, 0.3), 61)
    wmap = workspace_map(grid, params)
    dist = wmap.parallel_distance.reshape(-1)
    near = np.flatnonzero((dist < 0.01) & (wmap.serial_distance.reshape(-1) > 0.05))
    assert near.size > 20
    for idx in near[:: near.size // 8]:
        p0 = grid.point(int(idx))
        estimate, unit = _estimate_and_descent(p0)
        assert estimate == float(dist[idx])
        brute = _first_root(p0, unit, 0.03)
        assert abs(estimate - brute) <= PARALLEL_SLOPE * brute**2


def test_map_of_the_prototype_cube(params: og.OrthoglideParams) -> None:
    grid = cube_grid([CORNER] * 3, SIDE, 21)
    wmap = workspace_map(grid, params, block=1000)
    assert wmap.reachable.all()
    np.testing.assert_array_equal(
        wmap.transmission_factors, transmission_factor_map(grid, params.leg_length)
    )
    np.testing.assert_allclose(wmap.condition * wmap.inverse_condition, 1.0, rtol=EXACT_TOL)
    pts = grid.points()
    np.testing.assert_allclose(wmap.manipulability, og.manipulability(pts, L), rtol=EXACT_TOL)
    for name in INDEX_NAMES:
        assert wmap.index(name).shape == grid.shape
    with pytest.raises(InvalidParameterError):
        wmap.index("nonsense")


def test_reachability(params: og.OrthoglideParams) -> None:
    lo, hi = params.slider_lower, params.slider_upper
    grid = slice_grid("z", 0.0, (-1.1 * L, -1.1 * L), (1.1 * L, 1.1 * L), 61)
    wmap = workspace_map(grid, params)
    pts = grid.points().reshape(-1, 3)
    reach = wmap.reachable.reshape(-1)
    assert reach[np.argmin(np.linalg.norm(pts, axis=1))]  # home
    q = inverse_kinematics(pts, L, check=False)
    within = np.all((q >= lo - 1e-12) & (q <= hi + 1e-12), axis=1)
    eta = L - (q - pts)  # eta_i = p_i + L - q_i
    det = wmap.parallel_det.reshape(-1)
    expected = within & (eta >= REACH_MARGIN * L).all(axis=1) & (np.abs(det) >= REACH_MARGIN)
    np.testing.assert_array_equal(reach, expected)
    assert 0 < reach.sum() < reach.size
    out_of_reach = np.isnan(q).any(axis=1)
    assert out_of_reach.any()
    assert np.isnan(wmap.transmission_factors.reshape(-1, 3)[out_of_reach]).all()


def test_csv(params: og.OrthoglideParams, tmp_path: Path) -> None:
    grid = slice_grid("x", 0.01, (-0.05, -0.05), (0.05, 0.05), 4)
    wmap = workspace_map(grid, params)
    path = wmap.save_csv(tmp_path / "map.csv")
    assert [p.name for p in tmp_path.iterdir()] == ["map.csv"]
    lines = path.read_text().splitlines()
    assert lines[0].split(",")[:4] == ["x", "y", "z", "reachable"]
    data = np.genfromtxt(path, delimiter=",", names=True)
    assert data.size == grid.size
    np.testing.assert_allclose(data["condition"], wmap.condition.reshape(-1), rtol=1e-9)
    np.testing.assert_allclose(data["y"], grid.points().reshape(-1, 3)[:, 1], rtol=1e-9)
