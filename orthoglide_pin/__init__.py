"""orthoglide-pin: the reference open-source model of the Orthoglide.

The Orthoglide is a 3-axis translational parallel machine tool (IRCCyN,
Nantes): three orthogonal prismatic actuators each drive a P-R-Pa-R leg onto a
platform that only translates. This package provides its parametric xacro
description, the closed-loop Pinocchio model, and vectorised closed-form
kinematics. All quantities are SI ([m], [kg], [N], [rad]).

Quick tour::

    import orthoglide_pin as og

    params = og.prototype()                       # the paper's machine
    q = og.inverse_kinematics([0.05, 0.0, 0.02], params.leg_length)
    model = og.ClosedLoopModel(params)            # Pinocchio, loops closed
    assembly = model.solve(q)                     # every passive joint
    J = model.jacobian(assembly.q)                # p_dot = J q_dot
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from orthoglide_pin.description import (
    LoopClosure,
    LoopSpec,
    load_loops,
    prototype_urdf_path,
    render_urdf,
    urdf_path,
    write_urdf,
)
from orthoglide_pin.design import WorkspaceDesign, design_from_workspace, prototype_cube
from orthoglide_pin.exceptions import (
    DescriptionError,
    InvalidParameterError,
    NoAssemblyError,
    OrthoglideError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.indices import (
    IsotropyResiduals,
    KinetostaticIndices,
    condition_number,
    force_ellipsoid,
    indices_from_jacobian,
    indices_from_model,
    inverse_condition,
    isotropy_residuals,
    kinetostatic_indices,
    manipulability,
    transmission_factors,
    velocity_ellipsoid,
)
from orthoglide_pin.kinematics import (
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_vectors,
    slider_range_over_cube,
)
from orthoglide_pin.params import OrthoglideParams, prototype
from orthoglide_pin.plotting import plot_slice
from orthoglide_pin.workspace import (
    Grid,
    WorkspaceMap,
    cube_grid,
    slice_grid,
    transmission_factor_map,
    workspace_map,
)

if TYPE_CHECKING:
    from orthoglide_pin.closed_loop import Assembly, ClosedLoopModel

__version__ = "0.1.0"

# Names whose modules import Pinocchio: loaded on first use, so that the command
# line and the closed-form kinematics start fast.
_LAZY = {
    "Assembly": "orthoglide_pin.closed_loop",
    "ClosedLoopModel": "orthoglide_pin.closed_loop",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'orthoglide_pin' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "Assembly",
    "ClosedLoopModel",
    "DescriptionError",
    "Grid",
    "InvalidParameterError",
    "IsotropyResiduals",
    "KinetostaticIndices",
    "LoopClosure",
    "LoopSpec",
    "NoAssemblyError",
    "OrthoglideError",
    "OrthoglideParams",
    "SingularConfigurationError",
    "UnreachablePointError",
    "WorkspaceDesign",
    "WorkspaceMap",
    "__version__",
    "condition_number",
    "cube_grid",
    "design_from_workspace",
    "direct_kinematics",
    "force_ellipsoid",
    "ik_and_jacobian",
    "indices_from_jacobian",
    "indices_from_model",
    "inverse_condition",
    "inverse_jacobian",
    "inverse_kinematics",
    "isotropy_residuals",
    "jacobian",
    "kinetostatic_indices",
    "leg_vectors",
    "load_loops",
    "manipulability",
    "plot_slice",
    "prototype",
    "prototype_cube",
    "prototype_urdf_path",
    "render_urdf",
    "slice_grid",
    "slider_range_over_cube",
    "transmission_factor_map",
    "transmission_factors",
    "urdf_path",
    "velocity_ellipsoid",
    "workspace_map",
    "write_urdf",
]
