"""A CAD mesh from end to end: xacro argument, URDF, yourdfpy, Pinocchio, viewer, browser.

The test suite writes its own mesh with trimesh (a flat disc, much wider than
the platform's 80 mm cube), gives it as the platform's mesh, and follows it
through every step; the mesh file is deleted before the page is opened, so the
screenshot shows a mesh that travelled inside the page. The screenshots are
kept in ``artifacts/screenshots/`` (``mesh_platform.png``, ``mesh_none.png``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh
from viewer.test_browser import chromium, count_hue, machine_colours, mean_row, screenshot

import orthoglide_pin as og
from orthoglide_pin.machine import description
from orthoglide_pin.machine.loaders import validated_urdf
from orthoglide_pin.viewer import Viewer

__all__ = ["chromium"]  # the fixture, shared with the browser tests

#: The disc drawn as the platform: radius and thickness [m].
DISC_RADIUS = 0.11
DISC_THICKNESS = 0.012
#: Least growth of the platform's colour on screen with the disc instead of the cube.
MIN_GROWTH = 1.5
#: Largest distance between the disc's drawn vertices and where they belong [m].
PLACEMENT_TOL = 1e-6


@pytest.fixture
def disc(tmp_path: Path) -> Path:
    path = tmp_path / "platform_disc.stl"
    trimesh.creation.cylinder(radius=DISC_RADIUS, height=DISC_THICKNESS, sections=48).export(path)
    return path


def test_a_platform_mesh_goes_from_xacro_to_the_screen(
    chromium: str, disc: Path, tmp_path: Path
) -> None:
    lift = 0.02  # the disc's origin, above the platform centre [m]
    mesh = {"file": str(disc), "scale": 1.0, "origin": {"xyz": [0, 0, lift], "rpy": [0, 0, 0]}}
    params = og.prototype().replace(meshes={"platform": mesh})

    # xacro argument -> URDF.
    assert description.xacro_args(params)["platform_mesh"] == str(disc)
    urdf = description.render_urdf(params)
    platform = next(
        link for link in ET.fromstring(urdf).iter("link") if link.get("name") == "platform"
    )
    element = platform.find("visual/geometry/mesh")
    assert element is not None and element.get("filename") == str(disc)

    # yourdfpy: valid, and the file name resolves.
    robot = validated_urdf(urdf, build_scene=True)
    assert robot.validate_filenames()

    # Pinocchio reads the mesh visual; the viewer draws its triangles where it belongs.
    model = og.load_closed_loop(params)
    viewer = Viewer(model)
    visual = next(v for v in viewer.drawing.visuals if v.link == "platform")
    assert (visual.shape, visual.mesh, visual.size) == ("mesh", str(disc), (1.0, 1.0, 1.0))
    home = model.solve(np.zeros(3)).q
    placement = viewer.drawing.placements(home)[viewer.drawing.visuals.index(visual)]
    centre = -np.asarray(params.tool_offset)
    np.testing.assert_allclose(
        placement[:3, 3], centre + np.array([0.0, 0.0, lift]), atol=PLACEMENT_TOL
    )

    # The static page carries the mesh: it opens with the file gone.
    page = viewer.save_html(tmp_path / "mesh.html")
    plain = Viewer(og.load_closed_loop(og.prototype())).save_html(tmp_path / "plain.html")
    disc.unlink()
    assert str(disc) not in page.read_text()
    with_mesh = screenshot(chromium, page.as_uri(), "mesh_platform")
    without = screenshot(chromium, plain.as_uri(), "mesh_none")
    green = machine_colours(viewer)["platform"]
    grown = count_hue(with_mesh, green) / max(count_hue(without, green), 1)
    assert grown > MIN_GROWTH, f"the disc covers only {grown:.2f}x the cube's pixels"
    # Still the machine, upright: the carriages' colour above the platform's.
    carriage = machine_colours(viewer)["carriage"]
    assert mean_row(with_mesh, green) > mean_row(with_mesh, carriage)


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".dae"])
def test_each_mesh_format_is_drawn_scaled_and_inline(suffix: str, tmp_path: Path) -> None:
    """Pinocchio places it, trimesh reads it, its scaled vertices travel in the scene."""
    path = tmp_path / f"ball{suffix}"
    trimesh.creation.icosphere(subdivisions=1, radius=0.05).export(path)
    scale = (1.0, 2.0, 0.5)
    params = og.prototype().replace(meshes={"spindle": {"file": str(path), "scale": list(scale)}})
    drawing = Viewer(og.load_closed_loop(params)).drawing
    (k,) = [i for i, v in enumerate(drawing.visuals) if v.shape == "mesh"]
    assert drawing.visuals[k].link == "spindle" and drawing.visuals[k].size == scale
    geometry = drawing.objects()[k]["geometries"][0]
    assert geometry["type"] == "BufferGeometry"
    drawn = np.frombuffer(geometry["data"]["attributes"]["position"]["array"].data, np.float32)
    expected = trimesh.load(path, force="mesh").vertices * scale
    np.testing.assert_allclose(drawn.reshape(-1, 3), expected, atol=PLACEMENT_TOL)
