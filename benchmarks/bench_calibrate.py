"""Time to identify the 18 geometric parameters from 100 measured poses.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_calibrate.py``.
A simulated built machine (errors of 0.2 mm, 0.5 mrad and 0.1 mm) is measured
at 100 random poses of the prototype's cube with 5 um of tracker noise and two
gross outliers, then identified (target: under 1 s on 2 cores). All figures
come from one run, timed in turn: the whole identification, one direct
kinematics of the 100 poses and one identification Jacobian (the two costs
each Levenberg-Marquardt step pays), and a 60-pose D-optimal plan.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from _timing import best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.calibration.experiment import plan_poses
from orthoglide_pin.calibration.identification import identify, stacked_jacobian
from orthoglide_pin.calibration.model import GeometricModel

#: The target of the issue [s].
TARGET = 1.0
#: Poses of the benchmark.
POSES = 100


def bench_calibrate(repeats: int = 5) -> dict[str, Any]:
    """Wall times [s] of the identification and of its parts (see the module)."""
    params = og.prototype()
    nominal = GeometricModel.nominal(params.leg_length)
    rng = np.random.default_rng(0)
    scale = np.tile([2e-4, 2e-4, 2e-4, 5e-4, 5e-4, 1e-4], 3)
    true = GeometricModel.from_vector(nominal.vector() + scale * rng.normal(size=18))
    lo = np.asarray(params.workspace.corner)
    targets = rng.uniform(lo, lo + params.workspace.side, (POSES, 3))
    q = nominal.inverse_kinematics(targets)
    measured = true.direct_kinematics(q) + rng.normal(0.0, 5e-6, (POSES, 3))
    measured[[10, 60]] += 1e-3
    results: dict[str, Any] = {}

    def fit() -> None:
        results["fit"] = identify(q, measured, nominal)

    times = best_times(
        [
            fit,
            lambda: true.direct_kinematics(q),
            lambda: stacked_jacobian(true, q),
            lambda: plan_poses(params, 60, grid=7),
        ],
        repeats,
    )
    res = results["fit"]
    figures = {
        "identify_s": times[0],
        "direct_kinematics_us": 1e6 * times[1],
        "jacobian_us": 1e6 * times[2],
        "plan_60_poses_s": times[3],
        "identify_over_target": times[0] / TARGET,
        "outliers": list(res.outliers),
        "rms_after": res.rms_after,
    }
    print(f"Identification of 18 parameters from {POSES} poses (2 outliers):")
    print(
        f"  identify                : {times[0]:8.3f} s ({times[0] / TARGET:.2f} x the 1 s target)"
    )
    print(f"  direct kinematics (100) : {1e6 * times[1]:8.1f} us")
    print(f"  Jacobian (300 x 18)     : {1e6 * times[2]:8.1f} us")
    print(f"  D-optimal plan (60)     : {times[3]:8.3f} s")
    print(f"  outliers found {list(res.outliers)}, RMS after {1e6 * res.rms_after:.2f} um")
    return figures


if __name__ == "__main__":
    arguments = parse_args(__doc__.splitlines()[0])
    emit(arguments, bench_calibrate())
