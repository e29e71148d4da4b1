"""A plan's sections put together: their start times, the blocks' times, the totals.

:func:`~orthoglide_pin.planning.plan.plan_program` plans the short sections
together and the long ones in windows (:mod:`~orthoglide_pin.planning.windows`);
:func:`assemble` lays them end to end in the program's order, dwells included,
and merges their verifications: the largest use of each limit, and the time
each limit binds (summed over the sections, windows included).
:class:`BlockProgress` counts the blocks planned for a progress callback,
whichever route planned them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from orthoglide_pin.planning.parametrize import SectionPlan, laws_at
from orthoglide_pin.planning.path import Path, Samples, Section
from orthoglide_pin.planning.verify import Motion, binding_time, worst_uses
from orthoglide_pin.planning.windows import WindowedSection


@dataclass(frozen=True)
class BlockTime:
    """When a block of the program runs.

    Attributes:
        line: Its line in the program.
        kind: ``"rapid"``, ``"line"``, ``"arc"`` or ``"dwell"``.
        start: Start time [s].
        end: End time [s].
    """

    line: int
    kind: str
    start: float
    end: float


@dataclass(frozen=True)
class SectionResult:
    """A section planned and verified.

    Attributes:
        section: The section.
        start: Its start time in the cycle [s].
        grid: The planning grid's samples (``None`` for a lone dwell or a
            section planned in windows, :mod:`~orthoglide_pin.planning.windows`).
        plan: Its time law (``None`` for a lone dwell).
        motion: Its verification on the fine grid (``None`` for a lone dwell or
            a section planned in windows: its worst uses and binding times are
            in the plan's ``worst`` and ``binding``).
        rounds: How many times it was planned.
        scales: The smallest tightening factor of each limit it needed
            (:mod:`~orthoglide_pin.planning.tighten`).
    """

    section: Section
    start: float
    grid: Samples | None
    plan: SectionPlan | None
    motion: Motion | None
    rounds: int
    scales: dict[str, float]

    @property
    def duration(self) -> float:
        """The motion's duration, without the dwell [s]."""
        return 0.0 if self.plan is None else self.plan.duration


@dataclass(frozen=True)
class Verified:
    """The verification of a run of sections that kept only their time laws.

    Attributes:
        worst: The largest use of each limit on their verification grids [-].
        binding: The time each limit binds [s].
        grid_points: Points of their planning grids.
    """

    worst: dict[str, float]
    binding: dict[str, float]
    grid_points: int


@dataclass(frozen=True)
class Assembled:
    """The sections laid end to end (see :func:`assemble`).

    Attributes:
        results: Each section, in the program's order.
        cycle_time: The program's duration, dwells included [s].
        blocks: When each block runs.
        worst: The largest use of each limit on the verification grid [-].
        binding: The share of the cycle time each limit binds [-].
        grid_points: Points of the planning grids.
    """

    results: tuple[SectionResult, ...]
    cycle_time: float
    blocks: tuple[BlockTime, ...]
    worst: dict[str, float]
    binding: dict[str, float]
    grid_points: int


class BlockProgress:
    """Counts the blocks planned for a ``(done, total)`` callback, never going back.

    A moving section accounts for the blocks after the previous moving
    section's last one, up to its own last one (dwells and zero-length moves
    between them included); the callback is told at most ``total``.

    Args:
        callback: Called with (blocks planned, blocks), or ``None``.
        moving: The moving sections, in the program's order.
        total: The program's blocks.
    """

    def __init__(
        self, callback: Callable[[int, int], None] | None, moving: list[Section], total: int
    ) -> None:
        self.callback, self.total, self.done = callback, total, 0
        self._first: dict[int, int] = {}
        self._counted: dict[int, int] = {}
        after = 0
        for sec in moving:
            self._first[id(sec)] = after
            after = sec.pieces[-1].block + 1

    def planned(self, section: Section, block: int) -> None:
        """The section is planned up to its block ``block`` (an index in the program)."""
        count = block + 1 - self._first[id(section)]
        more = count - self._counted.get(id(section), 0)
        if more > 0:
            self._counted[id(section)] = count
            self.done += more

    def tell(self) -> None:
        """Call the callback with the blocks counted so far."""
        if self.callback is not None:
            self.callback(min(self.done, self.total), self.total)

    def finish(self) -> None:
        """Call the callback with every block planned."""
        if self.callback is not None:
            self.callback(self.total, self.total)


def assemble(
    path: Path,
    windowed: dict[int, WindowedSection],
    whole: list[SectionResult],
    summed: list[Verified] | None = None,
) -> Assembled:
    """Lay the sections end to end in the program's order and merge their verifications.

    Args:
        path: The path planned.
        windowed: The sections planned in windows, by ``id``.
        whole: The other moving sections, in order, their ``start`` not yet set.
        summed: The verifications of runs of ``whole`` that kept no grid or
            motion (a program of many sections), or ``None``.

    Returns:
        The sections with their start times, and the plan's totals.
    """
    results: list[SectionResult] = []
    clock, index = 0.0, 0
    for section in path.sections:
        if not section.pieces:
            results.append(SectionResult(section, clock, None, None, None, 0, {}))
            clock += section.dwell
            continue
        if id(section) in windowed:
            done = windowed[id(section)]
            result = SectionResult(section, clock, None, done.plan, None, done.rounds, done.scales)
        else:
            r = whole[index]
            result = SectionResult(section, clock, r.grid, r.plan, r.motion, r.rounds, r.scales)
            index += 1
        results.append(result)
        clock += result.duration + section.dwell
    grid_points = sum(r.grid.s.size for r in whole if r.grid is not None)
    grid_points += sum(done.grid_points for done in windowed.values())
    motions = [r.motion for r in results if r.motion is not None]
    worst, bound = worst_uses(motions), binding_time(motions)
    merged: list[WindowedSection | Verified] = [*windowed.values(), *(summed or [])]
    grid_points += sum(part.grid_points for part in summed or [])
    for part in merged:
        for name, use in part.worst.items():
            worst[name] = max(worst.get(name, 0.0), use)
        for name, t in part.binding.items():
            bound[name] = bound.get(name, 0.0) + t
    shares = {k: v / clock if clock > 0 else 0.0 for k, v in bound.items()}
    return Assembled(tuple(results), clock, block_times(path, results), worst, shares, grid_points)


def block_times(path: Path, results: list[SectionResult]) -> tuple[BlockTime, ...]:
    """Start and end time of every block (zero-length moves take no time)."""
    blocks = path.program.blocks
    start = np.full(len(blocks), np.nan)
    end = np.full(len(blocks), np.nan)
    planned = [r for r in results if r.plan is not None]
    if planned:  # every piece's start and end time, in one pass
        t_at = laws_at([r.plan for r in planned], [r.section.offsets for r in planned])[0]  # type: ignore[misc]
        sizes = [r.section.offsets.size for r in planned]
        at = np.repeat(np.array([r.start for r in planned]), sizes) + t_at
        first = np.ones(at.size, dtype=bool)
        first[np.cumsum(sizes) - 1] = False  # a piece starts at each offset but the last
        ends = np.roll(first, 1)  # and ends at each but the first
        b = np.array([p.block for r in planned for p in r.section.pieces], dtype=np.intp)
        np.fmin.at(start, b, at[first])
        np.fmax.at(end, b, at[ends])
    for r in results:
        sec = r.section
        if sec.dwell_block >= 0:
            t0 = r.start + r.duration
            start[sec.dwell_block], end[sec.dwell_block] = t0, t0 + sec.dwell
    out, last = [], 0.0
    for block, t_start, t_end in zip(blocks, start.tolist(), end.tolist(), strict=True):
        t0 = last if math.isnan(t_start) else t_start
        t1 = t0 if math.isnan(t_end) else t_end
        out.append(BlockTime(block.line, block.kind, t0, t1))
        last = t1
    return tuple(out)
