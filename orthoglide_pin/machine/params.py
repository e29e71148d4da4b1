"""Machine parameters: a typed, immutable, validated description of one Orthoglide.

Every length is in metres [m], every mass in kilograms [kg], densities in
[kg/m^3]. The three legs are identical (paper, section 2.1: symmetry of
construction), so one set of leg parameters serves all three.

Geometry (see the README for the figure in words):

* the world frame sits at the tool point of the isotropic configuration
  ("home"), slider ``i`` moves along ``+e_i`` and reads 0 at home;
* each leg is a P-R-Pa-R chain: a carriage on the slider, a revolute, a planar
  parallelogram of two bars of length ``leg_length`` spaced by
  ``parallelogram_width``, a revolute onto the platform;
* the platform only translates; the tool tip is at ``tool_offset`` from the
  platform centre, and each leg is attached ``platform_offset`` behind the
  platform centre along ``-e_i``;
* the carriage's own origin is ``carriage_offset`` behind its revolute along
  ``-e_i``.

Masses that are ``None`` are derived from the link sizes and ``density``
(uniform solids, tubes for the bars); the derivation lives in the xacro
description so that the URDF is the single source of the inertial model.

The prescribed workspace is part of the machine: the cube of lowest corner
``workspace_corner`` (Q1) and side ``workspace_side``
(:attr:`OrthoglideParams.workspace`). The slider limits are derived from it
unless given: when ``slider_lower`` or ``slider_upper`` is ``None`` (the
default), it is the exact range of the slider values over the cube
(:func:`~orthoglide_pin.kinematics.closed_form.slider_range_over_cube`),
re-derived whenever the leg length or the cube changes
(:meth:`~OrthoglideParams.replace`). Limits given explicitly are kept, and
refused if the sliders cannot reach the whole cube within them. Every value is
also checked against a plausible range
(:data:`~orthoglide_pin.machine.ranges.PLAUSIBLE_RANGES`), to catch a value
given in millimetres.

The criterion the cube was designed for is part of the machine too: bounds
``psi_min < 1 < psi_max`` on the velocity transmission factors over the cube
(:mod:`~orthoglide_pin.machine.criterion`), which ``certify``, ``summary``,
``sweep`` and ``report`` judge the machine by. The prototype carries the paper's
[0.5, 2]; with the paper's 310 mm legs its factors over its cube are
[0.4989, 2.0090] (the design method gives 310.58 mm for [0.5, 2], which the
paper rounded), so its cube does not quite meet its criterion.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from orthoglide_pin._io import atomic_write_text, parse_yaml_mapping, read_yaml_mapping
from orthoglide_pin._paths import given_path
from orthoglide_pin._validation import flag, instance_of, path_argument
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.criterion import CRITERION_FIELDS, PAPER_BOUNDS, check_bounds
from orthoglide_pin.machine.cube import Cube
from orthoglide_pin.machine.limits import check_limits
from orthoglide_pin.machine.meshes import PartMesh, parse_meshes
from orthoglide_pin.machine.parts import MASS_FIELDS, PartInertia, PartTable, parse_inertias
from orthoglide_pin.machine.program_axes import PROTOTYPE_PROGRAM_AXES, program_axes_value
from orthoglide_pin.machine.ranges import check_parameter

Vec3 = tuple[float, float, float]

#: Side of the paper's prescribed cubic workspace [m] (section 4).
PROTOTYPE_WORKSPACE_SIDE = 0.200
#: Leg (parallelogram bar) length of the paper's prototype [m] (section 4).
PROTOTYPE_LEG_LENGTH = 0.310
#: Diagonal coordinate of the prototype cube's lower corner Q1 [m]: the point of
#: the main diagonal, on the slider side, where a transmission factor reaches 2
#: for L = 0.31 m (``-0.31 / sqrt(18)``). A constant: another leg keeps this cube.
PROTOTYPE_CUBE_CORNER = -PROTOTYPE_LEG_LENGTH / math.sqrt(18.0)
#: The slider limits, derived from the cube when not given.
LIMIT_FIELDS = ("slider_lower", "slider_upper")
#: The prescribed workspace, the cube and the criterion it was designed for:
#: machine parameters that are not xacro arguments.
WORKSPACE_FIELDS = frozenset({"workspace_corner", "workspace_side", *CRITERION_FIELDS})


@dataclass(frozen=True)
class OrthoglideParams:
    """Parameters of one Orthoglide, in SI units.

    Attributes:
        leg_length: Length L of the parallelogram bars [m].
        parallelogram_width: Distance between the two bars of a parallelogram [m].
        slider_lower: Lower slider limit [m] (0 is the isotropic configuration).
            ``None`` (the default) derives it from the cube: the lowest slider
            value over it. Always a float once built.
        slider_upper: Upper slider limit [m]; ``None`` derives it likewise.
        carriage_offset: Distance from the carriage origin to its revolute axis,
            along ``+e_i`` [m].
        platform_offset: Distance from the platform centre to each leg's end
            revolute, along ``-e_i`` [m].
        tool_offset: Tool tip position in the platform frame [m], shape (3,).
        bar_radius: Outer radius of the parallelogram tubes [m].
        bar_wall: Wall thickness of the parallelogram tubes [m]
            (equal to ``bar_radius`` for solid bars).
        link_radius: Radius of the small end links of the parallelograms [m].
        carriage_size: Carriage box (along rail, across, height) [m], shape (3,).
        platform_size: Side of the cubic platform [m].
        spindle_radius: Radius of the spindle cylinder [m].
        spindle_length: Length of the spindle cylinder [m].
        rail_size: Side of the square cross-section of the drawn rails [m].
        density: Density of the structural material [kg/m^3].
        youngs_modulus: Young's modulus of the bars and small links [Pa]
            (aluminium alloy by default). Elastostatic model only.
        shear_modulus: Shear modulus of the bars and small links [Pa]
            (aluminium alloy by default). Elastostatic model only.
        actuator_stiffness: Axial stiffness of one actuator (ball screw, nut
            and thrust bearings in series) seen at the carriage [N/m].
            Elastostatic model only.
        joint_stiffness: Translational stiffness of the bearings of each
            revolute, radial and axial [N/m]. Elastostatic model only (the
            ``joints`` compliance source).
        joint_tilt_stiffness: Stiffness of the bearings of each revolute
            against tilting about the two axes normal to its own [N.m/rad].
            Elastostatic model only.
        spindle_mass: Mass of the spindle and tool [kg].
        bar_mass: Mass of one parallelogram bar [kg], ``None`` to derive it.
        link_mass: Mass of one small end link [kg], ``None`` to derive it.
        carriage_mass: Mass of one carriage [kg], ``None`` to derive it.
        platform_mass: Mass of the platform without spindle [kg], ``None`` to
            derive it.
        workspace_corner: Lowest corner Q1 of the prescribed cube [m], shape (3,)
            (the prototype's: ``-0.31 / sqrt(18)`` on each axis).
        workspace_side: Side of the prescribed cube [m] (the prototype's: 0.2).
        psi_min: Lower bound of the criterion on the velocity transmission
            factors over the cube [-], in (0, 1) (the prototype's: the paper's
            0.5; see :mod:`~orthoglide_pin.machine.criterion`).
        psi_max: Upper bound of the criterion [-], above 1 (the prototype's: 2).
        meshes: CAD mesh files drawn instead of the primitives, per part kind
            (:mod:`~orthoglide_pin.machine.parts`); geometry only, no mass.
        inertias: CAD mass, centre of mass and inertia per part kind; they
            replace the values derived from the sizes and ``density``.
        program_axes: A part program's X, Y, Z on the world axes, a rotation
            (:mod:`~orthoglide_pin.machine.program_axes`): X on +e2, Y on +e1, Z on -e3.
    """

    leg_length: float = PROTOTYPE_LEG_LENGTH
    parallelogram_width: float = 0.080
    # None derives the limit from the cube (see the module); a float once built.
    slider_lower: float = None  # type: ignore[assignment]
    slider_upper: float = None  # type: ignore[assignment]
    carriage_offset: float = 0.040
    platform_offset: float = 0.050
    tool_offset: Vec3 = (0.0, 0.0, 0.200)
    bar_radius: float = 0.010
    bar_wall: float = 0.0015
    link_radius: float = 0.012
    carriage_size: Vec3 = (0.100, 0.100, 0.040)
    platform_size: float = 0.080
    spindle_radius: float = 0.030
    spindle_length: float = 0.150
    rail_size: float = 0.040
    density: float = 2700.0
    youngs_modulus: float = 70.0e9
    shear_modulus: float = 26.0e9
    actuator_stiffness: float = 1.0e8
    joint_stiffness: float = 1.0e8
    joint_tilt_stiffness: float = 2.0e4
    spindle_mass: float = 2.0
    bar_mass: float | None = None
    link_mass: float | None = None
    carriage_mass: float | None = None
    platform_mass: float | None = None
    workspace_corner: Vec3 = (PROTOTYPE_CUBE_CORNER,) * 3
    workspace_side: float = PROTOTYPE_WORKSPACE_SIDE
    psi_min: float = PAPER_BOUNDS[0]
    psi_max: float = PAPER_BOUNDS[1]
    meshes: PartTable[PartMesh] = dataclasses.field(default_factory=PartTable)
    inertias: PartTable[PartInertia] = dataclasses.field(default_factory=PartTable)
    program_axes: tuple[int, int, int] = PROTOTYPE_PROGRAM_AXES
    # Which slider limits were given (the others are derived from the cube).
    _given_limits: tuple[bool, bool] = dataclasses.field(
        init=False, repr=False, default=(False, False)
    )

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            if f.name.startswith("_"):
                continue
            value = getattr(self, f.name)
            if f.name == "program_axes":
                object.__setattr__(self, f.name, program_axes_value(value))
            elif f.name == "meshes":
                object.__setattr__(self, f.name, parse_meshes(value))
            elif f.name == "inertias":
                object.__setattr__(self, f.name, parse_inertias(value))
            elif f.name in _VECTOR_FIELDS:
                object.__setattr__(self, f.name, _as_vec3(f.name, value))
            elif f.name in OPTIONAL_FIELDS or f.name in LIMIT_FIELDS:
                if value is not None:
                    object.__setattr__(self, f.name, _as_float(f.name, value))
            else:
                object.__setattr__(self, f.name, _as_float(f.name, value))
        given = (self.slider_lower is not None, self.slider_upper is not None)
        object.__setattr__(self, "_given_limits", given)
        _validate(self)

    @property
    def stroke(self) -> float:
        """Slider stroke ``slider_upper - slider_lower`` [m]."""
        return self.slider_upper - self.slider_lower

    @property
    def workspace(self) -> Cube:
        """The prescribed cube: corner Q1 (``workspace_corner``) and side [m]."""
        return Cube(self.workspace_corner, self.workspace_side)

    @property
    def derived_limits(self) -> tuple[str, ...]:
        """Names of the slider limits derived from the cube (not given)."""
        return tuple(n for n, g in zip(LIMIT_FIELDS, self._given_limits, strict=True) if not g)

    def replace(self, **changes: Any) -> OrthoglideParams:
        """Return a validated copy with some fields changed.

        Slider limits that were derived from the cube are derived again (for
        the new leg length or cube) unless ``changes`` gives them; limits that
        were given are kept. Give ``slider_lower=None`` to derive a limit.

        Raises:
            InvalidParameterError: On an unknown field name or a bad value.
        """
        _check_names(changes)
        values = {n: getattr(self, n) for n in (*field_names(), *PART_FIELDS, *AXES_FIELDS)}
        for name in self.derived_limits:
            values[name] = None
        values.update(changes)
        return OrthoglideParams(**values)

    def to_dict(self, *, derived_as_none: bool = False) -> dict[str, Any]:
        """Plain-Python dictionary of every parameter (vectors as lists).

        ``meshes`` and ``inertias`` are included only when given (as mappings
        of part kind to their plain form).

        Args:
            derived_as_none: Write the slider limits derived from the cube as
                ``None`` (what :meth:`to_yaml` does, so that a file read back
                derives them again); by default every value is a number.
        """
        out: dict[str, Any] = {}
        for name in field_names():
            value = getattr(self, name)
            out[name] = list(value) if isinstance(value, tuple) else value
        if flag("derived_as_none", derived_as_none):
            out.update(dict.fromkeys(self.derived_limits))
        if self.meshes:
            out["meshes"] = {k: m.to_dict() for k, m in self.meshes.items()}
        if self.inertias:
            out["inertias"] = {k: i.to_dict() for k, i in self.inertias.items()}
        if self.program_axes != PROTOTYPE_PROGRAM_AXES:
            out["program_axes"] = list(self.program_axes)
        return out

    @classmethod
    def from_dict(
        cls, data: Mapping[str, Any], base: OrthoglideParams | None = None
    ) -> OrthoglideParams:
        """Build parameters from a mapping, on top of ``base`` (default: the prototype).

        Raises:
            InvalidParameterError: On an unknown key or a bad value.
        """
        if not isinstance(data, Mapping):
            raise InvalidParameterError("data", data, "a mapping of parameter names to values")
        if base is None:
            base = prototype()
        base = instance_of("base", base, OrthoglideParams, "OrthoglideParams or None")
        return base.replace(**dict(data))

    def to_yaml(self) -> str:
        """Serialise to a YAML document (the inverse of :meth:`from_yaml`).

        Slider limits derived from the cube are written as ``null``: read back,
        they are derived again, so a file edited to another leg length keeps
        its cube.
        """
        return yaml.safe_dump(self.to_dict(derived_as_none=True), sort_keys=False)

    @classmethod
    def from_yaml(cls, text: str) -> OrthoglideParams:
        """Parse a YAML document; keys not given keep their prototype value.

        The document is read safely (see :func:`orthoglide_pin._io.parse_yaml_mapping`):
        at most 1 MB, no aliases, string keys only.

        Raises:
            InvalidParameterError: On invalid or unsafe YAML, unknown keys or bad values.
        """
        if not isinstance(text, str):
            raise InvalidParameterError("config text", text, "a YAML document (str)")
        return cls.from_dict(parse_yaml_mapping(text, "config text"))

    def save(self, path: str | Path) -> Path:
        """Write the parameters to a YAML file, atomically. Returns the path."""
        path = given_path(path_argument("path", path))
        atomic_write_text(path, self.to_yaml())
        return path

    @classmethod
    def load(cls, path: str | Path) -> OrthoglideParams:
        """Read parameters from a YAML file (see :meth:`from_yaml`).

        At most 1 MB is read (:data:`orthoglide_pin._io.MAX_INPUT_BYTES`), as
        UTF-8; a directory, a device or a FIFO never hangs the reader. Relative
        mesh files (``meshes``) are relative to the file's folder.

        Raises:
            InvalidParameterError: On an unreadable, oversized or non-UTF-8 file,
                or bad content (naming the path given).
        """
        if not isinstance(path, (str, os.PathLike)):
            raise InvalidParameterError("path", path, "a file path (str or os.PathLike)")
        data = read_yaml_mapping(path, "config")
        if data.get("meshes") is not None:
            data["meshes"] = parse_meshes(data["meshes"], Path(path).expanduser().parent)
        return cls.from_dict(data)


def field_names() -> tuple[str, ...]:
    """Public numeric parameter names, in declaration order (not :data:`PART_FIELDS`)."""
    return tuple(
        f.name
        for f in dataclasses.fields(OrthoglideParams)
        if not f.name.startswith("_") and f.name not in PART_FIELDS and f.name not in AXES_FIELDS
    )


#: CAD data per part kind (meshes, inertias): parameters that are not numbers.
PART_FIELDS = ("meshes", "inertias")
AXES_FIELDS = ("program_axes",)  #: A rotation, not numbers: not a xacro argument.


_VECTOR_FIELDS = frozenset({"tool_offset", "carriage_size", "workspace_corner"})
#: Parameters of the elastostatic model only (material moduli [Pa], drive and
#: bearing stiffnesses): they are not arguments of the xacro description.
_STIFFNESSES = ("actuator_stiffness", "joint_stiffness", "joint_tilt_stiffness")
ELASTIC_FIELDS = frozenset({"youngs_modulus", "shear_modulus", *_STIFFNESSES})
#: Mass fields that may be ``None``: derived from the link sizes and ``density``.
OPTIONAL_FIELDS = frozenset({"bar_mass", "link_mass", "carriage_mass", "platform_mass"})
_POSITIVE_FIELDS = (
    "leg_length",
    "parallelogram_width",
    "bar_radius",
    "bar_wall",
    "link_radius",
    "platform_size",
    "spindle_radius",
    "spindle_length",
    "rail_size",
    "workspace_side",
    "density",
    *sorted(ELASTIC_FIELDS),
)
_NONNEGATIVE_FIELDS = ("carriage_offset", "platform_offset", "spindle_mass", *OPTIONAL_FIELDS)


def _check_names(changes: Mapping[str, Any]) -> None:
    allowed = (*field_names(), *PART_FIELDS, *AXES_FIELDS)
    for name in changes:
        if name not in allowed:
            raise InvalidParameterError("parameter name", name, "one of " + ", ".join(allowed))


def _as_float(name: str, value: Any) -> float:
    if isinstance(value, bool):
        raise InvalidParameterError(name, value, "a finite number")
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "a finite number") from None
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, "a finite number")
    return out


def _as_vec3(name: str, value: Any) -> Vec3:
    if isinstance(value, str):
        value = [v for v in value.replace(",", " ").split() if v]
    try:
        items = list(value)
    except TypeError:
        raise InvalidParameterError(name, value, "three finite numbers") from None
    if len(items) != 3:
        raise InvalidParameterError(name, value, "three finite numbers")
    x, y, z = (_as_float(name, v) for v in items)
    return (x, y, z)


def _validate(p: OrthoglideParams) -> None:
    for name in _POSITIVE_FIELDS:
        value = getattr(p, name)
        if value <= 0.0:
            raise InvalidParameterError(name, value, "a positive number")
    for name in _NONNEGATIVE_FIELDS:
        value = getattr(p, name)
        if value is not None and value < 0.0:
            raise InvalidParameterError(name, value, "a non-negative number")
    if any(s <= 0.0 for s in p.carriage_size):
        raise InvalidParameterError("carriage_size", p.carriage_size, "three positive numbers")
    if p.bar_wall > p.bar_radius:
        raise InvalidParameterError(
            "bar_wall", p.bar_wall, f"at most bar_radius={p.bar_radius} (a solid bar)"
        )
    check_bounds(p.psi_min, p.psi_max)  # 0 < psi_min < 1 < psi_max, before the ranges
    for name in field_names():
        value = getattr(p, name)
        for v in value if isinstance(value, tuple) else (value,):
            if v is not None:
                check_parameter(name, v)
    for kind in p.inertias:
        field = MASS_FIELDS[kind]
        if field != "spindle_mass" and getattr(p, field) is not None:
            raise InvalidParameterError(
                field, getattr(p, field), f"None when inertias.{kind} gives the mass from CAD"
            )
    check_limits(p)


def prototype() -> OrthoglideParams:
    """The paper's prototype (section 4): its 200 mm cube, its 310 mm legs, its criterion.

    The paper designs it for a 200 mm cube and transmission factors in
    [0.5, 2] (``psi_min``, ``psi_max``, carried here as its criterion), and
    gives bars of 310 mm. The design method gives 310.58 mm for that cube and
    those bounds; the paper rounded it, and with 310 mm the factors over the
    cube lie in [0.4989, 2.0090] (both extremes at Q2): the prototype's cube
    does not quite meet its criterion (``orthoglide certify`` says VIOLATED,
    ``orthoglide summary`` shows the range). The cube has Q1, where the factor
    2 is reached on the slider side for 310 mm legs (``t = -0.31/sqrt(18)`` on
    each axis, stored as numbers: another leg length keeps this cube), as its
    lowest corner; the slider limits are derived, the range of the slider
    values over that whole cube, which gives the paper's 257 mm stroke.

    Returns:
        The prototype's parameters. Sizes and masses the paper does not give
        are stated assumptions (see the README).
    """
    return OrthoglideParams()
