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
    example_drive_file,
    example_drive_text,
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
from orthoglide_pin.elasticity import (
    CartesianStiffness,
    StiffnessMap,
    cartesian_stiffness,
    compliance_ellipsoid,
    frame_compliance,
    stiffness_map,
)
from orthoglide_pin.exceptions import (
    CalibrationError,
    CutConditionsError,
    DescriptionError,
    DesignMismatchError,
    InvalidParameterError,
    MissingExecutableError,
    MissingExtraError,
    NoAssemblyError,
    OrthoglideError,
    PortInUseError,
    ProgramError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.kinematics import (
    MAX_CONDITION,
    LegMotion,
    PathMotion,
    check_inverse_jacobian,
    direct_kinematics,
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
    leg_motion,
    leg_vectors,
    path_motion,
    singularity_measures,
    slider_range_over_cube,
    tool_motion_from_sliders,
)
from orthoglide_pin.kinetostatics import (
    Certification,
    FactorRange,
    Grid,
    IsotropyResiduals,
    KinetostaticIndices,
    WorkspaceDesign,
    WorkspaceMap,
    certify,
    certify_cube,
    condition_number,
    cube_grid,
    design_from_workspace,
    factor_range,
    force_ellipsoid,
    indices_from_jacobian,
    indices_from_model,
    inverse_condition,
    isotropy_residuals,
    kinetostatic_indices,
    largest_certified_side,
    manipulability,
    plot_slice,
    prototype_cube,
    prototype_note,
    slice_grid,
    transmission_factor_map,
    transmission_factors,
    velocity_ellipsoid,
    workspace_map,
)
from orthoglide_pin.machine import (
    CRITERION_TOL,
    DESIGN_FIELDS,
    DRIVE_RANGES,
    PAPER_BOUNDS,
    PART_KINDS,
    PLAUSIBLE_RANGES,
    Cube,
    LegGeometry,
    LoopClosure,
    LoopSpec,
    OrthoglideParams,
    PartInertia,
    PartMesh,
    check_design,
    design_digest,
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
    write_package,
    write_urdf,
)
from orthoglide_pin.machining import (
    ChatterSimulation,
    CutConditions,
    Engagement,
    ErrorBudget,
    Material,
    MillingForces,
    MillingProcess,
    ModalModel,
    StabilityLobes,
    StabilityMargin,
    Tool,
    ToolMode,
    critical_depths_sd,
    critical_depths_zoa,
    cut_conditions,
    error_budget,
    frequency_response,
    limit_depth_map,
    milling_forces,
    program_blocks,
    read_cut_file,
    shipped_cut_file,
    shipped_materials,
    simulate_chatter,
    single_mode,
    spectral_radius_sd,
    stability_lobes,
    stability_margin_along,
    tool_tip_model,
    tool_tip_models,
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
from orthoglide_pin.planning import (
    EXAMPLE_PROGRAMS,
    Block,
    Path,
    Piece,
    Program,
    Section,
    build_path,
    example_program_file,
    example_program_text,
    read_program,
    read_program_file,
)
from orthoglide_pin.program import (
    MOVE_KINDS,
    PROTOTYPE_AXES,
    Ignored,
    Move,
    ProgramAxes,
    ReadProgram,
    Refusal,
    Setup,
    check_refusals,
    compare_moves,
    design_axes,
    make_setup,
    read_moves,
    read_offsets,
    read_rs274,
    read_rs274_text,
    read_tool_table,
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
    from orthoglide_pin.calibration import (
        PARAMETER_NAMES,
        Calibration,
        GeometricModel,
        Identification,
        MeasurementPlan,
        Measurements,
        identify,
        load_calibration,
        parse_measurements,
        plan_poses,
        read_measurements,
        sensitivity,
        sensitivity_indices,
        write_calibration,
    )
    from orthoglide_pin.controller import CartesianLimits, certify_limits, configuration_files
    from orthoglide_pin.dynamics import (
        ClosedLoopDynamics,
        DynamicsResult,
        ForwardDynamics,
        Guarantees,
        MotionForm,
        PathForms,
        RequirementForms,
        WorstCase,
        mechanical_energy,
        path_forms_by_rnea,
        requirement_forms,
        worst_case_on_grid,
        worst_case_over_cube,
        worst_case_requirements,
    )
    from orthoglide_pin.dynamics.path_forms import path_forms
    from orthoglide_pin.elasticity import NaturalModes, frame_fea_modes, natural_frequencies
    from orthoglide_pin.machine import Assembly, ClosedLoopModel, PathAssembly
    from orthoglide_pin.machining import (
        AccuracyResult,
        BlockAccuracy,
        PlanStability,
        accuracy_along_plan,
        program_spindle_speed,
        stability_along_plan,
    )
    from orthoglide_pin.planning import BlockTime, Plan, PlanLimits, plan_program, stop_reasons
    from orthoglide_pin.report import ReportData, ReportFiles, assemble_report, write_report
    from orthoglide_pin.simulation import (
        ContourError,
        ServoSettings,
        SimulationRun,
        contour_error,
        mjcf_text,
        simulate,
        write_mjcf,
    )
    from orthoglide_pin.viewer import Viewer

__version__ = importlib.metadata.version("orthoglide-pin")

# Names whose modules import Pinocchio (or the viewer): loaded on first use, so
# that the command line and the closed-form kinematics start fast. Each resolves
# through its layer's own lazy export.
_LAZY_LAYERS = {
    "orthoglide_pin.calibration": (
        "Calibration",
        "GeometricModel",
        "Identification",
        "MeasurementPlan",
        "Measurements",
        "PARAMETER_NAMES",
        "identify",
        "load_calibration",
        "parse_measurements",
        "plan_poses",
        "read_measurements",
        "sensitivity",
        "sensitivity_indices",
        "write_calibration",
    ),
    "orthoglide_pin.machine": ("Assembly", "ClosedLoopModel", "PathAssembly"),
    "orthoglide_pin.dynamics": (
        "ClosedLoopDynamics",
        "DynamicsResult",
        "ForwardDynamics",
        "Guarantees",
        "MotionForm",
        "PathForms",
        "RequirementForms",
        "WorstCase",
        "mechanical_energy",
        "path_forms_by_rnea",
        "requirement_forms",
        "worst_case_on_grid",
        "worst_case_over_cube",
        "worst_case_requirements",
    ),
    "orthoglide_pin.controller": ("CartesianLimits", "certify_limits", "configuration_files"),
    "orthoglide_pin.machining": (
        "AccuracyResult",
        "BlockAccuracy",
        "accuracy_along_plan",
        "program_spindle_speed",
        "PlanStability",
        "stability_along_plan",
    ),
    "orthoglide_pin.planning": ("BlockTime", "Plan", "PlanLimits", "plan_program", "stop_reasons"),
    "orthoglide_pin.elasticity": ("NaturalModes", "frame_fea_modes", "natural_frequencies"),
    "orthoglide_pin.report": ("ReportData", "ReportFiles", "assemble_report", "write_report"),
    "orthoglide_pin.simulation": (
        "ContourError",
        "ServoSettings",
        "SimulationRun",
        "contour_error",
        "mjcf_text",
        "simulate",
        "write_mjcf",
    ),
    "orthoglide_pin.viewer": ("Viewer",),
}
#: Lazy names that share their module's name, so the layer cannot export them
#: (the package's attribute is the module once it is imported): from the module.
_LAZY_FROM_MODULE = {"path_forms": "orthoglide_pin.dynamics.path_forms"}
__getattr__, __dir__ = lazy_exports(
    __name__,
    {name: layer for layer, names in _LAZY_LAYERS.items() for name in names} | _LAZY_FROM_MODULE,
    globals(),
)

# fmt: off
__all__ = [
    "CRITERION_TOL", "DESIGN_FIELDS", "DRIVE_RANGES", "EXAMPLE_PROGRAMS", "MAX_CONDITION",
    "MOVE_KINDS", "PAPER_BOUNDS", "PARAMETER_NAMES", "PART_KINDS", "PLAUSIBLE_RANGES",
    "PROTOTYPE_AXES", "AccuracyResult", "ArcMove", "Assembly", "Block", "BlockAccuracy",
    "BlockTime", "BodyInertia", "Calibration", "CalibrationError", "CartesianLimits",
    "CartesianStiffness", "Certification", "ChatterSimulation", "ClosedLoopDynamics",
    "ClosedLoopModel", "ContourError", "Cube", "CutConditions", "CutConditionsError",
    "CycleStatistics", "DescriptionError", "DesignMismatchError", "Drive", "DriveSizing",
    "DriveTrain", "Dwell", "DynamicsResult", "Engagement", "ErrorBudget", "FactorRange",
    "ForwardDynamics", "GeometricModel", "Grid", "Guarantees", "Identification", "Ignored",
    "InertiaTable", "InvalidParameterError", "IsotropyResiduals", "KindSummary",
    "KinetostaticIndices", "LegGeometry", "LegMotion", "LineMove", "LoopClosure", "LoopSpec",
    "Material", "MeasurementPlan", "Measurements", "MillingForces", "MillingProcess",
    "MissingExecutableError", "MissingExtraError", "ModalModel", "MotionForm", "MotionLimits",
    "MotionProfile", "MotorCheck", "MotorData", "MotorDemand", "Move", "NaturalModes",
    "NoAssemblyError", "OrthoglideError", "OrthoglideParams", "PartInertia", "PartMesh", "Path",
    "PathAssembly", "PathForms", "PathMotion", "Piece", "Plan", "PlanLimits", "PlanStability",
    "PortInUseError",
    "ProfileSample", "Program", "ProgramAxes", "ProgramError", "ReadProgram", "Refusal",
    "ReportData", "ReportFiles", "RequirementForms", "Section", "Segment", "ServoSettings",
    "Setup", "SimulationRun", "SingularConfigurationError", "StabilityLobes", "StabilityMargin",
    "StiffnessMap", "SweepAxis", "SweepResult", "SweepSpec", "Tool", "ToolMode", "Trajectory",
    "UnreachablePointError", "Viewer", "WorkspaceDesign", "WorkspaceMap", "WorstCase",
    "__version__", "accuracy_along_plan", "assemble_report", "build_path", "build_trajectory",
    "cartesian_stiffness", "certify", "certify_cube", "certify_limits", "check_design",
    "check_inverse_jacobian", "check_motor", "check_refusals", "circle_limits", "circle_move",
    "compare_moves", "compliance_ellipsoid", "condition_number", "configuration_files",
    "contour_error", "critical_depths_sd", "critical_depths_zoa", "cube_grid", "cut_conditions",
    "cycle_statistics", "design_axes", "design_digest", "design_from_workspace",
    "direct_kinematics", "dwell", "error_budget", "evaluate_design", "example_drive_file",
    "example_drive_text", "example_program_file", "example_program_text", "factor_range",
    "footprint", "force_ellipsoid", "frame_compliance", "frame_fea_modes", "frequency_response",
    "identify", "ik_and_jacobian", "indices_from_jacobian", "indices_from_model",
    "inertia_assumptions", "inertia_table", "inverse_condition", "inverse_jacobian",
    "inverse_kinematics", "isotropy_residuals", "jacobian", "kinetostatic_indices",
    "largest_certified_side", "leg_motion", "leg_vectors", "limit_depth_map", "line_move",
    "load_calibration", "load_closed_loop", "load_drive", "load_loops", "load_pinocchio",
    "load_yourdfpy", "loops_path", "make_setup", "manipulability", "mechanical_energy",
    "milling_forces", "mjcf_text", "motor_demand", "natural_frequencies", "parse_measurements",
    "path_forms", "path_forms_by_rnea", "path_motion", "plan_poses", "plan_program", "plot_slice",
    "plot_sweep", "polygon_moves", "program_blocks", "program_spindle_speed", "prototype",
    "prototype_cube", "prototype_note", "prototype_urdf_path", "read_cut_file", "read_loops",
    "read_measurements", "read_moves", "read_offsets", "read_program", "read_program_file",
    "read_rs274", "read_rs274_text", "read_tool_table", "render_urdf", "requirement_forms",
    "run_sweep", "s_curve_profile", "sensitivity", "sensitivity_indices", "shipped_cut_file",
    "shipped_materials", "simulate", "simulate_chatter", "single_mode", "singularity_measures",
    "size_drives", "slice_grid", "slider_range_over_cube", "spectral_radius_sd",
    "stability_along_plan", "stability_lobes",
    "stability_margin_along", "standard_cycle", "standard_cycle_segments", "standard_limits",
    "stiffness_map", "stop_reasons", "sweep_figure", "sweep_table", "tool_motion_from_sliders",
    "tool_tip_model", "tool_tip_models", "transmission_factor_map", "transmission_factors",
    "trapezoidal_profile", "urdf_path", "velocity_ellipsoid", "workspace_map",
    "worst_case_on_grid", "worst_case_over_cube", "worst_case_requirements", "write_calibration",
    "write_loops", "write_mjcf", "write_package", "write_report", "write_urdf",
]
# fmt: on
