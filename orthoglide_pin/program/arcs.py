"""Arcs as LinuxCNC's interpreter and motion planner cut them.

The centre of an ``I J K`` arc is kept **as programmed** (LinuxCNC's
``arc_data_ijk``): no projection onto the chord's bisector. Where the radii to
the start ``r0`` and to the end ``r1`` differ, the tool follows LinuxCNC's
spiral: the radius varies linearly with the angle swept, from ``r0`` to
``r1``, and so does the helix's rise. The mismatch is refused only beyond
LinuxCNC's own tolerances (``interp_arc.cc`` and ``interp_internal.hh`` of
LinuxCNC 2.8 and 2.9, in the program's units), that is where::

    err > 100 SPIRAL_ABS_TOLERANCE, or
    err > SPIRAL_ABS_TOLERANCE and err / max(r0, r1) > SPIRAL_REL_TOLERANCE

with ``err = |r0 - r1|``, ``SPIRAL_ABS_TOLERANCE`` 0.02 sqrt(2) mm (0.002
sqrt(2) inch) and ``SPIRAL_REL_TOLERANCE`` 0.001;

and a radius below ``RADIUS_TOLERANCE`` (0.00127 mm, 0.00005 inch) is a zero
radius. An ``R`` arc's centre is LinuxCNC's ``arc_data_r``'s (a radius short of
half the chord by at most ``RADIUS_TOLERANCE`` is a half turn).

The angle swept is that of LinuxCNC's ``ARC_FEED`` (``emccanon.cc``): from the
start's direction to the end's, about the plane's normal (counter-clockwise
for ``turns > 0``, clockwise otherwise), an end direction no more than
:data:`MIN_ARC_ANGLE` ahead of the start's adding a full turn (so an end equal
to the start, or on the start's radius, is a full circle), then ``|turns| -
1`` more full turns (``P``).
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.program.moves import Move

FloatArray = NDArray[np.float64]

#: LinuxCNC's tolerances, in the program's units: millimetres, inches.
RADIUS_TOLERANCE_MM: Final[float] = 0.00005 * 25.4
RADIUS_TOLERANCE_INCH: Final[float] = 0.00005
SPIRAL_ABS_TOLERANCE_MM: Final[float] = 2 * 0.01 * math.sqrt(2.0)
SPIRAL_ABS_TOLERANCE_INCH: Final[float] = 2 * 0.001 * math.sqrt(2.0)
SPIRAL_REL_TOLERANCE: Final[float] = 0.001
#: ``arc_data_r``'s allowance for a half turn [-].
TINY: Final[float] = 1e-12
#: An end direction at most this ahead of the start's adds a full turn [rad]
#: (``min_arc_angle`` of LinuxCNC's ``ARC_FEED``).
MIN_ARC_ANGLE: Final[float] = 1e-12


def _fmt(x: float) -> str:
    return f"{x:.4f}"


def check_ijk(
    start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float], inch: bool
) -> str | None:
    """Why an ``I J K`` arc is refused (``None`` when LinuxCNC cuts it).

    Args:
        start: The start point in the plane [program units].
        end: The end point in the plane [program units].
        centre: The centre in the plane [program units].
        inch: The program is in inches (``G20``).
    """
    unit = "inch" if inch else "mm"
    r0 = math.hypot(centre[0] - start[0], centre[1] - start[1])
    r1 = math.hypot(centre[0] - end[0], centre[1] - end[1])
    zero = RADIUS_TOLERANCE_INCH if inch else RADIUS_TOLERANCE_MM
    if r0 < zero or r1 < zero:
        return (
            f"arc of zero radius: radius to the start {_fmt(r0)} {unit}, to the end "
            f"{_fmt(r1)} {unit} (LinuxCNC's least: {zero:g} {unit})"
        )
    err = abs(r0 - r1)
    spiral = SPIRAL_ABS_TOLERANCE_INCH if inch else SPIRAL_ABS_TOLERANCE_MM
    if err > 100.0 * spiral or (err > spiral and err / max(r0, r1) > SPIRAL_REL_TOLERANCE):
        return (
            f"arc radius to the end {_fmt(r1)} {unit} differs from the radius to the start "
            f"{_fmt(r0)} {unit} by {err:.4g} {unit} (LinuxCNC allows {spiral:.4g} {unit}, "
            f"or up to {100 * spiral:.4g} {unit} within {100 * SPIRAL_REL_TOLERANCE:g} % "
            "of the radius)"
        )
    return None


def centre_r(
    start: tuple[float, float],
    end: tuple[float, float],
    radius: float,
    clockwise: bool,
    inch: bool,
) -> tuple[float, float] | str:
    """The centre of an ``R`` arc in the plane [program units], or why it is refused.

    Args:
        start: The start point in the plane [program units].
        end: The end point in the plane [program units].
        radius: ``R`` [program units]; negative for more than half a turn.
        clockwise: ``G2``.
        inch: The program is in inches.
    """
    if end == start:
        return "an R arc whose end is its start (a full circle takes its centre by I J K)"
    size = abs(radius)
    mid = (0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1]))
    half = math.hypot(mid[0] - end[0], mid[1] - end[1])
    tolerance = RADIUS_TOLERANCE_INCH if inch else RADIUS_TOLERANCE_MM
    unit = "inch" if inch else "mm"
    if half - size > tolerance:
        return f"arc radius R{radius:g} {unit} is less than half the chord {_fmt(half)} {unit}"
    if size == 0.0:
        return "arc of zero radius (R0)"
    if half / size > 1.0 - TINY:
        half = size
    direction = math.atan2(end[1] - start[1], end[0] - start[0])
    theta = direction - math.pi / 2 if clockwise == (radius > 0) else direction + math.pi / 2
    offset = size * math.cos(math.asin(half / size))
    return (mid[0] + offset * math.cos(theta), mid[1] + offset * math.sin(theta))


def swept_angle(
    start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float], turns: int
) -> float:
    """The signed angle an arc sweeps about its plane's normal [rad] (see the module).

    Args:
        start: The start point in the plane.
        end: The end point in the plane.
        centre: The centre in the plane.
        turns: LinuxCNC's signed turn count (not 0).
    """
    theta_start = math.atan2(start[1] - centre[1], start[0] - centre[0])
    theta_end = math.atan2(end[1] - centre[1], end[0] - centre[0])
    if turns < 0:
        if theta_end + MIN_ARC_ANGLE >= theta_start:
            theta_end -= 2.0 * math.pi
        return theta_end - theta_start + 2.0 * math.pi * (turns + 1)
    if theta_end - MIN_ARC_ANGLE <= theta_start:
        theta_end += 2.0 * math.pi
    return theta_end - theta_start + 2.0 * math.pi * (turns - 1)


def plane_axes(normal: FloatArray) -> tuple[int, int, int]:
    """The in-plane axes and the normal axis of a plane by its normal (+Z, +Y or +X)."""
    k = int(np.argmax(np.abs(normal)))
    return {2: (0, 1, 2), 1: (2, 0, 1), 0: (1, 2, 0)}[k]


def arc_geometry(move: Move) -> tuple[float, float, float, float]:
    """An arc move's swept angle [rad], start and end radii [m] and rise [m].

    The angle is signed about the move's ``normal``; the rise is the end's
    advance along it.

    Raises:
        ValueError: The move is not an arc.
    """
    if move.kind != "arc" or move.center is None or move.normal is None:
        raise ValueError("arc_geometry takes an arc move")
    i, j, k = plane_axes(move.normal)
    s, e, c = move.start, move.end, move.center
    sweep = swept_angle((s[i], s[j]), (e[i], e[j]), (c[i], c[j]), move.turns)
    r0 = math.hypot(s[i] - c[i], s[j] - c[j])
    r1 = math.hypot(e[i] - c[i], e[j] - c[j])
    return sweep, r0, r1, float(e[k] - s[k])
