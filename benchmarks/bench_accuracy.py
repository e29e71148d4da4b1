"""Cost of part accuracy along a plan per cutting sample, against the stiffness model per point.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_accuracy.py``.
The shipped pocket with the shipped cut file, planned once on the prototype;
``accuracy_along_plan`` (forces over a revolution, compliance, surface errors,
budget with a temperature rise) is timed against ``cartesian_stiffness`` at the
same cutting points, in turn. The target: at most 4 times the stiffness model
per cutting sample (the stiffness model is the part of the work that cannot
be shared between samples).
"""

from __future__ import annotations

from typing import Any

from _timing import best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.planning.limits import PlanLimits

#: The target ratio.
TARGET = 4.0


def bench_accuracy(repeats: int = 3) -> dict[str, Any]:
    """Times [s] of accuracy along the shipped pocket and of the stiffness at its points."""
    params = og.prototype()
    program = og.read_program(og.example_program_text("pocket"), axes=og.design_axes(params))
    plan = og.plan_program(program, params, PlanLimits(slider_speed=1.2, slider_acceleration=20.0))
    cut = og.read_cut_file(og.shipped_cut_file())
    result = og.accuracy_along_plan(plan, cut, params, temperature_rise=1.0)
    points = result.samples.points[result.samples.cutting]
    times = best_times(
        [
            lambda: og.accuracy_along_plan(plan, cut, params, temperature_rise=1.0),
            lambda: og.cartesian_stiffness(points, params),
        ],
        repeats,
    )
    n = points.shape[0]
    per_sample, per_point = times[0] / n, times[1] / n
    ratio = per_sample / per_point
    summary = result.summary()
    print(f"Part accuracy along the shipped pocket ({n:,} cutting samples, prototype):")
    rows = {
        "accuracy_along_plan": (times[0], per_sample, "sample"),
        "cartesian_stiffness, same points": (times[1], per_point, "point"),
    }
    for name, (total, each, unit) in rows.items():
        print(f"  {name:<33}: {total:7.3f} s = {each * 1e6:6.1f} us/{unit}")
    print(f"  ratio {ratio:.2f} (target <= {TARGET:g}): {'met' if ratio <= TARGET else 'NOT met'}")
    print(
        f"  surface error: static {summary['surface_error_static_max'] * 1e6:.1f} um, "
        f"generated {summary['surface_error_generated_max'] * 1e6:.1f} um, "
        f"peak {summary['surface_error_peak_max'] * 1e6:.1f} um"
    )
    return {
        "cutting_samples": n,
        "accuracy_s": times[0],
        "stiffness_s": times[1],
        "ratio": ratio,
        "target_ratio": TARGET,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_accuracy())


if __name__ == "__main__":
    main()
