"""Milling forces: Altintas' mechanistic model, over one spindle revolution per sample.

The tool has ``N`` teeth of helix angle ``beta`` on a diameter ``D``; it turns
clockwise seen from the spindle (``M3``) at ``n`` [rev/s] and feeds along
``x`` of its **feed frame**: ``x`` the feed direction in the plane normal to
the tool's axis, ``z`` the tool's axis (the program's +Z, away from the part),
``y = z x x`` (left of the feed, seen from the spindle). Tooth ``j`` on the
axial disc at height ``z`` sits at the immersion angle
``phi_j(phi, z) = phi + 2 pi j / N - z tan(beta) / R``, measured from ``+y``
clockwise (Altintas, Manufacturing Automation, 2nd ed., 2012, ch. 2). While
``phi_st <= phi_j <= phi_ex`` (:meth:`~orthoglide_pin.machining.cutting.Engagement.immersion`)
it cuts the chip ``h = f_t sin(phi_j)`` with the feed per tooth
``f_t = v / (N n)`` and feels, per unit of axial length,

* ``dF_t = K_tc h + K_te`` (tangential), ``dF_r = K_rc h + K_re`` (radial),
  ``dF_a = K_ac h + K_ae`` (axial);
* on the tool, in the feed frame: ``dF_x = -dF_t cos(phi) - dF_r sin(phi)``,
  ``dF_y = dF_t sin(phi) - dF_r cos(phi)``, ``dF_z = -dF_a`` (a right-hand
  helix pulls the tool towards the part).

The force is summed over the teeth and :data:`DISCS` axial discs (midpoint
rule) at :data:`STEPS` angles of one tooth period (the force's period; the
revolution's mean and peak are those of the period). Its **mean** is computed
in closed form (the integral over the immersion, exact for any helix, since
the helix only shifts each disc's phase): for a slot (``phi_st = 0``,
``phi_ex = pi``) it is ``F_x = -N a K_rc f_t / 4 - N a K_re / pi``,
``F_y = N a K_tc f_t / 4 + N a K_te / pi``, ``F_z = -(N a K_ac f_t / pi + N a K_ae / 2)``.
The **peak** is the largest magnitude over the sampled period. The force is
linear in ``f_t`` (``F = f_t A + B``, ``A`` and ``B`` set by the engagement):
the period is summed once per engagement, then scaled for every sample.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, flag, float_array
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machining.cutting import MILLING, Material, Tool

FloatArray = NDArray[np.float64]

#: Angles sampled over one tooth period [-].
STEPS: Final[int] = 96
#: Axial discs of the helical edge (midpoint rule) [-].
DISCS: Final[int] = 12
#: How far inside the cut the generating edge is taken [rad] (on the wall, it
#: would be in or out of the cut by round-off).
WALL_NUDGE: Final[float] = 1e-9
#: Engagements or samples computed at once (bounds the memory: STEPS x teeth x DISCS each).
CHUNK: Final[int] = 256


@dataclass(frozen=True)
class MillingForces:
    """The milling force over one revolution at ``n`` cutting states, in their feed frames.

    Attributes:
        mean: Mean force on the tool [N], (n, 3): feed ``x``, normal ``y``, axial ``z``.
        peak: Largest magnitude over the revolution [N], (n,).
        at_peak: The force at that angle [N], (n, 3).
        angles: The angles sampled over one tooth period [rad], (STEPS,).
        over_period: The force at those angles [N], (n, STEPS, 3), or ``None``
            when not kept.
        at_wall: With the milling directions given: the force [N], (n, DISCS, 3),
            at the instant the edge of each axial disc (from the tool's tip up)
            passes the wall (``phi_st`` in up milling, ``phi_ex`` in down
            milling) and generates the machined surface there; else ``None``.
    """

    mean: FloatArray
    peak: FloatArray
    at_peak: FloatArray
    angles: FloatArray
    over_period: FloatArray | None
    at_wall: FloatArray | None = None


def _column(name: str, value: ArrayLike, n: int) -> FloatArray:
    arr = float_array(value)
    if arr.shape == ():
        arr = np.full(n, float(arr))
    if arr.shape != (n,) or not np.isfinite(arr).all() or (arr < 0.0).any():
        raise InvalidParameterError(name, value, f"{n} finite numbers >= 0")
    return np.asarray(arr, dtype=np.float64)


def _sides(milling: ArrayLike | None, n: int) -> FloatArray:
    """+1 for up milling, -1 for down milling, 0 when not given, (n,)."""
    if milling is None:
        return np.zeros(n)
    given = np.asarray(milling, dtype=object)
    given = np.full(n, given.item(), dtype=object) if given.shape == () else given
    if given.shape != (n,) or not all(m in MILLING for m in given):
        raise InvalidParameterError("milling", milling, f"'up' or 'down', one or {n}")
    return np.where(given == "up", 1.0, -1.0)


def _wall_angles(states: FloatArray, tool: Tool) -> FloatArray:
    """Spindle angles [rad], (m, DISCS), when each disc's edge passes the wall.

    ``states`` rows are ``(a, phi_st, phi_ex, side)``; tooth 0 of disc ``k``
    sits at ``phi - z_k tan(beta) / R``, so it reaches the wall angle
    ``phi_w`` at ``phi = phi_w + z_k tan(beta) / R`` (modulo a tooth period).
    """
    frac = (np.arange(DISCS) + 0.5) / DISCS
    lag = states[:, :1] * frac[None, :] * math.tan(tool.helix_angle) / (tool.diameter / 2.0)
    # just inside the cut: the generating edge is in contact (its edge force acts)
    wall = np.where(states[:, 3] > 0.0, states[:, 1] + WALL_NUDGE, states[:, 2] - WALL_NUDGE)
    return np.asarray(np.mod(wall[:, None] + lag, 2.0 * math.pi / tool.teeth), dtype=np.float64)


def mean_force(
    feed_per_tooth: FloatArray,
    depth: FloatArray,
    start: FloatArray,
    exit_: FloatArray,
    teeth: int,
    material: Material,
) -> FloatArray:
    """The closed-form mean force over a revolution [N], (n, 3) (see the module).

    Args:
        feed_per_tooth: f_t [m], (n,).
        depth: Axial depth a [m], (n,).
        start: Entry angle [rad], (n,).
        exit_: Exit angle [rad], (n,).
        teeth: N.
        material: The cutting coefficients.
    """
    m, f = material, feed_per_tooth

    def span(fn: FloatArray) -> FloatArray:  # fn at exit minus fn at start
        out: FloatArray = fn[1] - fn[0]
        return out

    ends = np.stack([start, exit_])
    i_sc = span(np.sin(ends) ** 2 / 2.0)
    i_c = span(np.sin(ends))
    i_ss = span(ends / 2.0 - np.sin(2.0 * ends) / 4.0)
    i_s = span(-np.cos(ends))
    i_1 = exit_ - start
    scale = teeth * depth / (2.0 * math.pi)
    fx = -(m.kt * f * i_sc + m.kte * i_c + m.kr * f * i_ss + m.kre * i_s)
    fy = m.kt * f * i_ss + m.kte * i_s - m.kr * f * i_sc - m.kre * i_c
    fz = -(m.ka * f * i_s + m.kae * i_1)
    mean: FloatArray = np.stack([fx, fy, fz], axis=-1) * scale[:, None]
    return mean


def _period(
    f: FloatArray,
    a: FloatArray,
    st: FloatArray,
    ex: FloatArray,
    tool: Tool,
    material: Material,
    angles: FloatArray,
) -> FloatArray:
    """The force at ``angles`` [rad], (n, S), of one chunk [N], (n, S, 3)."""
    m, n_teeth = material, tool.teeth
    radius = tool.diameter / 2.0
    frac = (np.arange(DISCS) + 0.5) / DISCS
    dz = a / DISCS  # (n,)
    lag = (a[:, None] * frac[None, :]) * math.tan(tool.helix_angle) / radius  # (n, K)
    pitch = 2.0 * math.pi * np.arange(n_teeth) / n_teeth
    # phi: (n, S, N, K), wrapped to [0, 2 pi)
    phi = angles[:, :, None, None] + pitch[None, None, :, None] - lag[:, None, None, :]
    phi = np.mod(phi, 2.0 * math.pi)
    inside = (phi >= st[:, None, None, None]) & (phi <= ex[:, None, None, None])
    inside &= (ex > st)[:, None, None, None]  # no width, no cut
    s, c = np.sin(phi), np.cos(phi)
    h = f[:, None, None, None] * s
    w = inside * dz[:, None, None, None]
    ft = (m.kt * h + m.kte) * w
    fr = (m.kr * h + m.kre) * w
    fa = (m.ka * h + m.kae) * w
    fx = (-ft * c - fr * s).sum(axis=(2, 3))
    fy = (ft * s - fr * c).sum(axis=(2, 3))
    fz = -fa.sum(axis=(2, 3))
    return np.stack([fx, fy, fz], axis=-1)


def milling_forces(
    feed_per_tooth: ArrayLike,
    axial_depth: ArrayLike,
    immersion: ArrayLike,
    tool: Tool,
    material: Material,
    *,
    keep_period: bool = False,
    milling: ArrayLike | None = None,
) -> MillingForces:
    """The milling force over one revolution at ``n`` cutting states (see the module).

    Args:
        feed_per_tooth: f_t [m], (n,) or a scalar.
        axial_depth: a [m], (n,) or a scalar.
        immersion: ``(phi_st, phi_ex)`` [rad], (n, 2) or (2,) (scalars and
            (2,) apply to every state).
        tool: The tool (teeth, diameter, helix).
        material: The cutting coefficients.
        keep_period: Keep the force at every sampled angle (``over_period``).
        milling: ``"up"`` or ``"down"``, (n,) or one for all: then the force
            as each disc's edge generates the wall (``at_wall``) is given too.

    Returns:
        Mean, peak and the force at the peak, in each state's feed frame.

    Raises:
        InvalidParameterError: Values of the wrong shape, negative or not finite,
            or immersion angles outside ``0 <= phi_st <= phi_ex <= pi``.
    """
    if not isinstance(tool, Tool) or not isinstance(material, Material):
        raise InvalidParameterError("tool", tool, "a Tool and a Material")
    imm = finite_rows("immersion", np.atleast_2d(float_array(immersion)), 2, "[rad]")
    keep_period = flag("keep_period", keep_period)
    n = max(imm.shape[0], float_array(feed_per_tooth).size, float_array(axial_depth).size)
    if imm.shape[0] == 1:
        imm = np.repeat(imm, n, axis=0)
    ft = _column("feed_per_tooth", feed_per_tooth, n)
    a = _column("axial_depth", axial_depth, n)
    st, ex = imm[:, 0], imm[:, 1]
    if (st < 0.0).any() or (ex < st).any() or (ex > math.pi + 1e-12).any():
        raise InvalidParameterError("immersion", immersion, "0 <= phi_st <= phi_ex <= pi [rad]")
    side = _sides(milling, n)
    angles = np.arange(STEPS, dtype=np.float64) * (2.0 * math.pi / tool.teeth / STEPS)
    mean = mean_force(ft, a, st, ex, tool.teeth, material)
    peak, at_peak = np.zeros(n), np.zeros((n, 3))
    kept = np.zeros((n, STEPS, 3)) if keep_period else None
    wall = np.zeros((n, DISCS, 3)) if milling is not None else None
    # the force is linear in f_t: F = f_t A + B, with A and B set by the engagement alone
    states, group = np.unique(np.stack([a, st, ex, side], axis=1), axis=0, return_inverse=True)
    group = group.reshape(-1)
    m = len(states)
    at = np.concatenate([np.broadcast_to(angles, (m, STEPS)), _wall_angles(states, tool)], axis=1)
    slope, offset = np.zeros((m, at.shape[1], 3)), np.zeros((m, at.shape[1], 3))
    for lo in range(0, m, CHUNK):
        sel = slice(lo, min(lo + CHUNK, m))
        e_a, e_st, e_ex = states[sel, 0], states[sel, 1], states[sel, 2]
        offset[sel] = _period(np.zeros(e_a.size), e_a, e_st, e_ex, tool, material, at[sel])
        unit = _period(np.ones(e_a.size), e_a, e_st, e_ex, tool, material, at[sel])
        slope[sel] = unit - offset[sel]
    for lo in range(0, n, CHUNK):
        sel = slice(lo, min(lo + CHUNK, n))
        g = group[sel]
        every = ft[sel, None, None] * slope[g] + offset[g]
        forces = every[:, :STEPS]
        size = np.linalg.norm(forces, axis=-1)
        k = np.argmax(size, axis=1)
        rows = np.arange(k.size)
        peak[sel], at_peak[sel] = size[rows, k], forces[rows, k]
        if kept is not None:
            kept[sel] = forces
        if wall is not None:
            wall[sel] = every[:, STEPS:]
    return MillingForces(mean, peak, at_peak, angles, kept, wall)
