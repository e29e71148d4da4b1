"""The tool's deflection under the cutting force, and the surface error it leaves.

At each tool point the machine's translational compliance ``C`` [m/N] comes
from the elastostatic model
(:func:`~orthoglide_pin.elasticity.stiffness.cartesian_stiffness`, its
``compliance[:3, :3]``: a force at the tool tip, no moment, the platform free
to tilt as the legs let it). The tool's and spindle's own modes add their
static compliance in series, ``1 / k`` along the program's X or Y axis of each
mode. The deflection under a force ``F`` on the tool is ``d = C F`` [m].

In the feed frame of a sample (:mod:`~orthoglide_pin.machining.forces`: ``x``
the feed, ``y`` left of it, ``z`` the tool's axis), the machined wall lies on
the engagement's side: ``+y`` in up milling, ``-y`` in down milling (a slot
is counted on the side of its milling direction). The **surface error** is
the deflection's component along the wall's outward normal, the direction
from the wall back into the tool: **positive leaves material** on the wall
(the tool was pushed away from it, an undercut), negative cuts into it. The
**feed error** is the component along the feed. Each comes **static** (under
the revolution's mean force, what a finishing pass leaves on average) and as
the **peak** over a revolution (the value of largest magnitude, with its sign).
The surface error is also given as **generated**: the wall at each height of
the cut is left by the edge passing it (at ``phi_st`` in up milling,
``phi_ex`` in down milling), so its error is the deflection's normal component
at that instant (Budak and Altintas, "Peripheral milling conditions for
improved dimensional accuracy", Int. J. Mach. Tools Manuf. 34 (1994)); the
value of largest magnitude over the heights is kept.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, float_array
from orthoglide_pin.elasticity.stiffness import cartesian_stiffness
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import Tool
from orthoglide_pin.program.axes import ProgramAxes

FloatArray = NDArray[np.float64]

#: Points per call of the stiffness model (bounds its memory).
STIFFNESS_BLOCK: Final[int] = 20_000


@dataclass(frozen=True)
class SurfaceError:
    """Deflection and surface error at ``n`` samples.

    Attributes:
        deflection: Static deflection under the mean force [m], (n, 3), world frame.
        surface_static: Surface error under the mean force [m], (n,) (positive: material left).
        surface_peak: Surface error of largest magnitude over a revolution [m], (n,).
        feed_static: Deflection along the feed under the mean force [m], (n,).
        feed_peak: Along the feed, of largest magnitude over a revolution [m], (n,).
        surface_generated: Surface error as the edge generates the wall, of
            largest magnitude over the cut's height [m], (n,) (zeros when the
            forces at the wall are not given).
    """

    deflection: FloatArray
    surface_static: FloatArray
    surface_peak: FloatArray
    feed_static: FloatArray
    feed_peak: FloatArray
    surface_generated: FloatArray


def feed_frames(tangent: ArrayLike, tool_axis: ArrayLike) -> FloatArray:
    """Feed frames ``[x y z]`` as columns, world frame, (n, 3, 3) (see the module).

    ``x`` is the tangent's part normal to the tool axis, normalised (``+e`` of
    any axis normal to the tool's where it has none), ``z`` the tool axis,
    ``y = z x x``.
    """
    t = finite_rows("tangent", tangent, 3)
    z = float_array(tool_axis)
    if z.shape != (3,) or not np.isclose(np.linalg.norm(z), 1.0):
        raise InvalidParameterError("tool_axis", tool_axis, "a unit vector, shape (3,)")
    x = t - np.outer(t @ z, z)
    size = np.linalg.norm(x, axis=1)
    spare = np.roll(np.abs(z), 1)  # a world axis normal to an axis-aligned tool axis
    fallback = np.cross(z, spare if np.linalg.norm(np.cross(z, spare)) > 0.5 else np.eye(3)[0])
    fallback /= np.linalg.norm(fallback)
    x = np.where(size[:, None] > 1e-12, x / np.where(size > 1e-12, size, 1.0)[:, None], fallback)
    y = np.cross(z, x)
    return np.stack([x, y, np.broadcast_to(z, x.shape)], axis=-1)


def tool_compliance(tool: Tool, axes: ProgramAxes) -> FloatArray:
    """The tool's and spindle's static compliance [m/N], (3, 3), world frame.

    The sum over the tool's modes of ``d d^T / k``, ``d`` the mode's program
    axis (X or Y) in the world frame.
    """
    r = axes.matrix
    c = np.zeros((3, 3))
    for mode in tool.modes:
        d = r[:, 0 if mode.direction == "x" else 1]
        c += np.outer(d, d) / mode.stiffness
    return c


def machine_compliance(
    points: ArrayLike, params: OrthoglideParams | None, extra: ArrayLike | None = None
) -> FloatArray:
    """Translational compliance at the tool tip [m/N], (n, 3, 3), plus ``extra`` (3, 3).

    Raises:
        InvalidParameterError, UnreachablePointError, SingularConfigurationError:
            As :func:`~orthoglide_pin.elasticity.stiffness.cartesian_stiffness`.
    """
    p = finite_rows("points", points, 3, "[m]")
    out = np.zeros((p.shape[0], 3, 3))
    for lo in range(0, p.shape[0], STIFFNESS_BLOCK):
        sel = slice(lo, lo + STIFFNESS_BLOCK)
        out[sel] = cartesian_stiffness(p[sel], params).compliance[:, :3, :3]
    if extra is not None:
        out += float_array(extra)
    return out


def wall_sides(milling: ArrayLike) -> FloatArray:
    """The wall's side along the feed frame's ``y``: +1 in up milling, -1 in down (n,)."""
    up = np.asarray(milling) == "up"
    return np.where(up, 1.0, -1.0)


def surface_errors(
    compliance: FloatArray,
    frames: FloatArray,
    sides: FloatArray,
    mean: FloatArray,
    over_period: FloatArray,
    at_wall: FloatArray | None = None,
) -> SurfaceError:
    """Deflections and surface errors from the forces in the feed frames (see the module).

    Args:
        compliance: ``C`` [m/N], (n, 3, 3), world frame.
        frames: Feed frames, (n, 3, 3) (:func:`feed_frames`).
        sides: The wall's side along ``y``, (n,) (:func:`wall_sides`).
        mean: Mean force on the tool [N], (n, 3), feed frame.
        over_period: The force over a tooth period [N], (n, S, 3), feed frame.
        at_wall: The force as each disc's edge passes the wall [N], (n, K, 3),
            feed frame, or ``None``.
    """
    # C in the feed frame: R^T C R, then the rows of y (signed by the side) and x
    local = np.swapaxes(frames, 1, 2) @ compliance @ frames
    mean_d = np.einsum("nij,nj->ni", local, mean)
    period_d = np.einsum("nij,nsj->nsi", local, over_period)
    normal = -sides  # the wall's outward normal along y
    surf = period_d[:, :, 1] * normal[:, None]
    feed = period_d[:, :, 0]
    rows = np.arange(mean.shape[0])
    surf_peak = surf[rows, np.argmax(np.abs(surf), axis=1)] if surf.size else np.zeros(0)
    feed_peak = feed[rows, np.argmax(np.abs(feed), axis=1)] if feed.size else np.zeros(0)
    generated = np.zeros(mean.shape[0])
    if at_wall is not None and at_wall.size:
        wall = np.einsum("nj,nkj->nk", local[:, 1, :], at_wall) * normal[:, None]
        generated = wall[rows, np.argmax(np.abs(wall), axis=1)]
    world = np.einsum("nij,nj->ni", frames, mean_d)
    return SurfaceError(
        world, mean_d[:, 1] * normal, surf_peak, mean_d[:, 0], feed_peak, generated
    )
