from __future__ import annotations

import io
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yaml
import yourdfpy

import orthoglide_pin as og
from orthoglide_pin.kinematics.closed_form import inverse_kinematics
from orthoglide_pin.machine import description, urdf_cache
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.legs import LEG_ARGUMENTS, LegGeometry

SOURCE = Path(__file__).resolve().parents[2] / "description"
MASS_TOL = 1e-12
POSITION_TOL = 1e-10


def test_rendered_urdf_is_valid_for_yourdfpy(params: og.OrthoglideParams) -> None:
    robot = yourdfpy.URDF.load(io.BytesIO(og.render_urdf(params).encode()))
    assert robot.validate()
    assert robot.validate_filenames()
    # Every revolute of both parallelogram bars is there: 5 revolutes and 1 slider per leg.
    kinds = [j.type for j in robot.robot.joints]
    assert kinds.count("prismatic") == 3
    assert kinds.count("revolute") == 15


def test_urdf_loads_in_pinocchio_as_a_cut_tree(params: og.OrthoglideParams) -> None:
    model = pin.buildModelFromXML(og.render_urdf(params))
    assert model.nq == model.nv == 18
    loops = og.load_loops()
    for closure in loops.closures:
        assert model.existFrame(closure.frame1) and model.existFrame(closure.frame2)
    for name in loops.actuated_joints:
        assert model.existJointName(name)


def test_loop_data_is_plain_yaml() -> None:
    data = yaml.safe_load((SOURCE / "orthoglide_loops.yaml").read_text())
    assert data["actuated_joints"] == ["leg1_slider", "leg2_slider", "leg3_slider"]
    kinds = sorted(c["type"] for c in data["closures"])
    assert kinds == ["frame", "frame", "point", "point", "point"]


def test_xacro_defaults_are_the_prototype(params: og.OrthoglideParams) -> None:
    text = (SOURCE / "orthoglide.urdf.xacro").read_text()
    defaults = dict(re.findall(r'<xacro:arg name="(\w+)" default="([^"]*)"', text))
    expected = description.xacro_args(params)
    assert set(expected) == set(description.parameter_arguments())
    assert set(defaults) == set(expected) | set(LEG_ARGUMENTS)
    drawing = LegGeometry.drawing(params.leg_length).xacro_args()
    for name in LEG_ARGUMENTS:  # the drawing's legs; a length of "" is the leg_length
        assert defaults[name] == ("" if name.endswith("_length") else drawing[name]), name
    for name, value in expected.items():
        if value == "auto":
            assert defaults[name] == "auto"
        else:  # one number, or several (mesh scale and origin), or none (no CAD)
            given = [float(v) for v in defaults[name].split()]
            assert given == pytest.approx([float(v) for v in value.split()], abs=1e-15), name


def test_shipped_prototype_urdf_is_current(params: og.OrthoglideParams) -> None:
    shipped = og.prototype_urdf_path()
    assert shipped.is_file()
    assert shipped.read_text() == og.render_urdf(params, use_cache=False)


def test_cache_is_keyed_and_atomic(params: og.OrthoglideParams) -> None:
    longer = params.replace(leg_length=0.33)
    path_a = og.urdf_path(params)
    path_b = og.urdf_path(longer)
    assert path_a != path_b
    assert path_a.parent == description.cache_dir()
    assert path_b.read_text() == og.render_urdf(longer)
    assert not list(path_a.parent.glob(".*.tmp"))
    # A second rendering comes from the cache and is identical.
    assert og.render_urdf(longer) == og.render_urdf(longer, use_cache=False)


def test_cache_survives_a_corrupt_memory_miss(params: og.OrthoglideParams) -> None:
    changed = params.replace(parallelogram_width=0.09)
    text = og.render_urdf(changed)
    urdf_cache.forget_all()
    assert og.render_urdf(changed) == text  # read back from disk


def test_write_urdf(tmp_path: Path, params: og.OrthoglideParams) -> None:
    out = og.write_urdf(tmp_path / "sub" / "m.urdf", params)
    assert pin.buildModelFromUrdf(str(out)).nq == 18
    assert sorted(p.name for p in out.parent.iterdir()) == ["m.loops.yaml", "m.urdf"]


def test_the_loops_travel_with_the_urdf(tmp_path: Path, params: og.OrthoglideParams) -> None:
    longer = params.replace(leg_length=0.36)
    out = og.write_urdf(tmp_path / "orthoglide.urdf", longer)
    loops = og.loops_path(out)
    assert loops == tmp_path / "orthoglide.loops.yaml"
    text = loops.read_text()
    assert text.splitlines()[0] == (
        "# orthoglide-pin: loop data of orthoglide.urdf (written with it)."
    )
    # the data beside it is the package's, and names frames and joints of that URDF
    spec = og.read_loops(loops)
    assert spec == og.load_loops()
    model = pin.buildModelFromUrdf(str(out))
    for closure in spec.closures:
        assert model.existFrame(closure.frame1) and model.existFrame(closure.frame2)
    assert all(model.existJointName(j) for j in spec.actuated_joints)
    # a second write replaces both; without loops only the URDF is written
    og.write_urdf(out, params)
    assert loops.read_text() == text
    og.write_urdf(tmp_path / "bare.urdf", params, loops=False)
    assert not (tmp_path / "bare.loops.yaml").exists()
    assert not list(tmp_path.glob(".*"))  # no temporary file left


def test_loops_path_names() -> None:
    assert og.loops_path("a/m.urdf") == Path("a/m.loops.yaml")
    assert og.loops_path("machine") == Path("machine.loops.yaml")
    assert og.loops_path("x.urdf.xml") == Path("x.urdf.loops.yaml")
    for bad in ("", ".", "/"):
        with pytest.raises(og.DescriptionError, match="file name"):
            og.loops_path(bad)


def test_a_foreign_loops_file_is_left_alone(tmp_path: Path, params: og.OrthoglideParams) -> None:
    foreign = tmp_path / "m.loops.yaml"
    foreign.write_text("my own notes\n")
    with pytest.raises(og.DescriptionError, match="left alone"):
        og.write_urdf(tmp_path / "m.urdf", params)
    assert foreign.read_text() == "my own notes\n"
    assert not (tmp_path / "m.urdf").exists()  # nothing half-written either
    with pytest.raises(og.DescriptionError, match="not loop data"):
        og.read_loops(foreign)
    with pytest.raises(og.DescriptionError, match="cannot read"):
        og.read_loops(tmp_path / "absent.yaml")


def test_shipped_prototype_loops_are_current() -> None:
    shipped = og.prototype_urdf_path()
    beside = og.loops_path(shipped)
    assert beside.read_text() == description.loops_text(shipped.name)


def _body_masses(model: pin.Model) -> dict[str, float]:
    return {model.names[j]: model.inertias[j].mass for j in range(1, model.njoints)}


def test_masses_derived_from_density_and_overrides(params: og.OrthoglideParams) -> None:
    masses = _body_masses(pin.buildModelFromXML(og.render_urdf(params)))
    ro, ri = params.bar_radius, params.bar_radius - params.bar_wall
    bar = params.density * math.pi * (ro**2 - ri**2) * params.leg_length
    assert masses["leg2_bar_b_base"] == pytest.approx(bar, abs=MASS_TOL)
    carriage = params.density * math.prod(params.carriage_size)
    assert masses["leg1_slider"] == pytest.approx(carriage, abs=MASS_TOL)
    # the platform's cube in thirds on the end revolutes, the spindle on leg 1's
    third = params.density * params.platform_size**3 / 3
    assert masses["leg1_end_revolute"] == pytest.approx(third + params.spindle_mass, abs=MASS_TOL)
    assert masses["leg2_end_revolute"] == pytest.approx(third, abs=MASS_TOL)
    assert masses["leg3_end_revolute"] == pytest.approx(third, abs=MASS_TOL)

    heavy = params.replace(bar_mass=0.5, carriage_mass=3.0)
    masses = _body_masses(pin.buildModelFromXML(og.render_urdf(heavy)))
    assert masses["leg2_bar_b_base"] == pytest.approx(0.5, abs=MASS_TOL)
    assert masses["leg3_slider"] == pytest.approx(3.0, abs=MASS_TOL)


@pytest.mark.parametrize("changes", [{}, {"leg_length": 0.36, "platform_mass": 0.4}])
def test_every_jointed_body_carries_mass(params: og.OrthoglideParams, changes: dict) -> None:
    """Read in the URDF itself, as an outside simulator does (no merging of fixed links)."""
    root = ET.fromstring(og.render_urdf(params.replace(**changes)))
    links = {link.get("name"): link for link in root.iter("link")}
    moving = [j for j in root.iter("joint") if j.get("type") != "fixed"]
    assert len(moving) == 18
    for joint in moving:
        child = links[joint.find("child").get("link")]
        inertial = child.find("inertial")
        assert inertial is not None, child.get("name")
        assert float(inertial.find("mass").get("value")) > 0.0
        i = inertial.find("inertia")
        matrix = np.array(
            [
                [float(i.get("ixx")), float(i.get("ixy")), float(i.get("ixz"))],
                [float(i.get("ixy")), float(i.get("iyy")), float(i.get("iyz"))],
                [float(i.get("ixz")), float(i.get("iyz")), float(i.get("izz"))],
            ]
        )
        assert np.linalg.eigvalsh(matrix)[0] > 0.0, child.get("name")


def test_longer_leg_changes_the_model(params: og.OrthoglideParams) -> None:
    point = np.array([0.05, -0.04, 0.07])
    longer = params.replace(leg_length=0.36)
    q_short = inverse_kinematics(point, params.leg_length)
    q_long = inverse_kinematics(point, longer.leg_length)
    assert np.max(np.abs(q_long - q_short)) > 1e-3
    model = ClosedLoopModel(longer)
    # The rendered model with the longer leg reaches the point with its own slider values...
    assert np.allclose(model.solve(q_long).tool_position, point, atol=POSITION_TOL)
    # ...and not with the shorter leg's.
    assert np.max(np.abs(model.solve(q_short).tool_position - point)) > 1e-3


def test_description_is_found_through_the_package() -> None:
    assert description.xacro_path().name == "orthoglide.urdf.xacro"
    assert (description.description_files() / "orthoglide_leg.xacro").is_file()


def test_rendering_does_not_depend_on_the_install_location(params: og.OrthoglideParams) -> None:
    text = og.render_urdf(params, use_cache=False)
    assert "autogenerated by xacro" not in text
    assert str(description.xacro_path().parent) not in text
