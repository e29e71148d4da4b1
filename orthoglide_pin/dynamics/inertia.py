"""Inertial model: mass, centre of mass and inertia of every moving body.

The values are read from the rendered URDF
(:func:`orthoglide_pin.machine.description.render_urdf`),
the single source of the inertial model, so they are exactly what Pinocchio
loads. The paper gives no masses: a mass parameter left to ``None`` is derived
in the description from the link sizes and ``density`` (tubes for the bars,
uniform solids for the rest), and every centre of mass and inertia is that of
a uniform solid of the drawn shape. :func:`assumptions` states them, one line
per body kind, ready to print in a report. Masses and sizes are parameters
(:class:`orthoglide_pin.machine.params.OrthoglideParams`, or YAML).

Body kinds: ``carriage`` (one per slider), ``small_link`` (the two small end
links of each parallelogram), ``bar`` (two per parallelogram), ``platform`` and
``spindle`` (spindle and tool, carried by the platform). The platform is one
body carried in thirds by the three end revolutes of the cut tree (links
``leg<i>_end_mount``, see the description): the table lists the three shares,
and :meth:`InertiaTable.by_kind` counts them as the one body they are. This
module does not import Pinocchio.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import choice
from orthoglide_pin._validation import text as check_text
from orthoglide_pin.exceptions import DescriptionError, short_repr
from orthoglide_pin.machine.coerce import URDF_TEXT, as_params
from orthoglide_pin.machine.description import render_urdf
from orthoglide_pin.machine.params import OrthoglideParams, prototype
from orthoglide_pin.machine.parts import MASS_FIELDS

FloatArray = NDArray[np.float64]

#: Body kinds, in the order of the reports.
KINDS: Final = ("carriage", "small_link", "bar", "platform", "spindle")
_KIND_OF: Final = (
    (re.compile(r"leg\d_carriage"), "carriage"),
    (re.compile(r"leg\d_(base|end)_link"), "small_link"),
    (re.compile(r"leg\d_bar_[ab]"), "bar"),
    (re.compile(r"platform|leg\d_end_mount"), "platform"),
    (re.compile(r"spindle"), "spindle"),
)
#: Kinds of one physical body carried in shares by several links of the cut tree.
SHARED_KINDS: Final = frozenset({"platform"})
#: Names of common structural materials by density [kg/m^3], for the reports.
_MATERIALS: Final = {2700.0: "aluminium", 7850.0: "steel", 7800.0: "steel", 4430.0: "titanium"}


@dataclass(frozen=True)
class BodyInertia:
    """Inertia of one URDF link.

    Attributes:
        link: Link name.
        kind: Body kind (see :data:`KINDS`), ``"other"`` if unknown.
        leg: Leg index 1-3 (for a platform share, the leg that holds it), or
            ``None`` for the platform side.
        joint: The moving joint that carries the link (through fixed joints).
        mass: Mass [kg].
        com: Centre of mass in the link frame [m], shape (3,).
        inertia: Inertia about the centre of mass, link axes [kg.m^2], shape (3, 3).
    """

    link: str
    kind: str
    leg: int | None
    joint: str
    mass: float
    com: FloatArray
    inertia: FloatArray


@dataclass(frozen=True)
class KindSummary:
    """Masses of one body kind.

    Attributes:
        kind: The body kind.
        count: Number of bodies of that kind (a body carried in shares, see
            :data:`SHARED_KINDS`, counts once).
        mass_each: Mass of one body [kg] (the largest, if they differ).
        total: Total mass [kg].
    """

    kind: str
    count: int
    mass_each: float
    total: float


@dataclass(frozen=True)
class InertiaTable:
    """Inertial model of every moving body.

    Attributes:
        bodies: One entry per link with an inertial, in URDF order.
    """

    bodies: tuple[BodyInertia, ...]

    @property
    def total_moving_mass(self) -> float:
        """Sum of the masses of every moving body [kg]."""
        return float(sum(b.mass for b in self.bodies))

    @property
    def platform_mass(self) -> float:
        """Platform with spindle and tool [kg]: the mass the tool point carries."""
        return float(sum(b.mass for b in self.bodies if b.kind in ("platform", "spindle")))

    def kind(self, kind: str) -> tuple[BodyInertia, ...]:
        """The bodies of one kind (one of :data:`KINDS` or ``"other"``)."""
        kind = choice("kind", kind, (*KINDS, "other"))
        return tuple(b for b in self.bodies if b.kind == kind)

    def by_kind(self) -> dict[str, KindSummary]:
        """Masses grouped by body kind, in the order of :data:`KINDS`."""
        out: dict[str, KindSummary] = {}
        for kind in (*KINDS, "other"):
            masses = [b.mass for b in self.kind(kind)]
            if masses and kind in SHARED_KINDS:
                masses = [float(sum(masses))]
            if masses:
                out[kind] = KindSummary(kind, len(masses), max(masses), float(sum(masses)))
        return out

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python (JSON-ready) form: bodies, per-kind sums and totals, SI units."""
        return {
            "bodies": [
                {
                    "link": b.link,
                    "kind": b.kind,
                    "leg": b.leg,
                    "joint": b.joint,
                    "mass": b.mass,
                    "com": b.com.tolist(),
                    "inertia": b.inertia.tolist(),
                }
                for b in self.bodies
            ],
            "by_kind": {
                k: {"count": s.count, "mass_each": s.mass_each, "total": s.total}
                for k, s in self.by_kind().items()
            },
            "platform_mass": self.platform_mass,
            "total_moving_mass": self.total_moving_mass,
        }


def _floats(text: str | None, count: int, what: str) -> list[float]:
    parts = (text or "").split()
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(values) != count:
        raise DescriptionError(f"bad {what} in the URDF: {short_repr(text)}", text)
    return values


def _kind(link: str) -> str:
    for pattern, kind in _KIND_OF:
        if pattern.fullmatch(link):
            return kind
    return "other"


def inertia_table(
    params: OrthoglideParams | None = None, *, urdf: str | None = None
) -> InertiaTable:
    """Read the inertial model of every moving link from the URDF.

    Args:
        params: Machine parameters; the prototype when ``None``.
        urdf: A URDF string to read instead of rendering ``params``.

    Returns:
        The inertia table.

    Raises:
        DescriptionError: If the URDF cannot be parsed or has a rotated inertial frame.
    """
    text = render_urdf(params) if urdf is None else check_text("urdf", urdf, URDF_TEXT)
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise DescriptionError(f"the URDF is not valid XML: {exc}") from exc
    parent: dict[str, tuple[str, str]] = {}  # child link -> (joint name, joint type)
    parent_link: dict[str, str] = {}
    for joint in root.iter("joint"):
        child, par = joint.find("child"), joint.find("parent")
        if child is not None and par is not None:
            parent[child.get("link", "")] = (joint.get("name", ""), joint.get("type", ""))
            parent_link[child.get("link", "")] = par.get("link", "")
    bodies = []
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        name = link.get("name", "")
        origin, mass_el, inertia_el = (inertial.find(t) for t in ("origin", "mass", "inertia"))
        com = (
            _floats(origin.get("xyz", "0 0 0"), 3, "inertial origin")
            if origin is not None
            else [0.0] * 3
        )
        rpy = (
            _floats(origin.get("rpy", "0 0 0"), 3, "inertial rpy")
            if origin is not None
            else [0.0] * 3
        )
        if any(rpy):
            raise DescriptionError(f"link {name}: rotated inertial frames are not supported", rpy)
        mass = _floats(mass_el.get("value") if mass_el is not None else None, 1, "mass")[0]
        keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
        ixx, ixy, ixz, iyy, iyz, izz = (
            _floats(inertia_el.get(k) if inertia_el is not None else None, 1, k)[0] for k in keys
        )
        inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        # The moving joint that carries the link, through fixed joints.
        walk, joint_name = name, ""
        while walk in parent:
            joint_name, kind = parent[walk]
            if kind != "fixed":
                break
            walk = parent_link[walk]
        leg = int(name[3]) if re.match(r"leg\d_", name) else None
        bodies.append(
            BodyInertia(name, _kind(name), leg, joint_name, mass, np.array(com), inertia)
        )
    return InertiaTable(tuple(bodies))


def _material(density: float) -> str:
    name = _MATERIALS.get(float(density))
    return f"{name} ({density:g} kg/m^3)" if name else f"a material of {density:g} kg/m^3"


def assumptions(params: OrthoglideParams | None = None) -> list[str]:
    """The assumptions behind the inertial model, one sentence per line, for reports.

    Args:
        params: Machine parameters; the prototype when ``None``.

    Returns:
        Sentences (lengths in mm, masses in kg) stating, for every body kind,
        its mass and whether it is measured (a CAD inertia of the parameters'
        ``inertias``), derived (with material and section) or given.
    """
    p = as_params(params)
    mm = 1e3
    by_kind = inertia_table(p).by_kind()
    each = {k: s.mass_each for k, s in by_kind.items()}
    material = _material(p.density)

    cad = p.inertias
    kind_of_field = {v: k for k, v in MASS_FIELDS.items()}

    def origin(field: str, derived: str) -> str:
        kind = kind_of_field[field]
        if kind in cad:
            return _cad_text(kind, cad[kind].com)
        if getattr(p, field) is None:
            return f"derived from its size: {derived}, {material}."
        return f"given ({field} = {getattr(p, field):g} kg)."

    tube = (
        f"tube {2 * p.bar_radius * mm:.1f} mm outer diameter x {p.bar_wall * mm:.1f} mm wall"
        if p.bar_wall < p.bar_radius
        else f"solid rod {2 * p.bar_radius * mm:.1f} mm in diameter"
    )
    sx, sy, sz = (s * mm for s in p.carriage_size)
    spindle_default = math.isclose(p.spindle_mass, prototype().spindle_mass)
    if "spindle" in cad:
        spindle = f"Spindle and tool: {cad['spindle'].mass:g} kg, " + origin("spindle_mass", "")
    else:
        spindle = (
            f"Spindle and tool: {p.spindle_mass:g} kg "
            + ("(assumed value of the prototype)" if spindle_default else "(given)")
            + f", inertia of a solid cylinder {2 * p.spindle_radius * mm:.0f} mm in diameter x "
            f"{p.spindle_length * mm:.0f} mm on the tool axis"
        )
    measured = [k for k in KINDS if k in cad]
    if measured:
        first = (
            f"Measured (CAD mass, centre of mass and inertia): {', '.join(measured)}; "
            "the other bodies below are assumed, not measured."
        )
    else:
        first = "The paper gives no masses: the inertial model below is assumed, not measured."
    return [
        first,
        f"Parallelogram bars (x6): {each.get('bar', 0.0):.4f} kg each, "
        + origin("bar_mass", f"{tube}, {p.leg_length * mm:.0f} mm long"),
        f"Small end links (x6): {each.get('small_link', 0.0):.4f} kg each, "
        + origin(
            "link_mass",
            f"solid cylinder {2 * p.link_radius * mm:.1f} mm in diameter x "
            f"{p.parallelogram_width * mm:.0f} mm (the parallelogram width)",
        ),
        f"Carriages (x3): {each.get('carriage', 0.0):.4f} kg each, "
        + origin("carriage_mass", f"solid box {sx:.0f} x {sy:.0f} x {sz:.0f} mm"),
        f"Platform: {each.get('platform', 0.0):.4f} kg (a third on each leg's end "
        "revolute in the cut tree, one rigid body once the loops are closed), "
        + origin("platform_mass", f"solid cube of {p.platform_size * mm:.0f} mm"),
        spindle.rstrip(".") + "; the tool itself is massless.",
        "Centres of mass and inertias"
        + (" of the assumed bodies" if measured else "")
        + ": uniform bodies of the shapes above, at their "
        "geometric centres; joints, bearings, rails and ball screws carry no mass here "
        "(screws and motors are in the drive model).",
        *(
            [
                f"CAD meshes ({', '.join(k for k in KINDS if k in p.meshes)}) are drawn only: "
                "a mesh is geometry, not mass."
            ]
            if p.meshes
            else []
        ),
    ]


def _cad_text(kind: str, com: tuple[float, float, float]) -> str:
    """How a CAD inertia is reported: measured, with its centre of mass in mm."""
    at = ", ".join(f"{1e3 * c:.1f}" for c in com)
    return f"measured (CAD: mass, centre of mass ({at}) mm in the {kind} frame, inertia tensor)."
