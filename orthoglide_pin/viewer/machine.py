"""The machine drawn from its own URDF: visual geometry placed by Pinocchio.

Every ``<visual>`` of the description (rails, carriages, small links, both bars
of each parallelogram, platform, spindle, tool) is read by Pinocchio's URDF
parser (``buildGeomFromUrdfString``, ``GeometryType.VISUAL``) with its shape,
size, placement on its link and material colour; there is no second drawing of
the machine. A configuration of the 18 joints of the cut tree, with its loops
closed (:meth:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel.configuration` or
:meth:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel.solve`), places every
visual through forward kinematics. Boxes, cylinders and spheres are drawn as
meshcat primitives; a CAD mesh of the description (STL, OBJ or DAE, see
:mod:`orthoglide_pin.machine.parts`) is read with trimesh, scaled, and drawn as
a triangle mesh whose vertices travel inside the scene, so that a static page
(:func:`~orthoglide_pin.viewer.html.static_html`) still opens offline.

meshcat draws a cylinder along its local y axis and a URDF cylinder runs along
local z: each cylinder mesh carries the fixed rotation ``Rx(pi/2)`` that maps
one onto the other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.exceptions import DescriptionError, InvalidParameterError
from orthoglide_pin.machine.meshes import read_mesh
from orthoglide_pin.viewer.scene import Scene, meshcat

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

FloatArray = NDArray[np.float64]

#: meshcat path of the machine's visuals, below the scene root.
MACHINE_PATH = "machine"
#: Rotation that turns meshcat's y-axis cylinder into the URDF's z-axis cylinder.
CYLINDER_TO_URDF = np.array(
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


@dataclass(frozen=True)
class Visual:
    """One visual of the URDF.

    Attributes:
        name: Pinocchio's geometry name (``<link>_<k>``), also its meshcat node.
        link: Name of the link that carries it.
        shape: ``"box"``, ``"cylinder"``, ``"sphere"`` or ``"mesh"``.
        size: Box sides ``(x, y, z)``; cylinder ``(radius, length)``; sphere
            ``(radius,)`` [m]; mesh: its scale per axis.
        rgba: Material colour, each in [0, 1].
        mesh: The mesh file, for a ``"mesh"``; ``""`` otherwise.
    """

    name: str
    link: str
    shape: str
    size: tuple[float, ...]
    rgba: tuple[float, float, float, float]
    mesh: str = ""


def rgb_int(rgb: ArrayLike) -> int:
    """An RGB colour in [0, 1] as three.js's ``0xRRGGBB`` integer."""
    r, g, b = (min(255, max(0, round(255 * float(c)))) for c in np.ravel(rgb)[:3])
    return (r << 16) | (g << 8) | b


def _visual(obj: Any, link: str) -> Visual:
    geo, kind = obj.geometry, type(obj.geometry).__name__
    rgba = tuple(float(c) for c in obj.meshColor)
    if kind == "Box":
        size: tuple[float, ...] = tuple(2.0 * float(h) for h in geo.halfSide)
        shape = "box"
    elif kind == "Cylinder":
        size, shape = (float(geo.radius), 2.0 * float(geo.halfLength)), "cylinder"
    elif kind == "Sphere":
        size, shape = (float(geo.radius),), "sphere"
    elif obj.meshPath:
        colour = (rgba[0], rgba[1], rgba[2], rgba[3])
        scale = tuple(float(s) for s in obj.meshScale)
        return Visual(obj.name, link, "mesh", scale, colour, str(obj.meshPath))
    else:
        raise DescriptionError(
            f"visual {obj.name!r} is a {kind}: only boxes, cylinders, spheres and meshes "
            "are drawn",
            obj.name,
        )
    return Visual(obj.name, link, shape, size, (rgba[0], rgba[1], rgba[2], rgba[3]))


class MachineDrawing:
    """The visuals of a closed-loop model, ready to draw in a :class:`Scene`.

    Args:
        model: The closed-loop model (its Pinocchio model places the visuals of
            the URDF it was built from).

    Attributes:
        visuals: Every visual of the URDF, in Pinocchio's order.
    """

    def __init__(self, model: ClosedLoopModel) -> None:
        self.model = model
        try:
            self._geometry = pin.buildGeomFromUrdfString(
                model.model, model.urdf, pin.GeometryType.VISUAL
            )
        except Exception as exc:  # Pinocchio raises ValueError/RuntimeError on bad XML
            raise DescriptionError(f"Pinocchio could not read the visuals: {exc}") from exc
        self._gdata = pin.GeometryData(self._geometry)
        self._data = model.model.createData()
        frames = model.model.frames
        self.visuals = tuple(
            _visual(obj, frames[obj.parentFrame].name) for obj in self._geometry.geometryObjects
        )

    def __len__(self) -> int:
        return len(self.visuals)

    def names(self) -> list[str]:
        """The visuals' names (their meshcat nodes below :data:`MACHINE_PATH`)."""
        return [v.name for v in self.visuals]

    def objects(self) -> list[dict[str, Any]]:
        """The lowered meshcat meshes of the visuals, in their own frames."""
        g = meshcat("geometry")
        out = []
        for v in self.visuals:
            intrinsic = np.eye(4)
            if v.shape == "box":
                geometry = g.Box(list(v.size))
            elif v.shape == "cylinder":
                geometry, intrinsic = g.Cylinder(v.size[1], v.size[0]), CYLINDER_TO_URDF
            elif v.shape == "mesh":
                vertices, faces = read_mesh(v.mesh)
                geometry = g.TriangularMeshGeometry(vertices * np.asarray(v.size), faces)
            else:
                geometry = g.Sphere(v.size[0])
            material = g.MeshLambertMaterial(color=rgb_int(v.rgba), opacity=v.rgba[3])
            lowered: dict[str, Any] = g.Mesh(geometry, material).lower()
            lowered["object"]["matrix"] = [float(x) for x in intrinsic.T.ravel()]
            out.append(lowered)
        return out

    def placements(self, configurations: ArrayLike) -> FloatArray:
        """World placements of every visual for configurations of the 18 joints.

        Args:
            configurations: Joint values [m, rad], shape (18,) or (N, 18).

        Returns:
            Homogeneous matrices [m], shape (n_visuals, 4, 4) or
            (N, n_visuals, 4, 4).

        Raises:
            InvalidParameterError: On a wrongly shaped or non-finite input.
        """
        q = np.asarray(configurations, dtype=float)
        nq = self.model.model.nq
        if q.ndim not in (1, 2) or q.shape[-1] != nq or not np.isfinite(q).all():
            raise InvalidParameterError(
                "configuration", f"array of shape {q.shape}", f"finite values of shape ({nq},)"
            )
        batch = q.reshape(-1, nq)
        out = np.empty((batch.shape[0], len(self.visuals), 4, 4))
        for k, qk in enumerate(batch):
            pin.forwardKinematics(self.model.model, self._data, qk)
            pin.updateGeometryPlacements(self.model.model, self._data, self._geometry, self._gdata)
            for i, placement in enumerate(self._gdata.oMg):
                out[k, i] = placement.homogeneous
        return out[0] if q.ndim == 1 else out

    def draw(self, scene: Scene, root: str, configuration: ArrayLike) -> None:
        """Add every visual under ``root/machine`` placed at ``configuration``."""
        for v, obj in zip(self.visuals, self.objects(), strict=True):
            scene.set_object(f"{root}/{MACHINE_PATH}/{v.name}", obj)
        self.place(scene, root, configuration)

    def place(self, scene: Scene, root: str, configuration: ArrayLike) -> None:
        """Move the drawn visuals to ``configuration`` (transforms only)."""
        for v, m in zip(self.visuals, self.placements(configuration), strict=True):
            scene.set_transform(f"{root}/{MACHINE_PATH}/{v.name}", m)

    def bounds(self, configuration: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Axis-aligned box around the drawn machine [m]: ``(lower, upper)``, shape (3,).

        Each visual counts as the sphere that encloses it.
        """
        centres = self.placements(configuration)[:, :3, 3]
        radii = np.array([_radius(v) for v in self.visuals])
        return (centres - radii[:, None]).min(axis=0), (centres + radii[:, None]).max(axis=0)


def _radius(v: Visual) -> float:
    """Radius of the sphere that encloses a visual [m]."""
    if v.shape == "box":
        return 0.5 * math.sqrt(sum(s * s for s in v.size))
    if v.shape == "cylinder":
        return math.hypot(v.size[0], 0.5 * v.size[1])
    if v.shape == "mesh":
        vertices = read_mesh(v.mesh)[0] * np.asarray(v.size)
        return float(np.sqrt((vertices**2).sum(axis=1)).max())
    return v.size[0]
