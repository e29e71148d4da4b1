"""CAD mesh files per kind of part, drawn instead of the primitives.

A mesh (STL, OBJ or DAE) is given per kind of part in the ``meshes``
parameter of :class:`~orthoglide_pin.machine.params.OrthoglideParams` (see
:mod:`~orthoglide_pin.machine.parts` for the kinds and their part frames). It
is checked when the parameters are built: the file exists, has a known format
and holds triangles (read with trimesh), its scale is positive and its origin
plausible. A mesh is geometry, not mass: the inertias stay those of the
parameters.
"""

from __future__ import annotations

import hashlib
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.exceptions import DescriptionError, InvalidParameterError
from orthoglide_pin.machine.parts import (
    PartTable,
    Vec3,
    check_kind,
    mapping_of,
    offset,
    vec3,
)

#: Mesh file formats drawn (through trimesh) and loaded by Pinocchio.
MESH_SUFFIXES: Final = (".stl", ".obj", ".dae")
#: Largest scale factor of a mesh.
MAX_SCALE: Final = 1e3
# Characters refused in a mesh file name: xacro evaluates $, XML needs the rest escaped.
_FORBIDDEN_PATH_CHARS: Final = frozenset('$"<>&')


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
    entry = mapping_of(name, value, ("file", "scale", "origin"))
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
    scale = vec3(f"{name}.scale", entry.get("scale", 1.0), uniform=True)
    if any(not 0.0 < s <= MAX_SCALE for s in scale):
        raise InvalidParameterError(
            f"{name}.scale", entry.get("scale"), f"positive numbers, at most {MAX_SCALE:g}"
        )
    origin = mapping_of(f"{name}.origin", entry.get("origin", {}), ("xyz", "rpy"))
    xyz = offset(f"{name}.origin.xyz", origin.get("xyz", (0.0, 0.0, 0.0)))
    rpy = vec3(f"{name}.origin.rpy", origin.get("rpy", (0.0, 0.0, 0.0)))
    if any(abs(a) > 4.0 * math.pi for a in rpy):
        raise InvalidParameterError(f"{name}.origin.rpy", list(rpy), "angles within 4 pi [rad]")
    return PartMesh(path, scale, xyz, rpy)


def parse_meshes(
    value: Any, base_dir: str | os.PathLike[str] | None = None
) -> PartTable[PartMesh]:
    """The ``meshes`` parameter: a mapping of part kind -> mesh entry (see :func:`mesh_from`)."""
    if value is None:
        return PartTable()
    if not isinstance(value, Mapping):
        raise InvalidParameterError("meshes", value, "a mapping of part kind to mesh file")
    return PartTable(
        {check_kind("meshes", k): mesh_from(k, v, base_dir) for k, v in value.items()}
    )


__all__ = ["MESH_SUFFIXES", "PartMesh", "mesh_from", "parse_meshes", "read_mesh"]
