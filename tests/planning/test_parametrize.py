"""The time-optimal plan of the line Q1 -> Q2 against a dense phase-plane solution."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import time_law
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.program.axes import ProgramAxes

#: Program axes equal to the world axes: the programs here name world points.
WORLD = ProgramAxes((1, 2, 3))

pytest.importorskip("toppra")

#: Cycle time of the plan against the phase-plane optimum (its grid of 2 mm).
CYCLE_RTOL = 5e-3
#: Phase-plane integration points along the line.
DENSE = 20_001
V_MAX, A_MAX = 1.2, 20.0


def _line_program(a: np.ndarray, b: np.ndarray) -> str:
    mm = 1e3
    return "".join(f"G0 X{mm * p[0]:.12f} Y{mm * p[1]:.12f} Z{mm * p[2]:.12f}\n" for p in (a, b))


def _phase_plane(params: og.OrthoglideParams, a: np.ndarray, b: np.ndarray) -> float:
    """Fastest rest-to-rest time along the line under |q'| <= V, |q''| <= A (Euler in x)."""
    length = float(np.linalg.norm(b - a))
    s = np.linspace(0.0, length, DENSE)
    t = (b - a) / length
    p = a + s[:, None] * t
    q = og.inverse_kinematics(p, params.leg_length)
    dq = og.inverse_jacobian(p, params.leg_length) @ t  # J^-1 p'
    ds = s[1] - s[0]
    ddq = np.gradient(dq, ds, axis=0)  # d2q/ds2 by differences of the closed form
    del q
    mvc = (V_MAX / np.abs(dq).max(axis=1)) ** 2

    def bounds(i: int, x: float) -> tuple[float, float]:
        lo = (-A_MAX - ddq[i] * x) / dq[i]
        hi = (A_MAX - ddq[i] * x) / dq[i]
        lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
        return float(lo.max()), float(hi.min())

    fwd = np.zeros(DENSE)
    for i in range(DENSE - 1):
        fwd[i + 1] = min(fwd[i] + 2.0 * ds * bounds(i, fwd[i])[1], mvc[i + 1])
    bwd = np.zeros(DENSE)
    for i in range(DENSE - 1, 0, -1):
        bwd[i - 1] = min(bwd[i] - 2.0 * ds * bounds(i, bwd[i])[0], mvc[i - 1])
    x = np.minimum(fwd, bwd)
    return time_law(s, x).duration


def test_q1_to_q2_matches_the_phase_plane_optimum(params: og.OrthoglideParams) -> None:
    a, b = params.workspace.q1, params.workspace.q2
    prog = read_program(_line_program(a, b), start=a, axes=WORLD)
    plan = plan_program(prog, params, PlanLimits(slider_speed=V_MAX, slider_acceleration=A_MAX))
    reference = _phase_plane(params, a, b)
    assert plan.cycle_time == pytest.approx(reference, rel=CYCLE_RTOL)
    assert plan.cycle_time >= reference * (1 - 1e-3)  # never faster than the optimum
    assert plan.worst["slider_speed"] == pytest.approx(1.0, abs=1e-3)
    assert plan.worst["slider_acceleration"] == pytest.approx(1.0, abs=1e-3)
    # on this machine the sliders' speeds differ along the diagonal: the plan is not
    # a trapezoid in the path speed (the transmission factors change from 2 to 0.5)
    speeds = plan.sections[-1].motion.sd
    assert speeds.max() > 1.5 * V_MAX / np.sqrt(3.0)


def test_another_design_and_a_face_diagonal() -> None:
    params = og.prototype().replace(leg_length=0.36)
    c = params.workspace
    half = np.array([0.0, 0.0, 0.5 * c.side])
    a, b = c.q1 + half, c.q2 - half
    prog = read_program(_line_program(a, b), start=a, axes=WORLD)
    plan = plan_program(prog, params, PlanLimits(slider_speed=V_MAX, slider_acceleration=A_MAX))
    assert plan.cycle_time == pytest.approx(_phase_plane(params, a, b), rel=CYCLE_RTOL)
