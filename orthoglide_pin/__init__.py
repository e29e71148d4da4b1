"""orthoglide-pin: the reference open-source model of the Orthoglide.

The Orthoglide is a 3-axis translational parallel machine tool (IRCCyN,
Nantes): three orthogonal prismatic actuators each drive a P-R-Pa-R leg onto a
platform that only translates. This package provides its parametric xacro
description, the closed-loop Pinocchio model, vectorised closed-form
kinematics, and tool trajectories with the prototype's standard test cycle.
All quantities are SI ([m], [kg], [N], [rad]).

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

from orthoglide_pin.cycle import (
    circle_limits,
    standard_cycle,
    standard_cycle_segments,
    standard_limits,
)
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
    PortInUseError,
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
from orthoglide_pin.inertia import (
    BodyInertia,
    InertiaTable,
    KindSummary,
    inertia_table,
)
from orthoglide_pin.inertia import assumptions as inertia_assumptions
from orthoglide_pin.joint_motion import LegMotion, leg_motion, tool_motion_from_sliders
from orthoglide_pin.kinematics import (
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_vectors,
    slider_range_over_cube,
)
from orthoglide_pin.motor import (
    Drive,
    DriveTrain,
    MotorData,
    MotorDemand,
    load_drive,
    motor_demand,
)
from orthoglide_pin.motor_sizing import (
    CycleStatistics,
    DriveSizing,
    MotorCheck,
    check_motor,
    cycle_statistics,
    size_drives,
)
from orthoglide_pin.params import OrthoglideParams, prototype
from orthoglide_pin.plotting import plot_slice
from orthoglide_pin.profiles import (
    MotionLimits,
    MotionProfile,
    ProfileSample,
    s_curve_profile,
    trapezoidal_profile,
)
from orthoglide_pin.segments import (
    ArcMove,
    Dwell,
    LineMove,
    Segment,
    circle_move,
    dwell,
    line_move,
    polygon_moves,
)
from orthoglide_pin.sweep import SweepAxis, SweepSpec, sweep_table
from orthoglide_pin.sweep_metrics import evaluate_design, footprint
from orthoglide_pin.sweep_plots import plot_sweep, sweep_figure
from orthoglide_pin.sweep_runner import SweepResult, run_sweep
from orthoglide_pin.trajectory import Trajectory, build_trajectory
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
    from orthoglide_pin.dynamics import ClosedLoopDynamics, DynamicsResult
    from orthoglide_pin.forward_dynamics import (
        ForwardDynamics,
        mechanical_energy,
        split_platform_model,
    )
    from orthoglide_pin.motion_forms import MotionForm, RequirementForms, requirement_forms
    from orthoglide_pin.report import ReportData, assemble_report
    from orthoglide_pin.report_files import ReportFiles, write_report
    from orthoglide_pin.requirements import (
        Guarantees,
        WorstCase,
        worst_case_on_grid,
        worst_case_over_cube,
        worst_case_requirements,
    )
    from orthoglide_pin.viewer import Viewer

__version__ = "0.1.0"

# Names whose modules import Pinocchio: loaded on first use, so that the command
# line and the closed-form kinematics start fast.
_LAZY = {
    "Assembly": "orthoglide_pin.closed_loop",
    "ClosedLoopModel": "orthoglide_pin.closed_loop",
    "ClosedLoopDynamics": "orthoglide_pin.dynamics",
    "DynamicsResult": "orthoglide_pin.dynamics",
    "ForwardDynamics": "orthoglide_pin.forward_dynamics",
    "mechanical_energy": "orthoglide_pin.forward_dynamics",
    "split_platform_model": "orthoglide_pin.forward_dynamics",
    "MotionForm": "orthoglide_pin.motion_forms",
    "RequirementForms": "orthoglide_pin.motion_forms",
    "requirement_forms": "orthoglide_pin.motion_forms",
    "ReportData": "orthoglide_pin.report",
    "assemble_report": "orthoglide_pin.report",
    "ReportFiles": "orthoglide_pin.report_files",
    "write_report": "orthoglide_pin.report_files",
    "Guarantees": "orthoglide_pin.requirements",
    "WorstCase": "orthoglide_pin.requirements",
    "worst_case_on_grid": "orthoglide_pin.requirements",
    "worst_case_over_cube": "orthoglide_pin.requirements",
    "worst_case_requirements": "orthoglide_pin.requirements",
    "Viewer": "orthoglide_pin.viewer",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'orthoglide_pin' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "ArcMove",
    "Assembly",
    "BodyInertia",
    "ClosedLoopDynamics",
    "ClosedLoopModel",
    "CycleStatistics",
    "DescriptionError",
    "Drive",
    "DriveSizing",
    "DriveTrain",
    "Dwell",
    "DynamicsResult",
    "ForwardDynamics",
    "Grid",
    "Guarantees",
    "InertiaTable",
    "InvalidParameterError",
    "IsotropyResiduals",
    "KindSummary",
    "KinetostaticIndices",
    "LegMotion",
    "LineMove",
    "LoopClosure",
    "LoopSpec",
    "MotionForm",
    "MotionLimits",
    "MotionProfile",
    "MotorCheck",
    "MotorData",
    "MotorDemand",
    "NoAssemblyError",
    "OrthoglideError",
    "OrthoglideParams",
    "PortInUseError",
    "ProfileSample",
    "ReportData",
    "ReportFiles",
    "RequirementForms",
    "Segment",
    "SingularConfigurationError",
    "SweepAxis",
    "SweepResult",
    "SweepSpec",
    "Trajectory",
    "UnreachablePointError",
    "Viewer",
    "WorkspaceDesign",
    "WorkspaceMap",
    "WorstCase",
    "__version__",
    "assemble_report",
    "build_trajectory",
    "check_motor",
    "circle_limits",
    "circle_move",
    "condition_number",
    "cube_grid",
    "cycle_statistics",
    "design_from_workspace",
    "direct_kinematics",
    "dwell",
    "evaluate_design",
    "footprint",
    "force_ellipsoid",
    "ik_and_jacobian",
    "indices_from_jacobian",
    "indices_from_model",
    "inertia_assumptions",
    "inertia_table",
    "inverse_condition",
    "inverse_jacobian",
    "inverse_kinematics",
    "isotropy_residuals",
    "jacobian",
    "kinetostatic_indices",
    "leg_motion",
    "leg_vectors",
    "line_move",
    "load_drive",
    "load_loops",
    "manipulability",
    "mechanical_energy",
    "motor_demand",
    "plot_slice",
    "plot_sweep",
    "polygon_moves",
    "prototype",
    "prototype_cube",
    "prototype_urdf_path",
    "render_urdf",
    "requirement_forms",
    "run_sweep",
    "s_curve_profile",
    "size_drives",
    "slice_grid",
    "slider_range_over_cube",
    "split_platform_model",
    "standard_cycle",
    "standard_cycle_segments",
    "standard_limits",
    "sweep_figure",
    "sweep_table",
    "tool_motion_from_sliders",
    "transmission_factor_map",
    "transmission_factors",
    "trapezoidal_profile",
    "urdf_path",
    "velocity_ellipsoid",
    "workspace_map",
    "worst_case_on_grid",
    "worst_case_over_cube",
    "worst_case_requirements",
    "write_report",
    "write_urdf",
]
