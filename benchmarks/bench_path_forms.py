"""Path dynamics as one batch (forces a s_ddot + b s_dot^2 + c), against inverse dynamics.

Run on demand: ``python benchmarks/bench_path_forms.py [--json]``. Every figure
is measured in this run, on a helix of 20,000 points through the prototype's
cube, and printed per point and as a ratio to one closed-form inverse-dynamics
point (``ClosedLoopDynamics.inverse_dynamics`` on the same batch, per point)
and to one raw ``pinocchio.rnea`` call, so the numbers carry over between
machines. Target: the forms at most 1.5 us per point where one inverse-dynamics
point costs 3.3 us, i.e. at most 0.45x one inverse-dynamics point.

The rnea route (three ``rneaInParallel`` columns per point) is timed too, with
one and two threads; its columns are compared bit for bit with ``pinocchio.rnea``.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin
from _timing import best_per_call, best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.dynamics.leg_harmonics import _CACHE, leg_harmonics

CUBE_CORNER = -og.prototype().leg_length / np.sqrt(18.0)
CUBE_SIDE = 0.2
N_POINTS = 20_000
TARGET_RATIO = 1.5 / 3.3  # the forms per point against one inverse-dynamics point
WRENCH = (40.0, -25.0, 60.0, 0.0, 0.0, 0.0)


def helix(n: int) -> tuple[np.ndarray, ...]:
    """Ten turns of radius 70 mm down the cube, by arc length: p, p', p''; and s_dot, s_ddot."""
    r, pitch, turns = 0.07, 0.015, 10
    centre = CUBE_CORNER + CUBE_SIDE / 2
    lead = pitch / (2 * np.pi)
    length = turns * 2 * np.pi * np.hypot(r, lead)
    s = np.linspace(0.0, length, n)
    w = s / np.hypot(r, lead)  # angle [rad]
    c, si = np.cos(w), np.sin(w)
    scale = 1.0 / np.hypot(r, lead)
    p = np.stack([centre + r * c, centre + r * si, centre - 0.07 + lead * w], axis=1)
    t = np.stack([-r * si, r * c, np.full(n, lead)], axis=1) * scale
    k = np.stack([-r * c, -r * si, np.zeros(n)], axis=1) * scale**2
    sd = 1.0 + 0.2 * np.sin(s)  # [m/s]
    sdd = 0.2 * np.cos(s) * sd  # d(sd)/dt = d(sd)/ds * sd [m/s^2]
    return p, t, k, sd, sdd


def bench_path_forms() -> dict[str, float | int | bool]:
    """Time the forms (both routes), inverse dynamics, rnea; check exactness and threads."""
    dyn = og.ClosedLoopDynamics()
    p, t, k, sd, sdd = helix(N_POINTS)
    v, a = t * sd[:, None], t * sdd[:, None] + k * (sd * sd)[:, None]
    begin = time.perf_counter()
    leg_harmonics(dyn)
    setup = time.perf_counter() - begin
    forms = og.path_forms(dyn, p, t, k, wrench=WRENCH)
    ref = dyn.inverse_dynamics(p, v, a, wrench=WRENCH)
    err = np.abs(forms.forces(sd, sdd) - ref.forces).max(axis=1)
    rel = float((err / np.linalg.norm(ref.forces, axis=1)).max())
    fast, by_rnea, point = (
        x / N_POINTS
        for x in best_times(
            [
                lambda: og.path_forms(dyn, p, t, k, wrench=WRENCH),
                lambda: og.path_forms_by_rnea(dyn, p, t, k, wrench=WRENCH),
                lambda: dyn.inverse_dynamics(p, v, a, wrench=WRENCH),
            ],
            repeats=5,
        )
    )
    model = dyn.pinocchio_model()
    data = model.createData()
    q, qd, qdd = (np.asfortranarray(x.T) for x in (ref.q, ref.v, ref.a))
    rnea = best_per_call(lambda: pin.rnea(model, data, q[:, 7], qd[:, 7], qdd[:, 7]), 20_000)
    threads, bitwise = {}, True
    single = np.array([pin.rnea(model, data, q[:, j], qd[:, j], qdd[:, j]) for j in range(2000)])
    for n_threads in (1, 2):
        pool = pin.ModelPool(model, n_threads)
        out = np.empty((model.nv, N_POINTS), order="F")
        threads[n_threads] = best_per_call(
            lambda n=n_threads, pl=pool, o=out: pin.rneaInParallel(n, pl, q, qd, qdd, o), 1, 5
        )
        bitwise &= bool(np.array_equal(out[:, :2000].T, single))
    col1, col2 = (threads[n] / N_POINTS for n in (1, 2))
    _CACHE.clear()
    print(f"path dynamics as one batch, helix of {N_POINTS} points (tool wrench {WRENCH[:3]} N)")
    print(f"  one pinocchio.rnea call (Python)           {rnea * 1e6:8.2f} us")
    for label, col in (("1 thread ", col1), ("2 threads", col2)):
        print(f"  rneaInParallel, per column, {label}      {col * 1e6:8.2f} us   ", end="")
        print(f"({col / rnea:.2f}x)")
    print(f"    bit for bit equal to pinocchio.rnea      {bitwise}")
    print(f"  one inverse-dynamics point (batched)       {point * 1e6:8.2f} us   (1.0x)")
    print(
        f"  path_forms, per point                      {fast * 1e6:8.2f} us   "
        f"({fast / point:.2f}x; target <= {TARGET_RATIO:.2f}x; {fast / rnea:.2f}x rnea)"
    )
    print(
        f"  path_forms_by_rnea (3 columns), per point  {by_rnea * 1e6:8.2f} us   "
        f"({by_rnea / point:.2f}x)"
    )
    print(f"  leg expansion set-up, once per machine     {setup * 1e3:8.1f} ms")
    print(f"  largest deviation from inverse dynamics    {rel:8.1e}   (relative, per point)")
    return {
        "points": N_POINTS,
        "path_forms_us_per_point": fast * 1e6,
        "rnea_route_us_per_point": by_rnea * 1e6,
        "inverse_dynamics_us_per_point": point * 1e6,
        "rnea_call_us": rnea * 1e6,
        "rnea_column_1_thread_us": col1 * 1e6,
        "rnea_column_2_threads_us": col2 * 1e6,
        "rnea_in_parallel_bitwise_equal": bitwise,
        "path_forms_over_point": fast / point,
        "path_forms_over_rnea": fast / rnea,
        "rnea_route_over_point": by_rnea / point,
        "setup_s": setup,
        "max_relative_deviation": rel,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_path_forms())


if __name__ == "__main__":
    main()
