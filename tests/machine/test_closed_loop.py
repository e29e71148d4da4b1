from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import cube_points

import orthoglide_pin as og
from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: The issue's closure requirement [m, rad].
RESIDUAL_TOL = 1e-10
#: Closed form vs Pinocchio Jacobian.
JACOBIAN_TOL = 1e-9
#: Finite differences through the loop-closure solver (step 1e-6 m, central).
FD_STEP = 1e-6
FD_TOL = 1e-7
ORIENTATION_TOL = 1e-10
POSITION_TOL = 1e-10


def test_home_is_assembled_and_isotropic(model: ClosedLoopModel) -> None:
    q0 = model.neutral()
    r, k = model.constraint_residual_and_jacobian(q0)
    assert r.shape == (21,) and k.shape == (21, 18)
    assert np.max(np.abs(r)) < RESIDUAL_TOL
    assert model.constraint_rank(q0) == 15
    assert model.mobility(q0) == 3
    assert model.passive_rank(q0) == 15
    np.testing.assert_allclose(model.jacobian(q0), np.eye(3), atol=JACOBIAN_TOL)
    np.testing.assert_allclose(model.tool_position(q0), 0.0, atol=POSITION_TOL)


def _frame_closure_errors(model: ClosedLoopModel, q: np.ndarray) -> float:
    """Loop closure measured on frame placements only (no constraint model)."""
    pin.framesForwardKinematics(model.model, model.data, q)
    worst = 0.0
    for closure in model.loops.closures:
        m1 = model.data.oMf[model.model.getFrameId(closure.frame1)]
        m2 = model.data.oMf[model.model.getFrameId(closure.frame2)]
        worst = max(worst, float(np.max(np.abs(m1.translation - m2.translation))))
        if closure.kind == "frame":
            worst = max(worst, float(np.linalg.norm(pin.log3(m1.rotation.T @ m2.rotation))))
    return worst


def test_solve_closes_every_loop_in_the_cube(model: ClosedLoopModel) -> None:
    for point in cube_points(40, seed=11):
        q_act = og.inverse_kinematics(point, model.params.leg_length)
        assembly = model.solve(q_act)
        assert assembly.residual <= RESIDUAL_TOL
        assert _frame_closure_errors(model, assembly.q) <= RESIDUAL_TOL
        np.testing.assert_allclose(assembly.tool_position, point, atol=POSITION_TOL)
        assert model.platform_orientation_error(assembly.q) <= ORIENTATION_TOL
        assert model.constraint_rank(assembly.q) == 15
        assert model.mobility(assembly.q) == 3


def test_passive_joints_match_the_leg_geometry(model: ClosedLoopModel) -> None:
    """Second route: the passive angles follow from each leg vector in closed form."""
    points = cube_points(30, seed=12)
    closed_form = model.configuration(points)
    assert closed_form.shape == (30, 18)
    for point, expected in zip(points, closed_form, strict=True):
        q = model.solve(expected[model.actuated]).q
        np.testing.assert_allclose(q, expected, atol=RESIDUAL_TOL)
        r, _ = model.constraint_residual_and_jacobian(expected)
        assert np.max(np.abs(r)) <= RESIDUAL_TOL
        np.testing.assert_allclose(model.tool_position(expected), point, atol=POSITION_TOL)
    np.testing.assert_array_equal(model.configuration(points[0]), closed_form[0])


def test_jacobian_projection_matches_closed_form(model: ClosedLoopModel) -> None:
    length = model.params.leg_length
    points = cube_points(200, seed=13)
    q_prev = None
    worst = 0.0
    for point in points:
        assembly = model.solve(og.inverse_kinematics(point, length), q_prev)
        q_prev = assembly.q
        error = model.jacobian(assembly.q) - og.jacobian(point, length)
        worst = max(worst, float(np.max(np.abs(error))))
    assert worst <= JACOBIAN_TOL


def test_jacobian_matches_finite_differences_of_the_solver(model: ClosedLoopModel) -> None:
    length = model.params.leg_length
    for point in cube_points(5, seed=14):
        q_act = og.inverse_kinematics(point, length)
        base = model.solve(q_act)
        fd = np.empty((3, 3))
        for k in range(3):
            dq = np.zeros(3)
            dq[k] = FD_STEP
            plus = model.solve(q_act + dq, base.q).tool_position
            minus = model.solve(q_act - dq, base.q).tool_position
            fd[:, k] = (plus - minus) / (2 * FD_STEP)
        np.testing.assert_allclose(model.jacobian(base.q), fd, atol=FD_TOL)
        np.testing.assert_allclose(og.jacobian(point, length), fd, atol=FD_TOL)


def test_velocity_map_spans_the_constraint_null_space(model: ClosedLoopModel) -> None:
    point = cube_points(1, seed=15)[0]
    q = model.solve(og.inverse_kinematics(point, model.params.leg_length)).q
    g = model.velocity_map(q)
    _, k = model.constraint_residual_and_jacobian(q)
    assert np.max(np.abs(k @ g)) < 1e-12
    np.testing.assert_array_equal(g[model.actuated], np.eye(3))


def test_point_anchor_jacobian_is_the_residual_derivative(model: ClosedLoopModel) -> None:
    rng = np.random.default_rng(16)
    q = rng.normal(scale=0.05, size=18)
    _, k = model.constraint_residual_and_jacobian(q)
    fd = np.empty_like(k)
    for j in range(18):
        dq = np.zeros(18)
        dq[j] = 1e-7
        fd[:, j] = (
            model.constraint_residual_and_jacobian(q + dq)[0]
            - model.constraint_residual_and_jacobian(q - dq)[0]
        ) / 2e-7
    assert np.max(np.abs(fd[:9] - k[:9])) < 1e-7  # the three parallelograms


def test_warm_start_is_faster_and_agrees(model: ClosedLoopModel) -> None:
    length = model.params.leg_length
    point = cube_points(1, seed=17)[0]
    first = model.solve(og.inverse_kinematics(point, length))
    nearby = og.inverse_kinematics(point + 1e-4, length)
    warm = model.solve(nearby, first.q)
    cold = model.solve(nearby)
    assert warm.iterations < cold.iterations
    np.testing.assert_allclose(warm.q, cold.q, atol=RESIDUAL_TOL)


def test_no_assembly_raises(model: ClosedLoopModel) -> None:
    # Carriages 0.3 m back: spheres of radius L around them do not meet.
    with pytest.raises(og.NoAssemblyError) as info:
        model.solve([-0.3, -0.3, -0.3])
    assert info.value.residual is not None and info.value.residual > RESIDUAL_TOL
    assert "-0.3" in str(info.value)
    np.testing.assert_array_equal(info.value.q, [-0.3, -0.3, -0.3])


@pytest.mark.parametrize("bad", [[0.0, 0.0], [0.0, np.nan, 0.0], "abc"])
def test_bad_slider_values(model: ClosedLoopModel, bad: object) -> None:
    with pytest.raises(og.InvalidParameterError):
        model.solve(bad)  # type: ignore[arg-type]


def test_bad_configuration(model: ClosedLoopModel) -> None:
    with pytest.raises(og.InvalidParameterError):
        model.tool_position(np.zeros(17))


# ---------------------------------------------------------- warm-started paths
#: Joint values [m, rad] and tool points [m] agree with an independent route to this.
WARM_TOL = 1e-11
#: A straight tool path: 200 points 0.5 mm apart.
PATH_STEP = 0.0005
PATH_POINTS = 200
PATH_START = np.array([-0.05, -0.03, 0.05])
PATH_DIRECTION = np.array([1.0, 0.6, -0.4]) / np.linalg.norm([1.0, 0.6, -0.4])


def _path() -> np.ndarray:
    return PATH_START + PATH_STEP * np.arange(PATH_POINTS)[:, None] * PATH_DIRECTION


def _warm_path(model: ClosedLoopModel, q_act: np.ndarray) -> list[og.Assembly]:
    out = [model.solve(q_act[0])]
    for q in q_act[1:]:
        out.append(model.solve(q, out[-1].q))
    return out


def test_warm_path_matches_the_closed_form(model: ClosedLoopModel) -> None:
    points = _path()
    q_act = og.inverse_kinematics(points, model.params.leg_length)
    assemblies = _warm_path(model, q_act)
    expected = model.configuration(points)
    for assembly, q, p in zip(assemblies, expected, points, strict=True):
        assert assembly.residual <= og.machine.closed_loop.CLOSURE_TOL
        np.testing.assert_allclose(assembly.q, q, rtol=0, atol=WARM_TOL)
        np.testing.assert_allclose(assembly.tool_position, p, rtol=0, atol=WARM_TOL)
    # the reused operators make warm solves short: fewer iterations than cold ones
    warm = np.mean([a.iterations for a in assemblies[1:]])
    cold = np.mean([ClosedLoopModel(model.params).solve(q).iterations for q in q_act[::50]])
    assert warm < cold


@pytest.mark.parametrize("offset", [0.0, 0.03])
def test_warm_path_matches_cold_solves_on_another_design(offset: float) -> None:
    params = og.prototype().replace(leg_length=0.36, platform_offset=offset)
    warm_model, cold_model = ClosedLoopModel(params), ClosedLoopModel(params)
    q_act = og.inverse_kinematics(_path(), params.leg_length)
    for assembly, q in zip(_warm_path(warm_model, q_act), q_act, strict=True):
        cold = cold_model.solve(q)  # from home each time: no operator reused
        np.testing.assert_allclose(assembly.q, cold.q, rtol=0, atol=WARM_TOL)
        np.testing.assert_allclose(assembly.tool_position, cold.tool_position, atol=WARM_TOL)


def test_a_warm_start_from_elsewhere_reuses_nothing(model: ClosedLoopModel) -> None:
    """A start that is not the last solution is solved by Newton from that start."""
    points = _path()[[0, -1]]
    q_act = og.inverse_kinematics(points, model.params.leg_length)
    first = model.solve(q_act[0])
    far = model.solve(q_act[1], first.q)  # the operators of the first point, 0.1 m away
    start = model.configuration(points[0])
    start[0] += 1e-9  # not the last solution
    other = model.solve(q_act[1], start)
    np.testing.assert_allclose(far.q, other.q, rtol=0, atol=WARM_TOL)
    np.testing.assert_allclose(far.q, model.configuration(points[1]), rtol=0, atol=WARM_TOL)


# ------------------------------------------------------------------ solve_many
def test_solve_many_matches_the_closed_form_and_row_by_row_solves(model: ClosedLoopModel) -> None:
    points = _path()
    q_act = og.inverse_kinematics(points, model.params.leg_length)
    path = model.solve_many(q_act)
    assert len(path) == PATH_POINTS
    assert np.all(path.residual <= og.machine.closed_loop.CLOSURE_TOL)
    np.testing.assert_allclose(path.q, model.configuration(points), rtol=0, atol=WARM_TOL)
    np.testing.assert_allclose(path.tool_position, points, rtol=0, atol=WARM_TOL)
    rows = _warm_path(ClosedLoopModel(model.params), q_act)
    np.testing.assert_allclose(path.q, [a.q for a in rows], rtol=0, atol=WARM_TOL)
    # the extrapolated starts leave about one Newton step per row on a smooth path
    assert np.mean(path.iterations[4:]) < np.mean([a.iterations for a in rows[4:]])
    assert np.mean(path.iterations[4:]) <= 1.1


@pytest.mark.parametrize("offset", [0.0, 0.03])
def test_solve_many_on_scattered_points_of_another_design(offset: float) -> None:
    """Rows that are no smooth path: every row still reaches the cold solution."""
    params = og.prototype().replace(leg_length=0.36, platform_offset=offset)
    model, cold_model = ClosedLoopModel(params), ClosedLoopModel(params)
    points = _path()[np.random.default_rng(3).permutation(40)]
    q_act = og.inverse_kinematics(points, params.leg_length)
    path = model.solve_many(q_act, model.neutral())
    for q_row, q in zip(path.q, q_act, strict=True):
        np.testing.assert_allclose(q_row, cold_model.solve(q).q, rtol=0, atol=WARM_TOL)


def test_solve_many_one_row_and_a_warm_start(model: ClosedLoopModel) -> None:
    q_act = og.inverse_kinematics(_path()[:2], model.params.leg_length)
    first = model.solve(q_act[0])
    one = model.solve_many(q_act[1], first.q)  # one row, warm from the last solution
    assert one.q.shape == (1, model.nv) and one.iterations.shape == (1,)
    np.testing.assert_allclose(one.q[0], model.solve(q_act[1]).q, rtol=0, atol=WARM_TOL)


def test_solve_many_errors(model: ClosedLoopModel) -> None:
    with pytest.raises(og.InvalidParameterError, match="q_actuated"):
        model.solve_many([[0.0, 0.0, np.nan]])
    with pytest.raises(og.InvalidParameterError, match="q_init"):
        model.solve_many([0.0, 0.0, 0.0], np.zeros(5))
    with pytest.raises(og.InvalidParameterError, match="max_iterations"):
        model.solve_many([0.0, 0.0, 0.0], max_iterations=-1)
    with pytest.raises(og.NoAssemblyError):
        model.solve_many([[0.0, 0.0, 0.0], [-0.3, -0.3, -0.3]])
