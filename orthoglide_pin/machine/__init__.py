"""The machine: its parameters, its xacro description and its closed-loop Pinocchio model.

* :mod:`~orthoglide_pin.machine.params`: :class:`OrthoglideParams`, validated,
  with the prototype's values (:func:`prototype`) and YAML round trip;
* :mod:`~orthoglide_pin.machine.digest`: the design digest a file records,
  :func:`design_digest`, and :func:`check_design`, which refuses another's;
* :mod:`~orthoglide_pin.machine.criterion`: the criterion a machine carries,
  bounds on its transmission factors over its cube, and the one tolerance rule;
* :mod:`~orthoglide_pin.machine.description`: the xacro rendered to a URDF
  (cached, atomic) and the loop data beside it;
* :mod:`~orthoglide_pin.machine.parts`: CAD per kind of part, its frames and
  measured inertias (:class:`PartInertia`), validated;
* :mod:`~orthoglide_pin.machine.meshes`: CAD mesh files (:class:`PartMesh`),
  checked (format, triangles, scale, origin) and read with trimesh;
* :mod:`~orthoglide_pin.machine.export`: a self-contained description folder
  (URDF, loop data, meshes) for other tools (:func:`write_package`);
* :mod:`~orthoglide_pin.machine.loaders`: one-line loaders for Pinocchio,
  yourdfpy and the closed-loop model, the URDF validated with yourdfpy;
* :mod:`~orthoglide_pin.machine.closed_loop`: :class:`ClosedLoopModel`, the
  Pinocchio cut tree with its five closures solved for real (loaded on first
  use: it imports Pinocchio; Newton's method in
  :mod:`~orthoglide_pin.machine.newton`), its Jacobians from
  :mod:`~orthoglide_pin.machine.projection` and its URDF loaded by
  :func:`~orthoglide_pin.machine.loading.load_model` (masses checked against
  the URDF's inertial elements).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.machine.criterion import CRITERION_TOL, PAPER_BOUNDS
from orthoglide_pin.machine.cube import Cube
from orthoglide_pin.machine.description import (
    LoopClosure,
    LoopSpec,
    load_loops,
    loops_path,
    prototype_urdf_path,
    read_loops,
    render_urdf,
    urdf_path,
    write_loops,
    write_urdf,
)
from orthoglide_pin.machine.digest import DESIGN_FIELDS, check_design, design_digest
from orthoglide_pin.machine.export import write_package
from orthoglide_pin.machine.legs import LegGeometry
from orthoglide_pin.machine.loaders import (
    load_closed_loop,
    load_pinocchio,
    load_yourdfpy,
    mesh_resolver,
)
from orthoglide_pin.machine.meshes import PartMesh
from orthoglide_pin.machine.params import OrthoglideParams, prototype
from orthoglide_pin.machine.parts import PART_KINDS, PartInertia
from orthoglide_pin.machine.ranges import DRIVE_RANGES, PLAUSIBLE_RANGES

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import Assembly, ClosedLoopModel, PathAssembly
    from orthoglide_pin.machine.loading import load_model

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "Assembly": "orthoglide_pin.machine.closed_loop",
        "ClosedLoopModel": "orthoglide_pin.machine.closed_loop",
        "PathAssembly": "orthoglide_pin.machine.closed_loop",
        "load_model": "orthoglide_pin.machine.loading",
    },
    globals(),
)

__all__ = [
    "CRITERION_TOL",
    "DESIGN_FIELDS",
    "DRIVE_RANGES",
    "PAPER_BOUNDS",
    "PART_KINDS",
    "PLAUSIBLE_RANGES",
    "Assembly",
    "ClosedLoopModel",
    "Cube",
    "LegGeometry",
    "LoopClosure",
    "LoopSpec",
    "OrthoglideParams",
    "PartInertia",
    "PartMesh",
    "PathAssembly",
    "check_design",
    "design_digest",
    "load_closed_loop",
    "load_loops",
    "load_model",
    "load_pinocchio",
    "load_yourdfpy",
    "loops_path",
    "mesh_resolver",
    "prototype",
    "prototype_urdf_path",
    "read_loops",
    "render_urdf",
    "urdf_path",
    "write_loops",
    "write_package",
    "write_urdf",
]
