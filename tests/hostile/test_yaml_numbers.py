"""One rule for numbers in every YAML file: ``1e-3`` is a number, as in YAML 1.2 and JSON.

PyYAML follows YAML 1.1 and reads ``1e-3`` (no dot, or an unsigned exponent)
as a string. The package's reader reads it as the number it is, in design and
configuration files, drive files, mesh entries and CAD inertias alike.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import trimesh

import orthoglide_pin as og
from orthoglide_pin._io import parse_yaml_mapping
from orthoglide_pin.drives.motor import load_drive

#: Spellings of 0.0025: PyYAML alone reads all but the last as strings.
SPELLINGS = ("25e-4", "25E-4", "+25e-4", "0.0025e0", "2.5e-3")


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1e-3", 1e-3),
        ("1E3", 1e3),
        ("-2e+2", -200.0),
        ("+.5e1", 5.0),
        ("7.e2", 700.0),
        ("1.0e-3", 1e-3),  # YAML 1.1's own spelling keeps working
        ("12", 12),
    ],
)
def test_the_reader_takes_yaml_12_numbers(text: str, value: float) -> None:
    read = parse_yaml_mapping(f"a: {text}\nb: [{text}, 0]\n", "config")
    assert read == {"a": value, "b": [value, 0]}
    assert type(read["a"]) is type(value)


@pytest.mark.parametrize("text", ["'1e-3'", '"1e-3"', "1e", "e3", "1e-3x", "1e3.5", "0x1e3"])
def test_quoted_values_and_other_words_are_not_numbers(text: str) -> None:
    assert not isinstance(parse_yaml_mapping(f"a: {text}", "config")["a"], float)


@pytest.mark.parametrize("spelling", SPELLINGS)
def test_a_design_file_reads_every_spelling(tmp_path: Path, spelling: str) -> None:
    path = tmp_path / "design.yaml"
    path.write_text(
        f"bar_wall: {spelling}\n"
        f"tool_offset: [0, {spelling}, 2e-1]\n"
        f"carriage_size: [1e-1, 1e-1, 4e-2]\n"
        f"joint_tilt_stiffness: 2e4\n"
    )
    params = og.OrthoglideParams.load(path)
    assert params.bar_wall == 0.0025 and params.tool_offset == (0.0, 0.0025, 0.2)
    assert params.carriage_size == (0.1, 0.1, 0.04) and params.joint_tilt_stiffness == 2e4
    assert og.OrthoglideParams.from_yaml(path.read_text()) == params


def test_mesh_scales_and_origins_follow_the_rule(tmp_path: Path) -> None:
    mesh = tmp_path / "part.stl"
    trimesh.creation.box((90.0, 70.0, 30.0)).export(mesh)  # a file in millimetres
    path = tmp_path / "design.yaml"
    path.write_text(
        "meshes:\n"
        "  carriage:\n"
        "    {file: part.stl, scale: 1e-3, origin: {xyz: [0, 1e-2, 0], rpy: [0, 0, 3e-1]}}\n"
        "  bar: {file: part.stl, scale: [1e-3, 2e-3, 1e-3]}\n"
    )
    meshes = og.OrthoglideParams.load(path).meshes
    assert meshes["carriage"].scale == (1e-3, 1e-3, 1e-3)
    assert meshes["carriage"].xyz == (0.0, 1e-2, 0.0) and meshes["carriage"].rpy == (0, 0, 0.3)
    assert meshes["bar"].scale == (1e-3, 2e-3, 1e-3)
    # The same number as text is accepted as every other numeric field accepts it.
    entry = {"file": str(mesh), "scale": "1e-3"}
    assert og.prototype().replace(meshes={"bar": entry}).meshes["bar"].scale == (1e-3,) * 3


def test_cad_inertias_follow_the_rule(tmp_path: Path) -> None:
    path = tmp_path / "design.yaml"
    path.write_text(
        "bar_mass: null\n"
        "inertias:\n"
        "  bar: {mass: 3.5e-1, com: [1.55e-1, 0, 0], inertia: [1.2e-5, 0, 0, 2.8e-3, 0, 2.8e-3]}\n"
    )
    bar = og.OrthoglideParams.load(path).inertias["bar"]
    assert bar.mass == 0.35 and bar.com == (0.155, 0.0, 0.0)
    assert bar.inertia == ((1.2e-5, 0.0, 0.0), (0.0, 2.8e-3, 0.0), (0.0, 0.0, 2.8e-3))


def test_drive_files_follow_the_rule(tmp_path: Path) -> None:
    path = tmp_path / "drive.yaml"
    path.write_text(
        "drive_train:\n"
        "  lead: 2e-2\n"
        "  screw_diameter: 16e-3\n"
        "  rotor_inertia: 1.2e-4\n"
        "  viscous_coefficient: 1e-4\n"
        "  screw_inertia: 5e-5\n"
        "motor:\n"
        "  name: 1e3 series\n"
        "  rated_torque: 1.27e0\n"
        "  max_speed: 5e3\n"
        "  speed_torque_curve: [[0, 3.8], [3e3, 3.8], [5e3, 2.5e0]]\n"
    )
    drive = load_drive(path)
    train, motor = drive.train, drive.motor
    assert (train.lead, train.screw_diameter, train.rotor_inertia) == (0.02, 0.016, 1.2e-4)
    assert (train.viscous_coefficient, train.screw_inertia) == (1e-4, 5e-5)
    assert motor is not None and motor.name == "1e3 series"
    assert (motor.rated_torque, motor.max_speed) == (1.27, 5000.0)
    assert motor.speed_torque_curve == ((0.0, 3.8), (3000.0, 3.8), (5000.0, 2.5))


def test_a_word_in_a_numeric_field_is_still_refused_by_name(tmp_path: Path) -> None:
    path = tmp_path / "design.yaml"
    path.write_text("leg_length: 1e-3m\n")
    with pytest.raises(og.InvalidParameterError, match=r"invalid leg_length='1e-3m'"):
        og.OrthoglideParams.load(path)
