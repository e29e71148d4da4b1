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
from orthoglide_pin.exceptions import (
    DescriptionError,
    InvalidParameterError,
    NoAssemblyError,
    OrthoglideError,
    SingularConfigurationError,
    UnreachablePointError,
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
    "InvalidParameterError",
    "LoopClosure",
    "LoopSpec",
    "NoAssemblyError",
    "OrthoglideError",
    "OrthoglideParams",
    "SingularConfigurationError",
    "UnreachablePointError",
    "__version__",
    "direct_kinematics",
    "ik_and_jacobian",
    "inverse_jacobian",
    "inverse_kinematics",
    "jacobian",
    "leg_vectors",
    "load_loops",
    "prototype",
    "prototype_urdf_path",
    "render_urdf",
    "slider_range_over_cube",
    "urdf_path",
    "write_urdf",
]
