"""G2 corner blends: what they cost to build and what they change in the shipped examples.

Run on demand: ``python benchmarks/bench_blend.py [--json]``. Printed:

* ``build_lines_ms_per_corner`` and ``build_arcs_ms_per_corner``: the time
  :func:`~orthoglide_pin.planning.path.build_path` spends per blended corner
  on 500 G1 corners and on 100 corners between arcs, best of 3, and their
  ratio to building the same programs under ``G61`` (no blend), measured in
  the same run;
* for each shipped example planned with the example drive: its cycle time
  [s] and the largest step of a slider acceleration where two pieces meet,
  at the planned speed [m/s^2] (with a circular fillet it is ``v^2 / r`` at
  a fillet's ends; with a G2 blend it vanishes to rounding).
"""

from __future__ import annotations

import time

import numpy as np
from _timing import emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import EXAMPLE_PROGRAMS, example_program_text, read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path
from orthoglide_pin.planning.plan import Plan, plan_program


def _lines() -> str:
    rng = np.random.default_rng(3)
    pts = rng.uniform(-60.0, 110.0, size=(501, 3))
    return "F30000\n" + "".join(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f}\n" for x, y, z in pts)


def _arcs() -> str:
    """100 quarter circles of 5 mm, each turning back by a right angle: a staircase."""
    lines = ["F6000", "G1 X0 Y0"]
    for k in range(100):
        x, y = 1.0 * k, 1.0 * k
        lines.append(
            f"G3 X{x + 1:.3f} Y{y + 1:.3f} R1" if k % 2 else f"G2 X{x + 1:.3f} Y{y + 1:.3f} R1"
        )
    return "\n".join(lines) + "\n"


def _build(text: str) -> tuple[float, int]:
    prog = read_program(text)
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        path = build_path(prog)
        best = min(best, time.perf_counter() - start)
    blends = sum(p.is_blend for s in path.sections for p in s.pieces)
    return best, blends


def _junction_step(plan: Plan, dyn: og.ClosedLoopDynamics) -> float:
    """The largest slider-acceleration step where two pieces meet, at the planned speed."""
    worst = 0.0
    for r in plan.sections:
        if r.plan is None:
            continue
        sec = r.section
        for k in range(1, len(sec.pieces)):
            a, b = sec.pieces[k - 1], sec.pieces[k]
            _, sd, sdd, _ = r.plan.at_lengths(sec.offsets[k : k + 1])
            acc = []
            for p, t, curv in (a.evaluate(np.array([a.length])), b.evaluate(np.array([0.0]))):
                res = dyn.inverse_dynamics(
                    p, t * sd[:, None], t * sdd[:, None] + curv * sd[:, None] ** 2
                )
                acc.append(res.slider_accelerations[0])
            worst = max(worst, float(np.abs(acc[0] - acc[1]).max()))
    return worst


def bench_blend() -> dict[str, float]:
    """Time the blends and measure the examples."""
    out: dict[str, float] = {}
    for name, text in (("lines", _lines()), ("arcs", _arcs())):
        blended, count = _build("G64 P0.01\n" + text)
        exact, _ = _build("G61\n" + text)
        out[f"build_{name}_ms_per_corner"] = 1e3 * blended / max(count, 1)
        out[f"build_{name}_over_g61"] = blended / exact
        print(f"{name}: {count} blends, {1e3 * blended / max(count, 1):.3f} ms per corner, "
              f"{blended / exact:.2f} x the same program under G61")  # fmt: skip
    dyn = og.ClosedLoopDynamics()
    # the whole motor torque, as when the guide's figures were measured
    limits = PlanLimits(drive=load_drive(str(example_drive_file())), torque_reserve=0.0)
    for name in EXAMPLE_PROGRAMS:
        plan = plan_program(read_program(example_program_text(name)), dyn, limits)
        step = _junction_step(plan, dyn)
        out[f"{name}_cycle_time"] = plan.cycle_time
        out[f"{name}_junction_step"] = step
        print(f"{name}: cycle time {plan.cycle_time:.4f} s, largest slider-acceleration "
              f"step at a junction {step:.3g} m/s^2")  # fmt: skip
    return out


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_blend())


if __name__ == "__main__":
    main()
