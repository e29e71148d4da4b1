"""Closed-loop inverse dynamics along a 10,000-point trajectory, against one raw rnea.

Run on demand: ``python benchmarks/bench_dynamics.py``. Every figure is measured
in this run and printed as a ratio to one ``pinocchio.rnea`` call on the same
model (the cut tree of 18 joints), so the numbers carry over between machines.
Target of the closed-form route: at most 10x one rnea call per point.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from _timing import best_per_call, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.dynamics.forward import ForwardDynamics
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics

CUBE_CORNER = -og.prototype().leg_length / np.sqrt(18.0)
CUBE_SIDE = 0.2
N_POINTS = 10_000
N_REFERENCE = 300


def circle(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A circle of radius 80 mm in a tilted plane of the cube, speeding up from 0.3 to 1.2 m/s."""
    t = np.linspace(0.0, 1.0, n)
    centre = np.full(3, CUBE_CORNER + CUBE_SIDE / 2)
    u = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    w = np.array([1.0, 1.0, -2.0]) / np.sqrt(6.0)
    r = 0.08
    w0, alpha = 0.3 / r, 0.9 / r  # angular speed [rad/s] and acceleration [rad/s^2]
    th, thd = w0 * t + 0.5 * alpha * t * t, w0 + alpha * t
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    p = centre + r * (c * u + s * w)
    pd = r * thd[:, None] * (-s * u + c * w)
    pdd = r * alpha * (-s * u + c * w) - r * (thd**2)[:, None] * (c * u + s * w)
    return p, pd, pdd


def bench_dynamics() -> dict[str, float]:
    """Time both inverse-dynamics routes and the forward dynamics, per point."""
    dyn = ClosedLoopDynamics()
    model = dyn.pinocchio_model()
    data = model.createData()
    p, pd, pdd = circle(N_POINTS)
    res = dyn.inverse_dynamics(p, pd, pdd)  # also warms the caches
    q0, v0, a0 = res.q[N_POINTS // 2], res.v[N_POINTS // 2], res.a[N_POINTS // 2]
    rnea = best_per_call(lambda: pin.rnea(model, data, q0, v0, a0), 20_000)
    fast = best_per_call(lambda: dyn.inverse_dynamics(p, pd, pdd), 1) / N_POINTS
    sub = slice(0, N_REFERENCE)
    ref = best_per_call(
        lambda: dyn.inverse_dynamics(p[sub], pd[sub], pdd[sub], method="projection"), 1, 3
    )
    ref /= N_REFERENCE
    fwd = ForwardDynamics(dyn)
    forward = best_per_call(
        lambda: fwd.accelerations(res.q[sub], res.v[sub], res.forces[sub]), 1, 3
    )
    forward /= N_REFERENCE
    peak = ", ".join(f"{f:.1f}" for f in np.max(np.abs(res.forces), axis=0))
    print(f"closed-loop inverse dynamics, circle of {N_POINTS} points (peak |F| = {peak} N)")
    print(f"  one pinocchio.rnea call                    {rnea * 1e6:8.2f} us   (1.0x)")
    print(
        f"  closed-form route, per point               {fast * 1e6:8.2f} us   "
        f"({fast / rnea:.1f}x rnea; target <= 10x)"
    )
    print(
        f"  projection route (warm-started), per point {ref * 1e6:8.1f} us   "
        f"({ref / rnea:.0f}x rnea, {N_REFERENCE} points)"
    )
    print(
        f"  forward dynamics (constraintDynamics)      {forward * 1e6:8.1f} us   "
        f"({forward / rnea:.0f}x rnea, {N_REFERENCE} points)"
    )
    return {
        "rnea_s": rnea,
        "closed_form_s": fast,
        "projection_s": ref,
        "forward_s": forward,
        "closed_form_over_rnea": fast / rnea,
        "projection_over_rnea": ref / rnea,
        "forward_over_rnea": forward / rnea,
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_dynamics())


if __name__ == "__main__":
    main()
