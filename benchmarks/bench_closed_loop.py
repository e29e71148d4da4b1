"""Loop-closure solve time per point, cold and warm-started, against one raw rnea.

Run on demand: ``python benchmarks/bench_closed_loop.py``. Every figure is
measured in this run and printed as a ratio to one ``pinocchio.rnea`` call on
the same model, so the numbers carry over between machines. Warm solves run
along a path of 0.5 mm steps, one ``solve`` call per point (each checks its
inputs) and in one ``solve_many`` call (inputs checked once, starts
extrapolated from the earlier solutions): the target applies to the latter.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin
from _timing import best_per_call, emit, parse_args

import orthoglide_pin as og

CUBE_CORNER = -og.prototype().leg_length / np.sqrt(18.0)
CUBE_SIDE = 0.2


def bench_loop_closure(n_points: int = 200) -> dict[str, float]:
    """Time cold and warm loop-closure solves and one rnea call, all on the prototype."""
    model = og.ClosedLoopModel()
    length = model.params.leg_length
    rng = np.random.default_rng(0)
    points = CUBE_CORNER + CUBE_SIDE * rng.random((n_points, 3))
    q_cold = og.inverse_kinematics(points, length)
    # A trajectory: consecutive points 0.5 mm apart, each solve warm-started from the last.
    direction = np.array([1.0, 0.6, -0.4]) / np.linalg.norm([1.0, 0.6, -0.4])
    path = 0.0005 * np.arange(n_points)[:, None] * direction + np.array([-0.05, -0.03, 0.05])
    q_path = og.inverse_kinematics(path, length)

    q0, v0, a0 = model.neutral(), np.zeros(model.nv), np.zeros(model.nv)
    rnea = best_per_call(lambda: pin.rnea(model.model, model.data, q0, v0, a0), 20000)

    def cold() -> None:
        for q in q_cold:
            model.solve(q)

    def warm() -> None:
        last = model.solve(q_path[0]).q
        for q in q_path[1:]:
            last = model.solve(q, last).q

    def path_solve() -> float:
        """One solve_many along the path from its solved start [s] (the start untimed)."""
        start = model.solve(q_path[0]).q  # leaves its operators, as in warm()
        begin = time.perf_counter()
        model.solve_many(q_path[1:], start)
        return time.perf_counter() - begin

    t_cold = best_per_call(cold, 1, repeats=3) / n_points
    t_warm = best_per_call(warm, 1, repeats=3) / (n_points - 1)
    t_path = min(path_solve() for _ in range(5)) / (n_points - 1)
    iterations_cold = np.mean([model.solve(q).iterations for q in q_cold])
    print("loop closure (Newton on 15 passive joints, residual <= 1e-12)")
    print(f"  one pinocchio.rnea call        {rnea * 1e6:9.2f} us   (1.0x)")
    print(
        f"  cold solve from home, per point {t_cold * 1e6:8.1f} us   ({t_cold / rnea:.0f}x rnea,"
        f" {iterations_cold:.1f} iterations)"
    )
    print(
        f"  warm solve on a path, per point {t_warm * 1e6:8.1f} us   ({t_warm / rnea:.0f}x rnea;"
        " one call per point)"
    )
    print(
        f"  solve_many on the path, per point {t_path * 1e6:6.1f} us   ({t_path / rnea:.0f}x rnea;"
        " target <= 10x)"
    )
    print(f"  warm / cold                                   {t_warm / t_cold:.2f}")
    return {
        "rnea_s": rnea,
        "cold_s": t_cold,
        "warm_s": t_warm,
        "cold_over_rnea": t_cold / rnea,
        "warm_over_rnea": t_warm / rnea,
        "path_s": t_path,
        "path_over_rnea": t_path / rnea,
        "cold_iterations": float(iterations_cold),
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_loop_closure())


if __name__ == "__main__":
    main()
