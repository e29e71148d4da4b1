"""CAD meshes per kind of part: validation, the URDF's visuals, the cache and loading."""

from __future__ import annotations

import struct
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.machine import description, meshes
from orthoglide_pin.machine.parts import PART_KINDS
from tests.conftest import run

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


# ------------------------------------------------------------------- caps
def _refusal(entry: object, kind: str = "bar") -> str:
    """The one-line message refusing a mesh entry; it names the mesh parameter."""
    with pytest.raises(og.InvalidParameterError) as info:
        og.prototype().replace(meshes={kind: entry})
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"invalid meshes.{kind}.")
    return message


@pytest.fixture
def no_loading(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if trimesh is asked to load a file (the caps come first)."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the mesh was loaded before its caps were checked")

    monkeypatch.setattr(trimesh, "load", refuse)


def test_a_file_over_the_size_cap_is_refused_before_it_is_read(
    tmp_path: Path, no_loading: None
) -> None:
    big = tmp_path / "big.stl"
    with big.open("wb") as fh:  # sparse: 200 MB announced, nothing written
        fh.write(b"\0" * 80 + struct.pack("<I", (200_000_000 - 84) // 50))
        fh.truncate(200_000_000)
    message = _refusal(str(big))
    assert f"at most {meshes.MAX_MESH_BYTES} bytes (64 MiB; it has 200000000)" in message


@pytest.mark.parametrize(
    ("count", "size"),
    [
        (2**32 - 1, 84),  # a header announcing 4 billion triangles, and nothing else
        (meshes.MAX_MESH_TRIANGLES + 1, 84 + 50 * (meshes.MAX_MESH_TRIANGLES + 1)),
    ],
)
def test_a_binary_stl_announcing_too_many_triangles_is_refused_unread(
    tmp_path: Path, no_loading: None, count: int, size: int
) -> None:
    path = tmp_path / "many.stl"
    with path.open("wb") as fh:
        fh.write(b"binary header".ljust(80, b"\0") + struct.pack("<I", count))
        fh.truncate(size)
    message = _refusal({"file": str(path), "scale": 0.001})
    assert f"at most {meshes.MAX_MESH_TRIANGLES} triangles (it announces {count})" in message


def test_an_obj_with_too_many_faces_or_vertices_is_refused_unread(
    tmp_path: Path, no_loading: None
) -> None:
    path = tmp_path / "many.obj"
    n = meshes.MAX_MESH_TRIANGLES + 1
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * n)
    assert f"(it announces {n})" in _refusal(str(path))
    n = meshes.MAX_MESH_VERTICES + 1
    path.write_bytes(b"v 0 0 0\n" * n + b"f 1 2 3\n")
    assert f"at most {meshes.MAX_MESH_VERTICES} vertices (it has {n})" in _refusal(str(path))


def test_the_triangle_cap_holds_for_every_format(
    stl: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ascii_stl = stl.with_name("ascii.stl")  # an ASCII STL announces no count: loaded, counted
    trimesh.creation.box((0.09, 0.07, 0.03)).export(ascii_stl, file_type="stl_ascii")
    monkeypatch.setattr(meshes, "MAX_MESH_TRIANGLES", 11)
    assert "at most 11 triangles (it has 12)" in _refusal(str(ascii_stl))


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_a_non_finite_vertex_is_refused_not_dropped(tmp_path: Path, value: str) -> None:
    path = tmp_path / "bad.obj"
    path.write_text(f"v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv {value} 0 0\nf 1 2 3\nf 1 2 4\n")
    assert "expected finite vertices" in _refusal(str(path))


@pytest.mark.parametrize(
    "content",
    [
        "v 0 0 0\nv 0.1 0 0\nv 0.2 0 0\nf 1 2 3\nf 3 2 1\n",  # collinear
        "v 0.1 0.1 0.1\nf 1 1 1\n",  # one point
    ],
)
def test_a_mesh_whose_triangles_have_no_area_is_refused(tmp_path: Path, content: str) -> None:
    path = tmp_path / "flat.obj"
    path.write_text(content)
    assert "expected triangles with area" in _refusal(str(path))


def test_an_all_zero_binary_stl_is_degenerate(tmp_path: Path) -> None:
    path = tmp_path / "zeros.stl"
    with path.open("wb") as fh:
        fh.write(b"\0" * 80 + struct.pack("<I", 1000))
        fh.truncate(84 + 50 * 1000)
    assert "(all 1000 are degenerate" in _refusal(str(path))


def test_a_mesh_in_millimetres_without_its_scale_gets_the_hint(tmp_path: Path) -> None:
    path = tmp_path / "carriage_mm.stl"
    trimesh.creation.box((100.0, 100.0, 40.0)).export(path)
    message = _refusal(str(path), "carriage")
    assert message.startswith("invalid meshes.carriage.scale=1.0: ")
    assert "it reaches 50 m and spans 100 m" in message
    assert message.endswith("did you mean scale: 0.001?")
    built = og.prototype().replace(meshes={"carriage": {"file": str(path), "scale": 0.001}})
    assert built.meshes["carriage"].scale == (0.001,) * 3
    tiny = _refusal({"file": str(path), "scale": 1e-6}, "carriage")
    assert "spans 0.0001 m" in tiny and tiny.endswith("did you mean scale: 0.001?")


def test_huge_coordinates_are_refused_without_overflow(tmp_path: Path) -> None:
    path = tmp_path / "far.obj"
    path.write_text("v 1e300 0 0\nv 0 1e300 0\nv 0 0 0\nf 1 2 3\n")
    message = _refusal(str(path))
    assert "within 10 m of its frame" in message and "reaches 1e+300 m" in message
    far = tmp_path / "offset.obj"  # small, but 50 m away from its frame
    far.write_text("v 50 0 0\nv 50.1 0 0\nv 50 0.1 0\nf 1 2 3\n")
    assert "reaches 50.1 m and spans 0.1 m" in _refusal(str(far))


def test_the_cli_refuses_a_200_mb_mesh_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    big = tmp_path / "big.stl"
    with big.open("wb") as fh:
        fh.truncate(200_000_000)
    config = tmp_path / "design.yaml"
    config.write_text("meshes:\n  platform: {file: big.stl, scale: 1.0e-3}\n")
    out = tmp_path / "view.html"
    code, stdout, err = run(capsys, "view", "--config", str(config), "--static", str(out))
    assert code == 2 and stdout == "" and err.count("\n") == 1
    assert "invalid meshes.platform.file='big.stl'" in err and "64 MiB" in err
    assert not out.exists()
