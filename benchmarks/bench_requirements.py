"""Worst-case requirements over every direction, against plain inverse dynamics.

Run on demand: ``python benchmarks/bench_requirements.py``. Every figure is
measured in this run and printed as a ratio to one closed-form inverse-dynamics
point (``ClosedLoopDynamics.inverse_dynamics`` on a batch, per point), so the
numbers carry over between machines. The exact worst case reads its forms from
the model (one mass matrix, the gravity torques and three ``rnea`` rows per
point); sampling directions instead needs as many inverse-dynamics points as it
has samples, and still only approaches the worst case from below.
"""

from __future__ import annotations

import numpy as np
from _timing import best_per_call, best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.report.assemble import assemble_report
from orthoglide_pin.report.vibration import MAX_CUBE_RESOLUTION, vibration_section

CUBE_CORNER = -og.prototype().leg_length / np.sqrt(18.0)
CUBE_SIDE = 0.2
N_POINTS = 8_000
SAMPLES = 1_000  # random (v, a) pairs per point for the sampling estimate


def bench_requirements() -> dict[str, float]:
    """Time the worst case per point, a sampled estimate and the report's assembly."""
    dyn = og.ClosedLoopDynamics()
    rng = np.random.default_rng(1)
    p = CUBE_CORNER + CUBE_SIDE * rng.random((N_POINTS, 3))
    v = rng.normal(size=(N_POINTS, 3))
    a = rng.normal(size=(N_POINTS, 3))
    # interleaved, so that the ratio holds on a shared, noisy machine
    one, worst = (
        t / N_POINTS
        for t in best_times(
            [lambda: dyn.inverse_dynamics(p, v, a), lambda: og.worst_case_requirements(dyn, p)],
            repeats=5,
        )
    )
    wc = og.worst_case_requirements(dyn, p[:1])
    rows = np.repeat(p[:1], SAMPLES, axis=0)
    vs = rng.normal(size=(SAMPLES, 3))
    as_ = rng.normal(size=(SAMPLES, 3))
    vs *= 1.2 / np.linalg.norm(vs, axis=1, keepdims=True)
    as_ *= 20.0 / np.linalg.norm(as_, axis=1, keepdims=True)
    sampled = best_per_call(lambda: dyn.inverse_dynamics(rows, vs, as_), 1, 3)
    reached = np.abs(dyn.inverse_dynamics(rows, vs, as_).forces).max(axis=0) / wc.force[0]
    report = best_per_call(lambda: assemble_report(), 1, 1)
    cube = og.prototype().workspace
    vibration = best_per_call(lambda: vibration_section(og.prototype(), cube.q1, cube.side), 1, 1)
    print(f"worst case over every direction (1.2 m/s, 20 m/s^2), {N_POINTS} cube points")
    print(f"  one inverse-dynamics point (batched)     {one * 1e6:8.2f} us   (1.0x)")
    print(
        f"  worst case, forces and torques, per point {worst * 1e6:7.2f} us   ({worst / one:.1f}x;"
        " target <= 5x)"
    )
    print(
        f"  {SAMPLES} sampled directions, per point     {sampled * 1e6:8.0f} us   "
        f"({sampled / one:.0f}x; reaches {100 * reached.min():.1f}% of the worst |F|)"
    )
    print(
        f"  report data (41^2 x 3 slices, 21^3 cube, cycle) {report:6.2f} s   "
        f"(as {report / one / 1e3:.0f}k inverse-dynamics points)"
    )
    print(
        f"    of which the vibration section ({MAX_CUBE_RESOLUTION}^3 platform model, one "
        "full-model point) "
        f"{vibration:5.2f} s ({100 * vibration / report:.0f}%)"
    )
    return {
        "point_s": one,
        "worst_s": worst,
        "sampled_s": sampled,
        "report_s": report,
        "vibration_s": vibration,
        "worst_over_point": worst / one,
        "sampled_over_point": sampled / one,
        "sampled_reaches": float(reached.min()),
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_requirements())


if __name__ == "__main__":
    main()
