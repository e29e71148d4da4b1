"""The machine the right way up on screen, the camera, the axis triad and ``--up``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run

import orthoglide_pin as og
from orthoglide_pin.cli import view as view_command
from orthoglide_pin.dynamics.inverse import DEFAULT_GRAVITY
from orthoglide_pin.viewer import Viewer, orientation

ROOT = "/meshcat/orthoglide"
#: meshcat's up direction on screen (its world frame).
SCREEN_UP = np.array([0.0, 0.0, 1.0])
EXACT_TOL = 1e-12
#: The camera sits above the scene's centre: least sine of its elevation.
MIN_ELEVATION_SINE = 0.3


def screen(viewer: Viewer, points: np.ndarray) -> np.ndarray:
    """Machine-frame points [m] where meshcat draws them (through the root node)."""
    root = viewer.scene.transform(ROOT)
    assert root is not None
    return np.asarray(points) @ root[:3, :3].T + root[:3, 3]


def centres(viewer: Viewer, link: str) -> np.ndarray:
    """World centres [m] of the visuals of ``link`` at the shown configuration, (n, 3)."""
    places = viewer.drawing.placements(viewer.configuration)
    rows = [k for k, v in enumerate(viewer.drawing.visuals) if v.link == link]
    assert rows, link
    return places[rows, :3, 3]


@pytest.fixture(scope="module")
def upright(model: og.ClosedLoopModel) -> Viewer:
    return Viewer(model)


def test_gravity_points_down_and_the_vertical_slider_sits_above(upright: Viewer) -> None:
    assert upright.up == "-z"
    root = upright.scene.transform(ROOT)
    assert root is not None
    rotation = root[:3, :3]
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=EXACT_TOL)
    assert np.linalg.det(rotation) == pytest.approx(1.0)  # right-handed on screen
    g = rotation @ np.asarray(DEFAULT_GRAVITY)
    np.testing.assert_allclose(g / np.linalg.norm(g), -SCREEN_UP, atol=EXACT_TOL)
    # The z slider's rail and carriage are above the platform, the tool below it;
    # the x and y sliders are beside it.
    platform = screen(upright, centres(upright, "platform")).mean(axis=0)
    for link in ("leg3_rail", "leg3_carriage"):
        assert (screen(upright, centres(upright, link))[:, 2] > platform[2] + 0.1).all()
    tip = screen(upright, np.zeros((1, 3)))[0]
    assert tip[2] < platform[2]
    for link in ("leg1_carriage", "leg2_carriage"):
        height = screen(upright, centres(upright, link))[:, 2]
        assert np.abs(height - platform[2]).max() < 0.1


@pytest.mark.parametrize("up", orientation.UP_DIRECTIONS)
def test_each_mounting_puts_its_axis_up(model: og.ClosedLoopModel, up: str) -> None:
    r = orientation.up_rotation(up)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=EXACT_TOL)
    assert np.linalg.det(r) == pytest.approx(1.0)
    axis = np.zeros(3)
    axis["xyz".index(up[1])] = 1.0 if up[0] == "+" else -1.0
    np.testing.assert_allclose(r @ axis, SCREEN_UP, atol=EXACT_TOL)
    np.testing.assert_allclose(orientation.up_vector(up), axis, atol=EXACT_TOL)
    # The camera looks from above, from the tool's side (away from every slider).
    d = orientation.view_direction(up)
    assert d @ axis > MIN_ELEVATION_SINE
    horizontal = d - (d @ axis) * axis
    assert (horizontal[np.abs(axis) < 0.5] > 0).all()
    viewer = Viewer(model, up=up.upper().replace("+", "") if up[0] == "+" else up)
    assert viewer.up == up
    root = viewer.scene.transform(ROOT)
    assert root is not None
    np.testing.assert_allclose(root[:3, :3], r, atol=EXACT_TOL)
    # The scene's centre lands at the viewer's origin, which the camera orbits.
    lower, upper = viewer.drawing.bounds(model.neutral())
    corner, side = viewer.workspace_cube()
    centre = 0.5 * (np.minimum(lower, corner) + np.maximum(upper, corner + side))
    np.testing.assert_allclose(screen(viewer, centre[None])[0], 0.0, atol=EXACT_TOL)
    legend = viewer.scene.legend
    assert legend is not None
    vertical = f"{up[1]} axis (up)" if up[0] == "+" else f"{up[1]} axis (down)"
    assert vertical in [item["label"] for item in legend["items"]]


def test_bad_up_is_refused(model: og.ClosedLoopModel) -> None:
    for bad in ("w", "+-z", "", "up"):
        with pytest.raises(og.InvalidParameterError, match="up"):
            orientation.check_up(bad)
    with pytest.raises(og.InvalidParameterError, match=r"-z, \+z"):
        Viewer(model, up="down")


def test_the_triad_is_the_machine_frame(upright: Viewer) -> None:
    _, side = upright.workspace_cube()
    length = 0.5 * side
    legend = upright.scene.legend
    assert legend is not None
    labels = {item["label"]: item["color"] for item in legend["items"]}
    for axis in "xyz":
        shaft = upright.scene.transform(f"{ROOT}/axes/{axis}_shaft")
        head = upright.scene.transform(f"{ROOT}/axes/{axis}_head")
        assert shaft is not None and head is not None
        e = np.eye(3)["xyz".index(axis)]
        # meshcat's cylinders run along their local y: here along the axis, from the origin.
        np.testing.assert_allclose(shaft[:3, 1], e, atol=EXACT_TOL)
        np.testing.assert_allclose(head[:3, 1], e, atol=EXACT_TOL)
        assert np.linalg.det(shaft[:3, :3]) == pytest.approx(1.0)
        tip = head[:3, 3] + 0.5 * orientation.HEAD_LENGTH * length * e
        np.testing.assert_allclose(tip, length * e, atol=EXACT_TOL)
        label = f"{axis} axis" + (" (down)" if axis == "z" else "")
        assert labels[label] == og.viewer.overlays.css(orientation.AXIS_RGB[axis])
    (command,) = [
        c
        for c in upright.scene.commands()
        if c.get("path") == f"{ROOT}/axes/z_head" and c["type"] == "set_object"
    ]
    geometry = command["object"]["geometries"][0]
    assert geometry["radiusTop"] == 0.0 and geometry["height"] == pytest.approx(0.2 * length)


def test_cli_up_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert view_command.UP_DIRECTIONS == orientation.UP_DIRECTIONS
    assert view_command.DEFAULT_UP == orientation.DEFAULT_UP
    target = tmp_path / "side.html"
    code, out, err = run(capsys, "view", "--up=+x", "--static", str(target))
    assert code == 0 and target.is_file(), err
    assert "+x up on screen" in out
    code, out, err = run(capsys, "view", "--json", "--static", str(target))
    assert code == 0 and json.loads(out)["up"] == "-z", err
    code, _, err = run(capsys, "view", "--up", "sideways", "--static", str(target) + "2")
    assert code == 2 and "-z, +z, -x, +x, -y, +y" in err.strip().splitlines()[-1]
    assert not Path(str(target) + "2").exists()
