"""Time to certify the paper's design over the continuum, and the number of boxes.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_certify.py``.
All figures come from one run, timed in turn. The paper's design is the design
method's machine for a 200 mm cube and factors in [0.5, 2], leg 310.58 mm (the
prototype rounds it to 310 mm, whose factors over the cube are [0.4989,
2.0090]); it is certified for [0.499, 2.001] with its enclosure refined to 1e-4
(target: under 10 s on 2 cores), then verdict-only, then the sweep's largest
certified cube (bisection to 0.1 mm) and a refuted 210 mm cube.
"""

from __future__ import annotations

from typing import Any

from _timing import best_times, emit, parse_args

from orthoglide_pin.kinetostatics.certify import certify_cube
from orthoglide_pin.kinetostatics.design import design_from_workspace
from orthoglide_pin.kinetostatics.largest_cube import largest_certified_side

#: The target of the issue [s].
TARGET = 10.0
#: Bounds of the benchmark: the paper's widened by 1e-3.
BOUNDS = (0.499, 2.001)


def bench_certify(repeats: int = 3) -> dict[str, Any]:
    """Wall times [s] and box counts of the certifications (see the module)."""
    made = design_from_workspace(0.2, 0.5, 2.0, grid_points=2)
    L, corner = made.leg_length, made.cube_corner
    centre = (made.q1 + made.q2) / 2
    results: dict[str, Any] = {}

    def run(name: str, **kwargs: Any) -> Any:
        def fn() -> None:
            results[name] = certify_cube(L, corner, **kwargs)

        return fn

    cases = {
        "certify (enclosure to 1e-4)": run("full", side=0.2, psi_min=BOUNDS[0], psi_max=BOUNDS[1]),
        "certify (verdict only)": run(
            "verdict", side=0.2, psi_min=BOUNDS[0], psi_max=BOUNDS[1], refine=False
        ),
        "refute a 210 mm cube": run("refuted", side=0.21, psi_min=0.5, psi_max=2.0),
    }

    def largest() -> None:
        results["largest"] = largest_certified_side(L, centre, 0.5, 2.0, guess=0.2)

    times = best_times([*cases.values(), largest], repeats)
    full = results["full"]
    print(f"Certification of the paper's design (leg {1e3 * L:.2f} mm, 200 mm cube):")
    for (name, key), t in zip(
        zip(cases, ("full", "verdict", "refuted"), strict=True), times[:3], strict=True
    ):
        r = results[key]
        print(
            f"  {name:<30}: {t:7.3f} s, {r.boxes:7,} boxes "
            f"({1e6 * t / r.boxes:5.1f} us per box), {r.status}"
        )
    print(
        f"  largest certified cube (0.1 mm)  : {times[-1]:7.3f} s, side {results['largest']:.5f} m"
    )
    lo, hi = full.factor_bounds
    print(f"  certified enclosure [{lo:.6f}, {hi:.6f}], attained {full.attained}")
    verdict = "met" if times[0] <= TARGET else "NOT met"
    print(f"  target: certify under {TARGET:g} s ({times[0] / TARGET:.3f} of it): {verdict}")
    return {
        "certify_s": times[0],
        "boxes": full.boxes,
        "verdict_only_s": times[1],
        "verdict_only_boxes": results["verdict"].boxes,
        "refute_210mm_s": times[2],
        "largest_side_s": times[3],
        "largest_side_m": results["largest"],
        "factor_bounds": list(full.factor_bounds),
        "target_s": TARGET,
        "ratio_to_target": times[0] / TARGET,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_certify())


if __name__ == "__main__":
    main()
