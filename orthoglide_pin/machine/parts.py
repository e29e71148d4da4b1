"""CAD data per kind of part: mesh files to draw, and measured inertias.

The machine is drawn with primitives (boxes, cylinders) and its inertias are
those of uniform solids of its sizes and ``density``. CAD can replace either,
per kind of part, through two parameters of
:class:`~orthoglide_pin.machine.params.OrthoglideParams`:

* ``meshes``: a mesh file (STL, OBJ or DAE) per kind, with a scale and an
  origin, drawn instead of the primitive. A mesh is geometry, not mass: the
  inertias stay those of the parameters.
* ``inertias``: a mass [kg], centre of mass [m] and inertia tensor about the
  centre of mass [kg.m^2] per kind, from CAD. They replace the values derived
  from the sizes and density (and the kind's mass parameter: giving both is
  refused, except ``spindle_mass``, which the CAD mass replaces).

In a design YAML file::

    meshes:
      carriage: {file: cad/carriage.stl, scale: 0.001, origin: {xyz: [0, 0, 0], rpy: [0, 0, 0]}}
    inertias:
      bar: {mass: 0.35, com: [0.155, 0, 0], inertia: [1.2e-5, 0, 0, 2.8e-3, 0, 2.8e-3]}

A relative mesh file is relative to the YAML file (to the current directory
when the parameters are built in Python); it is stored as an absolute path.
``inertia`` is a 3x3 matrix or its six values ``ixx ixy ixz iyy iyz izz``.

Each kind has one part frame, in which the mesh origin, the centre of mass and
the inertia tensor are given (:data:`PART_FRAMES`). The meshes themselves are
checked and read in :mod:`~orthoglide_pin.machine.meshes`; this module holds
the kinds, the inertias and the description's arguments for both.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from os import PathLike
from typing import Any, Final, Protocol, TypeVar

import numpy as np

from orthoglide_pin.exceptions import InvalidParameterError

Vec3 = tuple[float, float, float]
_T = TypeVar("_T")

#: Kinds of part that take a mesh or a CAD inertia.
PART_KINDS: Final = ("carriage", "bar", "small_link", "platform", "spindle")
#: The mass parameter that a CAD inertia of each kind replaces.
MASS_FIELDS: Final = {
    "carriage": "carriage_mass",
    "bar": "bar_mass",
    "small_link": "link_mass",
    "platform": "platform_mass",
    "spindle": "spindle_mass",
}
#: The frame of each kind in which mesh origins, centres of mass and inertias are given.
PART_FRAMES: Final = {
    "carriage": "centre of the carriage box; x along the rail (towards the platform), "
    "y along the leg's revolute axes",
    "bar": "centre of the bar's base revolute; x along the bar (to its tip), z along "
    "the parallelogram's revolute axes",
    "small_link": "centre of the small link; y along its length (the leg's revolute "
    "axes), x along the slider",
    "platform": "centre of the platform cube; machine axes (x, y, z)",
    "spindle": "centre of the spindle cylinder; machine axes, z along the tool axis",
}
#: Relative tolerance of the inertia checks (symmetry, triangle inequality).
INERTIA_RTOL: Final = 1e-9
#: Plausible bounds: mesh origins and centres of mass within this of the part
#: frame [m], principal moments at most this [kg.m^2].
MAX_OFFSET: Final = 10.0
MAX_MOMENT: Final = 1e3


class MeshLike(Protocol):
    """What the description needs of a mesh (:class:`~orthoglide_pin.machine.meshes.PartMesh`)."""

    @property
    def file(self) -> PathLike[str]: ...
    @property
    def scale(self) -> Vec3: ...
    @property
    def xyz(self) -> Vec3: ...
    @property
    def rpy(self) -> Vec3: ...


class PartTable(Mapping[str, _T]):
    """An immutable, hashable mapping of part kind -> value (meshes or inertias)."""

    __slots__ = ("_items",)

    def __init__(self, items: Mapping[str, _T] | None = None) -> None:
        self._items: tuple[tuple[str, _T], ...] = tuple(sorted((items or {}).items()))

    def __getitem__(self, kind: str) -> _T:
        for k, v in self._items:
            if k == kind:
                return v
        raise KeyError(kind)

    def __iter__(self) -> Iterator[str]:
        return iter(k for k, _ in self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __hash__(self) -> int:
        return hash(self._items)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, PartTable):
            return self._items == other._items
        return isinstance(other, Mapping) and dict(self._items) == dict(other)

    def __repr__(self) -> str:
        return f"PartTable({dict(self._items)!r})"


@dataclass(frozen=True)
class PartInertia:
    """Mass, centre of mass and inertia of one kind of part, from CAD.

    Attributes:
        mass: Mass [kg] (for the platform, the whole platform: the description
            shares it in thirds among the legs).
        com: Centre of mass in the part frame [m], shape (3,).
        inertia: Inertia tensor about the centre of mass, part-frame axes
            [kg.m^2], shape (3, 3), symmetric positive definite.
    """

    mass: float
    com: Vec3
    inertia: tuple[Vec3, Vec3, Vec3]

    def matrix(self) -> np.ndarray[Any, np.dtype[np.float64]]:
        """The inertia tensor [kg.m^2], shape (3, 3)."""
        return np.array(self.inertia, dtype=float)

    def xacro_value(self) -> str:
        """The description's argument: ``m cx cy cz ixx ixy ixz iyy iyz izz`` (SI)."""
        i = self.inertia
        values = (self.mass, *self.com, i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2])
        return " ".join(repr(float(v)) for v in values)

    def to_dict(self) -> dict[str, Any]:
        """Plain form, as in a design YAML file."""
        return {
            "mass": self.mass,
            "com": list(self.com),
            "inertia": [list(r) for r in self.inertia],
        }


def finite(name: str, value: Any, allowed: str = "a finite number") -> float:
    if isinstance(value, bool):
        raise InvalidParameterError(name, value, allowed)
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, allowed) from None
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, allowed)
    return out


def vec3(name: str, value: Any, *, uniform: bool = False) -> Vec3:
    if isinstance(value, str):
        value = value.replace(",", " ").split()
        if uniform and len(value) == 1:  # one number written as text, as elsewhere
            value = value[0]
    if uniform and not isinstance(value, (list, tuple)):
        v = finite(name, value, "a finite number or three finite numbers")
        return (v, v, v)
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InvalidParameterError(name, value, "three finite numbers")
    x, y, z = (finite(name, v, "three finite numbers") for v in value)
    return (x, y, z)


def offset(name: str, value: Any) -> Vec3:
    out = vec3(name, value)
    if any(abs(v) > MAX_OFFSET for v in out):
        raise InvalidParameterError(
            name, value, f"three numbers within {MAX_OFFSET:g} m of the part frame [m]"
        )
    return out


def check_kind(what: str, kind: Any) -> str:
    if kind not in PART_KINDS:
        raise InvalidParameterError(f"{what} kind", kind, "one of " + ", ".join(PART_KINDS))
    return str(kind)


def mapping_of(name: str, value: Any, keys: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InvalidParameterError(name, value, "a mapping with keys " + ", ".join(keys))
    for key in value:
        if key not in keys:
            raise InvalidParameterError(f"{name} key", key, "one of " + ", ".join(keys))
    return value


def _tensor(name: str, value: Any) -> np.ndarray[Any, np.dtype[np.float64]]:
    allowed = "a 3x3 matrix or six numbers ixx ixy ixz iyy iyz izz [kg.m^2]"
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise InvalidParameterError(name, value, allowed)
    if len(value) == 6 and not any(isinstance(v, (list, tuple)) for v in value):
        xx, xy, xz, yy, yz, zz = (finite(name, v, allowed) for v in value)
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    rows = [list(r) if isinstance(r, (list, tuple)) else None for r in value]
    if len(rows) != 3 or any(r is None or len(r) != 3 for r in rows):
        raise InvalidParameterError(name, value, allowed)
    return np.array([[finite(name, v, allowed) for v in r or ()] for r in rows])


def check_inertia(name: str, tensor: np.ndarray[Any, np.dtype[np.float64]]) -> None:
    """Refuse an inertia tensor that no rigid body has.

    It must be symmetric, positive definite, and its principal moments must
    satisfy the triangle inequality (each at most the sum of the other two),
    within :data:`INERTIA_RTOL` of the largest moment.

    Raises:
        InvalidParameterError: Naming which condition fails.
    """
    scale = float(np.abs(tensor).max()) if tensor.size else 0.0
    if not np.allclose(tensor, tensor.T, rtol=0.0, atol=INERTIA_RTOL * scale):
        raise InvalidParameterError(name, tensor.tolist(), "a symmetric matrix")
    moments = np.linalg.eigvalsh(0.5 * (tensor + tensor.T))
    if not moments[0] > 0.0:
        raise InvalidParameterError(
            name, tensor.tolist(), f"positive definite (principal moments {moments.tolist()})"
        )
    a, b, c = moments
    if c > MAX_MOMENT:
        raise InvalidParameterError(
            name, tensor.tolist(), f"principal moments at most {MAX_MOMENT:g} kg.m^2"
        )
    if c > a + b + INERTIA_RTOL * c:
        raise InvalidParameterError(
            name,
            tensor.tolist(),
            f"principal moments that satisfy the triangle inequality ({c:.6g} > "
            f"{a:.6g} + {b:.6g}: no mass distribution has them)",
        )


def inertia_from(kind: str, value: Any) -> PartInertia:
    """Validate one CAD inertia entry (a :class:`PartInertia` or its mapping form).

    Raises:
        InvalidParameterError: A mass not positive and finite, a non-finite
            centre of mass, or an inertia tensor that fails :func:`check_inertia`.
    """
    from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES, check_plausible

    name = f"inertias.{kind}"
    if isinstance(value, PartInertia):
        value = value.to_dict()
    entry = mapping_of(name, value, ("mass", "com", "inertia"))
    for key in ("mass", "com", "inertia"):
        if key not in entry:
            raise InvalidParameterError(f"{name}.{key}", None, "a value (mass, com, inertia)")
    mass = finite(f"{name}.mass", entry["mass"], "a positive number [kg]")
    if mass <= 0.0:
        raise InvalidParameterError(f"{name}.mass", entry["mass"], "a positive number [kg]")
    check_plausible(f"{name}.mass", mass, *PLAUSIBLE_RANGES[MASS_FIELDS[kind]])
    com = offset(f"{name}.com", entry["com"])
    tensor = _tensor(f"{name}.inertia", entry["inertia"])
    check_inertia(f"{name}.inertia", tensor)
    sym = 0.5 * (tensor + tensor.T)
    r0, r1, r2 = (tuple(float(v) for v in row) for row in sym)
    return PartInertia(
        mass, com, ((r0[0], r0[1], r0[2]), (r1[0], r1[1], r1[2]), (r2[0], r2[1], r2[2]))
    )


def parse_inertias(value: Any) -> PartTable[PartInertia]:
    """The ``inertias`` parameter: part kind -> CAD inertia (see :func:`inertia_from`)."""
    if value is None:
        return PartTable()
    if not isinstance(value, Mapping):
        raise InvalidParameterError("inertias", value, "a mapping of part kind to CAD inertia")
    return PartTable({check_kind("inertias", k): inertia_from(k, v) for k, v in value.items()})


def part_arguments() -> tuple[str, ...]:
    """Names of the description's arguments for meshes and CAD inertias."""
    names: list[str] = []
    for kind in PART_KINDS:
        names += [f"{kind}_mesh", f"{kind}_mesh_scale", f"{kind}_mesh_xyz", f"{kind}_mesh_rpy"]
        names.append(f"{kind}_inertial")
    return tuple(names)


def part_xacro_args(
    meshes: Mapping[str, MeshLike], inertias: Mapping[str, PartInertia]
) -> dict[str, str]:
    """The description's arguments for meshes and CAD inertias (all strings).

    A kind without a mesh gets ``""`` (the primitive is drawn); a kind without
    a CAD inertia gets ``""`` (sizes and density).
    """
    args: dict[str, str] = {}
    for kind in PART_KINDS:
        mesh = meshes.get(kind)
        scale, xyz, rpy = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        if mesh is not None:
            scale, xyz, rpy = mesh.scale, mesh.xyz, mesh.rpy
        args[f"{kind}_mesh"] = "" if mesh is None else str(mesh.file)
        args[f"{kind}_mesh_scale"] = " ".join(repr(float(v)) for v in scale)
        args[f"{kind}_mesh_xyz"] = " ".join(repr(float(v)) for v in xyz)
        args[f"{kind}_mesh_rpy"] = " ".join(repr(float(v)) for v in rpy)
        inertia = inertias.get(kind)
        args[f"{kind}_inertial"] = "" if inertia is None else inertia.xacro_value()
    return args


__all__ = [
    "PART_FRAMES",
    "PART_KINDS",
    "PartInertia",
    "PartTable",
    "check_inertia",
    "parse_inertias",
    "part_arguments",
    "part_xacro_args",
]
