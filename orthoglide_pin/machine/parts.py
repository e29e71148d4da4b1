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
the inertia tensor are given (:data:`PART_FRAMES`).
"""

from __future__ import annotations

import hashlib
import math
import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Final, TypeVar

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.exceptions import DescriptionError, InvalidParameterError

Vec3 = tuple[float, float, float]
_T = TypeVar("_T")

#: Kinds of part that take a mesh or a CAD inertia.
PART_KINDS: Final = ("carriage", "bar", "small_link", "platform", "spindle")
#: Mesh file formats drawn (through trimesh) and loaded by Pinocchio.
MESH_SUFFIXES: Final = (".stl", ".obj", ".dae")
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
#: frame [m], scales at most this, principal moments at most this [kg.m^2].
MAX_OFFSET: Final = 10.0
MAX_SCALE: Final = 1e3
MAX_MOMENT: Final = 1e3
_FORBIDDEN_PATH_CHARS: Final = frozenset('$"<>&')


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
class PartMesh:
    """A mesh file drawn for one kind of part.

    Attributes:
        file: Absolute path of the STL, OBJ or DAE file.
        scale: Scale applied to the file's coordinates, per axis (0.001 for a
            file in mm), shape (3,).
        xyz: Position of the mesh's own frame in the part frame [m], shape (3,).
        rpy: Roll, pitch, yaw of the mesh's own frame in the part frame [rad],
            shape (3,).
    """

    file: Path
    scale: Vec3 = (1.0, 1.0, 1.0)
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    def digest(self) -> str:
        """SHA-256 of the file's content (part of the URDF cache key)."""
        h = hashlib.sha256()
        with self.file.open("rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest()

    def to_dict(self) -> dict[str, Any]:
        """Plain form, as in a design YAML file (absolute file name)."""
        return {
            "file": str(self.file),
            "scale": list(self.scale),
            "origin": {"xyz": list(self.xyz), "rpy": list(self.rpy)},
        }


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


def read_mesh(path: str | os.PathLike[str]) -> tuple[NDArray[np.float64], NDArray[np.uint32]]:
    """Vertices [file units], shape (n, 3), and triangles, shape (m, 3), of a mesh file.

    STL, OBJ and DAE are read with trimesh (a file of several parts is merged).
    Cached on the file's path, size and modification time.

    Raises:
        DescriptionError: If the file cannot be read or holds no finite triangle.
    """
    try:
        st = os.stat(path)
    except OSError as exc:
        raise DescriptionError(f"cannot read the mesh {os.fspath(path)!r}: {exc}", path) from None
    return _read_mesh(os.fspath(path), st.st_size, st.st_mtime_ns)


@lru_cache(maxsize=64)
def _read_mesh(
    path: str, size: int, mtime_ns: int
) -> tuple[NDArray[np.float64], NDArray[np.uint32]]:
    import trimesh  # imported on first use: only a design with meshes needs it

    try:
        mesh = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many kinds of errors on bad files
        raise DescriptionError(f"cannot read the mesh {path!r}: {exc}", path) from None
    vertices = np.asarray(getattr(mesh, "vertices", ()), dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(getattr(mesh, "faces", ()), dtype=np.uint32).reshape(-1, 3)
    if not len(faces) or not np.isfinite(vertices).all():
        raise DescriptionError(f"the mesh {path!r} has no finite triangle", path)
    vertices.flags.writeable = False  # shared by the cache
    faces.flags.writeable = False
    return vertices, faces


def _finite(name: str, value: Any, allowed: str = "a finite number") -> float:
    if isinstance(value, bool):
        raise InvalidParameterError(name, value, allowed)
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, allowed) from None
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, allowed)
    return out


def _vec3(name: str, value: Any, *, uniform: bool = False) -> Vec3:
    if uniform and not isinstance(value, (list, tuple, str)):
        v = _finite(name, value, "a finite number or three finite numbers")
        return (v, v, v)
    if isinstance(value, str):
        value = value.replace(",", " ").split()
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InvalidParameterError(name, value, "three finite numbers")
    x, y, z = (_finite(name, v, "three finite numbers") for v in value)
    return (x, y, z)


def _offset(name: str, value: Any) -> Vec3:
    out = _vec3(name, value)
    if any(abs(v) > MAX_OFFSET for v in out):
        raise InvalidParameterError(
            name, value, f"three numbers within {MAX_OFFSET:g} m of the part frame [m]"
        )
    return out


def _check_kind(what: str, kind: Any) -> str:
    if kind not in PART_KINDS:
        raise InvalidParameterError(f"{what} kind", kind, "one of " + ", ".join(PART_KINDS))
    return str(kind)


def _mapping(name: str, value: Any, keys: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InvalidParameterError(name, value, "a mapping with keys " + ", ".join(keys))
    for key in value:
        if key not in keys:
            raise InvalidParameterError(f"{name} key", key, "one of " + ", ".join(keys))
    return value


def mesh_from(kind: str, value: Any, base_dir: str | os.PathLike[str] | None = None) -> PartMesh:
    """Validate one mesh entry (a :class:`PartMesh` or its mapping form).

    Args:
        kind: The part kind (for the messages).
        value: ``{file, scale, origin: {xyz, rpy}}``; ``scale`` one number or three.
        base_dir: Folder of a relative file name (the current directory if ``None``).

    Raises:
        InvalidParameterError: Naming the bad value: a missing file, another
            format than STL/OBJ/DAE, a file without triangles, a scale not
            positive and finite, a non-finite origin.
    """
    name = f"meshes.{kind}"
    if isinstance(value, PartMesh):
        value = value.to_dict()
    elif isinstance(value, (str, os.PathLike)):
        value = {"file": value}
    entry = _mapping(name, value, ("file", "scale", "origin"))
    if "file" not in entry or not isinstance(entry["file"], (str, os.PathLike)):
        raise InvalidParameterError(f"{name}.file", entry.get("file"), "a mesh file name")
    given = os.fspath(entry["file"])
    if not given or any(c in _FORBIDDEN_PATH_CHARS or ord(c) < 32 for c in given):
        raise InvalidParameterError(
            f"{name}.file", given, 'a file name without control characters or $ " < > &'
        )
    path = Path(given).expanduser()
    if not path.is_absolute():
        path = Path(base_dir if base_dir is not None else Path.cwd()) / path
    path = Path(os.path.abspath(path))
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise InvalidParameterError(f"{name}.file", given, "an STL, OBJ or DAE file")
    if not path.is_file():
        raise InvalidParameterError(f"{name}.file", given, f"an existing file (not found: {path})")
    try:
        read_mesh(path)
    except DescriptionError as exc:
        raise InvalidParameterError(
            f"{name}.file", given, f"a mesh with triangles ({exc})"
        ) from None
    scale = _vec3(f"{name}.scale", entry.get("scale", 1.0), uniform=True)
    if any(not 0.0 < s <= MAX_SCALE for s in scale):
        raise InvalidParameterError(
            f"{name}.scale", entry.get("scale"), f"positive numbers, at most {MAX_SCALE:g}"
        )
    origin = _mapping(f"{name}.origin", entry.get("origin", {}), ("xyz", "rpy"))
    xyz = _offset(f"{name}.origin.xyz", origin.get("xyz", (0.0, 0.0, 0.0)))
    rpy = _vec3(f"{name}.origin.rpy", origin.get("rpy", (0.0, 0.0, 0.0)))
    if any(abs(a) > 4.0 * math.pi for a in rpy):
        raise InvalidParameterError(f"{name}.origin.rpy", list(rpy), "angles within 4 pi [rad]")
    return PartMesh(path, scale, xyz, rpy)


def _tensor(name: str, value: Any) -> np.ndarray[Any, np.dtype[np.float64]]:
    allowed = "a 3x3 matrix or six numbers ixx ixy ixz iyy iyz izz [kg.m^2]"
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise InvalidParameterError(name, value, allowed)
    if len(value) == 6 and not any(isinstance(v, (list, tuple)) for v in value):
        xx, xy, xz, yy, yz, zz = (_finite(name, v, allowed) for v in value)
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    rows = [list(r) if isinstance(r, (list, tuple)) else None for r in value]
    if len(rows) != 3 or any(r is None or len(r) != 3 for r in rows):
        raise InvalidParameterError(name, value, allowed)
    return np.array([[_finite(name, v, allowed) for v in r or ()] for r in rows])


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
    entry = _mapping(name, value, ("mass", "com", "inertia"))
    for key in ("mass", "com", "inertia"):
        if key not in entry:
            raise InvalidParameterError(f"{name}.{key}", None, "a value (mass, com, inertia)")
    mass = _finite(f"{name}.mass", entry["mass"], "a positive number [kg]")
    if mass <= 0.0:
        raise InvalidParameterError(f"{name}.mass", entry["mass"], "a positive number [kg]")
    check_plausible(f"{name}.mass", mass, *PLAUSIBLE_RANGES[MASS_FIELDS[kind]])
    com = _offset(f"{name}.com", entry["com"])
    tensor = _tensor(f"{name}.inertia", entry["inertia"])
    check_inertia(f"{name}.inertia", tensor)
    sym = 0.5 * (tensor + tensor.T)
    r0, r1, r2 = (tuple(float(v) for v in row) for row in sym)
    return PartInertia(
        mass, com, ((r0[0], r0[1], r0[2]), (r1[0], r1[1], r1[2]), (r2[0], r2[1], r2[2]))
    )


def parse_meshes(
    value: Any, base_dir: str | os.PathLike[str] | None = None
) -> PartTable[PartMesh]:
    """The ``meshes`` parameter: a mapping of part kind -> mesh entry (see :func:`mesh_from`)."""
    if value is None:
        return PartTable()
    if not isinstance(value, Mapping):
        raise InvalidParameterError("meshes", value, "a mapping of part kind to mesh file")
    return PartTable(
        {_check_kind("meshes", k): mesh_from(k, v, base_dir) for k, v in value.items()}
    )


def parse_inertias(value: Any) -> PartTable[PartInertia]:
    """The ``inertias`` parameter: part kind -> CAD inertia (see :func:`inertia_from`)."""
    if value is None:
        return PartTable()
    if not isinstance(value, Mapping):
        raise InvalidParameterError("inertias", value, "a mapping of part kind to CAD inertia")
    return PartTable({_check_kind("inertias", k): inertia_from(k, v) for k, v in value.items()})


def part_arguments() -> tuple[str, ...]:
    """Names of the description's arguments for meshes and CAD inertias."""
    names: list[str] = []
    for kind in PART_KINDS:
        names += [f"{kind}_mesh", f"{kind}_mesh_scale", f"{kind}_mesh_xyz", f"{kind}_mesh_rpy"]
        names.append(f"{kind}_inertial")
    return tuple(names)


def part_xacro_args(
    meshes: Mapping[str, PartMesh], inertias: Mapping[str, PartInertia]
) -> dict[str, str]:
    """The description's arguments for meshes and CAD inertias (all strings).

    A kind without a mesh gets ``""`` (the primitive is drawn); a kind without
    a CAD inertia gets ``""`` (sizes and density).
    """
    args: dict[str, str] = {}
    for kind in PART_KINDS:
        mesh = meshes.get(kind)
        mesh = mesh if mesh is not None else PartMesh(Path(""))
        args[f"{kind}_mesh"] = str(mesh.file) if kind in meshes else ""
        args[f"{kind}_mesh_scale"] = " ".join(repr(float(v)) for v in mesh.scale)
        args[f"{kind}_mesh_xyz"] = " ".join(repr(float(v)) for v in mesh.xyz)
        args[f"{kind}_mesh_rpy"] = " ".join(repr(float(v)) for v in mesh.rpy)
        inertia = inertias.get(kind)
        args[f"{kind}_inertial"] = "" if inertia is None else inertia.xacro_value()
    return args


__all__ = [
    "MESH_SUFFIXES",
    "PART_FRAMES",
    "PART_KINDS",
    "PartInertia",
    "PartMesh",
    "PartTable",
    "check_inertia",
    "parse_inertias",
    "parse_meshes",
    "read_mesh",
]
