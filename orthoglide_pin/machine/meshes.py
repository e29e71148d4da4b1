"""CAD mesh files per kind of part, drawn instead of the primitives.

A mesh (STL, OBJ or DAE) is given per kind of part in the ``meshes``
parameter of :class:`~orthoglide_pin.machine.params.OrthoglideParams` (see
:mod:`~orthoglide_pin.machine.parts` for the kinds and their part frames). It
is checked when the parameters are built, and refused in one line naming the
mesh parameter otherwise:

* the file is a regular file (not a FIFO or a device) of at most
  :data:`MAX_MESH_BYTES`, checked before it is read;
* it holds at most :data:`MAX_MESH_TRIANGLES` triangles (and
  :data:`MAX_MESH_VERTICES` vertices): a binary STL's header and an OBJ's
  lines are counted before the mesh is loaded;
* it has a known format and holds triangles (read with trimesh), its vertices
  are finite and its triangles are not all degenerate (without area);
* its scale is positive and, scaled, every vertex lies within
  :data:`MAX_VERTEX_DISTANCE` of the mesh's frame and the mesh spans at least
  :data:`MIN_MESH_EXTENT`: a file in millimetres with the default scale 1 is
  refused with the hint ``scale: 0.001``;
* its origin is plausible.

A mesh is geometry, not mass: the inertias stay those of the parameters.
"""

from __future__ import annotations

import hashlib
import math
import os
import stat
import struct
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._paths import special_kind
from orthoglide_pin.exceptions import (
    DescriptionError,
    InvalidParameterError,
    cut_text,
    path_repr,
    short_repr,
)
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
#: Largest mesh file [bytes] (64 MiB: an ASCII STL of about 250,000 triangles).
MAX_MESH_BYTES: Final = 64 * 2**20
#: Most triangles in one mesh. A kind of part is drawn up to six times (the bars):
#: 185,000 triangles on the bars give a 27 MB page, written in 14 s (``view
#: --static``; the machine of primitives: 0.9 MB in 3 s).
MAX_MESH_TRIANGLES: Final = 200_000
#: Most vertices in one mesh file (three per triangle, as in an STL).
MAX_MESH_VERTICES: Final = 3 * MAX_MESH_TRIANGLES
#: Farthest a scaled vertex may lie from the mesh's own frame [m].
MAX_VERTEX_DISTANCE: Final = 10.0
#: Smallest span (largest side of the bounding box) of a scaled mesh [m].
MIN_MESH_EXTENT: Final = 1e-3
#: A triangle whose area is below this fraction of the squared span is degenerate.
AREA_RTOL: Final = 1e-12
# Triangles whose areas are computed at once.
_AREA_BLOCK = 65536
# Binary STL: an 80-byte header, the triangle count, then 50 bytes per triangle.
_STL_HEADER, _STL_TRIANGLE = 84, 50
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


class MeshRefusedError(DescriptionError):
    """A mesh file that is not drawn: too large, too many triangles, degenerate.

    Attributes:
        path: The mesh file.
        allowed: What a mesh must be, for the parameter's error message.
    """

    def __init__(self, path: str | os.PathLike[str], allowed: str) -> None:
        self.path = os.fspath(path)
        self.allowed = allowed
        super().__init__(
            f"the mesh {short_repr(Path(self.path))} is refused: expected {allowed}", self.path
        )


def check_mesh_file(path: str | os.PathLike[str]) -> os.stat_result:
    """Check a mesh file before it is read: regular, not too large, not too many triangles.

    The size comes from ``stat``, the triangle count of a binary STL from its
    84-byte header, and those of an OBJ from its vertex and face lines (read in
    blocks): nothing of the size of the file is held in memory.

    Raises:
        MeshRefusedError: Not a regular file, over :data:`MAX_MESH_BYTES`, or
            announcing more than :data:`MAX_MESH_TRIANGLES` triangles or
            :data:`MAX_MESH_VERTICES` vertices.
        DescriptionError: If the file cannot be read.
    """
    try:
        info = os.stat(path)
    except OSError as exc:
        raise DescriptionError(
            f"cannot read the mesh {short_repr(Path(os.fspath(path)))}: {exc}", path
        ) from None
    kind = special_kind(info.st_mode)
    if kind is not None or not stat.S_ISREG(info.st_mode):
        raise MeshRefusedError(path, f"a regular file (it is a {kind or 'directory'})")
    if info.st_size == 0:  # empty, or a file of /proc or /sys, which report no size
        raise MeshRefusedError(
            path, "a mesh with triangles (the file is empty, or reports no size)"
        )
    if info.st_size > MAX_MESH_BYTES:
        raise MeshRefusedError(
            path,
            f"a mesh file of at most {MAX_MESH_BYTES} bytes ({MAX_MESH_BYTES >> 20} MiB; "
            f"it has {info.st_size}): simplify the mesh",
        )
    suffix = os.fspath(path).lower().rsplit(".", 1)[-1]
    vertices = None
    try:
        with open(path, "rb") as fh:
            announced = _stl_triangles(fh, info.st_size) if suffix == "stl" else None
            if suffix == "obj":
                vertices, announced = _obj_lines(fh)
    except OSError as exc:
        raise DescriptionError(
            f"cannot read the mesh {short_repr(Path(os.fspath(path)))}: {exc}", path
        ) from None
    if announced is not None and announced > MAX_MESH_TRIANGLES:
        raise MeshRefusedError(
            path, f"at most {MAX_MESH_TRIANGLES} triangles (it announces {announced})"
        )
    if vertices is not None and vertices > MAX_MESH_VERTICES:
        raise MeshRefusedError(path, f"at most {MAX_MESH_VERTICES} vertices (it has {vertices})")
    return info


def _stl_triangles(fh: Any, size: int) -> int | None:
    """The triangle count of a binary STL's header, ``None`` for an ASCII STL."""
    head = fh.read(_STL_HEADER)
    if len(head) < _STL_HEADER:
        return None
    (count,) = struct.unpack_from("<I", head, 80)
    exact = size == _STL_HEADER + _STL_TRIANGLE * count
    return int(count) if exact or not head.startswith(b"solid") else None


def _obj_lines(fh: Any) -> tuple[int, int]:
    """Vertex and face lines of an OBJ file (``v ...``, ``f ...``), counted in 1 MiB blocks."""
    vertices = faces = 0
    previous = b"\n"
    for block in iter(lambda: fh.read(1 << 20), b""):
        text = previous + block  # a line start cut by the block's edge is counted once
        vertices += text.count(b"\nv ")
        faces += text.count(b"\nf ")
        previous = block[-2:] if len(block) >= 2 else previous[-1:] + block
    return vertices, faces


def read_mesh(path: str | os.PathLike[str]) -> tuple[NDArray[np.float64], NDArray[np.uint32]]:
    """Vertices [file units], shape (n, 3), and triangles, shape (m, 3), of a mesh file.

    STL, OBJ and DAE are read with trimesh (a file of several parts is merged),
    after :func:`check_mesh_file`. Cached on the file's path, size and
    modification time.

    Raises:
        MeshRefusedError: A file over the caps, a non-finite vertex, or
            triangles that all lack area.
        DescriptionError: If the file cannot be read or holds no triangle.
    """
    st = check_mesh_file(path)
    return _read_mesh(os.fspath(path), st.st_size, st.st_mtime_ns)


@lru_cache(maxsize=64)
def _read_mesh(
    path: str, size: int, mtime_ns: int
) -> tuple[NDArray[np.float64], NDArray[np.uint32]]:
    import trimesh  # imported on first use: only a design with meshes needs it

    try:  # as the file says: trimesh's processing would drop non-finite vertices silently
        mesh: Any = trimesh.load(path, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds of errors on bad files
        raise DescriptionError(
            f"cannot read the mesh {short_repr(Path(path))}: {cut_text(str(exc))}", path
        ) from None
    vertices = np.asarray(getattr(mesh, "vertices", ()), dtype=np.float64).reshape(-1, 3)
    triangles = np.asarray(getattr(mesh, "faces", ()), dtype=np.int64).reshape(-1, 3)
    if not len(triangles):
        raise DescriptionError(f"the mesh {short_repr(Path(path))} has no triangle", path)
    if len(triangles) > MAX_MESH_TRIANGLES:
        count = len(triangles)
        raise MeshRefusedError(path, f"at most {MAX_MESH_TRIANGLES} triangles (it has {count})")
    if len(vertices) > MAX_MESH_VERTICES:
        count = len(vertices)
        raise MeshRefusedError(path, f"at most {MAX_MESH_VERTICES} vertices (it has {count})")
    if not np.isfinite(vertices).all():
        raise MeshRefusedError(path, "finite vertices (it has an infinite or NaN coordinate)")
    if not _has_area(vertices, triangles):
        raise MeshRefusedError(
            path, f"triangles with area (all {len(triangles)} are degenerate: points or lines)"
        )
    with np.errstate(all="ignore"):  # huge coordinates overflow the merge's rounding
        mesh.merge_vertices()  # what trimesh's processing does to finite vertices
    vertices = np.asarray(getattr(mesh, "vertices", ()), dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(getattr(mesh, "faces", ()), dtype=np.uint32).reshape(-1, 3)
    vertices.flags.writeable = False  # shared by the cache
    faces.flags.writeable = False
    return vertices, faces


def _has_area(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> bool:
    """Whether some triangle has an area above :data:`AREA_RTOL` times the squared span.

    Computed on the vertices mapped into the unit box, so that no coordinate
    overflows (a file may hold 1e300) and the test does not depend on units.
    """
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    span = float((high - low).max())
    if not span > 0.0:
        return False
    for start in range(0, len(faces), _AREA_BLOCK):  # a real mesh answers in its first block
        block = faces[start : start + _AREA_BLOCK]
        a, b, c = ((vertices[block[:, k]] - low) / span for k in range(3))
        doubled = np.linalg.norm(np.cross(b - a, c - a), axis=1)
        if (doubled > 2.0 * AREA_RTOL).any():
            return True
    return False


def _check_size(name: str, given: str, vertices: NDArray[np.float64], scale: Vec3) -> None:
    """Refuse a scaled mesh too far from its frame, or too small, naming the scale meant.

    Scaled, every vertex must lie within :data:`MAX_VERTEX_DISTANCE` of the
    mesh frame and the mesh must span at least :data:`MIN_MESH_EXTENT`; a
    scale 1000 times smaller or larger that satisfies both is the hint.
    """
    with np.errstate(over="ignore"):  # 1e300 in a file, times the scale: inf, refused
        scaled = vertices * np.asarray(scale)
        reach = float(np.abs(scaled).max())
        span = float((scaled.max(axis=0) - scaled.min(axis=0)).max())

    def plausible(factor: float) -> bool:
        return factor * reach <= MAX_VERTEX_DISTANCE and factor * span >= MIN_MESH_EXTENT

    if plausible(1.0):
        return
    shown = list(dict.fromkeys(scale))
    allowed = (
        f"a scale that puts the mesh {short_repr(given)} within {MAX_VERTEX_DISTANCE:g} m "
        "of its frame "
        f"and at least {MIN_MESH_EXTENT * 1e3:g} mm across (scaled by {shown}, it reaches "
        f"{reach:.4g} m and spans {span:.4g} m)"
    )
    for factor in (1e-3, 1e3):  # a file in millimetres, or a scale for one given to metres
        if plausible(factor):
            meant = ", ".join(f"{factor * s:g}" for s in shown)
            allowed += f"; did you mean scale: {meant}?"
            break
    raise InvalidParameterError(f"{name}.scale", shown[0] if len(shown) == 1 else shown, allowed)


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
    if not path.exists():
        raise InvalidParameterError(
            f"{name}.file", given, f"an existing file (not found: {path_repr(str(path))})"
        )
    try:
        vertices = read_mesh(path)[0]
    except MeshRefusedError as exc:
        raise InvalidParameterError(f"{name}.file", given, exc.allowed) from None
    except DescriptionError as exc:
        raise InvalidParameterError(
            f"{name}.file", given, f"a mesh with triangles ({exc})"
        ) from None
    scale = vec3(f"{name}.scale", entry.get("scale", 1.0), uniform=True)
    if any(not 0.0 < s <= MAX_SCALE for s in scale):
        raise InvalidParameterError(
            f"{name}.scale", entry.get("scale"), f"positive numbers, at most {MAX_SCALE:g}"
        )
    _check_size(name, given, vertices, scale)
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


__all__ = [
    "MAX_MESH_BYTES",
    "MAX_MESH_TRIANGLES",
    "MESH_SUFFIXES",
    "MeshRefusedError",
    "PartMesh",
    "check_mesh_file",
    "mesh_from",
    "parse_meshes",
    "read_mesh",
]
