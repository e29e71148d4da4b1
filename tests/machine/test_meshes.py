"""CAD meshes per kind of part: validation, the URDF's visuals, the cache and loading."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.machine import description
from orthoglide_pin.machine.parts import PART_KINDS

#: Positions compared after the URDF's text round trip [m].
COM_TOL = 1e-12


@pytest.fixture
def stl(tmp_path: Path) -> Path:
    path = tmp_path / "cad" / "part.stl"
    path.parent.mkdir()
    trimesh.creation.box((0.09, 0.07, 0.03)).export(path)
    return path


def _links(urdf: str) -> dict[str, ET.Element]:
    return {link.get("name", ""): link for link in ET.fromstring(urdf).iter("link")}


def test_a_mesh_replaces_the_primitive_visual_only(stl: Path) -> None:
    mesh = {
        "file": str(stl),
        "scale": [1, 2, 0.5],
        "origin": {"xyz": [0, 0.01, 0], "rpy": [0, 0, 0.3]},
    }
    params = og.prototype().replace(meshes={"carriage": mesh, "small_link": str(stl)})
    links = _links(description.render_urdf(params))
    for leg in (1, 2, 3):
        visual = links[f"leg{leg}_carriage"].find("visual")
        assert visual is not None
        el = visual.find("geometry/mesh")
        assert el is not None and el.get("filename") == str(stl)
        assert [float(v) for v in el.get("scale", "").split()] == [1.0, 2.0, 0.5]
        origin = visual.find("origin")
        assert origin is not None
        assert [float(v) for v in origin.get("xyz", "").split()] == [0.0, 0.01, 0.0]
        assert links[f"leg{leg}_carriage"].find("collision/geometry/box") is not None
        # The end link's part frame is its centre, w/2 along -y from its joint.
        end = links[f"leg{leg}_end_link"].find("visual/origin")
        assert end is not None
        assert float(end.get("xyz", "").split()[1]) == pytest.approx(-0.04, abs=COM_TOL)
    assert links["leg1_bar_a"].find("visual/geometry/cylinder") is not None
    # A mesh is geometry, not mass: the inertial model is the prototype's.
    for a, b in zip(inertia_table(params).bodies, inertia_table().bodies, strict=True):
        assert a.mass == b.mass
        assert np.array_equal(a.com, b.com) and np.array_equal(a.inertia, b.inertia)


@pytest.mark.parametrize(
    ("entry", "fragment"),
    [
        ({"file": "missing.stl"}, "an existing file"),
        ({"file": "part.step"}, "STL, OBJ or DAE"),
        ({"file": "STL", "scale": 0}, "positive"),
        ({"file": "STL", "scale": [1, 1, float("nan")]}, "finite"),
        ({"file": "STL", "origin": {"xyz": [0, 0, float("inf")]}}, "finite"),
        ({"file": "STL", "origin": {"xyz": [0, 0]}}, "three finite numbers"),
        ({"file": "STL", "origin": {"xyz": [0, 0, 1e3]}}, "within 10 m"),
        ({"file": "STL", "origin": {"rpy": [0, 0, 1e9]}}, "within 4 pi"),
        ({"file": "STL", "scale": 1e6}, "at most 1000"),
        ({"file": "STL", "colour": "red"}, "one of file, scale, origin"),
        ({"file": "$(find x)/part.stl"}, "without control characters"),
    ],
)
def test_bad_meshes_are_refused_by_name(
    stl: Path, entry: dict[str, object], fragment: str
) -> None:
    entry = {k: (str(stl) if v == "STL" else v) for k, v in entry.items()}
    with pytest.raises(og.InvalidParameterError, match=r"meshes\.bar") as info:
        og.prototype().replace(meshes={"bar": entry})
    assert fragment in str(info.value)


def test_an_unknown_part_kind_is_refused(stl: Path) -> None:
    with pytest.raises(og.InvalidParameterError, match="one of carriage, bar, small_link"):
        og.prototype().replace(meshes={"rail": str(stl)})


def test_the_cache_key_follows_the_mesh_content(stl: Path) -> None:
    params = og.prototype().replace(meshes={"platform": str(stl)})
    key = description.cache_key(params)
    assert key != description.cache_key(og.prototype())
    trimesh.creation.box((0.05, 0.05, 0.05)).export(stl)  # edited in place
    assert description.cache_key(params) != key


def test_every_kind_takes_a_mesh_and_the_machine_loads(stl: Path) -> None:
    params = og.prototype().replace(meshes=dict.fromkeys(PART_KINDS, str(stl)))
    robot = og.load_yourdfpy(params)
    assert robot.validate_filenames()
    names = {
        str(g.geometry.mesh.filename)
        for link in robot.robot.links
        for g in link.visuals
        if g.geometry.mesh
    }
    assert names == {str(stl)}
    assert og.load_closed_loop(params).model.nq == 18


@pytest.mark.parametrize("content", ["solid x\nfacet nonsense\n", ""])
def test_a_mesh_without_triangles_is_refused(content: str, tmp_path: Path) -> None:
    bad = tmp_path / "bad.stl"
    bad.write_text(content)
    with pytest.raises(og.InvalidParameterError, match="a mesh with triangles"):
        og.prototype().replace(meshes={"carriage": str(bad)})
