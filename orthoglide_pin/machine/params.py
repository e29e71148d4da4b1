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
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import slider_range_over_cube

Vec3 = tuple[float, float, float]

#: Side of the paper's prescribed cubic workspace [m] (section 4).
PROTOTYPE_WORKSPACE_SIDE = 0.200
#: Leg (parallelogram bar) length of the paper's prototype [m] (section 4).
PROTOTYPE_LEG_LENGTH = 0.310
#: Diagonal coordinate of the prototype cube's lower corner Q1 [m]: the point of
#: the main diagonal, on the slider side, where a transmission factor reaches 2.
PROTOTYPE_CUBE_CORNER = -PROTOTYPE_LEG_LENGTH / math.sqrt(18.0)
_PROTOTYPE_SLIDER_RANGE = slider_range_over_cube(
    PROTOTYPE_LEG_LENGTH, (PROTOTYPE_CUBE_CORNER,) * 3, PROTOTYPE_WORKSPACE_SIDE
)


@dataclass(frozen=True)
class OrthoglideParams:
    """Parameters of one Orthoglide, in SI units.

    Attributes:
        leg_length: Length L of the parallelogram bars [m].
        parallelogram_width: Distance between the two bars of a parallelogram [m].
        slider_lower: Lower slider limit [m] (0 is the isotropic configuration).
        slider_upper: Upper slider limit [m].
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
        spindle_mass: Mass of the spindle and tool [kg].
        bar_mass: Mass of one parallelogram bar [kg], ``None`` to derive it.
        link_mass: Mass of one small end link [kg], ``None`` to derive it.
        carriage_mass: Mass of one carriage [kg], ``None`` to derive it.
        platform_mass: Mass of the platform without spindle [kg], ``None`` to
            derive it.
    """

    leg_length: float = PROTOTYPE_LEG_LENGTH
    parallelogram_width: float = 0.080
    slider_lower: float = _PROTOTYPE_SLIDER_RANGE[0]
    slider_upper: float = _PROTOTYPE_SLIDER_RANGE[1]
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
    spindle_mass: float = 2.0
    bar_mass: float | None = None
    link_mass: float | None = None
    carriage_mass: float | None = None
    platform_mass: float | None = None

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            if f.name.startswith("_"):
                continue
            value = getattr(self, f.name)
            if f.name in _VECTOR_FIELDS:
                object.__setattr__(self, f.name, _as_vec3(f.name, value))
            elif f.name in OPTIONAL_FIELDS:
                if value is not None:
                    object.__setattr__(self, f.name, _as_float(f.name, value))
            else:
                object.__setattr__(self, f.name, _as_float(f.name, value))
        _validate(self)

    @property
    def stroke(self) -> float:
        """Slider stroke ``slider_upper - slider_lower`` [m]."""
        return self.slider_upper - self.slider_lower

    def replace(self, **changes: Any) -> OrthoglideParams:
        """Return a validated copy with some fields changed.

        Raises:
            InvalidParameterError: On an unknown field name or a bad value.
        """
        _check_names(changes)
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python dictionary of every parameter (vectors as lists)."""
        out: dict[str, Any] = {}
        for name in field_names():
            value = getattr(self, name)
            out[name] = list(value) if isinstance(value, tuple) else value
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
            raise InvalidParameterError("config", data, "a mapping of parameter names to values")
        base = prototype() if base is None else base
        return base.replace(**dict(data))

    def to_yaml(self) -> str:
        """Serialise to a YAML document (the inverse of :meth:`from_yaml`)."""
        return yaml.safe_dump(self.to_dict(), sort_keys=False)

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
        return cls.from_dict(parse_yaml_mapping(text, "config"))

    def save(self, path: str | Path) -> Path:
        """Write the parameters to a YAML file, atomically. Returns the path."""
        path = Path(path)
        atomic_write_text(path, self.to_yaml())
        return path

    @classmethod
    def load(cls, path: str | Path) -> OrthoglideParams:
        """Read parameters from a YAML file (see :meth:`from_yaml`).

        At most 1 MB is read (:data:`orthoglide_pin._io.MAX_INPUT_BYTES`), as
        UTF-8; a directory, a device or a FIFO never hangs the reader.

        Raises:
            InvalidParameterError: On an unreadable, oversized or non-UTF-8 file,
                or bad content (naming the path given).
        """
        if not isinstance(path, (str, os.PathLike)):
            raise InvalidParameterError("path", path, "a file path (str or os.PathLike)")
        return cls.from_dict(read_yaml_mapping(path, "config"))


def field_names() -> tuple[str, ...]:
    """Public parameter names, in declaration order."""
    return tuple(
        f.name for f in dataclasses.fields(OrthoglideParams) if not f.name.startswith("_")
    )


_VECTOR_FIELDS = frozenset({"tool_offset", "carriage_size"})
#: Parameters of the elastostatic model only (material moduli [Pa], actuator
#: stiffness [N/m]): they are not arguments of the xacro description.
ELASTIC_FIELDS = frozenset({"youngs_modulus", "shear_modulus", "actuator_stiffness"})
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
    "density",
    "youngs_modulus",
    "shear_modulus",
    "actuator_stiffness",
)
_NONNEGATIVE_FIELDS = ("carriage_offset", "platform_offset", "spindle_mass", *OPTIONAL_FIELDS)


def _check_names(changes: Mapping[str, Any]) -> None:
    allowed = field_names()
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
    if not p.slider_lower <= 0.0:
        raise InvalidParameterError(
            "slider_lower", p.slider_lower, "<= 0 (the isotropic configuration is at 0)"
        )
    if not p.slider_upper >= 0.0:
        raise InvalidParameterError(
            "slider_upper", p.slider_upper, ">= 0 (the isotropic configuration is at 0)"
        )
    if not p.slider_upper > p.slider_lower:
        raise InvalidParameterError(
            "slider_upper", p.slider_upper, f"> slider_lower={p.slider_lower}"
        )
    reach = max(p.slider_upper, -p.slider_lower)
    if not reach < p.leg_length:
        # A leg long enough for the stroke: at every slider value the leg's joint
        # point B_i = (q_i - L) e_i stays on its own side of the isotropic tool
        # point, so the leg never has to pass through the platform's position.
        raise InvalidParameterError(
            "leg_length",
            p.leg_length,
            f"longer than the largest slider excursion {reach:.6g} m from home "
            f"(slider limits [{p.slider_lower:.6g}, {p.slider_upper:.6g}] m); "
            "lengthen the leg or shorten the stroke",
        )


def prototype() -> OrthoglideParams:
    """The paper's prototype (section 4).

    A 200 mm cube with transmission factors in [0.5, 2], bars of 310 mm. The
    cube has the reference points Q1 and Q2 of the design method as opposite
    corners on the main diagonal (Q1 where the factor 2 is reached on the
    slider side, at ``t = -L/sqrt(18)``); the slider limits are the range of
    the slider values over that whole cube, which gives the paper's 257 mm
    stroke.

    Returns:
        The prototype's parameters. Sizes and masses the paper does not give
        are stated assumptions (see the README).
    """
    return OrthoglideParams(
        leg_length=PROTOTYPE_LEG_LENGTH,
        slider_lower=_PROTOTYPE_SLIDER_RANGE[0],
        slider_upper=_PROTOTYPE_SLIDER_RANGE[1],
    )
