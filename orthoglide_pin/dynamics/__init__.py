"""Dynamics of the closed-loop machine: inertias, inverse and forward dynamics, worst cases.

* :mod:`~orthoglide_pin.dynamics.inertia`: the per-body inertial table and its
  stated assumptions;
* :mod:`~orthoglide_pin.dynamics.inverse`: closed-loop inverse dynamics
  (closed-form route and projection route), :class:`ClosedLoopDynamics`;
* :mod:`~orthoglide_pin.dynamics.forward`: forward dynamics and energies;
* :mod:`~orthoglide_pin.dynamics.motion_forms`: the slider forces as an affine
  plus quadratic form of the tool's velocity and acceleration;
* :mod:`~orthoglide_pin.dynamics.requirements`: the exact worst-case force and
  motor torque over every direction, on a grid or over the cube;
* :mod:`~orthoglide_pin.dynamics.leg_harmonics`: each leg's dynamics as exact
  trigonometric polynomials of its two angles, read from the Pinocchio model;
* :mod:`~orthoglide_pin.dynamics.path_forms`: the slider forces along a path
  as ``a s_ddot + b s_dot^2 + c``, for time-optimal feed planning. Its function
  ``path_forms`` has the module's name, so it is reached as
  ``orthoglide_pin.path_forms`` or from the module, not from this package.

Every module but :mod:`~orthoglide_pin.dynamics.inertia` imports Pinocchio and
is loaded on first use of one of its names.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.dynamics.inertia import (
    BodyInertia,
    InertiaTable,
    KindSummary,
    assumptions,
    inertia_table,
)

if TYPE_CHECKING:
    from orthoglide_pin.dynamics.forward import (
        ForwardDynamics,
        mechanical_energy,
    )
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics, DynamicsResult
    from orthoglide_pin.dynamics.motion_forms import (
        MotionForm,
        RequirementForms,
        requirement_forms,
    )
    from orthoglide_pin.dynamics.path_forms import PathForms, path_forms_by_rnea
    from orthoglide_pin.dynamics.requirements import (
        Guarantees,
        WorstCase,
        worst_case_on_grid,
        worst_case_over_cube,
        worst_case_requirements,
    )

_INVERSE = "orthoglide_pin.dynamics.inverse"
_FORWARD = "orthoglide_pin.dynamics.forward"
_FORMS = "orthoglide_pin.dynamics.motion_forms"
_REQUIREMENTS = "orthoglide_pin.dynamics.requirements"
_PATH = "orthoglide_pin.dynamics.path_forms"
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "ClosedLoopDynamics": _INVERSE,
        "DynamicsResult": _INVERSE,
        "ForwardDynamics": _FORWARD,
        "mechanical_energy": _FORWARD,
        "MotionForm": _FORMS,
        "RequirementForms": _FORMS,
        "requirement_forms": _FORMS,
        "PathForms": _PATH,
        "path_forms_by_rnea": _PATH,
        "Guarantees": _REQUIREMENTS,
        "WorstCase": _REQUIREMENTS,
        "worst_case_on_grid": _REQUIREMENTS,
        "worst_case_over_cube": _REQUIREMENTS,
        "worst_case_requirements": _REQUIREMENTS,
    },
    globals(),
)

__all__ = [
    "BodyInertia",
    "ClosedLoopDynamics",
    "DynamicsResult",
    "ForwardDynamics",
    "Guarantees",
    "InertiaTable",
    "KindSummary",
    "MotionForm",
    "PathForms",
    "RequirementForms",
    "WorstCase",
    "assumptions",
    "inertia_table",
    "mechanical_energy",
    "path_forms_by_rnea",
    "requirement_forms",
    "worst_case_on_grid",
    "worst_case_over_cube",
    "worst_case_requirements",
]
