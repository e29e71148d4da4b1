"""The stability margin along a path: each block's limiting depth over its engaged depth.

For each block (one tool point, e.g. its middle), the tool tip's modes there
are turned along the block's feed, and the limiting axial depth at the
block's spindle speed (:mod:`~orthoglide_pin.machining.stability`) is divided
by the depth the cut file engages on the block's program line: above 1 the
block is stable, 0.5 says the cut is twice as deep as it may be. Blocks that do
not cut (no engagement on their line, a rapid, a plunge along the tool's axis)
get no margin (``nan``). Blocks with the same engagement are computed together,
100 at a time.

These are the lower-level functions: the caller chooses the points and feed
directions. :func:`program_blocks` reads them off a program without planning
it (one point per block, its chord's middle, along its chord), which is cheap
but may miss the worst points of a long line or an arc (on the shipped helix,
each line a full turn, with the default drive train: 0.48 to 0.96 at the one
point of each turn it gives, 2.4 to 2.8 at the turn's middle sample of the
plan, 0.22 to 0.30 as the smallest over five samples of the turn).
``orthoglide accuracy``, ``report --cut`` and ``sweep --cut`` all take the
margin along the plan instead
(:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`: up to
five of each line's cutting samples, along the planned feed there, the
smallest kept), which calls :func:`stability_margin_along` on those samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import capped_points, instance_of
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import CutConditions, Engagement
from orthoglide_pin.machining.regeneration import paired
from orthoglide_pin.machining.stability import (
    MAX_POINTS,
    _check,
    _engagement,
    _limits,
    _speeds,
    milling_process,
)
from orthoglide_pin.program.axes import ProgramAxes, design_axes

FloatArray = NDArray[np.float64]

__all__ = ["StabilityMargin", "feed_angles", "program_blocks", "stability_margin_along"]

#: Feed-plane motion below which a block does not cut sideways (a plunge) [m].
PLUNGE: Final[float] = 1e-9


@dataclass(frozen=True)
class StabilityMargin:
    """The stability margin of each block along a path.

    Attributes:
        points: One tool point per block, world frame [m], shape (b, 3).
        speeds: Spindle speed of each block [rad/s], shape (b,).
        depths: Engaged axial depth of each block [m] (``nan``: not cutting), (b,).
        limits: Limiting axial depth at that speed there [m], shape (b,).
        margin: ``limits / depths`` (> 1 stable; ``nan`` where not cutting), shape (b,).
    """

    points: FloatArray
    speeds: FloatArray
    depths: FloatArray
    limits: FloatArray
    margin: FloatArray

    @property
    def stable(self) -> NDArray[np.bool_]:
        """Blocks that cut without chatter (and those that do not cut), shape (b,)."""
        return np.asarray(~(self.margin <= 1.0))

    @property
    def worst(self) -> int:
        """Index of the block with the smallest margin (-1 if no block cuts)."""
        finite = np.where(np.isnan(self.margin), np.inf, self.margin)
        return -1 if not np.any(np.isfinite(finite)) else int(np.argmin(finite))


def feed_angles(points: ArrayLike, axes: ProgramAxes | None = None) -> FloatArray:
    """Each block's feed direction in the program's X-Y plane [rad], from point to point.

    A block's direction is from the previous point to its own (the first
    block takes the second's); a block that does not move in X-Y keeps the
    last direction (0 at the start).
    """
    p = capped_points(points, "points", MAX_POINTS).reshape(-1, 3)
    frame = design_axes() if axes is None else axes
    prog = instance_of("axes", frame, ProgramAxes, "ProgramAxes or None").to_program(p)
    step = np.diff(prog[:, :2], axis=0)
    step = np.concatenate([step[:1], step]) if step.size else np.zeros((p.shape[0], 2))
    moving = np.hypot(step[:, 0], step[:, 1]) > 1e-9
    angle = np.arctan2(step[:, 1], step[:, 0])
    idx = np.maximum.accumulate(np.where(moving, np.arange(p.shape[0]), -1))
    return np.asarray(np.where(idx >= 0, angle[np.maximum(idx, 0)], 0.0))


def stability_margin_along(
    points: ArrayLike,
    conditions: CutConditions,
    *,
    lines: ArrayLike | None = None,
    angles: ArrayLike | None = None,
    speeds: ArrayLike | None = None,
    params: OrthoglideParams | None = None,
    drive: Drive | DriveTrain | None = None,
    model: str = "platform",
    axes: ProgramAxes | None = None,
) -> StabilityMargin:
    """The stability margin of each block: limiting depth / engaged depth (see the module).

    One margin per point given; the points and feed directions are the
    caller's. Along a planned program, prefer
    :func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`
    (several points per line, the planned feed; the figures of the commands).

    Args:
        points: One tool point per block (e.g. its middle), world frame [m], (b, 3).
        conditions: The cut; each block's engagement is that of its line.
        lines: Each block's program line (1-based); ``None``: every block takes
            the default engagement.
        angles: Each block's feed direction in the program's X-Y plane [rad];
            ``None``: from point to point (:func:`feed_angles`).
        speeds: Each block's spindle speed [rad/s] (or one for all); ``None``:
            the conditions'.
        params: Machine parameters; the prototype when ``None``.
        drive: A drive whose rotary inertia is reflected onto the carriages.
        model: The machine's vibration model, ``"platform"`` or ``"full"``.
        axes: The program's axes on the machine (the design's when ``None``).

    Returns:
        The margin per block (``nan`` for the blocks that do not cut).
    """
    _check(conditions)
    if np.size(points) == 0:  # nothing cuts
        empty = np.zeros(0)
        return StabilityMargin(np.zeros((0, 3)), empty, empty, empty, empty)
    p = capped_points(points, "points", MAX_POINTS).reshape(-1, 3)
    b = p.shape[0]
    omega = _speeds(conditions, speeds, b)
    ang = feed_angles(p, axes) if angles is None else paired("angles", angles, b, -math.inf)
    engaged: list[Engagement | None]
    if lines is None:
        engaged = [_engagement(conditions, None)] * b
    else:
        line = np.atleast_1d(np.asarray(lines)) if not isinstance(lines, (str, dict)) else None
        if (
            line is None
            or line.ndim != 1
            or line.size not in (1, b)
            or line.dtype.kind not in "iu"
        ):
            raise InvalidParameterError("lines", lines, f"1 or {b} program line numbers (int)")
        engaged = [conditions.engagement_at(int(n)) for n in np.broadcast_to(line, (b,))]
    depth = np.array([np.nan if e is None else e.axial_depth for e in engaged])
    limit = np.full(b, np.nan)
    options = {"drive": drive, "model": model, "axes": axes}
    for eng in {e for e in engaged if e is not None}:
        sel = np.flatnonzero([e == eng for e in engaged])
        process = milling_process(conditions, eng)
        limit[sel] = _limits(conditions, p[sel], omega[sel], ang[sel], process, params, options)
    return StabilityMargin(p, omega, depth, limit, limit / depth)


def program_blocks(
    program: Any, axes: ProgramAxes | None = None
) -> tuple[FloatArray, NDArray[np.intp], FloatArray]:
    """The cutting blocks of a read program: points, lines and feed angles.

    One point per block, without a plan: a quick look at a program. It is not
    what the commands report: they judge each line at up to five points of the
    plan (:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`),
    and the middle of a block may miss its worst point by far.

    Feed moves (lines and arcs) that move in the program's X-Y plane; each
    gives its chord's middle (world frame [m]), its program line and its
    chord's direction in the X-Y plane (an arc's tangent at its middle); a
    full circle (its chord zero) in the X-Y plane gives its start and the
    tangent there.

    Args:
        program: A program read by :func:`~orthoglide_pin.planning.gcode.read_program`
            (its ``moves`` in the program's axes, its ``blocks`` in the world frame).
        axes: The program's axes on the machine (the program's own, else the
            design's, when ``None``).

    Returns:
        ``points`` (b, 3) [m], ``lines`` (b,), ``angles`` (b,) [rad].
    """
    if axes is not None:
        instance_of("axes", axes, ProgramAxes, "ProgramAxes or None")
    if not hasattr(program, "moves"):
        raise InvalidParameterError("program", program, "a program read by read_program")
    own = getattr(program, "axes", None)
    frame = axes or (own if isinstance(own, ProgramAxes) else None) or design_axes()
    moves, blocks = list(getattr(program, "moves", ())), list(getattr(program, "blocks", ()))
    offset = np.zeros(3)  # the part zero: world = R machine + offset
    if moves and blocks:
        offset = np.asarray(blocks[0].start) - frame.to_world(moves[0].start)
    points, lines, angles = [], [], []
    for move in moves:
        if move.kind not in ("line", "arc"):
            continue
        start, end = np.asarray(move.start), np.asarray(move.end)
        chord = end[:2] - start[:2]
        if math.hypot(*chord) > PLUNGE:
            points.append(0.5 * (start + end))
            angles.append(math.atan2(chord[1], chord[0]))
        elif move.kind == "arc" and move.center is not None and move.normal is not None:
            radius = start[:2] - np.asarray(move.center)[:2]
            if abs(move.normal[2]) < 0.5 or move.turns == 0 or math.hypot(*radius) <= PLUNGE:
                continue  # not a circle in the X-Y plane: no sideways cut
            sign = math.copysign(1.0, move.turns * move.normal[2])  # counter-clockwise about +Z
            points.append(start)
            angles.append(math.atan2(sign * radius[0], -sign * radius[1]))
        else:
            continue
        lines.append(move.line)
    if not points:
        return np.zeros((0, 3)), np.zeros(0, dtype=np.intp), np.zeros(0)
    world = frame.to_world(np.array(points)) + offset
    return world, np.array(lines, dtype=np.intp), np.array(angles)
