"""Warm-started loop closure: the operators reused along a path give the same assemblies."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og

#: Joint values [m, rad] and tool points [m] agree with an independent route to this.
Q_TOL = 1e-11
#: A straight tool path: 200 points 0.5 mm apart.
STEP = 0.0005
N_POINTS = 200
START = np.array([-0.05, -0.03, 0.05])
DIRECTION = np.array([1.0, 0.6, -0.4]) / np.linalg.norm([1.0, 0.6, -0.4])


def _path() -> np.ndarray:
    return START + STEP * np.arange(N_POINTS)[:, None] * DIRECTION


def _warm_path(model: og.ClosedLoopModel, q_act: np.ndarray) -> list[og.Assembly]:
    out = [model.solve(q_act[0])]
    for q in q_act[1:]:
        out.append(model.solve(q, out[-1].q))
    return out


def test_warm_path_matches_the_closed_form(model: og.ClosedLoopModel) -> None:
    points = _path()
    q_act = og.inverse_kinematics(points, model.params.leg_length)
    assemblies = _warm_path(model, q_act)
    expected = model.configuration(points)
    for assembly, q, p in zip(assemblies, expected, points, strict=True):
        assert assembly.residual <= og.machine.closed_loop.CLOSURE_TOL
        np.testing.assert_allclose(assembly.q, q, rtol=0, atol=Q_TOL)
        np.testing.assert_allclose(assembly.tool_position, p, rtol=0, atol=Q_TOL)
    # the reused operators make warm solves short: fewer iterations than cold ones
    warm = np.mean([a.iterations for a in assemblies[1:]])
    cold = np.mean([og.ClosedLoopModel(model.params).solve(q).iterations for q in q_act[::50]])
    assert warm < cold


@pytest.mark.parametrize("offset", [0.0, 0.03])
def test_warm_path_matches_cold_solves_on_another_design(offset: float) -> None:
    params = og.prototype().replace(leg_length=0.36, platform_offset=offset)
    warm_model, cold_model = og.ClosedLoopModel(params), og.ClosedLoopModel(params)
    q_act = og.inverse_kinematics(_path(), params.leg_length)
    for assembly, q in zip(_warm_path(warm_model, q_act), q_act, strict=True):
        cold = cold_model.solve(q)  # from home each time: no operator reused
        np.testing.assert_allclose(assembly.q, cold.q, rtol=0, atol=Q_TOL)
        np.testing.assert_allclose(assembly.tool_position, cold.tool_position, atol=Q_TOL)


def test_a_warm_start_from_elsewhere_reuses_nothing(model: og.ClosedLoopModel) -> None:
    """A start that is not the last solution is solved by Newton from that start."""
    points = _path()[[0, -1]]
    q_act = og.inverse_kinematics(points, model.params.leg_length)
    first = model.solve(q_act[0])
    far = model.solve(q_act[1], first.q)  # the operators of the first point, 0.1 m away
    start = model.configuration(points[0])
    start[0] += 1e-9  # not the last solution
    other = model.solve(q_act[1], start)
    np.testing.assert_allclose(far.q, other.q, rtol=0, atol=Q_TOL)
    np.testing.assert_allclose(far.q, model.configuration(points[1]), rtol=0, atol=Q_TOL)
