"""MuJoCo's joint order against Pinocchio's, and the MJCF compiled or refused."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import DescriptionError
from orthoglide_pin.simulation.engine import compile_mjcf, joint_order, mujoco_state
from orthoglide_pin.simulation.mjcf import mjcf_text

mujoco = pytest.importorskip("mujoco")

#: The tool's position in MuJoCo against the closed-loop model [m].
POSITION_TOL = 1e-12


@pytest.mark.parametrize("leg", [0.31, 0.36])
def test_a_closed_loop_state_puts_the_tool_where_pinocchio_does(leg: float) -> None:
    params = og.prototype().replace(leg_length=leg)
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    model = compile_mjcf(mjcf_text(params))
    order = joint_order(model, dyn.closed_loop.model)
    names = [model.joint(i).name for i in range(model.njnt)]
    pm = dyn.closed_loop.model
    assert [pm.names[pm.getJointId(n)] for n in names] == names
    data = mujoco.MjData(model)
    rng = np.random.default_rng(3)
    points = 0.04 * (leg / 0.31) * rng.uniform(-1.0, 1.0, (10, 3))
    res = dyn.inverse_dynamics(points, np.zeros_like(points), np.zeros_like(points))
    for k, p in enumerate(points):
        data.qpos[:], data.qvel[:] = mujoco_state(order, res.q[k], res.v[k])
        mujoco.mj_kinematics(model, data)
        assert np.abs(data.xpos[model.body("tool").id] - p).max() < POSITION_TOL
        for e in range(model.neq):  # the loops closed in MuJoCo too
            gap = data.site_xpos[model.eq_obj1id[e]] - data.site_xpos[model.eq_obj2id[e]]
            assert np.linalg.norm(gap) < POSITION_TOL


def test_bad_documents_are_refused_in_one_line() -> None:
    with pytest.raises(DescriptionError, match="MuJoCo refuses") as info:
        compile_mjcf("<mujoco><worldbody><body><joint type='no'/></body></worldbody></mujoco>")
    assert "\n" not in str(info.value)
