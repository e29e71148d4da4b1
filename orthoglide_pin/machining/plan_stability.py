"""Chatter stability along a planned program: the margin of every block that cuts.

:func:`stability_along_plan` takes the cutting samples of
:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan` and, for each
program line that cuts, a few of its samples evenly spread over it (its first,
its last and up to :data:`POINTS_PER_BLOCK` in all, fewer on a long program so
that the whole program asks at most :data:`MAX_POINTS` points): at each, the
limiting axial depth at the run's spindle speed, with the machine's modes at
that point, the feed direction of the planned path there and the line's
engagement (:func:`~orthoglide_pin.machining.stability_path.stability_margin_along`).
A block's margin is the smallest of its points' (its limit over its engaged
depth: above 1 it is stable, 0.5 means the cut is twice as deep as it may be);
its point is where that smallest margin is. Each cutting sample carries the
margin of its block (:attr:`PlanStability.sample_margin`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.accuracy import AccuracyResult
from orthoglide_pin.machining.stability_path import stability_margin_along
from orthoglide_pin.planning.plan import Plan

FloatArray = NDArray[np.float64]

#: Most points per block of the program (its first and last cutting samples among them).
POINTS_PER_BLOCK: Final[int] = 5
#: Most points over the whole program: fewer per block on a long program.
MAX_POINTS: Final[int] = 3000
#: Points per call to the margin (each call reports progress).
CHUNK: Final[int] = 50


@dataclass(frozen=True)
class PlanStability:
    """The stability margin of every program line that cuts, arrays per line (b,).

    Attributes:
        lines: The program lines that cut, in order.
        points: Each line's point of smallest margin, world frame [m], (b, 3).
        angles: The feed direction there, in the program's X-Y plane [rad].
        depths: Each line's engaged axial depth [m].
        limits: The limiting axial depth at its point [m] (``inf``: stable up
            to the depth searched).
        margin: ``limits / depths``, the smallest over the line's points [-].
        speed: Spindle speed [rad/s].
        points_per_block: Points computed per line, at most.
        sample_margin: Margin of each sample's line [-], ``nan`` where the
            sample does not cut, (n,).
    """

    lines: NDArray[np.intp]
    points: FloatArray
    angles: FloatArray
    depths: FloatArray
    limits: FloatArray
    margin: FloatArray
    speed: float
    points_per_block: int
    sample_margin: FloatArray

    @property
    def unstable(self) -> int:
        """Lines whose margin is at most 1 (they chatter)."""
        return int(np.sum(self.margin <= 1.0))

    @property
    def worst(self) -> int:
        """Index of the line of smallest margin (-1 when nothing cuts)."""
        return int(np.argmin(self.margin)) if self.margin.size else -1


def _picks(count: int, per_block: int) -> NDArray[np.intp]:
    """Up to ``per_block`` indices evenly spread over ``count`` samples, ends included."""
    return np.unique(np.round(np.linspace(0, count - 1, min(count, per_block))).astype(np.intp))


def stability_along_plan(
    plan: Plan,
    result: AccuracyResult,
    params: OrthoglideParams | None = None,
    *,
    drive: Drive | DriveTrain | None = None,
    model: str = "platform",
    points_per_block: int = POINTS_PER_BLOCK,
    progress: Callable[[int, int], None] | None = None,
) -> PlanStability:
    """The stability margin of every block that cuts (see the module).

    Args:
        plan: The plan ``result`` was computed on (its program's axes give the feed angle).
        result: Accuracy along the plan
            (:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`).
        params: The machine; the prototype when ``None``.
        drive: A drive whose rotary inertia is reflected onto the carriages.
        model: The machine's vibration model, ``"platform"`` or ``"full"``.
        points_per_block: Most points per line, 1 to 50.
        progress: Called with (points done, points) after each batch.

    Raises:
        InvalidParameterError: A bad argument (named).
    """
    instance_of("plan", plan, Plan, "a Plan (plan_program)")
    instance_of("result", result, AccuracyResult, "an AccuracyResult (accuracy_along_plan)")
    if isinstance(points_per_block, bool) or not isinstance(points_per_block, int):
        raise InvalidParameterError("points_per_block", points_per_block, "an integer, 1 to 50")
    if not 1 <= points_per_block <= 50:
        raise InvalidParameterError("points_per_block", points_per_block, "an integer, 1 to 50")
    if progress is not None and not callable(progress):
        raise InvalidParameterError("progress", progress, "None or a callable (done, total)")
    s = result.samples
    idx = np.flatnonzero(s.cutting)
    lines = np.unique(s.line[idx]).astype(np.intp)
    per_block = max(1, min(points_per_block, MAX_POINTS // max(1, lines.size)))
    chosen: list[NDArray[np.intp]] = []
    owner: list[NDArray[np.intp]] = []
    for k, ln in enumerate(lines):
        own = idx[s.line[idx] == ln]
        pick = own[_picks(own.size, per_block)]
        chosen.append(pick)
        owner.append(np.full(pick.size, k, dtype=np.intp))
    at = np.concatenate(chosen) if chosen else np.zeros(0, dtype=np.intp)
    block_of = np.concatenate(owner) if owner else np.zeros(0, dtype=np.intp)
    axes = plan.path.program.axes
    tangent = axes.to_program(s.tangent[at]) if at.size else np.zeros((0, 3))
    angles = np.arctan2(tangent[:, 1], tangent[:, 0])
    limits = np.full(at.size, np.nan)
    depths = np.full(at.size, np.nan)
    options: dict[str, Any] = {"drive": drive, "model": model, "axes": axes, "params": params}
    for lo in range(0, at.size, CHUNK):
        sl = slice(lo, lo + CHUNK)
        m = stability_margin_along(
            s.points[at[sl]], result.cut, lines=s.line[at[sl]], angles=angles[sl],
            speeds=result.spindle_speed, **options,
        )  # fmt: skip
        limits[sl], depths[sl] = m.limits, m.depths
        if progress is not None:
            progress(min(lo + CHUNK, at.size), at.size)
    ratio = limits / depths
    b = lines.size
    best = np.zeros(b, dtype=np.intp)
    for k in range(b):
        mine = np.flatnonzero(block_of == k)
        best[k] = mine[int(np.argmin(ratio[mine]))]
    sample_margin = np.full(s.t.size, np.nan)
    for k, ln in enumerate(lines):
        sample_margin[idx[s.line[idx] == ln]] = ratio[best[k]]
    return PlanStability(
        lines, s.points[at[best]] if b else np.zeros((0, 3)), angles[best], depths[best],
        limits[best], ratio[best], float(result.spindle_speed), per_block, sample_margin,
    )  # fmt: skip
