"""A self-contained description folder, loaded as it is by yourdfpy and Pinocchio."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import trimesh
import yourdfpy
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.machine.export import PACKAGE_URDF, package_urdf, write_package

#: Masses of the folder's URDF against the parameters' model (relative).
MASS_RTOL = 1e-12
CAD_BAR = {"mass": 0.3, "com": [0.155, 0.0, 0.0], "inertia": [1e-5, 0, 0, 2.5e-3, 0, 2.5e-3]}


@pytest.fixture
def cad_params(tmp_path: Path) -> og.OrthoglideParams:
    cad = tmp_path / "cad"
    cad.mkdir()
    trimesh.creation.box((0.1, 0.1, 0.04)).export(cad / "Carriage.STL")
    trimesh.creation.icosphere(radius=0.05).export(cad / "platform.obj")
    meshes = {
        "carriage": {"file": str(cad / "Carriage.STL"), "scale": 1.0},
        "platform": {"file": str(cad / "platform.obj"), "origin": {"xyz": [0, 0, 0.01]}},
    }
    return og.prototype().replace(leg_length=0.33, meshes=meshes, inertias={"bar": CAD_BAR})


def test_the_folder_holds_the_urdf_its_loops_and_its_meshes(
    cad_params: og.OrthoglideParams, tmp_path: Path
) -> None:
    urdf = write_package(tmp_path / "pkg", cad_params)
    names = sorted(p.name for p in urdf.parent.iterdir() if not p.name.startswith("."))
    assert names == ["carriage.stl", "orthoglide.loops.yaml", "orthoglide.urdf", "platform.obj"]
    text = urdf.read_text()
    assert 'filename="carriage.stl"' in text and 'filename="platform.obj"' in text
    assert str(tmp_path) not in text  # nothing points outside the folder
    assert (urdf.parent / "carriage.stl").read_bytes() == (
        cad_params.meshes["carriage"].file.read_bytes()
    )
    assert og.read_loops(urdf.with_suffix(".loops.yaml")) == og.load_loops()


def test_another_tool_loads_the_folder_from_elsewhere(
    cad_params: og.OrthoglideParams, tmp_path: Path
) -> None:
    """A fresh Python process, in another directory, with yourdfpy and Pinocchio only."""
    folder = write_package(tmp_path / "pkg", cad_params).parent
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    script = textwrap.dedent(
        f"""
        import sys, pinocchio as pin, yourdfpy
        folder = {str(folder)!r}
        urdf = folder + "/orthoglide.urdf"
        robot = yourdfpy.URDF.load(urdf)  # mesh names resolved against the URDF's folder
        assert robot.validate() and robot.validate_filenames(), robot.errors
        assert len(robot.scene.geometry) > 0
        model = pin.buildModelFromUrdf(urdf)
        geom = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.VISUAL, package_dirs=[folder])
        meshes = sorted({{o.meshPath for o in geom.geometryObjects
                          if type(o.geometry).__name__.startswith("BVH")}})
        print(model.nq, sum(i.mass for i in model.inertias), *meshes)
        assert "orthoglide_pin" not in sys.modules
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=elsewhere, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr[-2000:]
    nq, mass, *meshes = done.stdout.split()
    assert int(nq) == 18
    reference, _ = og.load_pinocchio(cad_params)
    assert float(mass) == pytest.approx(sum(i.mass for i in reference.inertias), rel=MASS_RTOL)
    assert meshes == [str(folder / "carriage.stl"), str(folder / "platform.obj")]


def test_the_folder_is_the_machine_of_the_parameters(cad_params: og.OrthoglideParams) -> None:
    """Same joints, placements and inertias as the parameters' own URDF."""
    a = pin.buildModelFromXML(package_urdf(cad_params))
    b, _ = og.load_pinocchio(cad_params)
    q = np.random.default_rng(7).uniform(-0.1, 0.1, b.nq)
    da, db = a.createData(), b.createData()
    pin.forwardKinematics(a, da, q)
    pin.forwardKinematics(b, db, q)
    for ma, mb in zip(da.oMi, db.oMi, strict=True):
        np.testing.assert_allclose(ma.homogeneous, mb.homogeneous, atol=1e-15)
    for ia, ib in zip(a.inertias, b.inertias, strict=True):
        assert ia.isApprox(ib, 1e-15)


def test_a_directory_it_did_not_write_is_refused(
    cad_params: og.OrthoglideParams, tmp_path: Path
) -> None:
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("keep me")
    with pytest.raises(OutputPathError, match="not empty"):
        write_package(folder, cad_params)
    assert sorted(os.listdir(folder)) == ["notes.txt"]
    write_package(folder, cad_params, force=True)  # forced: the other file is kept
    assert (folder / "notes.txt").read_text() == "keep me"
    assert (folder / PACKAGE_URDF).is_file()


def test_the_folder_can_be_written_again(cad_params: og.OrthoglideParams, tmp_path: Path) -> None:
    write_package(tmp_path / "pkg", cad_params)
    urdf = write_package(tmp_path / "pkg", og.prototype())  # its own folder: rewritten
    assert "<mesh" not in urdf.read_text()
    robot = yourdfpy.URDF.load(str(urdf))
    assert robot.validate() and robot.validate_filenames()


def test_cli_package_dir(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, cad_params: og.OrthoglideParams
) -> None:
    config = cad_params.save(tmp_path / "design.yaml")
    data = run_json(capsys, "urdf", "--config", str(config), "--package-dir", str(tmp_path / "d"))
    assert data["files"] == [
        "carriage.stl",
        "orthoglide.loops.yaml",
        "orthoglide.urdf",
        "platform.obj",
    ]
    assert Path(data["urdf"]) == (tmp_path / "d" / PACKAGE_URDF).resolve()
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "x").write_text("x")
    code, out, err = run(capsys, "urdf", "--package-dir", str(tmp_path / "other"))
    assert (code, out) == (2, "")
    assert err.startswith("orthoglide urdf: error: ") and err.count("\n") == 1
    code, _, err = run(capsys, "urdf", "-o", str(tmp_path / "a.urdf"), "--package-dir", "d2")
    assert code == 2 and "--package-dir" in err
