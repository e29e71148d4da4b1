"""Every public callable, walked with wrong-typed arguments: only the package's errors.

For each callable of ``orthoglide_pin.__all__`` the table :data:`VALID` gives
one call that works. Each argument in turn is then replaced by a value of the
wrong kind (``None``, a string, a dict, NaN where numbers are expected, an
array of the wrong shape), the others kept valid. What may come out is a
result (the value was acceptable: ``None`` for an option, a string for a
label) or an :class:`~orthoglide_pin.exceptions.OrthoglideError` whose one-line
message names that argument; never a ``TypeError``, ``AttributeError`` or
numpy warning from deep inside.

Result types (built by the package, read by the user) are listed in
:data:`RESULTS`; a public name in neither table fails the test, so a new
entry point gets walked.
"""

from __future__ import annotations

import inspect
import os
import re
import shutil
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import OrthoglideError

#: A point well inside the prototype's cube [m].
POINT = (0.01, 0.02, -0.015)
#: A second one, for moves.
OTHER = (-0.02, 0.01, 0.03)
L = 0.31

#: Result types: built by the package and handed to the user, not entry points.
#: A short part program (mm) for the planning calls.
PROGRAM = "G21 G90\nG1 X10 Y5 F3000\nG0 X0 Y0\nM2\n"

#: A move, for the comparison of readings.
MOVE = og.Move(2, "line", np.zeros(3), np.array([0.01, 0.005, 0.0]), feed=0.05)
#: Options of the LinuxCNC reader: a work offset and a tool.
RS274_OPTIONS: dict[str, Any] = {
    "work_offsets": {"G54": (0.0, 0.0, 0.01)},
    "tools": {1: (0.05, 0.006)},
    "block_delete": False,
    "timeout": 30.0,
}
#: A tool-tip mode and a cut, for the chatter calls.
MODE = og.ModalModel(
    np.array([900.0]), np.array([0.02]), np.array([0.05]), np.array([[1.0], [0.0]])
)
PROCESS = og.MillingProcess(2, 6e8, 2e8, 0.0, 1.0)
#: Callables that run LinuxCNC's rs274 (skipped where it is not installed).
NEEDS_RS274 = {"read_rs274", "read_rs274_text"}

RESULTS = {
    "AccuracyResult",
    "PlanStability",
    "ChatterSimulation",
    "StabilityLobes",
    "StabilityMargin",
    "BlockAccuracy",
    "ErrorBudget",
    "MillingForces",
    "CartesianLimits",
    "Ignored",
    "Move",
    "ReadProgram",
    "Refusal",
    "Setup",
    "NaturalModes",
    "Block",
    "BlockTime",
    "Path",
    "Piece",
    "Plan",
    "Program",
    "Section",
    "SimulationRun",
    "ContourError",
    "ArcMove",
    "Assembly",
    "BodyInertia",
    "Calibration",
    "CartesianStiffness",
    "Certification",
    "CycleStatistics",
    "DriveSizing",
    "DynamicsResult",
    "Dwell",
    "FactorRange",
    "Guarantees",
    "Identification",
    "InertiaTable",
    "IsotropyResiduals",
    "KindSummary",
    "KinetostaticIndices",
    "LegMotion",
    "LineMove",
    "MeasurementPlan",
    "Measurements",
    "MotionForm",
    "MotionProfile",
    "MotorCheck",
    "MotorDemand",
    "PathAssembly",
    "PathForms",
    "PathMotion",
    "ProfileSample",
    "ReportData",
    "ReportFiles",
    "RequirementForms",
    "Segment",
    "StiffnessMap",
    "SweepResult",
    "Trajectory",
    "WorkspaceDesign",
    "WorkspaceMap",
    "WorstCase",
}


@dataclass
class World:
    """Valid objects to build the calls from (one of each, built once)."""

    tmp: Path

    def __post_init__(self) -> None:
        self.params = og.prototype()
        self.other = self.params.replace(leg_length=0.36)
        self.model = og.ClosedLoopModel(self.params)
        self.dyn = og.ClosedLoopDynamics(self.model)
        self.limits = og.standard_limits()
        self.trajectory = og.build_trajectory([og.line_move(POINT, OTHER, self.limits)])
        t = self.trajectory
        self.result = self.dyn.inverse_dynamics(t.p, t.v, t.a)
        r = self.result
        self.demand = og.motor_demand(r.forces, r.slider_velocities, r.slider_accelerations)
        self.stats = og.cycle_statistics(self.demand, t.t)
        self.motor = og.MotorData(rated_torque=1.3, peak_torque=4.0, max_speed=3000.0)
        self.grid = og.cube_grid(*og.prototype_cube(self.params), 3)
        self.slice = og.slice_grid("z", 0.0, (-0.05, -0.05), (0.05, 0.05), 4)
        self.wmap = og.workspace_map(self.slice, self.params)
        self.spec = og.SweepSpec(axes=("leg_length=0.3,0.32",), grid=3, requirement_grid=2)
        self.design = self.spec.designs()[0]
        self.rows = [og.evaluate_design(d) for d in self.spec.designs()]
        self.table = og.sweep_table(self.rows, ["leg_length"])
        self.report = og.assemble_report(self.params, resolution=3, cube_resolution=2)
        self.q = self.model.configuration(np.array(POINT))
        self.count = 0
        self.program = og.read_program(PROGRAM)
        self.plan = og.plan_program(
            self.program, self.dyn, og.PlanLimits(slider_speed=1.2, slider_acceleration=20.0)
        )
        self.nominal = og.GeometricModel.nominal(L)
        rng = np.random.default_rng(7)
        corner, side = og.prototype_cube(self.params)
        pts = rng.uniform(corner, corner + side, (30, 3))
        self.cal_q = self.nominal.inverse_kinematics(pts)
        self.cal_p = pts + rng.normal(0.0, 5e-6, pts.shape)
        fit = og.identify(self.cal_q, self.cal_p, self.nominal)
        data = og.Measurements(self.cal_q, self.cal_p, sha256="ab" * 32)
        self.calibration = og.Calibration.from_identification(fit, data)
        self.calibration_file = self.tmp / "calibration.yaml"
        og.write_calibration(self.calibration_file, self.calibration)
        self.measurements_file = self.tmp / "measurements.csv"
        rows = np.hstack([self.cal_q, self.cal_p])
        lines = ["q1,q2,q3,x,y,z", *(",".join(repr(float(v)) for v in r) for r in rows)]
        self.measurements_file.write_text("\n".join(lines) + "\n")

    def program_file(self) -> Path:
        """A file holding :data:`PROGRAM`."""
        path = self.out("part.ngc")
        path.write_text(PROGRAM, encoding="utf-8")
        return path

    def out(self, name: str) -> Path:
        """A fresh output path in the test's directory."""
        self.count += 1
        return self.tmp / f"{self.count}-{name}"

    def text_file(self, name: str, text: str) -> Path:
        """A fresh file holding ``text``."""
        path = self.out(name)
        path.write_text(text)
        return path


Valid = Callable[[World], dict[str, Any]]

#: One working call of each public callable, by argument name.
VALID: dict[str, Valid] = {
    "accuracy_along_plan": lambda w: {
        "plan": w.plan,
        "cut": og.read_cut_file(og.shipped_cut_file()),
        "params": w.params,
        "dt": 0.01,
        "spindle_speed": 1000.0,
        "servo": ([0.0, 1.0], [1e-6, 2e-6]),
        "temperature_rise": 1.0,
    },
    "stability_along_plan": lambda w: {
        "plan": w.plan,
        "result": og.accuracy_along_plan(
            w.plan, og.read_cut_file(og.shipped_cut_file()), w.params, dt=0.05
        ),
        "params": w.params,
        "drive": og.Drive(),
        "model": "platform",
        "points_per_block": 1,
        "progress": lambda done, total: None,
    },
    "error_budget": lambda w: {
        "points": [POINT],
        "params": w.params,
        "compliance": [[1e-6, 0.0, 0.0]],
        "servo": [1e-6],
        "normals": [[0.0, 1.0, 0.0]],
        "temperature_rise": 1.0,
    },
    "program_spindle_speed": lambda w: {"program_text": "G0 X1 S12000\nM3\n"},
    "milling_forces": lambda w: {
        "feed_per_tooth": 1e-4,
        "axial_depth": 0.002,
        "immersion": (0.0, 1.0),
        "tool": og.Tool(0.01, 2),
        "material": og.shipped_materials()["benchmark"],
    },
    "CutConditions": lambda w: {
        "tool": og.Tool(0.01, 2),
        "material": og.shipped_materials()["benchmark"],
        "engagements": (og.Engagement(0.002, 0.005),),
        "spindle_speed": 1000.0,
        "modal_damping": 0.02,
    },
    "Engagement": lambda w: {"axial_depth": 0.002, "radial_width": 0.005, "lines": (1, 5)},
    "Material": lambda w: {"name": "m", "kt": 1e9, "kr": 3e8, "ka": 1e8, "kte": 1e4},
    "Tool": lambda w: {"diameter": 0.01, "teeth": 2, "helix_angle": 0.5},
    "ToolMode": lambda w: {"frequency": 900.0, "damping": 0.02, "stiffness": 1e7},
    "cut_conditions": lambda w: {
        "data": {
            "tool": {"diameter": 0.01, "teeth": 2},
            "material": "benchmark",
            "engagement": {"axial_depth": 0.002, "radial_width": 0.005},
        }
    },
    "read_cut_file": lambda w: {"path": og.shipped_cut_file()},
    "ModalModel": lambda w: {
        "frequencies": [900.0],
        "damping": [0.02],
        "masses": [0.05],
        "shapes": [[1.0], [0.0]],
        "sources": ("tool x",),
    },
    "MillingProcess": lambda w: {
        "teeth": 2,
        "kt": 6e8,
        "kr": 2e8,
        "phi_start": 0.0,
        "phi_exit": 1.0,
    },
    "frequency_response": lambda w: {"model": MODE, "frequencies": [100.0, 900.0]},
    "single_mode": lambda w: {
        "frequency": 900.0,
        "damping": 0.02,
        "stiffness": 1e7,
        "direction": "y",
        "source": "spindle",
    },
    "tool_tip_model": lambda w: {"params": w.params, "point": POINT},
    "tool_tip_models": lambda w: {
        "params": w.params,
        "points": [POINT, OTHER],
        "damping": 0.03,
        "tool": MODE,
        "drive": None,
        "count": 4,
        "model": "platform",
        "axes": og.design_axes(),
    },
    "critical_depths_sd": lambda w: {
        "model": MODE,
        "process": PROCESS,
        "speeds": [1500.0],
        "depth_range": (1e-5, 0.05),
        "steps": 12,
        "guess": [1e-3],
    },
    "spectral_radius_sd": lambda w: {
        "model": MODE,
        "process": PROCESS,
        "speeds": [1500.0],
        "depths": [1e-3],
        "steps": 12,
    },
    "critical_depths_zoa": lambda w: {"model": MODE, "process": PROCESS, "speeds": [1500.0]},
    "simulate_chatter": lambda w: {
        "model": MODE,
        "process": PROCESS,
        "speeds": [1500.0],
        "depths": [1e-3],
        "periods": 20,
    },
    "stability_lobes": lambda w: {
        "conditions": og.read_cut_file(og.shipped_cut_file()),
        "point": POINT,
        "params": w.params,
        "speeds": [1000.0, 1200.0],
        "feed_angle": 0.1,
        "engagement": og.Engagement(0.002, 0.005),
        "drive": None,
        "model": "platform",
        "axes": og.design_axes(),
        "zero_order": True,
        "steps": 12,
    },
    "limit_depth_map": lambda w: {
        "conditions": og.read_cut_file(og.shipped_cut_file()),
        "points": [POINT],
        "speed": 1000.0,
        "feed_angle": 0.0,
        "engagement": og.Engagement(0.002, 0.005),
        "params": w.params,
    },
    "stability_margin_along": lambda w: {
        "points": [POINT, OTHER],
        "conditions": og.read_cut_file(og.shipped_cut_file()),
        "lines": [1, 2],
        "angles": [0.0, 0.1],
        "speeds": 1000.0,
        "params": w.params,
        "drive": None,
        "model": "platform",
        "axes": og.design_axes(),
    },
    "program_blocks": lambda w: {"program": w.program, "axes": og.design_axes()},
    "shipped_cut_file": lambda w: {"name": "aluminium_finish"},
    "shipped_materials": lambda w: {},
    "ClosedLoopDynamics": lambda w: {"model": w.model},
    "ClosedLoopModel": lambda w: {"params": w.params},
    "Cube": lambda w: {"corner": (-0.07, -0.07, -0.07), "side": 0.2},
    "Drive": lambda w: {"train": og.DriveTrain(), "motor": w.motor},
    "DriveTrain": lambda w: {},
    "ForwardDynamics": lambda w: {"dynamics": w.dyn},
    "GeometricModel": lambda w: {
        "anchors": w.nominal.anchors,
        "alpha": w.nominal.alpha,
        "beta": w.nominal.beta,
        "lengths": w.nominal.lengths,
    },
    "Grid": lambda w: {"x": np.zeros(2), "y": np.zeros(2), "z": np.zeros(2)},
    "LegGeometry": lambda w: {
        "offsets": np.zeros((3, 3)),
        "axes": np.eye(3),
        "lengths": np.full(3, L),
    },
    "LoopClosure": lambda w: {"name": "c", "kind": "point", "frame1": "a", "frame2": "b"},
    "LoopSpec": lambda w: {
        "actuated_joints": ("a", "b", "c"),
        "platform_frame": "p",
        "tool_frame": "t",
        "closures": (),
    },
    "MotionLimits": lambda w: {"v_max": 1.0, "a_max": 10.0},
    "MotorData": lambda w: {"rated_torque": 1.0, "peak_torque": 2.0, "max_speed": 3000.0},
    "OrthoglideParams": lambda w: {"leg_length": 0.31},
    "PartInertia": lambda w: {
        "mass": 1.0,
        "com": (0.0, 0.0, 0.0),
        "inertia": ((1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (0.0, 0.0, 1e-3)),
    },
    "PartMesh": lambda w: (
        {"file": w.params.meshes["bar"].file} if w.params.meshes else {"file": Path("bar.stl")}
    ),
    "SweepAxis": lambda w: {"name": "leg_length", "values": (0.3, 0.32)},
    "SweepSpec": lambda w: {"grid": 3, "requirement_grid": 2},
    "Viewer": lambda w: {"model": w.model},
    "assemble_report": lambda w: {"params": w.params, "resolution": 3, "cube_resolution": 2},
    "build_trajectory": lambda w: {"segments": [og.line_move(POINT, OTHER, w.limits)]},
    "cartesian_stiffness": lambda w: {"points": POINT, "params": w.params},
    "certify": lambda w: {"params": w.params, "tol": 1e-2},
    "certify_limits": lambda w: {
        "params": w.params,
        "joint_speed": 1.2,
        "joint_acceleration": 20.0,
        "joint_jerk": 500.0,
    },
    "configuration_files": lambda w: {
        "params": w.params,
        "limits": og.certify_limits(w.params, 1.2, 20.0),
        "digest": "abc123",
        "source": " from a file",
    },
    "certify_cube": lambda w: {
        "leg_length": L,
        "corner": (-0.07, -0.07, -0.07),
        "side": 0.2,
        "psi_min": 0.4,
        "psi_max": 2.5,
        "tol": 1e-2,
    },
    "check_design": lambda w: {
        "recorded": og.design_digest(w.params),
        "params": w.params,
        "what": "calibration.yaml",
        "leg_length": w.params.leg_length,
    },
    "check_inverse_jacobian": lambda w: {"j_inv": np.eye(3), "points": POINT},
    "check_motor": lambda w: {"motor": w.motor, "stats": w.stats, "demand": w.demand},
    "circle_limits": lambda w: {"limits": w.limits, "radius": 0.02},
    "circle_move": lambda w: {
        "center": POINT,
        "normal": (0.0, 0.0, 1.0),
        "radius": 0.02,
        "limits": w.limits,
    },
    "compare_moves": lambda w: {"a": [MOVE], "b": [MOVE], "tol": 1e-6, "limit": 3},
    "compliance_ellipsoid": lambda w: {"points": POINT, "params": w.params},
    "condition_number": lambda w: {"points": POINT, "leg_length": L},
    "cube_grid": lambda w: {"corner": (-0.07, -0.07, -0.07), "side": 0.2, "n": 3},
    "cycle_statistics": lambda w: {"demand": w.demand, "time": w.trajectory.t},
    "design_digest": lambda w: {"params": w.params},
    "design_from_workspace": lambda w: {"side": 0.2, "psi_min": 0.5, "psi_max": 2.0},
    "direct_kinematics": lambda w: {"q": (0.0, 0.01, -0.01), "leg_length": L},
    "dwell": lambda w: {"point": POINT, "duration": 0.1},
    "evaluate_design": lambda w: {"design": w.design},
    "example_drive_file": lambda w: {},
    "example_drive_text": lambda w: {},
    "factor_range": lambda w: {"params": w.params, "grid_points": 5},
    "footprint": lambda w: {"params": w.params},
    "force_ellipsoid": lambda w: {"points": POINT, "leg_length": L},
    "frame_compliance": lambda w: {"point": POINT, "params": w.params},
    "frame_fea_modes": lambda w: {"params": w.params, "point": POINT, "count": 2, "segments": 2},
    "identify": lambda w: {"q": w.cal_q, "measured": w.cal_p, "nominal": w.nominal},
    "ik_and_jacobian": lambda w: {"points": POINT, "leg_length": L},
    "indices_from_jacobian": lambda w: {"J": np.eye(3)},
    "indices_from_model": lambda w: {"model": w.model, "q": w.q},
    "inertia_assumptions": lambda w: {"params": w.params},
    "inertia_table": lambda w: {"params": w.params},
    "inverse_condition": lambda w: {"points": POINT, "leg_length": L},
    "inverse_jacobian": lambda w: {"points": POINT, "leg_length": L},
    "inverse_kinematics": lambda w: {"points": POINT, "leg_length": L},
    "isotropy_residuals": lambda w: {"points": POINT, "leg_length": L},
    "jacobian": lambda w: {"points": POINT, "leg_length": L},
    "kinetostatic_indices": lambda w: {"points": POINT, "leg_length": L},
    "largest_certified_side": lambda w: {
        "leg_length": L,
        "centre": (0.0, 0.0, 0.0),
        "psi_min": 0.5,
        "psi_max": 2.0,
        "guess": 0.1,
        "resolution": 1e-2,
    },
    "leg_motion": lambda w: {
        "points": [POINT],
        "velocities": [(0.1, 0.0, 0.0)],
        "accelerations": [(0.0, 1.0, 0.0)],
        "leg_length": L,
    },
    "leg_vectors": lambda w: {"points": POINT, "leg_length": L},
    "line_move": lambda w: {"start": POINT, "end": OTHER, "limits": w.limits},
    "load_calibration": lambda w: {"path": w.calibration_file},
    "load_closed_loop": lambda w: {"params": w.params},
    "load_drive": lambda w: {"path": og.example_drive_file()},
    "load_loops": lambda w: {},
    "load_pinocchio": lambda w: {"params": w.params},
    "load_yourdfpy": lambda w: {"params": w.params},
    "loops_path": lambda w: {"urdf": "machine.urdf"},
    "manipulability": lambda w: {"points": POINT, "leg_length": L},
    "mechanical_energy": lambda w: {"dynamics": w.dyn, "q": w.result.q, "v": w.result.v},
    "motor_demand": lambda w: {
        "forces": w.result.forces,
        "slider_velocities": w.result.slider_velocities,
        "slider_accelerations": w.result.slider_accelerations,
    },
    "path_forms": lambda w: {
        "model": w.dyn,
        "points": [POINT],
        "tangents": [(1.0, 0.0, 0.0)],
        "curvatures": [(0.0, 0.0, 0.0)],
    },
    "path_forms_by_rnea": lambda w: {
        "model": w.dyn,
        "points": [POINT],
        "tangents": [(1.0, 0.0, 0.0)],
        "curvatures": [(0.0, 0.0, 0.0)],
    },
    "path_motion": lambda w: {
        "points": [POINT],
        "tangents": [(1.0, 0.0, 0.0)],
        "curvatures": [(0.0, 0.0, 0.0)],
        "leg_length": L,
    },
    "plan_poses": lambda w: {"params": w.params, "count": 12, "grid": 3},
    "parse_measurements": lambda w: {
        "data": w.measurements_file.read_bytes(),
        "source": "measurements.csv",
    },
    "sensitivity": lambda w: {"leg_length": L, "points": POINT},
    "natural_frequencies": lambda w: {"params": w.params, "points": POINT, "count": 3},
    "mjcf_text": lambda w: {"params": w.params, "drive": og.Drive(), "gravity": (0, 0, 9.81)},
    "write_mjcf": lambda w: {"path": w.out("machine.xml"), "params": w.params},
    "PlanLimits": lambda w: {"slider_speed": 1.2, "slider_acceleration": 20.0},
    "build_path": lambda w: {"program": w.program},
    "example_program_file": lambda w: {"name": "contour"},
    "example_program_text": lambda w: {"name": "contour"},
    "plan_program": lambda w: {
        "program": w.program,
        "machine": w.dyn,
        "limits": og.PlanLimits(slider_speed=1.2, slider_acceleration=20.0),
        "feed_override": 1.5,
        "rapid_override": 0.5,
        "blend": 2e-5,
        "progress": lambda done, total: None,
    },
    "stop_reasons": lambda w: {"path": w.plan.path},
    "read_program": lambda w: {"text": PROGRAM, "origin": (0.0, 0.0, 0.0)},
    "read_rs274": lambda w: {"path": w.program_file(), **RS274_OPTIONS},
    "read_rs274_text": lambda w: {"text": PROGRAM, **RS274_OPTIONS},
    "read_program_file": lambda w: {
        "path": og.example_program_file("contour"),
        "origin": (0.0, 0.0, 0.0),
    },
    "read_moves": lambda w: {"text": PROGRAM, "setup": og.make_setup()},
    "check_refusals": lambda w: {"read": og.read_moves(PROGRAM)},
    "make_setup": lambda w: {
        "origin": POINT,
        "offsets": {5221: 1.0},
        "tools": {1: 0.05},
        "start": OTHER,
        "block_delete": True,
    },
    "read_offsets": lambda w: {"path": w.text_file("offsets.var", "5221 1.0\n")},
    "read_tool_table": lambda w: {"path": w.text_file("tool.tbl", "T1 P1 Z50\n")},
    "design_axes": lambda w: {"params": w.params},
    "ProgramAxes": lambda w: {"mapping": (2, 1, -3)},
    "ServoSettings": lambda w: {"controller": "pd", "rate": 2000.0, "encoder_counts": 4096},
    "simulate": lambda w: {
        "plan": w.plan,
        "machine": w.dyn,
        "drive": og.Drive(),
        "settings": og.ServoSettings(rate=1000.0),
    },
    "contour_error": lambda w: {"path": w.plan.path, "points": [POINT, OTHER]},
    "plot_slice": lambda w: {"wmap": w.wmap, "index": "condition"},
    "plot_sweep": lambda w: {"table": w.table, "path": w.out("sweep.png")},
    "polygon_moves": lambda w: {"vertices": [POINT, OTHER, (0.0, 0.0, 0.0)], "limits": w.limits},
    "prototype": lambda w: {},
    "prototype_cube": lambda w: {"params": w.params},
    "prototype_note": lambda w: {"params": w.params},
    "prototype_urdf_path": lambda w: {},
    "read_loops": lambda w: {"path": og.loops_path(og.prototype_urdf_path())},
    "read_measurements": lambda w: {"path": w.measurements_file},
    "render_urdf": lambda w: {"params": w.params},
    "requirement_forms": lambda w: {"machine": w.dyn, "points": POINT},
    "run_sweep": lambda w: {"spec": w.spec, "out": w.out("sweep"), "progress": False},
    "sensitivity_indices": lambda w: {"leg_length": L, "points": [POINT]},
    "s_curve_profile": lambda w: {"distance": 0.1, "v_max": 1.0, "a_max": 10.0, "jerk": 500.0},
    "singularity_measures": lambda w: {"j_inv": np.eye(3)},
    "size_drives": lambda w: {"result": w.result, "time": w.trajectory.t},
    "slice_grid": lambda w: {
        "axis": "z",
        "value": 0.0,
        "lower": (-0.05, -0.05),
        "upper": (0.05, 0.05),
        "n": 3,
    },
    "slider_range_over_cube": lambda w: {
        "leg_length": L,
        "corner": (-0.07, -0.07, -0.07),
        "side": 0.2,
    },
    "standard_cycle": lambda w: {"params": w.params},
    "standard_cycle_segments": lambda w: {"params": w.params},
    "standard_limits": lambda w: {},
    "stiffness_map": lambda w: {"grid": w.grid, "params": w.params},
    "sweep_figure": lambda w: {"table": w.table},
    "sweep_table": lambda w: {"rows": w.rows, "names": ["leg_length"]},
    "tool_motion_from_sliders": lambda w: {
        "q": [(0.0, 0.01, -0.01)],
        "q_dot": [(0.1, 0.0, 0.0)],
        "q_ddot": [(0.0, 1.0, 0.0)],
        "leg_length": L,
    },
    "transmission_factor_map": lambda w: {"grid": w.grid, "leg_length": L},
    "transmission_factors": lambda w: {"points": POINT, "leg_length": L},
    "trapezoidal_profile": lambda w: {"distance": 0.1, "v_max": 1.0, "a_max": 10.0},
    "urdf_path": lambda w: {"params": w.params},
    "velocity_ellipsoid": lambda w: {"points": POINT, "leg_length": L},
    "workspace_map": lambda w: {"grid": w.slice, "params": w.params},
    "worst_case_on_grid": lambda w: {"machine": w.dyn, "grid": w.grid},
    "worst_case_over_cube": lambda w: {"machine": w.dyn, "resolution": 2},
    "worst_case_requirements": lambda w: {"machine": w.dyn, "points": POINT},
    "write_calibration": lambda w: {"path": w.out("c.yaml"), "calibration": w.calibration},
    "write_loops": lambda w: {"urdf": w.out("machine.urdf")},
    "write_package": lambda w: {"directory": w.out("package"), "params": w.params},
    "write_report": lambda w: {"out": w.out("report"), "data": w.report},
    "write_urdf": lambda w: {"path": w.out("machine.urdf"), "params": w.params},
}


def _public_callables() -> list[str]:
    return sorted(
        name
        for name in og.__all__
        if callable(getattr(og, name))
        and not (isinstance(getattr(og, name), type) and issubclass(getattr(og, name), Exception))
    )


def test_every_public_callable_is_walked_or_is_a_result() -> None:
    names = set(_public_callables())
    assert names - RESULTS - set(VALID) == set(), "add a valid call to VALID"
    assert set(VALID) - names == set() and RESULTS - names == set()


def _bad_values(valid: Any) -> Iterator[tuple[str, Any]]:
    """The wrong kinds of value tried in place of ``valid``."""
    yield "None", None
    yield "str", "abc"
    yield "dict", {"a": 1}
    try:
        shape = np.shape(valid) if not isinstance(valid, (str, dict)) else ()
        numeric = np.asarray(valid, dtype=float)
    except (TypeError, ValueError):
        shape, numeric = (3,), None
    yield (
        "nan",
        float("nan") if numeric is not None and shape == () else np.full(shape or (3,), np.nan),
    )
    yield "shape", np.zeros((4, 5))


#: Keyword arguments that are not values of the call (``**options``).
_VARIADIC = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)


def _arguments(name: str) -> list[str]:
    signature = inspect.signature(getattr(og, name))
    return [p.name for p in signature.parameters.values() if p.kind not in _VARIADIC]


@pytest.fixture(scope="module")
def world(tmp_path_factory: pytest.TempPathFactory) -> World:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return World(tmp_path_factory.mktemp("walk"))


#: Where the message may name the thing in the user's words rather than the
#: argument: (callable, argument) -> the word it may use instead.
ALIASES = {
    ("SweepAxis", "name"): "sweep axis",  # as the command line's --param says
    ("SweepAxis", "values"): "leg_length",  # the axis whose values are bad
    ("SweepSpec", "axes"): "axis",  # one text NAME=VALUES is one axis
    ("read_rs274", "path"): "program",  # the file is the program
    ("cut_conditions", "data"): "cut file",  # the mapping is a cut file's
    ("read_rs274", "executable"): "program",  # the program rs274 is not found
    ("read_rs274_text", "executable"): "program",
}
#: Errors that are the documented answer to a wrong value of an argument.
EXPECTED: dict[tuple[str, str], type[OrthoglideError]] = {
    # a non-finite J^-1 is a singular one (an infinite row: eta_i = 0)
    ("check_inverse_jacobian", "j_inv"): og.SingularConfigurationError,
    # a text that is not G-code is a program error, named by its line
    ("read_program", "text"): og.ProgramError,
    # a file that records no design is refused as such, with the line to add
    ("check_design", "recorded"): og.DesignMismatchError,
    ("read_rs274_text", "text"): og.ProgramError,
}


def _names_argument(exc: OrthoglideError, name: str, argument: str) -> bool:
    if isinstance(exc, EXPECTED.get((name, argument), ())):
        return True
    words = {argument, ALIASES.get((name, argument), argument)}
    return any(re.search(rf"\b{re.escape(w)}\b", str(exc), re.IGNORECASE) for w in words)


def _walk(world: World, name: str) -> list[str]:
    """The calls of ``name`` with one wrong argument that end in a foreign error."""
    function = getattr(og, name)
    signature = inspect.signature(function)
    base = VALID[name](world)
    failures = []
    for argument in _arguments(name):
        parameter = signature.parameters[argument]
        valid = base.get(argument, parameter.default)
        path = "Path" in str(parameter.annotation)
        for label, bad in _bad_values(valid):
            if bad is None and parameter.default is None:
                continue  # None is the documented default
            if path and label == "str":
                continue  # a string is a path: which file it names is not this test's
            kwargs = {**VALID[name](world), argument: bad}
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                warnings.simplefilter("error", RuntimeWarning)
                try:
                    function(**kwargs)
                except OrthoglideError as exc:
                    if not _names_argument(exc, name, argument) or "\n" in str(exc):
                        failures.append(f"{name}({argument}={label}): {type(exc).__name__}: {exc}")
                except Exception as exc:  # the failure this test is about
                    failures.append(f"{name}({argument}={label}): {type(exc).__name__}: {exc}")
    return failures


@pytest.mark.parametrize("name", sorted(VALID))
def test_wrong_arguments_raise_the_package_error_naming_them(
    world: World, name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # a string taken as a relative path lands here
    if name in NEEDS_RS274 and shutil.which("rs274") is None:
        message = "rs274 not found on PATH (Debian: apt-get install linuxcnc-uspace)"
        if os.environ.get("ORTHOGLIDE_REQUIRE_LINUXCNC") == "1":
            pytest.fail(f"{message}, and ORTHOGLIDE_REQUIRE_LINUXCNC=1 requires it")
        pytest.skip(f"{message}: {name} not walked")
    VALID[name](world)  # the valid call's arguments build
    function = getattr(og, name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        function(**VALID[name](world))  # and the call works
    failures = _walk(world, name)
    assert not failures, "\n".join(failures)


#: Annotations of an argument that is the machine's model or dynamics.
_MODEL_WORDS = ("ClosedLoopModel", "ClosedLoopDynamics", "Machine")


def _model_arguments() -> list[tuple[str, str]]:
    out = []
    for name in sorted(VALID):
        for p in inspect.signature(getattr(og, name)).parameters.values():
            if any(word in str(p.annotation) for word in _MODEL_WORDS):
                out.append((name, p.name))
    return out


def test_the_entry_points_that_need_a_model_are_found() -> None:
    found = set(_model_arguments())
    assert found >= {
        ("ClosedLoopDynamics", "model"),
        ("ForwardDynamics", "dynamics"),
        ("Viewer", "model"),
        ("indices_from_model", "model"),
        ("mechanical_energy", "dynamics"),
        ("requirement_forms", "machine"),
        ("worst_case_on_grid", "machine"),
        ("worst_case_over_cube", "machine"),
        ("worst_case_requirements", "machine"),
    }
    for name, argument in found:  # each says it takes the parameters too
        annotation = str(inspect.signature(getattr(og, name)).parameters[argument].annotation)
        assert "OrthoglideParams" in annotation or annotation == "Machine", (name, annotation)


@pytest.mark.parametrize(("name", "argument"), _model_arguments())
def test_every_entry_point_that_needs_a_model_takes_the_parameters(
    world: World, name: str, argument: str
) -> None:
    function = getattr(og, name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for machine in (world.params, world.model, None):
            function(**{**VALID[name](world), argument: machine})


def test_no_public_name_is_shadowed_by_a_module() -> None:
    # a function named like its module: once the module is imported (by the
    # package itself or a user), the package's attribute is the module
    import importlib
    import pkgutil
    from types import ModuleType

    for info in pkgutil.walk_packages(og.__path__, "orthoglide_pin."):
        if ".cli" not in info.name and not info.name.endswith("__main__"):
            importlib.import_module(info.name)
    shadowed = [n for n in og.__all__ if isinstance(getattr(og, n), ModuleType)]
    assert shadowed == []
