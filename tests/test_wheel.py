"""The built wheel ships the description and renders it from a fresh environment."""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest
from _wheel import ROOT, fresh_environment, run

SHIPPED = (
    "orthoglide_pin/_description/orthoglide.urdf.xacro",
    "orthoglide_pin/_description/orthoglide_leg.xacro",
    "orthoglide_pin/_description/orthoglide_loops.yaml",
    "orthoglide_pin/_description/urdf/orthoglide_prototype.urdf",
    "orthoglide_pin/_description/urdf/orthoglide_prototype.loops.yaml",
    "orthoglide_pin/drives/examples/prototype_drive.yaml",
    "orthoglide_pin/py.typed",
)

pytestmark = pytest.mark.slow


def test_wheel_ships_the_description(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    missing = [n for n in SHIPPED if n not in names]
    assert not missing


def test_wheel_ships_every_subpackage(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    source = ROOT / "orthoglide_pin"
    for init in source.rglob("__init__.py"):
        relative = init.relative_to(ROOT).as_posix()
        assert relative in names
        for module in init.parent.glob("*.py"):
            assert module.relative_to(ROOT).as_posix() in names


def test_wheel_ships_the_materials_and_the_example_cut_files(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    folder = ROOT / "orthoglide_pin" / "machining"
    for data in [folder / "materials.yaml", *(folder / "examples").glob("*.yaml")]:
        assert data.relative_to(ROOT).as_posix() in names


def test_fresh_environment_renders_the_urdf(wheel: Path, tmp_path: Path) -> None:
    env_dir = tmp_path / "fresh"
    python = fresh_environment(wheel, env_dir)
    script = (
        "import orthoglide_pin as og, orthoglide_pin.cli, pinocchio as pin\n"
        "print(og.__file__)\n"
        "print(orthoglide_pin.cli.__file__)\n"
        "print(og.machine.description.xacro_path())\n"
        "text = og.render_urdf(og.prototype(), use_cache=False)\n"
        "print(pin.buildModelFromXML(text).nq)\n"
        "print(text == og.prototype_urdf_path().read_text())\n"
    )
    lines = run(python, "-c", script, cwd=tmp_path).split()
    assert all(line.startswith(str(env_dir)) for line in lines[:3])
    assert lines[3:] == ["18", "True"]
    urdf = tmp_path / "m.urdf"
    run(env_dir / "bin" / "orthoglide", "urdf", "-o", urdf, cwd=tmp_path)
    assert "leg3_bar_b_tip" in urdf.read_text()
    assert "leg3_bar_b_tip" in (tmp_path / "m.loops.yaml").read_text()
    example = run(env_dir / "bin" / "orthoglide", "drive", "--example", cwd=tmp_path)
    assert "rotor_inertia" in example and "motor:" in example
