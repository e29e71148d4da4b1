"""Cost of the vectorised stiffness model per point, against one Pinocchio ``rnea`` call.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_stiffness.py``.
All figures come from one run, timed in turn, and are printed as ratios. The
target: the full 6x6 compliance (actuators and links) at most 20 times the
cost of one ``rnea`` call on the closed-loop model's 18-joint tree, per point.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin
from _timing import best_times, emit, parse_args

from orthoglide_pin.elasticity.stiffness import cartesian_stiffness
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.params import prototype

#: Points of the batch (the prototype's cube); fewer with the joints (dense assembly).
POINTS = 20_000
JOINT_POINTS = 2_000
#: rnea calls timed per repeat.
RNEA_CALLS = 2_000
#: The target ratio of the issue.
TARGET = 20.0
SEED = 20261127


def bench_stiffness(repeats: int = 5) -> dict[str, Any]:
    """Per-point times [s] of the stiffness model (by sources) and of one ``rnea``."""
    params = prototype()
    corner = np.asarray(params.workspace_corner)
    rng = np.random.default_rng(SEED)
    points = corner + params.workspace_side * rng.random((POINTS, 3))
    model = ClosedLoopModel(params)
    q = model.configuration(points[0])
    v, a = np.linspace(-1.0, 1.0, model.nv), np.linspace(1.0, -1.0, model.nv)

    def rnea_batch() -> None:
        for _ in range(RNEA_CALLS):
            pin.rnea(model.model, model.data, q, v, a)

    cases = {
        "actuators+links": ("actuators", "links"),
        "links": ("links",),
        "actuators": ("actuators",),
    }
    fns = [rnea_batch] + [
        (lambda s=s: cartesian_stiffness(points, params, s)) for s in cases.values()
    ]
    joints = ("actuators", "links", "joints")
    fns.append(lambda: cartesian_stiffness(points[:JOINT_POINTS], params, joints))
    times = best_times(fns, repeats)
    rnea = times[0] / RNEA_CALLS
    per_point = {name: t / POINTS for name, t in zip(cases, times[1:-1], strict=True)}
    per_point["actuators+links+joints"] = times[-1] / JOINT_POINTS
    ratios = {name: t / rnea for name, t in per_point.items()}
    print(
        f"Cartesian stiffness of {POINTS:,} points of the prototype cube "
        f"({JOINT_POINTS:,} with the joints):"
    )
    print(f"  one pinocchio.rnea call (18 joints)     : {rnea * 1e6:8.2f} us")
    for name, t in per_point.items():
        print(f"  {name + ' per point':<40}: {t * 1e6:8.2f} us = {ratios[name]:6.2f} x rnea")
    verdict = "met" if ratios["actuators+links"] <= TARGET else "NOT met"
    print(f"  target <= {TARGET:g} x rnea per point (actuators+links): {verdict}")
    return {
        "points": POINTS,
        "rnea_s": rnea,
        "per_point_s": per_point,
        "ratio_to_rnea": ratios,
        "target_ratio": TARGET,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_stiffness())


if __name__ == "__main__":
    main()
