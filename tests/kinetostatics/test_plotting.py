"""Tests of the slice heat maps (orthoglide_pin.kinetostatics.plotting)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.plotting import INDEX_LABELS, new_figure, plot_slice
from orthoglide_pin.kinetostatics.workspace import (
    INDEX_NAMES,
    cube_grid,
    slice_grid,
    workspace_map,
)

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
    plot_slice(wmap, "condition", path, cube=(corner, side), markers=markers, dpi=DPI)
    return path


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
    fig = plot_slice(wmap, index, tmp_path / f"{index}.png", dpi=40)
    assert (tmp_path / f"{index}.png").read_bytes()[:8] == PNG_MAGIC
    heat, bar = fig.axes
    assert bar.get_ylabel() == INDEX_LABELS[index]
    assert heat.get_xlabel() == "tool position y [m]" and heat.get_ylabel().endswith("z [m]")


def test_bad_maps_write_nothing(params: og.OrthoglideParams, tmp_path: Path) -> None:
    cube = workspace_map(cube_grid([-0.05] * 3, 0.1, 3), params)
    with pytest.raises(InvalidParameterError):
        plot_slice(cube, "condition", tmp_path / "cube.png")
    plane = workspace_map(slice_grid("z", 0.0, (-0.1, -0.1), (0.1, 0.1), 5), params)
    with pytest.raises(InvalidParameterError):
        plot_slice(plane, "nonsense", tmp_path / "bad.png")
    for vmin, vmax in ((2.0, 1.0), (float("nan"), None), (None, float("inf"))):
        with pytest.raises(InvalidParameterError, match="vm"):
            plot_slice(plane, "condition", tmp_path / "bad.png", vmin=vmin, vmax=vmax)
    assert list(tmp_path.iterdir()) == []


def test_no_reachable_point(tmp_path: Path) -> None:
    far = og.prototype()
    wmap = workspace_map(slice_grid("z", 0.3, (0.25, 0.25), (0.3, 0.3), 5), far)
    assert not wmap.reachable.any()
    plot_slice(wmap, "condition", tmp_path / "empty.png", dpi=40)
    assert (tmp_path / "empty.png").read_bytes()[:8] == PNG_MAGIC


def test_every_index_is_labelled_in_words() -> None:
    assert set(INDEX_LABELS) == set(INDEX_NAMES)
    for name, label in INDEX_LABELS.items():
        assert "_" not in label and label.endswith(("[-]", "[m]")), name


def _mesh_norm(ax: object) -> tuple[float, float]:
    (mesh,) = ax.collections[:1]  # type: ignore[attr-defined]
    return float(mesh.norm.vmin), float(mesh.norm.vmax)


def test_two_designs_share_one_colour_scale(tmp_path: Path) -> None:
    # The prototype and a longer-legged machine, side by side in one figure.
    designs = (og.prototype(), og.prototype().replace(leg_length=0.36))
    plane = slice_grid("z", 0.0, (-0.12, -0.12), (0.12, 0.12), 41)
    maps = [workspace_map(plane, p) for p in designs]
    own = [_mesh_norm(plot_slice(m, "condition").axes[0]) for m in maps]
    assert own[0] != pytest.approx(own[1])  # each alone gets its own range
    lo = min(n[0] for n in own)
    hi = max(n[1] for n in own)
    fig = new_figure(12.0, 5.0)
    axes = fig.subplots(1, 2)
    for ax, m in zip(axes, maps, strict=True):
        assert plot_slice(m, "condition", ax=ax, vmin=lo, vmax=hi) is fig
    assert [_mesh_norm(ax) for ax in axes] == [(lo, hi), (lo, hi)]
    assert len(fig.axes) == 4  # two maps and their colour bars
    # The condition number there is at least 1, and larger for the shorter leg.
    assert lo >= 1.0 and own[0][1] > own[1][1]
    out = tmp_path / "two.png"
    assert plot_slice(maps[0], "psi_min", out, ax=axes[0], dpi=DPI) is fig
    assert out.read_bytes()[:8] == PNG_MAGIC


def test_figures_show_as_images_in_a_notebook() -> None:
    fig = new_figure(3.0, 2.0)
    fig.add_subplot().plot([0, 1], [1, 0])
    assert type(fig) is type(new_figure(1.0, 1.0))  # one class, whatever the call
    png = fig._repr_png_()  # what Jupyter calls to display it
    assert png[:8] == PNG_MAGIC
    from IPython.core.formatters import PNGFormatter

    assert PNGFormatter()(fig) == png
