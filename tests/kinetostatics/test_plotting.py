"""Tests of the slice heat maps (orthoglide_pin.kinetostatics.plotting)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.plotting import plot_slice
from orthoglide_pin.kinetostatics.workspace import cube_grid, slice_grid, workspace_map

L = 0.31
#: Figure size [in] x resolution [dpi] of plot_slice.
FIGSIZE = (7.0, 6.0)
DPI = 80
#: RGB of the serial curve of leg 3 (matplotlib's tab:blue) and the match tolerance.
LEG3_RGB = np.array([31, 119, 180]) / 255.0
COLOUR_TOL = 0.03
#: Pixels of a drawn circle of radius L (the legend's sample line has far fewer).
MIN_CURVE_PIXELS = 300
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def params() -> og.OrthoglideParams:
    return og.prototype()


def _leg3_pixels(path: Path) -> int:
    import matplotlib.image

    rgb = matplotlib.image.imread(path)[..., :3]
    return int((np.abs(rgb - LEG3_RGB).max(axis=-1) < COLOUR_TOL).sum())


def _plot(params: og.OrthoglideParams, half: float, path: Path) -> Path:
    wmap = workspace_map(slice_grid("z", 0.0, (-half, -half), (half, half), 81), params)
    corner, side = og.prototype_cube(params)
    markers = {"isotropic": np.zeros(3), "Q1": corner, "Q2": corner + side}
    return plot_slice(wmap, "condition", path, cube=(corner, side), markers=markers, dpi=DPI)


def test_writes_a_png_atomically(params: og.OrthoglideParams, tmp_path: Path) -> None:
    out = _plot(params, 1.1 * L, tmp_path / "map.png")
    assert out == tmp_path / "map.png"
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert [p.name for p in tmp_path.iterdir()] == ["map.png"]
    import matplotlib.image

    height, width = matplotlib.image.imread(out).shape[:2]
    assert (width, height) == (round(FIGSIZE[0] * DPI), round(FIGSIZE[1] * DPI))


def test_draws_the_serial_curves_in_view(params: og.OrthoglideParams, tmp_path: Path) -> None:
    # On z = 0 the serial cylinder of leg 3 is the circle x^2 + y^2 = L^2.
    wide = _leg3_pixels(_plot(params, 1.1 * L, tmp_path / "wide.png"))
    narrow = _leg3_pixels(_plot(params, 0.5 * L, tmp_path / "narrow.png"))
    assert wide > MIN_CURVE_PIXELS
    assert narrow < MIN_CURVE_PIXELS / 10


@pytest.mark.parametrize("index", ["psi_min", "psi_max", "manipulability", "parallel_distance"])
def test_every_index(params: og.OrthoglideParams, tmp_path: Path, index: str) -> None:
    wmap = workspace_map(slice_grid("x", 0.05, (-0.2, -0.2), (0.2, 0.2), 21), params)
    out = plot_slice(wmap, index, tmp_path / f"{index}.png", dpi=40)
    assert out.read_bytes()[:8] == PNG_MAGIC


def test_bad_maps_write_nothing(params: og.OrthoglideParams, tmp_path: Path) -> None:
    cube = workspace_map(cube_grid([-0.05] * 3, 0.1, 3), params)
    with pytest.raises(InvalidParameterError):
        plot_slice(cube, "condition", tmp_path / "cube.png")
    plane = workspace_map(slice_grid("z", 0.0, (-0.1, -0.1), (0.1, 0.1), 5), params)
    with pytest.raises(InvalidParameterError):
        plot_slice(plane, "nonsense", tmp_path / "bad.png")
    assert list(tmp_path.iterdir()) == []


def test_no_reachable_point(tmp_path: Path) -> None:
    far = og.prototype()
    wmap = workspace_map(slice_grid("z", 0.3, (0.25, 0.25), (0.3, 0.3), 5), far)
    assert not wmap.reachable.any()
    out = plot_slice(wmap, "condition", tmp_path / "empty.png", dpi=40)
    assert out.read_bytes()[:8] == PNG_MAGIC
