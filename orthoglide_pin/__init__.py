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

import importlib.metadata
from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.drives import (
    CycleStatistics,
    Drive,
    DriveSizing,
    DriveTrain,
    MotorCheck,
    MotorData,
    MotorDemand,
    check_motor,
    cycle_statistics,
    load_drive,
    motor_demand,
    size_drives,
)
from orthoglide_pin.dynamics import (
    BodyInertia,
    InertiaTable,
    KindSummary,
    inertia_table,
)
from orthoglide_pin.dynamics import assumptions as inertia_assumptions
from orthoglide_pin.exceptions import (
    DescriptionError,
    InvalidParameterError,
    NoAssemblyError,
    OrthoglideError,
    PortInUseError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.kinematics import (
    LegMotion,
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_motion,
    leg_vectors,
    slider_range_over_cube,
    tool_motion_from_sliders,
)
from orthoglide_pin.kinetostatics import (
    CartesianStiffness,
    Grid,
    IsotropyResiduals,
    KinetostaticIndices,
    WorkspaceDesign,
    WorkspaceMap,
    cartesian_stiffness,
    condition_number,
    cube_grid,
    design_from_workspace,
    force_ellipsoid,
    indices_from_jacobian,
    indices_from_model,
    inverse_condition,
    isotropy_residuals,
    kinetostatic_indices,
    manipulability,
    plot_slice,
    prototype_cube,
    slice_grid,
    transmission_factor_map,
    transmission_factors,
    velocity_ellipsoid,
    workspace_map,
)
from orthoglide_pin.machine import (
    LoopClosure,
    LoopSpec,
    OrthoglideParams,
    load_closed_loop,
    load_loops,
    load_pinocchio,
    load_yourdfpy,
    loops_path,
    prototype,
    prototype_urdf_path,
    read_loops,
    render_urdf,
    urdf_path,
    write_loops,
    write_urdf,
)
from orthoglide_pin.motion import (
    ArcMove,
    Dwell,
    LineMove,
    MotionLimits,
    MotionProfile,
    ProfileSample,
    Segment,
    Trajectory,
    build_trajectory,
    circle_limits,
    circle_move,
    dwell,
    line_move,
    polygon_moves,
    s_curve_profile,
    standard_cycle,
    standard_cycle_segments,
    standard_limits,
    trapezoidal_profile,
)
from orthoglide_pin.sweep import (
    SweepAxis,
    SweepResult,
    SweepSpec,
    evaluate_design,
    footprint,
    plot_sweep,
    run_sweep,
    sweep_figure,
    sweep_table,
)

if TYPE_CHECKING:
    from orthoglide_pin.dynamics import (
        ClosedLoopDynamics,
        DynamicsResult,
        ForwardDynamics,
        Guarantees,
        MotionForm,
        RequirementForms,
        WorstCase,
        mechanical_energy,
        requirement_forms,
        worst_case_on_grid,
        worst_case_over_cube,
        worst_case_requirements,
    )
    from orthoglide_pin.machine import Assembly, ClosedLoopModel
    from orthoglide_pin.report import ReportData, ReportFiles, assemble_report, write_report
    from orthoglide_pin.viewer import Viewer

__version__ = importlib.metadata.version("orthoglide-pin")

# Names whose modules import Pinocchio (or the viewer): loaded on first use, so
# that the command line and the closed-form kinematics start fast. Each resolves
# through its layer's own lazy export.
_LAZY_LAYERS = {
    "orthoglide_pin.machine": ("Assembly", "ClosedLoopModel"),
    "orthoglide_pin.dynamics": (
        "ClosedLoopDynamics",
        "DynamicsResult",
        "ForwardDynamics",
        "Guarantees",
        "MotionForm",
        "RequirementForms",
        "WorstCase",
        "mechanical_energy",
        "requirement_forms",
        "worst_case_on_grid",
        "worst_case_over_cube",
        "worst_case_requirements",
    ),
    "orthoglide_pin.report": ("ReportData", "ReportFiles", "assemble_report", "write_report"),
    "orthoglide_pin.viewer": ("Viewer",),
}
__getattr__, __dir__ = lazy_exports(
    __name__,
    {name: layer for layer, names in _LAZY_LAYERS.items() for name in names},
    globals(),
)

__all__ = [
    "ArcMove",
    "Assembly",
    "BodyInertia",
    "CartesianStiffness",
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
    "cartesian_stiffness",
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
    "load_closed_loop",
    "load_drive",
    "load_loops",
    "load_pinocchio",
    "load_yourdfpy",
    "loops_path",
    "manipulability",
    "mechanical_energy",
    "motor_demand",
    "plot_slice",
    "plot_sweep",
    "polygon_moves",
    "prototype",
    "prototype_cube",
    "prototype_urdf_path",
    "read_loops",
    "render_urdf",
    "requirement_forms",
    "run_sweep",
    "s_curve_profile",
    "size_drives",
    "slice_grid",
    "slider_range_over_cube",
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
    "write_loops",
    "write_report",
    "write_urdf",
]
