"""The time a slider jerk limit costs, and what its planning costs, on the shipped programs.

Run on demand: ``python benchmarks/bench_plan_jerk.py [--json]``. Each shipped
program is planned with the example drive and a slider acceleration of
20 m/s^2, without and with a jerk limit of 500 m/s^3. Printed per program:
the cycle times (``*_second_order_s``, ``*_with_jerk_s``), their ratio, the
stops added where the curvature steps, and the planning time with the jerk
limit and without it (``*_plan_s_with_jerk``, ``*_plan_s_second_order``)
and their ratio (``*_plan_time_ratio``, measured in one run, interleaved).
Then the straight move Q1 -> Q2 against the closed-form
7-segment S-curve (``diagonal_*_over_s_curve``) for a few speed,
acceleration and jerk limits.
"""

from __future__ import annotations

import math

import numpy as np
from _timing import best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import EXAMPLE_PROGRAMS, example_program_text, read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program

JERK, ACCELERATION = 500.0, 20.0
DIAGONAL = ((0.3, 10.0, 1000.0), (0.5, 20.0, 1000.0), (0.5, 10.0, 200.0), (1.2, 20.0, 500.0))


def _s_curve(distance: float, v: float, a: float, j: float) -> float:
    rise = v / a + a / j if v * j >= a * a else 2.0 * math.sqrt(v / j)
    return 2.0 * rise + (distance - v * rise) / v


def bench_plan_jerk() -> dict[str, float]:
    """Cycle times and planning times with and without the jerk limit."""
    dyn = og.ClosedLoopDynamics()
    drive = load_drive(str(example_drive_file()))
    # the whole motor torque, as when the guide's figures were measured
    second = PlanLimits(slider_acceleration=ACCELERATION, drive=drive, torque_reserve=0.0)
    third = PlanLimits(
        slider_acceleration=ACCELERATION, slider_jerk=JERK, drive=drive, torque_reserve=0.0
    )
    out: dict[str, float] = {}
    for name in EXAMPLE_PROGRAMS:
        prog = read_program(example_program_text(name))
        plans = {}

        def run(limits: PlanLimits, key: str, prog: og.Program = prog) -> None:
            plans[key] = plan_program(prog, dyn, limits)  # noqa: B023

        t2, t3 = best_times([lambda: run(second, "2"), lambda: run(third, "3")], repeats=1)
        cost = plans["3"].jerk_time_cost
        assert cost is not None
        out[f"{name}_second_order_s"] = cost["second_order"]
        out[f"{name}_with_jerk_s"] = cost["with_jerk"]
        out[f"{name}_ratio"] = cost["ratio"]
        out[f"{name}_curvature_stops"] = cost["curvature_stops"]
        out[f"{name}_worst_use"] = max(plans["3"].worst.values())
        out[f"{name}_plan_s_second_order"] = t2
        out[f"{name}_plan_s_with_jerk"] = t3
        out[f"{name}_plan_time_ratio"] = t3 / t2
    params = og.prototype()
    a, b = params.workspace.q1, params.workspace.q2
    text = "".join(
        f"G0 X{1e3 * p[0]:.12f} Y{1e3 * p[1]:.12f} Z{1e3 * p[2]:.12f}\n" for p in (a, b)
    )
    prog = read_program(text, start=a)
    q = og.inverse_kinematics(np.stack([a, b]), params.leg_length)
    for v, acc, j in DIAGONAL:
        plan = plan_program(
            prog, dyn, PlanLimits(slider_speed=v, slider_acceleration=acc, slider_jerk=j)
        )
        key = f"diagonal_{v:g}_{acc:g}_{j:g}_over_s_curve"
        out[key] = plan.cycle_time / _s_curve(float(q[1, 0] - q[0, 0]), v, acc, j)
    return out


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    figures = bench_plan_jerk()
    for key, value in figures.items():
        print(f"{key:<40} {value:.6g}")
    emit(args, figures)


if __name__ == "__main__":
    main()
