"""Every public method of the public classes, walked with wrong-typed arguments.

The companion of ``test_api_walk.py``: the classes of ``orthoglide_pin.__all__``
are enumerated, and each public method that takes arguments is called once
validly (:data:`VALID`), then with each argument in turn replaced by ``None``,
a string, a dict, NaN and an array of the wrong shape. What may come out is a
result or an :class:`~orthoglide_pin.exceptions.OrthoglideError` whose one-line
message names the argument; never a ``TypeError`` or numpy warning from deep
inside.

The classes of the planning and simulation layers are not walked here: they
are changing and are walked with their own layers' tests. A method in neither
:data:`VALID` nor :data:`EXEMPT` fails the test, so a new method gets walked.
"""

from __future__ import annotations

import inspect
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hostile.test_api_walk import OTHER, POINT, World, _bad_values, _names_argument

import orthoglide_pin as og
from orthoglide_pin.exceptions import OrthoglideError

#: Layers whose classes this walk leaves to their own tests (they are changing).
SKIPPED_LAYERS = ("orthoglide_pin.planning", "orthoglide_pin.simulation")

#: Methods that take no user data, or only what the package built, with why.
EXEMPT = {
    # start a server: walked without one would mean binding ports in a unit test
    "Viewer.serve": "starts a server (its port is checked by test_viewer_host)",
    "Viewer.serve_forever": "starts a server and blocks",
}

#: Where the message may name the thing in the user's words rather than the
#: argument: (method, argument) -> the word it may use instead.
ALIASES = {
    ("OrthoglideParams.from_dict", "data"): "parameter name",  # the unknown key, named
    ("SweepAxis.parse", "text"): "axis",  # as the command line's --param says
}

Instance = Callable[[World], Any]

#: One instance of each walked class, small, on the prototype.
INSTANCES: dict[str, Instance] = {
    "ArcMove": lambda w: og.circle_move(POINT, (0.0, 0.0, 1.0), 0.02, w.limits),
    "ProgramAxes": lambda w: og.design_axes(),
    "Calibration": lambda w: w.calibration,
    "CartesianStiffness": lambda w: og.cartesian_stiffness(POINT, w.params),
    "ClosedLoopDynamics": lambda w: w.dyn,
    "ClosedLoopModel": lambda w: w.model,
    "Drive": lambda w: og.Drive(),
    "DriveTrain": lambda w: og.DriveTrain(),
    "CutConditions": lambda w: og.read_cut_file(og.shipped_cut_file()),
    "Engagement": lambda w: og.Engagement(0.002, 0.005),
    "MillingProcess": lambda w: og.MillingProcess(2, 6e8, 2e8, 0.0, 1.0),
    "ModalModel": lambda w: og.single_mode(900.0, 0.02, 1e7, "x"),
    "StabilityLobes": lambda w: og.stability_lobes(
        og.read_cut_file(og.shipped_cut_file()), POINT, speeds=[1000.0, 1200.0]
    ),
    "Dwell": lambda w: og.dwell(POINT, 0.1),
    "ForwardDynamics": lambda w: og.ForwardDynamics(w.dyn),
    "GeometricModel": lambda w: w.nominal,
    "Grid": lambda w: w.grid,
    "InertiaTable": lambda w: og.inertia_table(w.params),
    "KinetostaticIndices": lambda w: og.kinetostatic_indices(POINT, w.params.leg_length),
    "LegGeometry": lambda w: og.LegGeometry(np.zeros((3, 3)), np.eye(3), np.full(3, 0.31)),
    "LineMove": lambda w: og.line_move(POINT, OTHER, w.limits),
    "MotionForm": lambda w: og.requirement_forms(w.dyn, POINT).forces,
    "MotionLimits": lambda w: w.limits,
    "MotionProfile": lambda w: og.s_curve_profile(0.1, 1.0, 10.0, 500.0),
    "OrthoglideParams": lambda w: w.params,
    "PathForms": lambda w: og.path_forms(w.dyn, [POINT], [(1.0, 0.0, 0.0)], [(0.0, 0.0, 0.0)]),
    "RequirementForms": lambda w: og.requirement_forms(w.dyn, POINT),
    "Segment": lambda w: og.line_move(POINT, OTHER, w.limits),
    "SweepAxis": lambda w: og.SweepAxis("leg_length", (0.3, 0.32)),
    "Trajectory": lambda w: w.trajectory,
    "Viewer": lambda w: og.Viewer(w.model),
    "WorkspaceDesign": lambda w: og.design_from_workspace(0.2, 0.5, 2.0),
    "WorkspaceMap": lambda w: w.wmap,
    "WorstCase": lambda w: og.worst_case_on_grid(w.dyn, og.cube_grid((-0.05,) * 3, 0.1, 2)),
}

Valid = Callable[[World], dict[str, Any]]
Q_A = (0.0, 0.01, -0.01)

#: One working call of each walked method, by argument name.
VALID: dict[str, Valid] = {
    "CutConditions.engagement_at": lambda w: {"line": 3},
    "Engagement.immersion": lambda w: {"diameter": 0.01},
    "MillingProcess.directional": lambda w: {"angles": [0.1, 0.5]},
    "MillingProcess.interval_means": lambda w: {"steps": 4},
    "ModalModel.rotated": lambda w: {"angle": 0.3},
    "ModalModel.significant": lambda w: {"share": 0.01, "resonant": True},
    "ModalModel.with_modes": lambda w: {"other": og.single_mode(500.0, 0.03, 2e7, "y")},
    "StabilityLobes.limit_at": lambda w: {"speed": 1100.0},
    "ProgramAxes.to_world": lambda w: {"points": POINT},
    "ProgramAxes.to_program": lambda w: {"points": POINT},
    "ArcMove.evaluate": lambda w: {"tau": np.linspace(0.0, 1.0, 3)},
    "ArcMove.point": lambda w: {"angle": 0.3},
    "Calibration.check_design": lambda w: {"params": w.params, "what": "calibration.yaml"},
    "Calibration.direct_kinematics": lambda w: {"q": Q_A},
    "Calibration.legs": lambda w: {"params": w.params},
    "Calibration.inverse_kinematics": lambda w: {"points": POINT},
    "CartesianStiffness.deflection": lambda w: {"wrench": (10.0, 0.0, 0.0, 0.0, 0.0, 0.0)},
    "ClosedLoopDynamics.engine": lambda w: {"gravity": (0.0, 0.0, -9.81)},
    "ClosedLoopDynamics.gravity_vector": lambda w: {"gravity": (0.0, 0.0, -9.81)},
    "ClosedLoopDynamics.inverse_dynamics": lambda w: {
        "p": [POINT],
        "p_dot": [(0.1, 0.0, 0.0)],
        "p_ddot": [(0.0, 1.0, 0.0)],
    },
    "ClosedLoopDynamics.inverse_dynamics_sliders": lambda w: {
        "q": [Q_A],
        "q_dot": [(0.1, 0.0, 0.0)],
        "q_ddot": [(0.0, 1.0, 0.0)],
    },
    "ClosedLoopDynamics.pinocchio_model": lambda w: {"gravity": (0.0, 0.0, -9.81)},
    "ClosedLoopDynamics.static_forces": lambda w: {"p": POINT, "wrench": (1.0, 0, 0, 0, 0, 0)},
    "ClosedLoopModel.configuration": lambda w: {"points": POINT},
    "ClosedLoopModel.constraint_rank": lambda w: {"q": w.q},
    "ClosedLoopModel.constraint_residual_and_jacobian": lambda w: {"q": w.q},
    "ClosedLoopModel.inverse_jacobian": lambda w: {"q": w.q},
    "ClosedLoopModel.jacobian": lambda w: {"q": w.q},
    "ClosedLoopModel.mobility": lambda w: {"q": w.q},
    "ClosedLoopModel.passive_rank": lambda w: {"q": w.q},
    "ClosedLoopModel.platform_orientation_error": lambda w: {"q": w.q},
    "ClosedLoopModel.platform_rotation": lambda w: {"q": w.q},
    "ClosedLoopModel.solve": lambda w: {"q_actuated": Q_A},
    "ClosedLoopModel.solve_many": lambda w: {"q_actuated": [Q_A]},
    "ClosedLoopModel.tool_position": lambda w: {"q": w.q},
    "ClosedLoopModel.velocity_map": lambda w: {"q": w.q},
    "Drive.from_dict": lambda w: {"data": {"drive_train": {"lead": 0.02}}},
    "DriveTrain.friction": lambda w: {"motor_speed": np.array([10.0, -5.0])},
    "DriveTrain.motor_speed": lambda w: {"slider_velocity": np.array([0.1, -0.2])},
    "Dwell.evaluate": lambda w: {"tau": np.linspace(0.0, 1.0, 3)},
    "ForwardDynamics.accelerations": lambda w: {
        "q": w.result.q[0],
        "v": w.result.v[0],
        "forces": w.result.forces[0],
    },
    "GeometricModel.direct_kinematics": lambda w: {"q": Q_A},
    "GeometricModel.from_vector": lambda w: {"theta": w.nominal.vector()},
    "GeometricModel.inverse_jacobian": lambda w: {"points": POINT},
    "GeometricModel.inverse_kinematics": lambda w: {"points": POINT},
    "GeometricModel.jacobian": lambda w: {"points": POINT},
    "GeometricModel.legs": lambda w: {"leg_length": 0.31},
    "GeometricModel.nominal": lambda w: {"leg_length": 0.31},
    "GeometricModel.parameter_jacobian": lambda w: {"q": [Q_A]},
    "Grid.point": lambda w: {"index": 1},
    "Grid.blocks": lambda w: {"block": 4},
    "Grid.fill": lambda w: {"start": 0, "stop": 3, "rows": np.zeros((3, 4))},
    "Calibration.from_identification": lambda w: {
        "result": og.identify(w.cal_q, w.cal_p, w.nominal),
        "data": og.Measurements(w.cal_q, w.cal_p, sha256="ab" * 32),
    },
    "KinetostaticIndices.from_parts": lambda w: {
        "factors": np.array([0.8, 1.0, 1.3]),
        "det": np.array(1.04),
        "directions": np.eye(3),
    },
    "InertiaTable.kind": lambda w: {"kind": "bar"},
    "LegGeometry.drawing": lambda w: {"leg_length": 0.31},
    "LegGeometry.from_points": lambda w: {
        "anchors": w.nominal.anchors,
        "axes": np.eye(3),
        "lengths": np.full(3, 0.31),
        "leg_length": 0.31,
    },
    "LineMove.evaluate": lambda w: {"tau": np.linspace(0.0, 1.0, 3)},
    "MotionForm.bounds": lambda w: {"v_max": 1.0, "a_max": 10.0},
    "MotionForm.combine": lambda w: {
        "scale": 1.0,
        "other": og.requirement_forms(w.dyn, POINT).slider_accelerations,
        "other_scale": 2.0,
    },
    "MotionForm.evaluate": lambda w: {
        "velocity": [(0.1, 0.0, 0.0)],
        "acceleration": [(0, 1.0, 0)],
    },
    "MotionForm.worst_motion": lambda w: {"v_max": 1.0, "a_max": 10.0},
    "MotionLimits.profile": lambda w: {"distance": 0.1},
    "MotionLimits.scaled": lambda w: {"v_max": 0.5, "a_max": 5.0},
    "MotionProfile.sample": lambda w: {"t": np.linspace(0.0, 0.05, 4)},
    "OrthoglideParams.from_dict": lambda w: {"data": {"leg_length": 0.32}},
    "OrthoglideParams.from_yaml": lambda w: {"text": "leg_length: 0.32\n"},
    "OrthoglideParams.load": lambda w: {"path": w.params.save(w.out("params.yaml"))},
    "OrthoglideParams.replace": lambda w: {"leg_length": 0.32},
    "OrthoglideParams.save": lambda w: {"path": w.out("params.yaml")},
    "OrthoglideParams.to_dict": lambda w: {"derived_as_none": False},
    "PathForms.forces": lambda w: {"s_dot": np.array([0.1]), "s_ddot": np.array([1.0])},
    "PathForms.slider_motion": lambda w: {"s_dot": np.array([0.1]), "s_ddot": np.array([1.0])},
    "RequirementForms.slider_speed": lambda w: {"v_max": 1.0},
    "RequirementForms.torques": lambda w: {"train": og.DriveTrain()},
    "Segment.evaluate": lambda w: {"tau": np.linspace(0.0, 1.0, 3)},
    "SweepAxis.parse": lambda w: {"text": "leg_length=0.3,0.32"},
    "Trajectory.where": lambda w: {"label": w.trajectory.labels[0]},
    "Viewer.add_ellipsoids": lambda w: {"points": [POINT]},
    "Viewer.add_path": lambda w: {"points": [POINT, OTHER]},
    "Viewer.add_workspace": lambda w: {},
    "Viewer.grid_points": lambda w: {"n": 2},
    "Viewer.iframe": lambda w: {"height": 300},
    "Viewer.play": lambda w: {"trajectory": w.trajectory, "fps": 10.0, "time_scale": 20.0},
    "Viewer.play_mode": lambda w: {"point": POINT, "mode": 1},
    "Viewer.save_html": lambda w: {"path": w.out("scene.html")},
    "Viewer.show": lambda w: {"configuration": w.q},
    "Viewer.show_point": lambda w: {"point": POINT},
    "Viewer.show_sliders": lambda w: {"q_actuated": Q_A},
    "WorkspaceDesign.certify": lambda w: {"tol": 1e-2},
    "WorkspaceDesign.model": lambda w: {},
    "WorkspaceDesign.to_params": lambda w: {},
    "WorkspaceDesign.urdf": lambda w: {},
    "WorkspaceMap.index": lambda w: {"name": "condition"},
    "WorkspaceMap.save_csv": lambda w: {"path": w.out("map.csv")},
    "WorstCase.grid_field": lambda w: {"name": "force"},
    "WorstCase.peak": lambda w: {"name": "force"},
}

#: Keyword arguments that are not values of the call (``**options``).
_VARIADIC = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)


def _walked_classes() -> list[str]:
    return sorted(
        name
        for name in og.__all__
        if isinstance(getattr(og, name), type)
        and not issubclass(getattr(og, name), Exception)
        and not getattr(og, name).__module__.startswith(SKIPPED_LAYERS)
    )


def _methods() -> list[str]:
    """``Class.method`` of every public method that takes an argument."""
    out = []
    for cls_name in _walked_classes():
        cls = getattr(og, cls_name)
        for attr in dir(cls):
            raw = inspect.getattr_static(cls, attr)
            if attr.startswith("_") or not (
                inspect.isfunction(raw) or isinstance(raw, (staticmethod, classmethod))
            ):
                continue
            parameters = inspect.signature(getattr(cls, attr)).parameters
            if [p for p in parameters if p not in ("self", "cls")]:
                out.append(f"{cls_name}.{attr}")
    return out


def test_every_public_method_is_walked_or_exempt() -> None:
    methods = set(_methods())
    assert methods - set(VALID) - set(EXEMPT) == set(), "add a valid call to VALID"
    assert set(VALID) - methods == set() and set(EXEMPT) - methods == set()
    assert set(VALID).isdisjoint(EXEMPT)


def test_the_changing_layers_are_the_only_ones_left_out() -> None:
    left = {
        getattr(og, n).__module__.split(".")[1]
        for n in og.__all__
        if isinstance(getattr(og, n), type) and n not in _walked_classes()
        if not issubclass(getattr(og, n), Exception)
    }
    assert left <= {"planning", "simulation"}


@pytest.fixture(scope="module")
def world(tmp_path_factory: pytest.TempPathFactory) -> World:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return World(tmp_path_factory.mktemp("methods"))


@pytest.fixture(scope="module")
def instances(world: World) -> dict[str, Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return {name: make(world) for name, make in INSTANCES.items()}


def _bound(instances: dict[str, Any], method: str) -> Callable[..., Any]:
    cls_name, attr = method.split(".")
    return getattr(instances[cls_name], attr)  # type: ignore[no-any-return]


def _walk(world: World, instances: dict[str, Any], method: str) -> list[str]:
    """The calls of ``method`` with one wrong argument that end in a foreign error."""
    function = _bound(instances, method)
    signature = inspect.signature(function)
    base = VALID[method](world)
    failures = []
    for parameter in signature.parameters.values():
        argument = parameter.name
        variadic = parameter.kind in _VARIADIC
        if variadic and argument not in base:
            continue
        valid = base.get(argument, None if variadic else parameter.default)
        path = "Path" in str(parameter.annotation)
        for label, bad in _bad_values(valid):
            if bad is None and parameter.default is None:
                continue  # None is the documented default
            if path and label == "str":
                continue  # a string is a path
            kwargs = {**VALID[method](world), argument: bad}
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                warnings.simplefilter("error", RuntimeWarning)
                try:
                    result = function(**kwargs)
                    if inspect.isgenerator(result):
                        list(result)  # a lazy method fails when iterated
                except OrthoglideError as exc:
                    named = _names_argument(exc, method, argument) or re.search(
                        rf"\b{ALIASES.get((method, argument), argument)}\b", str(exc)
                    )
                    if not named or "\n" in str(exc):
                        failures.append(
                            f"{method}({argument}={label}): {type(exc).__name__}: {exc}"
                        )
                except Exception as exc:  # the failure this test is about
                    failures.append(f"{method}({argument}={label}): {type(exc).__name__}: {exc}")
    return failures


@pytest.mark.parametrize("method", sorted(VALID))
def test_wrong_arguments_to_methods_raise_the_package_error_naming_them(
    world: World,
    instances: dict[str, Any],
    method: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)  # a string taken as a relative path lands here
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        _bound(instances, method)(**VALID[method](world))  # the valid call works
    failures = _walk(world, instances, method)
    assert not failures, "\n".join(failures)
