"""Chatter stability: lobes at one point, and the margin along a 1,000-block program.

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_lobes.py``.
The shipped cut file (``aluminium_finish``: a 10 mm three-flute end mill, 2 mm
deep, 1 mm wide, climb milling, 12,000 rpm, the tool's own modes at 2.2 kHz)
on the prototype. The targets: the lobes over 200 spindle speeds at one point
(semi-discretization, the machine's modes at the point included) in at most
1 s, and the stability margin of every block of a 1,000-block zigzag pocket
in at most 30 s. The lobes' lowest limit and the limit at the cut file's speed
at home and at Q2 are printed with them.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from _timing import best_times, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.machining.cutting import RPM_PER_RAD_S
from orthoglide_pin.machining.stability import stability_lobes
from orthoglide_pin.machining.stability_path import program_blocks, stability_margin_along

#: Blocks of the program.
BLOCKS = 1000
#: The targets of the issue [s].
TARGET_LOBES_S = 1.0
TARGET_MARGIN_S = 30.0


def pocket(blocks: int = BLOCKS) -> str:
    """A zigzag pocket 40 mm wide, 2 mm deep, with ``blocks`` cutting lines."""
    step = 40.0 / blocks
    lines = [f"G1 X{20 if i % 2 == 0 else -20} Y{-20 + i * step:.4f}" for i in range(blocks)]
    return "G21 G90 G17\nG0 X-20 Y-20 Z5\nG1 Z-2 F600\n" + "\n".join(lines) + "\nG0 Z5\n"


def bench_lobes(repeats: int = 2) -> dict[str, Any]:
    """Times [s] of the lobes at one point and of the margin along the program; the limits."""
    params = og.prototype()
    cut = og.read_cut_file(og.shipped_cut_file())
    program = og.read_program(pocket(), axes=og.design_axes(params))
    points, lines, angles = program_blocks(program, og.design_axes(params))
    out: dict[str, Any] = {}

    def lobes() -> None:
        out["home"] = stability_lobes(cut, (0.0, 0.0, 0.0), params=params, zero_order=False)

    def margin() -> None:
        out["margin"] = stability_margin_along(
            points, cut, lines=lines, angles=angles, params=params
        )

    lobes_s, margin_s = best_times([lobes, margin], repeats)
    cpu = []  # the processor time of the lobes (the wall time includes other users' load)
    for _ in range(3):
        start = time.process_time()
        lobes()
        cpu.append(time.process_time() - start)
    lobes_cpu = min(cpu)
    q2 = stability_lobes(cut, params.workspace.q2, params=params, zero_order=False)
    home, along = out["home"], out["margin"]
    speed = float(cut.spindle_speed or 0.0)
    print(f"Stability lobes on the prototype, shipped cut file ({speed * RPM_PER_RAD_S:.0f} rpm):")
    print(
        f"  lobes, {home.speeds.size} speeds at one point : {lobes_s:7.3f} s (target <= "
        f"{TARGET_LOBES_S:g} s: {'met' if lobes_s <= TARGET_LOBES_S else 'NOT met'})"
    )
    print(f"  lobes, processor time           : {lobes_cpu:7.3f} s")
    print(
        f"  margin along {len(lines):,} blocks     : {margin_s:7.3f} s (target <= "
        f"{TARGET_MARGIN_S:g} s: {'met' if margin_s <= TARGET_MARGIN_S else 'NOT met'})"
    )
    for name, lobe in (("home", home), ("Q2", q2)):
        print(
            f"  {name:4s}: lowest mode {lobe.model.frequencies[0]:6.1f} Hz, lowest limit "
            f"{lobe.minimum * 1e3:6.3f} mm, at {speed * RPM_PER_RAD_S:.0f} rpm "
            f"{lobe.limit_at(speed) * 1e3:6.3f} mm"
        )
    print(
        f"  margin along the pocket: {np.nanmin(along.margin):.3f} to "
        f"{np.nanmax(along.margin):.3f} (depth {cut.engagements[0].axial_depth * 1e3:g} mm)"
    )
    return {
        "lobe_speeds": int(home.speeds.size),
        "lobes_s": lobes_s,
        "lobes_cpu_s": lobes_cpu,
        "target_lobes_s": TARGET_LOBES_S,
        "blocks": len(lines),
        "margin_s": margin_s,
        "target_margin_s": TARGET_MARGIN_S,
        "home_lowest_mode_hz": float(home.model.frequencies[0]),
        "q2_lowest_mode_hz": float(q2.model.frequencies[0]),
        "home_min_depth_mm": home.minimum * 1e3,
        "q2_min_depth_mm": q2.minimum * 1e3,
        "home_depth_at_speed_mm": home.limit_at(speed) * 1e3,
        "q2_depth_at_speed_mm": q2.limit_at(speed) * 1e3,
        "margin_min": float(np.nanmin(along.margin)),
        "margin_max": float(np.nanmax(along.margin)),
    }


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_lobes())


if __name__ == "__main__":
    main()
