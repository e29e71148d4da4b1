"""API misuse raises the package's own errors, naming the argument.

Each case used to end in an ``AttributeError``, ``TypeError``, ``ValueError``
or a numpy warning from deep inside; now it is an :class:`OrthoglideError`
whose message names the argument, in one line.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import Drive, DriveTrain, load_drive, motor_demand
from orthoglide_pin.dynamics.requirements import worst_case_requirements
from orthoglide_pin.exceptions import InvalidParameterError, OrthoglideError
from orthoglide_pin.kinematics.closed_form import ik_and_jacobian
from orthoglide_pin.kinetostatics.indices import indices_from_jacobian
from orthoglide_pin.kinetostatics.workspace import workspace_map
from orthoglide_pin.machine.description import render_urdf
from orthoglide_pin.motion.cycle import standard_cycle
from orthoglide_pin.motion.trajectory import build_trajectory

ZEROS = np.zeros((1, 3))

Case = tuple[str, Callable[[og.ClosedLoopModel], Any], str]
CASES: list[Case] = [
    ("render_urdf(str)", lambda m: render_urdf("prototype"), "params"),  # type: ignore[arg-type]
    ("ClosedLoopModel(dict)", lambda m: og.ClosedLoopModel({"leg_length": 0.3}), "params"),  # type: ignore[arg-type]
    ("ClosedLoopDynamics(str)", lambda m: og.ClosedLoopDynamics("prototype"), "model"),  # type: ignore[arg-type]
    ("standard_cycle(str)", lambda m: standard_cycle("prototype"), "params"),  # type: ignore[arg-type]
    ("workspace_map(str)", lambda m: workspace_map("grid", og.prototype()), "grid"),  # type: ignore[arg-type]
    ("build_trajectory(str)", lambda m: build_trajectory("segments"), "segments"),  # type: ignore[arg-type]
    ("build_trajectory([1])", lambda m: build_trajectory([1]), "segments[0]"),  # type: ignore[list-item]
    (
        "worst_case(drive=str)",
        lambda m: worst_case_requirements(None, [0, 0, 0], drive="d"),
        "drive",
    ),  # type: ignore[arg-type]
    ("Drive(train=str)", lambda m: Drive(train="t"), "train"),  # type: ignore[arg-type]
    ("motor_demand(train=str)", lambda m: motor_demand(ZEROS, ZEROS, ZEROS, train="t"), "train"),  # type: ignore[arg-type]
    ("load_drive(3)", lambda m: load_drive(3), "path"),  # type: ignore[arg-type]
    ("OrthoglideParams.load(None)", lambda m: og.OrthoglideParams.load(None), "path"),  # type: ignore[arg-type]
    ("ik_and_jacobian(str)", lambda m: ik_and_jacobian("abc", 0.31), "points.shape"),
    (
        "ik_and_jacobian(ragged)",
        lambda m: ik_and_jacobian([[1, 2, 3], [1, 2]], 0.31),
        "points.shape",
    ),
    ("indices_from_jacobian(0)", lambda m: indices_from_jacobian(np.zeros((3, 3))), "J"),
    (
        "indices_from_jacobian(rank 2)",
        lambda m: indices_from_jacobian(np.diag([1.0, 1.0, 0.0])),
        "J",
    ),
    (
        "solve(max_iterations=str)",
        lambda m: m.solve([0, 0, 0], max_iterations="9"),
        "max_iterations",
    ),  # type: ignore[arg-type]
    ("solve(tol=-1)", lambda m: m.solve([0.01, 0, 0], tol=-1.0), "tol"),
    ("jacobian(q of 2 x 18)", lambda m: m.jacobian(np.zeros((2, 18))), "q"),
]


@pytest.mark.parametrize(("label", "call", "name"), CASES, ids=[c[0] for c in CASES])
def test_misuse_raises_the_package_error_naming_the_argument(
    model: og.ClosedLoopModel, label: str, call: Callable[[og.ClosedLoopModel], Any], name: str
) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warning on the way
        with pytest.raises(OrthoglideError) as info:
            call(model)
    assert isinstance(info.value, InvalidParameterError), label
    assert info.value.name == name, (label, info.value.name)
    message = str(info.value)
    assert message.startswith(f"invalid {name}=") and "\n" not in message


def test_a_missing_drive_file_names_the_path_given(tmp_path: Path) -> None:
    missing = tmp_path / "no-such-drive.yaml"
    with pytest.raises(InvalidParameterError) as info:
        load_drive(missing)
    assert str(missing) in str(info.value) and "No such file" in str(info.value)


def test_well_formed_calls_still_work(model: og.ClosedLoopModel) -> None:
    rng = np.random.default_rng(5)
    point = rng.uniform(-0.05, 0.05, 3)
    q, J = ik_and_jacobian(point, 0.31)
    res = indices_from_jacobian(J)
    assert res.condition >= 1.0 and np.isfinite(res.force_axes).all()
    assert Drive(DriveTrain()).motor is None
    assert model.solve(q, tol=1e-12, max_iterations=np.int64(20)).residual <= 1e-12
