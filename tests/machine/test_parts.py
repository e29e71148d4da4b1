"""CAD inertias per kind of part: validation, the URDF's inertials, the design file."""

from __future__ import annotations

import os
import pickle
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import trimesh

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.machine.parts import PartInertia, check_inertia

#: Inertia components compared after the URDF's text round trip [kg.m^2] and [m].
INERTIA_TOL = 1e-12
COM_TOL = 1e-12
#: A CAD platform with an off-centre centre of mass and products of inertia.
CAD_PLATFORM = {
    "mass": 3.2,
    "com": [0.004, -0.006, 0.011],
    "inertia": [[4.1e-3, 2.0e-4, -3.0e-4], [2.0e-4, 3.6e-3, 1.5e-4], [-3.0e-4, 1.5e-4, 5.2e-3]],
}


@pytest.fixture
def stl(tmp_path: Path) -> Path:
    path = tmp_path / "cad" / "part.stl"
    path.parent.mkdir()
    trimesh.creation.box((0.09, 0.07, 0.03)).export(path)
    return path


@pytest.mark.parametrize("index", [0, 1])
def test_a_cad_platform_is_the_sum_of_its_three_shares(index: int) -> None:
    """The thirds, placed by Pinocchio in the machine's axes, add up to the CAD body."""
    base = [og.prototype(), og.prototype().replace(leg_length=0.36, tool_offset=(0.01, 0, 0.18))]
    params = base[index].replace(inertias={"platform": CAD_PLATFORM})
    model, _ = og.load_pinocchio(params)
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    total = pin.Inertia.Zero()
    for leg in (1, 2, 3):
        joint = model.getJointId(f"leg{leg}_end_revolute")
        total += data.oMi[joint].act(model.inertias[joint])
    # Leg 1's end revolute also carries the spindle (a solid cylinder on the tool axis).
    centre = -np.asarray(params.tool_offset)  # the platform centre at home
    spindle = pin.Inertia.FromCylinder(
        params.spindle_mass, params.spindle_radius, params.spindle_length
    )
    tx, ty, _ = params.tool_offset
    at = pin.SE3(np.eye(3), centre + np.array([tx, ty, params.spindle_length / 2]))
    platform = total - at.act(spindle)
    assert platform.mass == pytest.approx(CAD_PLATFORM["mass"], rel=1e-14)
    np.testing.assert_allclose(platform.lever, centre + CAD_PLATFORM["com"], atol=COM_TOL)
    np.testing.assert_allclose(platform.inertia, CAD_PLATFORM["inertia"], atol=INERTIA_TOL)


def test_cad_inertias_of_the_leg_parts_are_in_their_part_frames() -> None:
    bar = PartInertia(0.41, (0.16, 0.001, 0.0), ((2e-5, 0, 0), (0, 3.4e-3, 0), (0, 0, 3.4e-3)))
    link = {"mass": 0.09, "com": [0, 0.002, 0], "inertia": [6e-5, 0, 0, 1e-5, 0, 6e-5]}
    params = og.prototype().replace(inertias={"bar": bar, "small_link": link})
    table = inertia_table(params)
    for body in table.kind("bar"):
        assert body.mass == bar.mass
        np.testing.assert_allclose(body.com, bar.com, atol=COM_TOL)
        np.testing.assert_allclose(body.inertia, bar.matrix(), atol=INERTIA_TOL)
    ends = [b for b in table.kind("small_link") if "end" in b.link]
    assert len(ends) == 3
    for body in ends:  # the centre of an end link is w/2 along -y from its joint
        np.testing.assert_allclose(body.com, [0, -0.04 + 0.002, 0], atol=COM_TOL)
    assert table.kind("carriage")[0].mass == inertia_table().kind("carriage")[0].mass


@pytest.mark.parametrize(
    ("inertia", "fragment"),
    [
        ([[1e-3, 1e-4, 0], [0, 1e-3, 0], [0, 0, 1e-3]], "symmetric"),
        ([1e-3, 0, 0, 1e-3, 0, -1e-4], "positive definite"),
        ([1e-3, 0, 0, 1e-3, 0, 0], "positive definite"),
        ([1e-3, 0, 0, 1e-3, 0, 2.5e-3], "triangle inequality"),
        ([1e-3, 0, 0, 1e-3], "six numbers"),
        ([1e4, 0, 0, 1e4, 0, 1e4], "at most 1000 kg.m^2"),
    ],
)
def test_impossible_inertias_are_refused(inertia: object, fragment: str) -> None:
    entry = {"mass": 1.0, "com": [0, 0, 0], "inertia": inertia}
    with pytest.raises(og.InvalidParameterError, match=r"inertias\.carriage") as info:
        og.prototype().replace(inertias={"carriage": entry})
    assert fragment in str(info.value)


def test_a_thin_rod_is_the_limit_of_the_triangle_inequality() -> None:
    check_inertia("rod", np.diag([1e-3, 1e-3, 2e-3]))  # a flat plate: c = a + b exactly
    with pytest.raises(og.InvalidParameterError):
        check_inertia("rod", np.diag([1e-3, 1e-3, 2.001e-3]))


@pytest.mark.parametrize(
    ("mass", "com", "fragment"),
    [
        (0.0, [0, 0, 0], "positive"),
        (-1.0, [0, 0, 0], "positive"),
        (1.0, [0, float("nan"), 0], "finite"),
        (1.0, [0, 1e300, 0], "within 10 m"),
        (1e9, [0, 0, 0], r"inertias\.spindle\.mass"),
    ],
)
def test_bad_cad_masses_and_centres_are_refused(
    mass: float, com: list[float], fragment: str
) -> None:
    entry = {"mass": mass, "com": com, "inertia": [1e-3, 0, 0, 1e-3, 0, 1e-3]}
    with pytest.raises(og.InvalidParameterError, match=fragment):
        og.prototype().replace(inertias={"spindle": entry})


def test_a_mass_given_twice_is_refused() -> None:
    entry = {"mass": 0.5, "com": [0.155, 0, 0], "inertia": [1e-5, 0, 0, 4e-3, 0, 4e-3]}
    with pytest.raises(og.InvalidParameterError, match="bar_mass"):
        og.prototype().replace(bar_mass=0.4, inertias={"bar": entry})


def test_yaml_round_trip_resolves_meshes_beside_the_file(stl: Path, tmp_path: Path) -> None:
    config = tmp_path / "design.yaml"
    config.write_text(
        "leg_length: 0.33\n"
        "meshes:\n  spindle: {file: cad/part.stl, scale: 0.5}\n"
        "inertias:\n  platform: " + str(CAD_PLATFORM).replace("'", "") + "\n"
    )
    cwd = os.getcwd()
    try:
        os.chdir(stl.parent)  # the mesh is found beside the YAML file, not here
        params = og.OrthoglideParams.load(config)
    finally:
        os.chdir(cwd)
    assert params.meshes["spindle"].file == stl
    assert params.meshes["spindle"].scale == (0.5, 0.5, 0.5)
    again = og.OrthoglideParams.from_yaml(params.to_yaml())
    assert again == params
    assert hash(again) == hash(params)
    assert pickle.loads(pickle.dumps(params)) == params  # for worker processes
