"""The machine as MJCF (MuJoCo's model format), with its loops, drives and limits.

The MJCF is written from the URDF of the design, one to one:

* every URDF link is a MuJoCo body of the same name, every URDF joint a joint
  of the same name (fixed joints become bodies without a joint); the inertials
  are copied exactly (``fullinertia`` in the body frame), and the compiler is
  told not to merge bodies nor to derive any inertia from the geometry
  (``fusestatic``, ``inertiafromgeom``, ``balanceinertia`` all ``false``);
* the world frame is the machine's (origin at the isotropic point), gravity is
  the package's default :data:`~orthoglide_pin.dynamics.inverse.DEFAULT_GRAVITY`
  (``e3`` points down) or the one given;
* each loop closure of the loop data (:func:`~orthoglide_pin.machine.description.load_loops`)
  is an equality between two sites placed at the origins of its two frames:
  ``connect`` for a 3D point, ``weld`` for a 6D frame;
* each slider joint keeps its stroke as a limit, gets the drive's reflected
  rotor and screw inertia ``(J_rotor + J_screw / n^2) k^2`` as ``armature``
  (``k = 2 pi n / lead`` [rad/m]), its Coulomb friction ``T_c k`` as
  ``frictionloss`` [N] and its viscous friction ``b k^2`` as ``damping``
  [N.s/m]; the screw's efficiency has no MJCF counterpart and is left out;
* one ``motor`` actuator per slider, whose control is the slider force [N],
  limited to the force that the motor's peak torque gives through the screw,
  ``eta k T_peak`` (no limit without motor data);
* the URDF's visuals as geoms that neither collide nor carry mass (its meshes: STL, OBJ).

Numbers are written with :func:`repr` (17 significant digits): MuJoCo's own
writer (``MjSpec.to_xml``) rounds to 6, which moves the inertias by 1e-7. The
drive's terms come from :mod:`~orthoglide_pin.simulation.slider_drive`;
:mod:`~orthoglide_pin.simulation.engine` compiles and writes the document.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import gravity_vector, instance_of, path_argument
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.dynamics.inverse import DEFAULT_GRAVITY
from orthoglide_pin.exceptions import DescriptionError, short_repr
from orthoglide_pin.machine.description import LoopSpec, load_loops, render_urdf
from orthoglide_pin.machine.loaders import mesh_resolver
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.simulation.slider_drive import drive_terms, slider_force_limit

FloatArray = NDArray[np.float64]

#: Simulation time step [s] written in the file (4 kHz, a servo rate).
TIMESTEP: Final = 2.5e-4
#: ``solref`` of the loop equalities: time constant [s] (twice the step, the
#: stiffest MuJoCo keeps stable) and damping ratio.
EQUALITY_SOLREF: Final = (2.0 * TIMESTEP, 1.0)
#: ``solimp`` of the loop equalities: impedance 0.9999 whatever the violation.
EQUALITY_SOLIMP: Final = (0.9999, 0.9999, 0.001, 0.5, 2.0)
#: Constraint solver, its tolerance and iteration budget.
SOLVER: Final[dict[str, str]] = {"solver": "Newton", "tolerance": "1e-12", "iterations": "200"}
#: Mesh formats that MuJoCo reads.
MESH_SUFFIXES: Final = (".stl", ".obj")
#: Site names of a closure: ``<closure>_frame1`` and ``<closure>_frame2``.
SITE_SUFFIXES: Final = ("_frame1", "_frame2")


def _num(value: float) -> str:
    return repr(float(value))


def _vec(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


def _floats(text: str | None, n: int, default: float = 0.0) -> FloatArray:
    if text is None:
        return np.full(n, default)
    values = np.array([float(s) for s in text.split()], dtype=float)
    if values.shape != (n,):
        raise DescriptionError(f"URDF value {short_repr(text)}: expected {n} numbers", text)
    return values


def rpy_matrix(rpy: ArrayLike) -> FloatArray:
    """Rotation ``Rz(y) Ry(p) Rx(r)`` of URDF roll, pitch, yaw [rad], shape (3, 3)."""
    r, p, y = np.asarray(rpy, dtype=float)
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def rpy_quaternion(rpy: ArrayLike) -> FloatArray:
    """Unit quaternion ``(w, x, y, z)`` of URDF roll, pitch, yaw [rad], shape (4,)."""
    r, p, y = 0.5 * np.asarray(rpy, dtype=float)
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    return np.array(
        [
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ]
    )


def _pose(node: ET.Element, origin: ET.Element | None) -> None:
    """Set ``pos`` and ``quat`` of ``node`` from a URDF ``<origin>``."""
    xyz = _floats(None if origin is None else origin.get("xyz"), 3)
    rpy = _floats(None if origin is None else origin.get("rpy"), 3)
    node.set("pos", _vec(xyz))
    if np.any(rpy):
        node.set("quat", _vec(rpy_quaternion(rpy)))


def _inertial(body: ET.Element, link: ET.Element) -> None:
    inertial = link.find("inertial")
    mass_node = None if inertial is None else inertial.find("mass")
    mass = float(mass_node.get("value", "0")) if mass_node is not None else 0.0
    if inertial is None or mass <= 0.0:  # written, so that no reader derives one from geoms
        ET.SubElement(body, "inertial", pos="0 0 0", mass="0", diaginertia="0 0 0")
        return
    inertia_node = inertial.find("inertia")
    origin = inertial.find("origin")
    xyz = _floats(None if origin is None else origin.get("xyz"), 3)
    rot = rpy_matrix(_floats(None if origin is None else origin.get("rpy"), 3))
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    get = (lambda k: float(inertia_node.get(k, "0"))) if inertia_node is not None else None
    i = [get(k) if get is not None else 0.0 for k in names]
    local = np.array([[i[0], i[3], i[4]], [i[3], i[1], i[5]], [i[4], i[5], i[2]]])
    full = rot @ local @ rot.T  # about the centre of mass, in the body frame
    ET.SubElement(
        body,
        "inertial",
        pos=_vec(xyz),
        mass=_num(mass),
        fullinertia=_vec(full[[0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]]),
    )


def _geoms(body: ET.Element, link: ET.Element, assets: ET.Element, mesh_dir: Path | None) -> None:
    resolve = mesh_resolver(mesh_dir)
    for k, visual in enumerate(link.findall("visual")):
        geometry = visual.find("geometry")
        shape = None if geometry is None else next(iter(geometry), None)
        if shape is None:
            continue
        geom = ET.Element("geom", name=f"{link.get('name')}_visual{k}")
        _pose(geom, visual.find("origin"))
        if shape.tag == "box":
            geom.set("type", "box")
            geom.set("size", _vec(0.5 * _floats(shape.get("size"), 3)))
        elif shape.tag == "cylinder":
            geom.set("type", "cylinder")
            radius, length = float(shape.get("radius", "0")), float(shape.get("length", "0"))
            geom.set("size", _vec((radius, 0.5 * length)))
        elif shape.tag == "sphere":
            geom.set("type", "sphere")
            geom.set("size", _num(float(shape.get("radius", "0"))))
        elif shape.tag == "mesh":
            path = Path(resolve(shape.get("filename", "")))
            if path.suffix.lower() not in MESH_SUFFIXES:
                raise DescriptionError(
                    f"mesh {short_repr(str(path))}: MuJoCo reads "
                    f"{', '.join(MESH_SUFFIXES)} meshes only",
                    str(path),
                )
            name = f"{link.get('name')}_mesh{k}"
            ET.SubElement(
                assets,
                "mesh",
                name=name,
                file=str(path),
                scale=_vec(_floats(shape.get("scale"), 3, 1.0)),
            )
            geom.set("type", "mesh")
            geom.set("mesh", name)
        else:
            continue
        material = visual.find("material")
        if material is not None and material.get("name"):
            geom.set("material", str(material.get("name")))
        geom.set("contype", "0")
        geom.set("conaffinity", "0")
        geom.set("group", "1")
        body.append(geom)


def _joint(body: ET.Element, joint: ET.Element, drive: Drive, sliders: set[str]) -> None:
    kind = joint.get("type")
    if kind == "fixed":
        return
    if kind not in ("revolute", "prismatic", "continuous"):
        raise DescriptionError(
            f"URDF joint type {short_repr(kind)} has no MJCF counterpart here", str(kind)
        )
    name = str(joint.get("name"))
    axis = joint.find("axis")
    node = ET.SubElement(
        body,
        "joint",
        name=name,
        type="slide" if kind == "prismatic" else "hinge",
        pos="0 0 0",
        axis=_vec(_floats(None if axis is None else axis.get("xyz"), 3, 1.0)),
    )
    limit = joint.find("limit")
    if kind != "continuous" and limit is not None and "lower" in limit.attrib:
        node.set("limited", "true")
        node.set("range", _vec((float(limit.get("lower", "0")), float(limit.get("upper", "0")))))
    else:
        node.set("limited", "false")
    if name in sliders:
        for key, value in drive_terms(drive).items():
            if key != "force_limit" and value is not None:
                node.set(key, _num(value))


def _tree(robot: ET.Element) -> tuple[dict[str, ET.Element], dict[str, list[ET.Element]], str]:
    links = {str(link.get("name")): link for link in robot.findall("link")}
    children: dict[str, list[ET.Element]] = {name: [] for name in links}
    has_parent: set[str] = set()
    for joint in robot.findall("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            raise DescriptionError(
                f"URDF joint {short_repr(joint.get('name'))} lacks parent or child", ""
            )
        children[str(parent.get("link"))].append(joint)
        has_parent.add(str(child.get("link")))
    roots = [name for name in links if name not in has_parent]
    if len(roots) != 1:
        raise DescriptionError(f"the URDF has {len(roots)} root links, not one", str(roots))
    return links, children, roots[0]


def _options(model: ET.Element, gravity: FloatArray) -> None:
    ET.SubElement(
        model,
        "compiler",
        angle="radian",
        fusestatic="false",
        inertiafromgeom="false",
        balanceinertia="false",
        boundmass="0",
        boundinertia="0",
        autolimits="true",
    )
    option = ET.SubElement(model, "option", timestep=_num(TIMESTEP), gravity=_vec(gravity))
    option.attrib.update(
        {"integrator": "implicitfast", "cone": "elliptic", "jacobian": "dense", **SOLVER}
    )
    default = ET.SubElement(model, "default")
    ET.SubElement(default, "equality", solref=_vec(EQUALITY_SOLREF), solimp=_vec(EQUALITY_SOLIMP))


def mjcf_text(
    params: OrthoglideParams | None = None,
    drive: Drive | None = None,
    *,
    gravity: ArrayLike | None = None,
    mesh_dir: str | Path | None = None,
) -> str:
    """The MJCF of a design (see module).

    Args:
        params: Machine parameters; the prototype when ``None``.
        drive: The drive of each slider; the default drive train without motor
            data (so no force limit) when ``None``.
        gravity: Gravity in the machine frame [m/s^2], shape (3,); the package's
            default ``(0, 0, +9.81)`` when ``None``.
        mesh_dir: Folder against which relative mesh names are resolved (the
            current directory when ``None``).

    Returns:
        The MJCF document.

    Raises:
        InvalidParameterError: A drive that is not a :class:`Drive`, a gravity that is
            not three finite numbers of magnitude at most 1000 m/s^2.
        DescriptionError: A mesh MuJoCo cannot read, a URDF this cannot translate.
    """
    if drive is None:
        drive = Drive()
    instance_of("drive", drive, Drive, "a Drive (orthoglide_pin.load_drive)")
    g = gravity_vector(DEFAULT_GRAVITY if gravity is None else gravity)
    loops = load_loops()
    robot = ET.fromstring(render_urdf(params))
    links, children, root = _tree(robot)
    model = ET.Element("mujoco", model=str(robot.get("name", "orthoglide")))
    _options(model, g)
    assets = ET.SubElement(model, "asset")
    for material in robot.findall("material"):
        color = material.find("color")
        rgba = "0.5 0.5 0.5 1" if color is None else str(color.get("rgba", "0.5 0.5 0.5 1"))
        ET.SubElement(assets, "material", name=str(material.get("name")), rgba=rgba)
    world = ET.SubElement(model, "worldbody")
    sites = _closure_sites(loops)
    sliders = set(loops.actuated_joints)
    mdir = None if mesh_dir is None else Path(path_argument("mesh_dir", mesh_dir))

    def add(parent: ET.Element, link_name: str, joint: ET.Element | None) -> None:
        link = links[link_name]
        if joint is None:
            body = parent  # the URDF's root link is MuJoCo's world body
        else:
            body = ET.SubElement(parent, "body", name=link_name)
            _pose(body, joint.find("origin"))
            _inertial(body, link)
            _joint(body, joint, drive, sliders)
        _geoms(body, link, assets, mdir)
        for site in sites.get(link_name, ()):
            ET.SubElement(body, "site", name=site, pos="0 0 0", size="0.004", group="3")
        for child_joint in children[link_name]:
            child = child_joint.find("child")
            assert child is not None  # checked by _tree
            add(body, str(child.get("link")), child_joint)

    add(world, root, None)
    _equalities(model, loops)
    _actuators(model, loops, drive)
    if not len(assets):
        model.remove(assets)
    ET.indent(model)
    return ET.tostring(model, encoding="unicode") + "\n"


def _closure_sites(loops: LoopSpec) -> Mapping[str, list[str]]:
    sites: dict[str, list[str]] = {}
    for closure in loops.closures:
        for frame, suffix in zip((closure.frame1, closure.frame2), SITE_SUFFIXES, strict=True):
            sites.setdefault(frame, []).append(closure.name + suffix)
    return sites


def _equalities(model: ET.Element, loops: LoopSpec) -> None:
    equality = ET.SubElement(model, "equality")
    for closure in loops.closures:
        kind = {"point": "connect", "frame": "weld"}.get(closure.kind)
        if kind is None:
            raise DescriptionError(
                f"loop type {short_repr(closure.kind)}: allowed point, frame", closure.kind
            )
        s1, s2 = (closure.name + s for s in SITE_SUFFIXES)
        ET.SubElement(equality, kind, name=closure.name, site1=s1, site2=s2)


def _actuators(model: ET.Element, loops: LoopSpec, drive: Drive) -> None:
    actuator = ET.SubElement(model, "actuator")
    limit = slider_force_limit(drive)
    for joint in loops.actuated_joints:
        node = ET.SubElement(actuator, "motor", name=f"{joint}_motor", joint=joint, gear="1")
        if limit is not None:
            node.set("ctrlrange", _vec((-limit, limit)))
            node.set("forcerange", _vec((-limit, limit)))
