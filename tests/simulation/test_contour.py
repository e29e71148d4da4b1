"""The contour error against points put at known distances, and a brute-force search."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.simulation.contour import contour_error

#: The distances found against those built in [m].
DISTANCE_TOL = 1e-12

PROGRAM = (
    "G21 G90 G17 G64 P0.01\nG1 X20 F3000\nG1 Y20\nG2 X40 Y0 I0 J-20\n"
    "G2 X40 Y0 Z-10 I-10 J0\nG0 X0 Y0 Z0\nM30\n"
)


def _path() -> og.Path:
    return og.build_path(og.read_program(PROGRAM))


def test_points_off_the_path_along_its_normal() -> None:
    path = _path()
    rng = np.random.default_rng(2)
    pieces = [p for s in path.sections for p in s.pieces]
    pts, dist = [], []
    for piece in pieces:
        s = rng.uniform(0.05, 0.95, 20) * piece.length
        p, dp, ddp = piece.evaluate(s)
        if piece.is_arc:  # the principal normal, away from the axis: the nearest stays p
            normal = -ddp / np.linalg.norm(ddp, axis=1)[:, None]
            d = rng.uniform(0.0, 5e-6, s.size)
        else:
            other = np.cross(dp, rng.standard_normal((s.size, 3)))
            normal = other / np.linalg.norm(other, axis=1)[:, None]
            d = rng.uniform(0.0, 5e-6, s.size)
        pts.append(p + d[:, None] * normal)
        dist.append(d)
    x, d = np.concatenate(pts), np.concatenate(dist)
    got = contour_error(path, x)
    assert np.abs(got.distance - d).max() < DISTANCE_TOL
    assert got.maximum == pytest.approx(d.max(), abs=DISTANCE_TOL)
    assert got.rms == pytest.approx(np.sqrt(np.mean(d**2)), abs=DISTANCE_TOL)


def test_brute_force_agrees_near_corners_and_the_closed_circle() -> None:
    text = "G21 G90 G17\nG1 X15 F3000\nG2 X15 Y0 I-15 J0\nG1 X30\nM30\n"  # a full circle
    path = og.build_path(og.read_program(text))
    rng = np.random.default_rng(8)
    x = np.array([0.015, 0.0, 0.0]) + rng.normal(0.0, 2e-4, (60, 3))
    got = contour_error(path, x)
    pieces = [p for s in path.sections for p in s.pieces]
    dense = np.concatenate([p.evaluate(np.linspace(0, p.length, 100_001))[0] for p in pieces])
    brute = np.array([np.linalg.norm(dense - xi, axis=1).min() for xi in x])
    spacing = max(p.length for p in pieces) / 100_000
    assert np.all(got.distance <= brute + DISTANCE_TOL)  # never farther than a sample
    assert np.all(brute - got.distance <= spacing)  # and the samples' error is bounded


def test_cut_only_measures_a_point_by_a_rapid_against_the_cut() -> None:
    """A point 1 um off a rapid line, 15 mm from the cut: 1 um to the path, 15 mm to the cut."""
    path = og.build_path(og.read_program("G21 G90\nG0 X20\nG1 Y10 F3000\nM30\n"))
    pieces = [p for s in path.sections for p in s.pieces]
    rapid = next(p for p in pieces if p.feed is None)
    cut = next(p for p in pieces if p.feed is not None)
    on_rapid, along, _ = rapid.evaluate(np.array([0.25 * rapid.length]))
    side = np.cross(along[0], cut.evaluate(np.array([0.0]))[1][0])  # off both lines
    x = on_rapid + 1e-6 * side / np.linalg.norm(side)
    whole = contour_error(path, x)
    assert whole.distance[0] == pytest.approx(1e-6, abs=DISTANCE_TOL) and whole.line[0] == 2
    only = contour_error(path, x, cut_only=True)
    start = cut.evaluate(np.array([0.0]))[0][0]  # the nearest point of the cut: its start
    assert only.distance[0] == pytest.approx(np.linalg.norm(x[0] - start), abs=DISTANCE_TOL)
    assert only.distance[0] > 0.0149 and only.line[0] == 3
    assert np.allclose(only.nearest[0], start, atol=DISTANCE_TOL)


def test_cut_only_refuses_a_path_without_a_feed_move() -> None:
    path = og.build_path(og.read_program("G21 G90\nG0 X20\nM30\n"))
    with pytest.raises(InvalidParameterError, match="without a feed move"):
        contour_error(path, np.zeros((1, 3)), cut_only=True)
    with pytest.raises(InvalidParameterError, match="cut_only"):
        contour_error(path, np.zeros((1, 3)), cut_only=1)  # type: ignore[arg-type]


def test_bad_points_are_refused() -> None:
    with pytest.raises(InvalidParameterError, match="points"):
        contour_error(_path(), np.zeros((4, 2)))
    with pytest.raises(InvalidParameterError, match="path"):
        contour_error("G1 X1", np.zeros((4, 3)))  # type: ignore[arg-type]


def test_brute_force_agrees_near_blended_corners() -> None:
    """Blends are projected on their own parameter: as near as a dense search of them."""
    text = "G21 G90 G64 P0.5\nG1 X10 F3000\nG1 Y10\nG1 X0 Z5\nG1 X-5 Y-5\nM30\n"
    path = og.build_path(og.read_program(text))
    pieces = [p for s in path.sections for p in s.pieces]
    assert any(p.is_blend for p in pieces)
    rng = np.random.default_rng(5)
    corners = np.array([[0.01, 0.0, 0.0], [0.01, 0.01, 0.0], [0.0, 0.01, 0.005]])
    x = corners[rng.integers(0, 3, 90)] + rng.normal(0.0, 4e-4, (90, 3))
    got = contour_error(path, x)
    dense = np.concatenate([p.evaluate(np.linspace(0, p.length, 100_001))[0] for p in pieces])
    brute = np.array([np.linalg.norm(dense - xi, axis=1).min() for xi in x])
    spacing = max(p.length for p in pieces) / 100_000
    assert np.all(got.distance <= brute + DISTANCE_TOL)
    assert np.all(brute - got.distance <= spacing)


def test_the_meter_measures_in_chunks_what_one_call_does() -> None:
    from orthoglide_pin.simulation.contour import ContourMeter

    path = _path()
    rng = np.random.default_rng(4)
    pieces = [p for s in path.sections for p in s.pieces]
    x = np.concatenate([p.evaluate(rng.uniform(0, p.length, 30))[0] for p in pieces])
    x += rng.normal(0.0, 1e-5, x.shape)
    whole = contour_error(path, x)
    meter = ContourMeter(path)
    parts = [meter.measure(chunk) for chunk in np.array_split(x, 7)]
    got = np.concatenate([p.distance for p in parts])  # Newton stops with its group:
    np.testing.assert_allclose(got, whole.distance, rtol=0.0, atol=DISTANCE_TOL)  # to its tol
    assert np.array_equal(np.concatenate([p.line for p in parts]), whole.line)


def test_a_path_longer_than_the_index_is_measured_a_call_at_a_time(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from orthoglide_pin.simulation import contour
    from orthoglide_pin.simulation.contour import ContourMeter

    rows = ["G21 G90 G64 P0.01", "G0 X0 Y0 Z1", "G1 Z0 F3000"]
    for k in range(12):  # a raster: 600 mm of passes 2 mm apart, arcs at their ends
        x, y = (60 if k % 2 == 0 else 0), 2 * k
        rows += [f"G1 X{x} Y{y}", f"G{3 if k % 2 == 0 else 2} X{x} Y{y + 2} R1"]
    rows += ["G0 Z5", "G0 X0 Y0", "M30"]
    path = og.build_path(og.read_program("\n".join(rows) + "\n"))
    pieces = [p for s in path.sections for p in s.pieces]
    rng = np.random.default_rng(6)
    x = np.concatenate([p.evaluate(rng.uniform(0, p.length, 8))[0] for p in pieces])
    x += rng.normal(0.0, 5e-5, x.shape)
    for cut_only in (False, True):
        whole = ContourMeter(path, cut_only=cut_only).measure(x)
        with monkeypatch.context() as patch:
            patch.setattr(contour, "MAX_SAMPLES", 1000)  # the path needs some 3,800
            meter = ContourMeter(path, cut_only=cut_only)
            assert not meter.whole
            parts = [meter.measure(chunk) for chunk in np.array_split(x, 40)]
        got = np.concatenate([p.distance for p in parts])
        np.testing.assert_allclose(got, whole.distance, rtol=0.0, atol=DISTANCE_TOL)
        assert np.array_equal(np.concatenate([p.line for p in parts]), whole.line)


def test_a_call_with_too_many_samples_near_its_points_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from orthoglide_pin.simulation import contour
    from orthoglide_pin.simulation.contour import ContourMeter

    path = og.build_path(og.read_program("G1 X300 F600\nG1 Y1\n"))
    line = path.sections[0].pieces[0]
    side = np.cross(line.u, [0.0, 0.0, 1.0])  # across the 300 mm line, in its plane
    near = line.evaluate(np.array([0.15]))[0] + 5e-4 * side
    monkeypatch.setattr(contour, "MAX_SAMPLES", 1000)  # the path needs some 1,500
    meter = ContourMeter(path)
    assert not meter.whole  # 0.15 m from either end: the line's samples near the point alone
    assert meter.measure(near).distance[0] == pytest.approx(5e-4, abs=DISTANCE_TOL)
    with pytest.raises(InvalidParameterError, match="near the points"):
        meter.measure(near + 0.2 * side)  # the whole path within reach
