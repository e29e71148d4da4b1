"""What a machine's controller adds to a program: overrides, the default path mode, the stops.

As on a CNC panel:

* the **feed override** multiplies every programmed feed (``F``), within
  :data:`FEED_OVERRIDE_RANGE` (0 to 200 %); the machine's limits still bound
  the motion, so above 1 the feed rises only where they leave room;
* the **rapid override** slows the rapid moves (``G0``), within
  :data:`RAPID_OVERRIDE_RANGE` (0 to 100 %): on a rapid move the path speed
  is capped at that share of the speed the slider and motor speed limits
  allow at each point (so it needs one of them when below 1);
* the **default path-control mode**: a block before any ``G61`` or ``G64``
  of the program runs in the mode a LinuxCNC machine starts in, continuous
  (``G64``: LinuxCNC's canon starts in ``CANON_CONTINUOUS`` with no
  tolerance, "the best speed possible, no matter how far away from the
  programmed point"). We bound the deviation: such blocks are blended within
  ``blend`` [m] (:data:`~orthoglide_pin.planning.gcode.DEFAULT_TOLERANCE`,
  0.01 mm, as ``G64`` without ``P``, when not given), as if the program
  began with ``G64 P<blend>``. ``blend = 0`` stops at every corner that is
  not tangent. The program's own ``G61`` or ``G64`` rules the blocks after it.

:func:`stop_reasons` counts where the planned tool comes to rest, and why:
``exact stop (G61)``, ``sharp corner`` (a corner that cannot be blended
within the tolerance, or turns back on itself), ``rapid/feed change`` (the
tool stops between a rapid and a feed move), ``curvature step`` (where a jerk
limit stops the tool), ``dwell`` (G4) and ``end`` (the program's end).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of, positive_number
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.gcode import DEFAULT_TOLERANCE, Program
from orthoglide_pin.planning.limits import PlanLimits, Scales, speed_bound
from orthoglide_pin.planning.path import TANGENT_TOL, Path

FloatArray = NDArray[np.float64]

#: The feed override's range, as on a CNC panel: (0, 2] [-].
FEED_OVERRIDE_RANGE: Final = (0.0, 2.0)
#: The rapid override's range: (0, 1] [-].
RAPID_OVERRIDE_RANGE: Final = (0.0, 1.0)
#: The largest blending tolerance ``blend`` [m] (10 mm).
MAX_BLEND: Final[float] = 0.01
#: The reasons of :func:`stop_reasons`, in the order they are told.
STOP_REASONS: Final = (
    "exact stop (G61)", "sharp corner", "rapid/feed change", "curvature step", "dwell", "end",
)  # fmt: skip


def check_override(name: str, value: float, top: float) -> float:
    """An override in ``(0, top]`` [-], or an error naming it and its range."""
    number = positive_number(name, value, f"a fraction in (0, {top:g}]")
    if number > top:
        raise InvalidParameterError(name, value, f"a fraction in (0, {top:g}]")
    return number


def check_blend(value: float | None) -> float | None:
    """A blending tolerance in ``[0, MAX_BLEND]`` [m], or ``None``."""
    if value is None:
        return None
    allowed = f"a tolerance in [0, {1e3 * MAX_BLEND:g} mm], in metres"
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError("blend", value, allowed) from None
    if not (math.isfinite(number) and 0.0 <= number <= MAX_BLEND) or isinstance(value, bool):
        raise InvalidParameterError("blend", value, allowed)
    return number


def with_controller(
    program: Program, *, feed_override: float = 1.0, blend: float | None = None
) -> Program:
    """The program as the controller runs it: feeds overridden, the default mode set.

    Args:
        program: The program read.
        feed_override: Multiplies every feed, in :data:`FEED_OVERRIDE_RANGE`.
        blend: The tolerance of the default mode ``G64 P<blend>`` [m]
            (:data:`~orthoglide_pin.planning.gcode.DEFAULT_TOLERANCE` when ``None``).

    Raises:
        InvalidParameterError: An override or a tolerance out of its range.
    """
    feed_override = check_override("feed_override", feed_override, FEED_OVERRIDE_RANGE[1])
    tol = check_blend(blend)
    tol = DEFAULT_TOLERANCE if tol is None else tol
    first = program.mode_line or math.inf  # blocks before it run in the default mode
    blocks = []
    for b in program.blocks:
        changes: dict[str, object] = {}
        if b.line < first and b.kind != "dwell":
            changes.update(exact_stop=False, tolerance=tol)
        if b.feed is not None and feed_override != 1.0:
            changes["feed"] = b.feed * feed_override
        blocks.append(dataclasses.replace(b, **changes) if changes else b)  # type: ignore[arg-type]
    return dataclasses.replace(program, blocks=tuple(blocks))


def rapid_caps(
    feed: FloatArray, forms: PathForms, limits: PlanLimits, override: float
) -> FloatArray:
    """The path-speed caps of a section with the rapid override: ``override`` x the speed bound.

    Raises:
        InvalidParameterError: An override below 1 on a rapid move no speed limit bounds.
    """
    rapid = np.isinf(feed)
    if override == 1.0 or not rapid.any():
        return feed
    bound = speed_bound(limits, forms, np.full(feed.shape, np.inf), Scales())
    if not np.all(np.isfinite(bound[rapid])):
        raise InvalidParameterError(
            "rapid_override",
            override,
            "1 when no speed limit bounds the rapid moves (give a slider speed or a motor "
            "maximum speed)",
        )
    out: FloatArray = np.array(feed, dtype=np.float64)
    out[rapid] = override * np.sqrt(bound[rapid])
    return out


def default_mode_text(program: Program, blend: float | None) -> str:
    """The path-control mode of the blocks before any ``G61``/``G64``, as the summary says it."""
    tol = DEFAULT_TOLERANCE if blend is None else blend
    mode = f"G64 P{1e3 * tol:g} mm (blended)" if tol > 0 else "G64 P0 (stops at every corner)"
    line = program.mode_line
    if line and not any(b.line < line for b in program.blocks):
        return f"the program's own (G61/G64 at line {line}, before any move)"
    if line:
        return f"{mode} until line {line} (default mode), then the program's own"
    return f"{mode}: the default mode, the program says neither G61 nor G64"


def stop_reasons(path: Path) -> dict[str, int]:
    """How many times the tool comes to rest along the path, by reason (see the module).

    Args:
        path: A plan's path (``plan.path``: with a jerk limit, it holds the
            stops the limit adds), or :func:`~orthoglide_pin.planning.path.build_path`'s.

    Returns:
        Each reason of :data:`STOP_REASONS` -> how many times.

    Raises:
        InvalidParameterError: Not a Path.
    """
    path = instance_of("path", path, Path, "a Path (build_path, or a plan's path)")
    blocks = path.program.blocks
    counts = dict.fromkeys(STOP_REASONS, 0)
    moving = [k for k, sec in enumerate(path.sections) if sec.pieces]
    for n, k in enumerate(moving):
        sec = path.sections[k]
        last = sec.pieces[-1]
        if sec.dwell > 0.0 or sec.dwell_block >= 0:
            reason = "dwell"
        elif n == len(moving) - 1:
            reason = "end"
        else:
            nxt = path.sections[moving[n + 1]].pieces[0]
            tangent = float(np.clip(last.end_tangent() @ nxt.start_tangent(), -1.0, 1.0))
            if blocks[last.block].exact_stop:
                reason = "exact stop (G61)"
            elif (last.feed is None) != (nxt.feed is None):
                reason = "rapid/feed change"
            elif math.acos(tangent) > TANGENT_TOL:
                reason = "sharp corner"
            else:
                reason = "curvature step"
        counts[reason] += 1
    return counts
