"""The kinematics component, built by ``halcompile`` and called as LinuxCNC calls it.

The module LinuxCNC loads is built from the exported ``orthoglide_kins.comp``
(``halcompile --compile``, in a temporary folder) and its entry points are
called through ``ctypes``: inverse then forward kinematics round-trip, and both
agree with the package's closed form, on 1,000 poses of the cube, for the
prototype and for another design (other legs, other program axes): the pose is
in the design's program axes, as ``orthoglide plan`` reads programs.
"""

from __future__ import annotations

import ctypes
import os

import numpy as np
import pytest
from controller._support import Pose, halcompile

from orthoglide_pin.controller import COMPONENT, component_text
from orthoglide_pin.kinematics.closed_form import direct_kinematics, inverse_jacobian
from orthoglide_pin.kinematics.closed_form import inverse_kinematics as package_ik
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.program.axes import design_axes

#: Round trip and agreement [mm].
TOL_MM = 1e-9
#: Poses per design.
POSES = 1000
SEED = 20261206
DESIGNS = {
    "prototype": OrthoglideParams(),
    "long-legs": OrthoglideParams(leg_length=0.4, program_axes=(1, -2, -3)),
}
_FLAGS = ctypes.c_ulong


@pytest.fixture(scope="module", params=list(DESIGNS))
def built(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> tuple:
    params = DESIGNS[request.param]
    folder = tmp_path_factory.mktemp(request.param)
    comp = folder / f"{COMPONENT}.comp"
    comp.write_text(component_text(params), encoding="utf-8")
    halcompile(comp)
    so = comp.with_suffix(".so")
    lib = ctypes.CDLL(str(so), mode=os.RTLD_LAZY | os.RTLD_LOCAL)  # no HAL needed for these
    return params, lib


def _poses(params: OrthoglideParams) -> np.ndarray:
    rng = np.random.default_rng(SEED)
    world = np.asarray(params.workspace_corner) + params.workspace_side * rng.random((POSES, 3))
    return 1e3 * design_axes(params).to_program(world)  # [mm]


def _inverse(lib: ctypes.CDLL, pose: np.ndarray) -> np.ndarray:
    p, j, f = Pose(*pose), (ctypes.c_double * 9)(), _FLAGS(0)
    assert lib.kinematicsInverse(ctypes.byref(p), j, ctypes.byref(f), ctypes.byref(f)) == 0
    return np.array(j[:3])


def _forward(lib: ctypes.CDLL, joints: np.ndarray) -> np.ndarray:
    j, p, f = (ctypes.c_double * 9)(*joints), Pose(), _FLAGS(0)
    assert lib.kinematicsForward(j, ctypes.byref(p), ctypes.byref(f), ctypes.byref(f)) == 0
    return np.array([p.x, p.y, p.z])


def test_round_trip_and_agreement(built: tuple) -> None:
    params, lib = built
    axes = design_axes(params)
    poses = _poses(params)
    joints = np.array([_inverse(lib, x) for x in poses])
    back = np.array([_forward(lib, q) for q in joints])
    assert np.abs(back - poses).max() <= TOL_MM
    world = axes.to_world(1e-3 * poses)
    assert np.abs(joints - 1e3 * package_ik(world, params.leg_length)).max() <= TOL_MM
    fk = 1e3 * axes.to_program(direct_kinematics(1e-3 * joints, params.leg_length))
    assert np.abs(back - fk).max() <= TOL_MM


def test_jacobian_is_pr_4550s(built: tuple) -> None:
    """``jac[j][a]`` = d joint j / d pose a: ``J^-1`` times the design's program axes."""
    params, lib = built
    axes = design_axes(params)
    mapping = axes.matrix
    for pose in _poses(params)[:50]:
        p, jac = Pose(*pose), ((ctypes.c_double * 9) * 16)()
        assert lib.kinematicsJacobian(None, ctypes.byref(p), jac) == 0
        got = np.array([[jac[r][c] for c in range(3)] for r in range(3)])
        want = inverse_jacobian(axes.to_world(1e-3 * pose), params.leg_length) @ mapping
        assert np.allclose(got, want, atol=1e-12)


def test_unreachable_pose_is_refused(built: tuple) -> None:
    _, lib = built
    p, j, f = Pose(1e4, 1e4, 1e4), (ctypes.c_double * 9)(), _FLAGS(0)
    assert lib.kinematicsInverse(ctypes.byref(p), j, ctypes.byref(f), ctypes.byref(f)) == -1
