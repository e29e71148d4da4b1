"""One-line loaders: each is checked against its own library, on two designs."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import orthoglide_pin as og
from orthoglide_pin.machine.loaders import mesh_resolver, validated_urdf

#: yourdfpy's forward kinematics against Pinocchio's, and loop closures in yourdfpy [m].
PLACEMENT_TOL = 1e-12
CLOSURE_TOL = 1e-9
#: A tool point inside the prototype's cube [m].
POINT = (0.03, -0.02, 0.05)
DESIGNS = {"prototype": og.prototype(), "long_leg": og.prototype().replace(leg_length=0.36)}


def _joint_names(model: og.ClosedLoopModel) -> list[str]:
    return [str(n) for n in model.model.names[1:]]


def _assembled(params: og.OrthoglideParams) -> tuple[og.ClosedLoopModel, np.ndarray]:
    model = og.load_closed_loop(params)
    return model, model.solve(og.inverse_kinematics(POINT, params.leg_length)).q


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_pinocchio_loader_gives_the_cut_tree_and_its_loops(name: str) -> None:
    params = DESIGNS[name]
    model, loops = og.load_pinocchio(params)
    assert isinstance(model, pin.Model)
    assert (model.nq, model.nv) == (18, 18)
    assert len(loops.closures) == 5
    assert [c.kind for c in loops.closures].count("frame") == 2
    for joint in loops.actuated_joints:
        assert model.existJointName(joint)
    masses = [model.inertias[j].mass for j in range(1, model.njoints)]
    assert sum(masses) == pytest.approx(og.inertia_table(params).total_moving_mass, rel=1e-12)


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_yourdfpy_places_the_tool_where_pinocchio_closes_the_loops(name: str) -> None:
    params = DESIGNS[name]
    robot = og.load_yourdfpy(params)
    assert isinstance(robot, yourdfpy.URDF)
    assert robot.scene is not None and len(robot.scene.geometry) > 0
    closed, q = _assembled(params)
    _, loops = og.load_pinocchio(params)
    cfg = np.array(
        [
            q[closed.model.joints[closed.model.getJointId(n)].idx_q]
            for n in robot.actuated_joint_names
        ]
    )
    robot.update_cfg(cfg)
    pin.framesForwardKinematics(closed.model, closed.data, q)
    tool = closed.data.oMf[closed.tool_frame].homogeneous
    np.testing.assert_allclose(robot.get_transform(loops.tool_frame), tool, atol=PLACEMENT_TOL)
    np.testing.assert_allclose(tool[:3, 3], POINT, atol=CLOSURE_TOL)
    # The closures hold in yourdfpy too: both frames of each coincide.
    for c in loops.closures:
        a, b = robot.get_transform(c.frame1), robot.get_transform(c.frame2)
        rows = 4 if c.kind == "frame" else 3
        np.testing.assert_allclose(a[:3, 3], b[:3, 3], atol=CLOSURE_TOL, err_msg=c.name)
        if rows == 4:
            np.testing.assert_allclose(a[:3, :3], b[:3, :3], atol=CLOSURE_TOL, err_msg=c.name)


def test_closed_loop_loader_matches_the_model_class() -> None:
    params = DESIGNS["long_leg"]
    loaded = og.load_closed_loop(params)
    assert isinstance(loaded, og.ClosedLoopModel)
    assert loaded.params == params
    direct = og.ClosedLoopModel(params)
    q_a = og.inverse_kinematics(POINT, params.leg_length)
    np.testing.assert_allclose(
        loaded.jacobian(loaded.solve(q_a).q), direct.jacobian(direct.solve(q_a).q), atol=1e-12
    )


def test_loaders_refuse_what_is_not_a_design() -> None:
    for loader in (og.load_pinocchio, og.load_yourdfpy, og.load_closed_loop):
        with pytest.raises(og.InvalidParameterError, match="OrthoglideParams") as info:
            loader("prototype")  # type: ignore[arg-type]
        assert info.value.name == "params"


def _with_visual_mesh(urdf: str, filename: str) -> str:
    mesh = f'<visual><geometry><mesh filename="{filename}"/></geometry></visual>'
    return re.sub(r"(<link name=\"platform\"[^>]*>)", r"\1" + mesh, urdf, count=1)


def test_an_invalid_description_is_named() -> None:
    urdf = og.render_urdf()
    broken = re.sub(r'<joint name="leg2_slider" type="prismatic"', '<joint type="prismatic"', urdf)
    assert broken != urdf
    with pytest.raises(og.DescriptionError, match="name"):
        validated_urdf(broken)
    with pytest.raises(og.DescriptionError, match="does not load"):
        validated_urdf("<robot name='x'><link")


def test_mesh_files_are_resolved_without_ros(tmp_path: Path) -> None:
    import trimesh

    trimesh.creation.box(extents=(0.01, 0.02, 0.03)).export(tmp_path / "part.stl")
    urdf = og.render_urdf()
    resolver = mesh_resolver(tmp_path)
    relative = validated_urdf(_with_visual_mesh(urdf, "part.stl"), resolver=resolver)
    assert relative.validate_filenames()
    uri = (tmp_path / "part.stl").as_uri()
    assert validated_urdf(_with_visual_mesh(urdf, uri)).validate_filenames()
    with pytest.raises(og.DescriptionError, match=r"not found.*missing\.stl"):
        validated_urdf(_with_visual_mesh(urdf, "missing.stl"), resolver=resolver)
    with pytest.raises(og.DescriptionError, match="package://"):
        validated_urdf(_with_visual_mesh(urdf, "package://orthoglide/part.stl"))
    found = validated_urdf(
        _with_visual_mesh(urdf, "package://orthoglide/part.stl"),
        resolver=mesh_resolver(tmp_path, package=lambda s: str(tmp_path / Path(s).name)),
    )
    assert found.validate_filenames()
