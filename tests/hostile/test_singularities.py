"""Both routes of the Jacobian and of the indices refuse the same singular points.

The closed form judges a point from its leg geometry; the Pinocchio route from
``J^-1`` obtained by projection on the loop-closure constraints. The measures
agree (same ``eta_i / L``, same ``det(u_1, u_2, u_3)``), so the thresholds of
:mod:`orthoglide_pin.kinematics.closed_form` apply to both.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import (
    PARALLEL_TOL,
    SERIAL_TOL,
    inverse_jacobian,
    inverse_kinematics,
    jacobian,
)
from orthoglide_pin.kinematics.singularity import (
    MAX_CONDITION,
    check_inverse_jacobian,
    singularity_measures,
)
from orthoglide_pin.kinetostatics.indices import indices_from_model, kinetostatic_indices
from tests.conftest import run

L = 0.31
#: The parallel singularity of the main diagonal: the three legs coincide.
T_SINGULAR = L / math.sqrt(3.0)
#: Agreement of the two routes' J^-1 away from singularities (relative).
ROUTE_RTOL = 1e-9
#: Agreement of the measures near the singularity, where J^-1 has entries ~1/det.
MEASURE_RTOL = 1e-4
#: Tool position reached by the loop closure [m]: at a parallel singularity the
#: sliders fix the tool only to about the square root of the closure tolerance.
POSITION_TOL = 1e-6
#: Agreement of the indices' condition number with cond(J^-1) at 1e6 (relative):
#: the closed-form factors keep about 1e-5 of the smallest one there.
CONDITION_RTOL = 1e-5


def _assembly(model: og.ClosedLoopModel, point: np.ndarray) -> np.ndarray:
    q = model.solve(inverse_kinematics(point, model.params.leg_length, check=False)).q
    np.testing.assert_allclose(model.tool_position(q), point, rtol=0, atol=POSITION_TOL)
    return q


def test_the_projected_inverse_jacobian_is_the_closed_form(model: og.ClosedLoopModel) -> None:
    rng = np.random.default_rng(11)
    for point in rng.uniform(-0.07, 0.07, size=(5, 3)):
        j_inv = model.inverse_jacobian(_assembly(model, point))
        np.testing.assert_allclose(j_inv, inverse_jacobian(point, L), rtol=ROUTE_RTOL, atol=1e-12)
        np.testing.assert_allclose(
            j_inv @ model.jacobian(model.configuration(point)), np.eye(3), rtol=0, atol=1e-9
        )


def test_exactly_at_the_parallel_singularity_both_routes_refuse(
    model: og.ClosedLoopModel,
) -> None:
    point = np.full(3, T_SINGULAR)
    q = _assembly(model, point)
    for call in (
        lambda: jacobian(point, L),
        lambda: kinetostatic_indices(point, L),
        lambda: model.jacobian(q),
        lambda: indices_from_model(model, q),
    ):
        with pytest.raises(SingularConfigurationError) as info:
            call()
        assert info.value.kind == "parallel" and info.value.leg is None
        assert f"< {PARALLEL_TOL:g}" in str(info.value)
    # J^-1 itself stays defined there, by both routes, and singular
    _, det, _ = singularity_measures(model.inverse_jacobian(q))
    assert abs(float(det)) < PARALLEL_TOL


@pytest.mark.parametrize("relative", [1e-12, 1e-9, 1e-7])
def test_just_off_the_parallel_singularity_both_routes_agree(
    model: og.ClosedLoopModel, relative: float
) -> None:
    point = np.full(3, T_SINGULAR * (1.0 - relative))
    q = _assembly(model, point)
    closed = singularity_measures(inverse_jacobian(point, L))
    projected = singularity_measures(model.inverse_jacobian(q))
    assert abs(float(closed[1])) < PARALLEL_TOL and abs(float(projected[1])) < PARALLEL_TOL
    for route in (lambda: kinetostatic_indices(point, L), lambda: indices_from_model(model, q)):
        with pytest.raises(SingularConfigurationError, match="parallel"):
            route()


@pytest.mark.parametrize("relative", [1e-5, 1e-4, 1e-2])
def test_near_the_parallel_singularity_the_measures_agree(
    model: og.ClosedLoopModel, relative: float
) -> None:
    point = np.full(3, T_SINGULAR * (1.0 - relative))
    q = _assembly(model, point)
    closed = singularity_measures(inverse_jacobian(point, L))
    projected = singularity_measures(model.inverse_jacobian(q))
    for a, b in zip(closed, projected, strict=True):
        np.testing.assert_allclose(b, a, rtol=MEASURE_RTOL)


def _towards_serial(s: float) -> np.ndarray:
    """Points reaching the serial singularity of leg 3 (``x^2 + y^2 = L^2``) at ``s = 1``."""
    return np.array([0.6 * L * s, 0.8 * L * s, 0.05])


def test_the_condition_limit_is_the_same_for_both_routes(model: og.ClosedLoopModel) -> None:
    # cond(J) grows like L / eta_3 towards the serial singularity: bisect for
    # the limit, then check both routes just below and just above it
    def cond(s: float) -> float:
        return float(singularity_measures(inverse_jacobian(_towards_serial(s), L))[2])

    lo, hi = 0.9, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cond(mid) < MAX_CONDITION else (lo, mid)
    below, above = _towards_serial(lo - 1e-14), _towards_serial(hi + 1e-14)
    assert cond(lo - 1e-14) < MAX_CONDITION < cond(hi + 1e-14)
    q_below, q_above = (
        model.solve(inverse_kinematics(p, L), model.configuration(p)).q for p in (below, above)
    )
    limit = MAX_CONDITION * (1.0 + CONDITION_RTOL)
    assert kinetostatic_indices(below, L).condition < limit
    # these points are beyond the prototype's sliders: the conditioning is what is judged here
    assert indices_from_model(model, q_below, check_limits=False).condition < limit
    for route in (
        lambda: kinetostatic_indices(above, L),
        lambda: indices_from_model(model, q_above),
        lambda: model.jacobian(q_above),
    ):
        with pytest.raises(SingularConfigurationError, match=r"condition number .* > 1e\+06"):
            route()
    # a caller may accept worse conditioning explicitly
    loose = indices_from_model(model, q_above, max_condition=1e9, check_limits=False)
    assert loose.condition > MAX_CONDITION
    # on the main diagonal PARALLEL_TOL binds first: det ~ (1 - t/T)^2, cond ~ T / (T - t)
    near = np.full(3, T_SINGULAR * (1.0 - 1e-5))
    _, det, condition = singularity_measures(inverse_jacobian(near, L))
    assert abs(float(det)) < PARALLEL_TOL and float(condition) < MAX_CONDITION


def test_serial_singularities_refused_by_both_routes(model: og.ClosedLoopModel) -> None:
    # leg 3 orthogonal to its slider: x^2 + y^2 = L^2
    point = np.array([0.6 * L, 0.8 * L, 0.05])
    with pytest.raises(SingularConfigurationError) as info:
        kinetostatic_indices(point, L)
    assert info.value.kind == "serial" and info.value.leg == 3
    # near it, in both routes: eta / L below SERIAL_TOL is serial; the limit first
    near = np.array([0.6 * L, 0.8 * L * (1.0 - 1e-13), 0.05])  # eta / L about 4e-7
    cos_closed = singularity_measures(inverse_jacobian(near, L))[0]
    q = model.solve(inverse_kinematics(near, L), model.configuration(near)).q
    cos_projected = singularity_measures(model.inverse_jacobian(q))[0]
    np.testing.assert_allclose(cos_projected, cos_closed, rtol=MEASURE_RTOL)
    assert SERIAL_TOL < cos_closed[2] < 1.0 / MAX_CONDITION
    for route in (lambda: kinetostatic_indices(near, L), lambda: model.jacobian(q)):
        with pytest.raises(SingularConfigurationError) as info:
            route()
        assert info.value.kind == "serial" and info.value.leg == 3
        assert "near a serial singularity" in str(info.value)


def test_a_zero_or_non_finite_inverse_jacobian_is_refused() -> None:
    for bad in (np.zeros((3, 3)), np.full((3, 3), np.nan), np.diag([1.0, 1.0, np.inf])):
        with pytest.raises(SingularConfigurationError):
            check_inverse_jacobian(bad, np.zeros(3))
    check_inverse_jacobian(np.eye(3), np.zeros(3))


@pytest.mark.parametrize("method", ["closed-form", "pinocchio"])
@pytest.mark.parametrize("command", ["jacobian", "indices"])
def test_the_cli_refuses_the_singular_point_by_both_methods(
    capsys: pytest.CaptureFixture[str], method: str, command: str
) -> None:
    t = repr(T_SINGULAR)
    code, out, err = run(capsys, command, t, t, t, "--method", method, "--json")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "parallel singularity" in err


def test_other_designs_are_judged_the_same_way() -> None:
    params = og.prototype().replace(leg_length=0.4)
    model = og.ClosedLoopModel(params)
    t = 0.4 / math.sqrt(3.0)
    q = model.solve(inverse_kinematics(np.full(3, t), 0.4, check=False)).q
    with pytest.raises(SingularConfigurationError, match="parallel"):
        model.jacobian(q)
    point = np.array([0.03, 0.05, -0.04])
    q = model.solve(inverse_kinematics(point, 0.4)).q
    np.testing.assert_allclose(
        model.inverse_jacobian(q), inverse_jacobian(point, 0.4), rtol=ROUTE_RTOL, atol=1e-12
    )
