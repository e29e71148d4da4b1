"""Cost of the platform vibration model per point, against one Pinocchio ``rnea`` call.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_modes.py``.
All figures come from one run, timed in turn. The targets: the platform model
(six frequencies and shapes, with a drive) at most 20 times the cost of one
``rnea`` call per point, and a 21^3 map of the lowest frequency over the
prototype's cube in at most 2 s. The full model's time per point, and that of
its OpenSees check (``frame_fea_modes``, when the ``[modal]`` extra is
installed), are printed for reference.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pinocchio as pin
from _timing import best_times, emit, parse_args

from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.elasticity.frame_modal_fea import frame_fea_modes
from orthoglide_pin.elasticity.modes import natural_frequencies
from orthoglide_pin.exceptions import MissingExtraError
from orthoglide_pin.kinetostatics.workspace import cube_grid
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.params import prototype

#: Points of the batch (the prototype's cube).
POINTS = 5_000
#: rnea calls timed per repeat.
RNEA_CALLS = 2_000
#: The map's grid points per axis.
MAP_SIDE = 21
#: The targets of the issue.
TARGET_RATIO = 20.0
TARGET_MAP_S = 2.0
SEED = 20261201


def bench_modes(repeats: int = 3) -> dict[str, Any]:
    """Per-point times [s] of the platform model and of one ``rnea``; the map's time [s]."""
    params = prototype()
    drive = load_drive(str(example_drive_file()))
    cube = params.workspace
    rng = np.random.default_rng(SEED)
    points = cube.q1 + cube.side * rng.random((POINTS, 3))
    grid = cube_grid(cube.q1, cube.side, MAP_SIDE).points()
    model = ClosedLoopModel(params)
    q = model.configuration(points[0])
    v, a = np.linspace(-1.0, 1.0, model.nv), np.linspace(1.0, -1.0, model.nv)
    natural_frequencies(params, points[:10], drive)  # warm the caches (URDF, model)

    def rnea_batch() -> None:
        for _ in range(RNEA_CALLS):
            pin.rnea(model.model, model.data, q, v, a)

    times = best_times(
        [
            rnea_batch,
            lambda: natural_frequencies(params, points, drive),
            lambda: natural_frequencies(params, grid, drive, count=1),
        ],
        repeats,
    )
    rnea, per_point, map_s = times[0] / RNEA_CALLS, times[1] / POINTS, times[2]
    start = time.perf_counter()
    natural_frequencies(params, cube.center, drive, model="full")
    full = time.perf_counter() - start
    fea: float | None = None
    try:
        start = time.perf_counter()
        frame_fea_modes(params, cube.center, drive)
        fea = time.perf_counter() - start
    except MissingExtraError:
        pass
    ratio = per_point / rnea
    print("Natural frequencies on the prototype cube, with the example drive:")
    print(f"  one pinocchio.rnea call (18 joints)     : {rnea * 1e6:8.2f} us")
    print(
        f"  platform model per point ({POINTS:,} points): {per_point * 1e6:8.2f} us = "
        f"{ratio:6.2f} x rnea (target <= {TARGET_RATIO:g}: "
        f"{'met' if ratio <= TARGET_RATIO else 'NOT met'})"
    )
    print(
        f"  {MAP_SIDE}^3 map of the lowest frequency     : {map_s:8.3f} s (target <= "
        f"{TARGET_MAP_S:g} s: {'met' if map_s <= TARGET_MAP_S else 'NOT met'})"
    )
    print(f"  full model at one point (reference)     : {full:8.3f} s")
    if fea is not None:
        print(f"  its OpenSees check at one point         : {fea:8.3f} s")
    return {
        "points": POINTS,
        "rnea_s": rnea,
        "platform_per_point_s": per_point,
        "ratio_to_rnea": ratio,
        "target_ratio": TARGET_RATIO,
        "map_points": MAP_SIDE**3,
        "map_s": map_s,
        "target_map_s": TARGET_MAP_S,
        "full_point_s": full,
        "fea_point_s": fea,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_modes())


if __name__ == "__main__":
    main()
