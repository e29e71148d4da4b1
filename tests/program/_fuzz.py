"""Seeded random programs of the common subset, for the differential tests.

Each program sets its units (G20/G21) and distance mode (G90/G91), then writes
rapids, feeds, arcs in G17/G18/G19 (centre format I J K with a radius mismatch
well within LinuxCNC's tolerance, radius format R, near-full circles whose end
misses the start by a few micrometres, full turns with P) and dwells. Every
motion or dwell block gives exactly one canonical move: its line is recorded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Per plane G code: (first, second, normal) axis indices, and centre-offset letters.
PLANES = {17: ((0, 1, 2), "IJ"), 18: ((2, 0, 1), "KI"), 19: ((1, 2, 0), "JK")}
AXES = "XYZ"
OFFSET_LETTER = "IJK"
#: Largest coordinate [mm] and smallest arc radius [mm].
SPAN = 60.0
MIN_RADIUS = 2.0
#: Radius mismatch of centre-format arcs [mm] (LinuxCNC allows 0.05 mm, or 0.1 %).
MISMATCH = 0.002
#: End-to-start miss of near-full circles [mm].
NEAR_FULL = 0.005


@dataclass(frozen=True)
class Generated:
    """A random program and the lines of its moves (1 for the first line)."""

    text: str
    move_lines: tuple[int, ...]


def _fmt(value: float) -> str:
    return f"{value:.4f}"


def program(rng: np.random.Generator, blocks: int = 10) -> Generated:
    """One random program of ``blocks`` motion or dwell blocks."""
    inch = bool(rng.random() < 0.3)
    scale = 1 / 25.4 if inch else 1.0  # program units per mm
    absolute = bool(rng.random() < 0.7)
    lines = [f"{'G20' if inch else 'G21'} {'G90' if absolute else 'G91'} G17 G94"]
    lines.append(f"F{_fmt(rng.uniform(50, 3000) * scale)}")
    pos = np.zeros(3)  # program units (the machine origin; no offsets)
    moves: list[int] = []

    def target(new: np.ndarray) -> str:
        shown = new if absolute else new - pos
        return " ".join(f"{AXES[k]}{_fmt(shown[k])}" for k in range(3))

    for _ in range(blocks):
        kind = rng.choice(["rapid", "line", "arc", "arc", "full", "r", "dwell"])
        if kind == "dwell":
            lines.append(f"G4 P{rng.uniform(0, 1.5):.3f}")
            moves.append(len(lines))
            continue
        if kind in ("rapid", "line"):
            new = np.round(rng.uniform(-SPAN, SPAN, 3) * scale, 4)
            lines.append(f"{'G0' if kind == 'rapid' else 'G1'} {target(new)}")
            moves.append(len(lines))
            pos = new if absolute else pos + np.round(new - pos, 4)
            continue
        plane = int(rng.choice([17, 18, 19]))
        (a, b, n), letters = PLANES[plane]
        cw = bool(rng.random() < 0.5)
        head = f"G{plane} {'G2' if cw else 'G3'}"
        new = pos.copy()
        if rng.random() < 0.3:  # a helix
            new[n] = round(pos[n] + rng.uniform(-5, 5) * scale, 4)
        if kind == "r":
            chord = rng.uniform(2 * MIN_RADIUS, 40) * scale
            phi = rng.uniform(0, 2 * math.pi)
            new[a] = round(pos[a] + chord * math.cos(phi), 4)
            new[b] = round(pos[b] + chord * math.sin(phi), 4)
            radius = chord / 2 * rng.uniform(1.05, 3.0) * (1 if rng.random() < 0.5 else -1)
            lines.append(f"{head} {target(new)} R{_fmt(radius)}")
        else:
            radius = rng.uniform(MIN_RADIUS, 30) * scale
            start_angle = rng.uniform(0, 2 * math.pi)
            centre = pos.copy()
            centre[a] -= radius * math.cos(start_angle)
            centre[b] -= radius * math.sin(start_angle)
            offset = np.round(centre - pos, 4)
            centre = pos + offset
            r0 = float(np.hypot(offset[a], offset[b]))
            if kind == "full":
                miss = NEAR_FULL * scale * float(rng.choice([0.0, 1.0]))
                direction = rng.uniform(0, 2 * math.pi)
                new[a] = round(pos[a] + miss * math.cos(direction), 4)
                new[b] = round(pos[b] + miss * math.sin(direction), 4)
            else:
                end_angle = rng.uniform(0, 2 * math.pi)
                r1 = r0 + rng.uniform(-MISMATCH, MISMATCH) * scale
                new[a] = round(centre[a] + r1 * math.cos(end_angle), 4)
                new[b] = round(centre[b] + r1 * math.sin(end_angle), 4)
            words = f"{letters[0]}{_fmt(offset[a])} {letters[1]}{_fmt(offset[b])}"
            turns = f" P{int(rng.integers(2, 4))}" if rng.random() < 0.15 else ""
            lines.append(f"{head} {target(new)} {words}{turns}")
        moves.append(len(lines))
        pos = new
    lines.append("M2")
    return Generated("\n".join(lines) + "\n", tuple(moves))


def programs(seed: int, count: int) -> list[Generated]:
    """``count`` random programs from the seed ``seed``."""
    rng = np.random.default_rng(seed)
    return [program(rng, int(rng.integers(4, 16))) for _ in range(count)]


#: Block that puts LinuxCNC back to a program's start between batched programs.
RESET = "G21 G90 G17 G94 G40 G49 G80 G92.1 G54\nG0 X0 Y0 Z0"


def batch(generated: list[Generated]) -> tuple[str, list[range]]:
    """All programs in one text (each after :data:`RESET`), and each one's lines in it.

    Running ``rs274`` once on the batch instead of once per program saves its
    start-up time; the moves of program ``k`` are those whose line is in
    ``ranges[k]`` (line numbers are then shifted back by ``ranges[k].start - 1``).
    """
    parts: list[str] = []
    ranges: list[range] = []
    line = 1
    for g in generated:
        body = g.text.replace("\nM2\n", "\n").rstrip("\n").split("\n")
        line += RESET.count("\n") + 1
        ranges.append(range(line, line + len(body)))
        parts += [RESET, *body]
        line += len(body)
    return "\n".join([*parts, "M2"]) + "\n", ranges
