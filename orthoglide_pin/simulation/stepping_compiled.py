"""The servo loop compiled with numba, MuJoCo's steps called from it.

:meth:`~orthoglide_pin.simulation.stepping.Stepper.run` spends, at every servo
period, some microseconds of Python around MuJoCo's steps: reading the
sliders, the position loop, the speed-torque curve, the screw's efficiency,
the controls, the row of the energy account. :func:`run_compiled` runs the
same arithmetic, in the same order, in one compiled loop (numba) that calls
MuJoCo's ``mj_step1``, ``mj_step2`` and ``mj_step`` itself, through the C
library that the ``mujoco`` package ships (``ctypes``), on the same model and
data: the values are those of the Python loop to the last digit
(``tests/simulation/test_stepping_compiled.py``). The loop returns to Python
when the energy account's block of rows is full and at every progress tick.

It runs when numba is installed (the ``[sim]`` and ``[plan]`` extras,
:data:`~orthoglide_pin.planning.reach_compiled.AVAILABLE`) and the C library
is found (:func:`library`); otherwise the Python loop runs.
"""

from __future__ import annotations

import ctypes
import functools
import math
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._compiled import jit
from orthoglide_pin.planning.reach_compiled import AVAILABLE

FloatArray = NDArray[np.float64]

#: Indices of the loop's constants in the array :func:`run_compiled` is given.
PERIOD, RESOLUTION, RATIO, EFFICIENCY, TO_TORQUE, INERTIA_K = 0, 1, 2, 3, 4, 5
COULOMB, VISCOUS, LAST_T, PEAK, LAST_W, SUBSTEPS, WRENCH = 6, 7, 8, 9, 10, 11, 12
#: Rows of the servo state array: the encoder's last reading, the integral,
#: frozen (0/1), driving (0/1), the efficiency factor and the thrust.
LAST, INTEGRAL, FROZEN, DRIVING, FACTOR, THRUST = 0, 1, 2, 3, 4, 5


@functools.cache
def library(mujoco: Any) -> tuple[Any, Any, Any] | None:
    """MuJoCo's ``mj_step1``, ``mj_step2`` and ``mj_step`` from its C library, or ``None``.

    The library is the one beside the ``mujoco`` package (``libmujoco.so.*``,
    ``libmujoco.*.dylib`` or ``mujoco.dll``), loaded once; ``None`` when numba
    is missing, the library is not found, or the bindings do not give the
    model's and data's addresses.
    """
    if not AVAILABLE or not hasattr(mujoco.MjData, "_address"):
        return None
    folder = Path(mujoco.__file__).parent
    found = sorted(folder.glob("libmujoco.so*")) + sorted(folder.glob("libmujoco*.dylib"))
    found += sorted(folder.glob("mujoco.dll"))
    if not found:
        return None
    try:
        lib = ctypes.CDLL(str(found[0]))
        funcs = (lib.mj_step1, lib.mj_step2, lib.mj_step)
    except (OSError, AttributeError):
        return None
    for f in funcs:
        f.argtypes, f.restype = [ctypes.c_void_p, ctypes.c_void_p], None
    return funcs


def _bisect_right(values: FloatArray, x: float) -> int:
    """:func:`bisect.bisect_right` of ``x`` in sorted ``values`` (the same search)."""
    lo, hi = 0, values.size
    while lo < hi:
        mid = (lo + hi) // 2
        if x < values[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


def _control(
    j: int,
    qpos: FloatArray,
    qvel: FloatArray,
    qacc: FloatArray,
    ctrl: FloatArray,
    armature: FloatArray,
    frictionloss: FloatArray,
    damping: FloatArray,
    index: NDArray[np.intp],
    refs: FloatArray,
    gains: FloatArray,
    consts: FloatArray,
    base: FloatArray,
    curve: FloatArray,
    state: FloatArray,
    out: FloatArray,
) -> None:
    """One period's controls: the arithmetic of the Python loop, in its order."""
    period, res, k, eta = consts[PERIOD], consts[RESOLUTION], consts[RATIO], consts[EFFICIENCY]
    to_torque, inertia_k = consts[TO_TORQUE], consts[INERTIA_K]
    coulomb, viscous, peak = consts[COULOMB], consts[VISCOUS], consts[PEAK]
    top_i = curve.shape[1]
    for i in range(3):
        v = index[1, i]
        q, qd = qpos[index[0, i]], qvel[v]
        out[0, j, i], out[1, j, i] = q, qd
        if math.isnan(res):
            read_q, read_qd = q, qd
        else:
            read_q = (np.rint(q / res) + 0.0) * res  # + 0.0: no -0, as Python's round
            read_qd = (read_q - state[LAST, i]) / period
            state[LAST, i] = read_q
        error = refs[0, j, i] - read_q
        if state[FROZEN, i] == 0.0:
            state[INTEGRAL, i] += error * period
        force = (
            gains[0, i] * error
            + gains[1, i] * (refs[1, j, i] - read_qd)
            + gains[2, i] * state[INTEGRAL, i]
        )
        asked = refs[2, j, i] + to_torque * force
        w = k * qd
        s = w if w >= 0.0 else -w
        g = _bisect_right(curve[0], s)
        if g < top_i:
            top = curve[2, g] + curve[3, g] * (s - curve[1, g]) / curve[4, g]
        else:
            top = consts[LAST_T] if s == consts[LAST_W] else 0.0
        a = top if top < peak else peak
        t = a if asked > a else (-a if asked < -a else asked)
        frozen = asked > a or asked < -a
        state[FROZEN, i] = 1.0 if frozen else 0.0
        friction = (coulomb if w > 0.0 else (-coulomb if w < 0.0 else 0.0)) + viscous * w
        now = (t - inertia_k * qacc[v] - friction) * qd >= 0.0
        if now != (state[DRIVING, i] != 0.0):
            state[DRIVING, i] = 1.0 if now else 0.0
            state[FACTOR, i] = eta if now else 1.0 / eta
            state[THRUST, i] = state[FACTOR, i] * k
            scale = state[FACTOR, i] / eta
            armature[v] = scale * base[0, i]
            frictionloss[v] = scale * base[1, i]
            damping[v] = scale * base[2, i]
        ctrl[i] = state[THRUST, i] * t
        out[2, j, i], out[3, j, i] = t, a
        out[4, j, i] = 1.0 if frozen else 0.0


def _row(
    row: FloatArray, parts: tuple[FloatArray, ...], xpos: FloatArray, energy: FloatArray, tool: int
) -> None:
    """Copy one step's row of the energy account (``stepping._Record``'s ``parts``)."""
    at = 0
    for p in parts:
        for x in range(p.size):
            row[at + x] = p[x]
        at += p.size
    row[at], row[at + 1], row[at + 2] = xpos[tool, 0], xpos[tool, 1], xpos[tool, 2]
    row[at + 3], row[at + 4] = energy[0], energy[1]


def _loop(
    j: int,
    sub: int,
    stop: int,
    c: int,
    step1: Any,
    step2: Any,
    step: Any,
    m: int,
    d: int,
    qpos: FloatArray,
    qvel: FloatArray,
    qacc: FloatArray,
    ctrl: FloatArray,
    armature: FloatArray,
    frictionloss: FloatArray,
    damping: FloatArray,
    index: NDArray[np.intp],
    refs: FloatArray,
    gains: FloatArray,
    consts: FloatArray,
    base: FloatArray,
    curve: FloatArray,
    state: FloatArray,
    out: FloatArray,
    buffer: FloatArray,
    parts: tuple[FloatArray, ...],
    xpos: FloatArray,
    energy: FloatArray,
    push: FloatArray,
    platform_c: FloatArray,
    wrench: FloatArray,
) -> tuple[int, int, int]:
    """Periods ``j`` to ``stop`` from substep ``sub``; returns early when the block is full."""
    substeps, tool = int(consts[SUBSTEPS]), index[2, 0]
    while j < stop:
        if sub == 0:
            _control(
                j, qpos, qvel, qacc, ctrl, armature, frictionloss, damping, index,
                refs, gains, consts, base, curve, state, out,
            )  # fmt: skip
            step1(m, d)
            if consts[WRENCH] != 0.0:  # the moment about the platform's centre of mass
                rx = xpos[tool, 0] - platform_c[0]
                ry = xpos[tool, 1] - platform_c[1]
                rz = xpos[tool, 2] - platform_c[2]
                fx, fy, fz = wrench[0], wrench[1], wrench[2]
                push[3] = wrench[3] + (ry * fz - rz * fy)
                push[4] = wrench[4] + (rz * fx - rx * fz)
                push[5] = wrench[5] + (rx * fy - ry * fx)
            step2(m, d)
        else:
            step(m, d)
        _row(buffer[c], parts, xpos, energy, tool)
        c += 1
        sub += 1
        if sub == substeps:
            sub = 0
            j += 1
        if c == buffer.shape[0]:
            break
    return j, sub, c


if AVAILABLE:
    _bisect_right = jit(_bisect_right)
    _control = jit(_control)
    _row = jit(_row)
    _loop = jit(_loop)


def run_compiled(
    funcs: tuple[Any, Any, Any],
    model: Any,
    data: Any,
    position: tuple[int, int, int],
    arrays: dict[str, Any],
) -> tuple[int, int, int]:
    """Run periods from ``position`` ``(j, substep, row)`` up to ``arrays["stop"]``.

    Args:
        funcs: :func:`library`'s functions.
        model: MuJoCo's model.
        data: Its data.
        position: The period, the substep within it and the energy account's
            next row.
        arrays: The loop's arrays, as
            :class:`~orthoglide_pin.simulation.stepping.Stepper` makes them.

    Returns:
        The next ``(j, substep, row)``: ``row`` is the block's size when it is full.
    """
    j, sub, c = position
    a = arrays
    out: tuple[int, int, int] = _loop(
        j, sub, int(a["stop"]), c, *funcs, model._address, data._address,
        data.qpos, data.qvel, data.qacc, data.ctrl,
        model.dof_armature, model.dof_frictionloss, model.dof_damping,
        a["index"], a["refs"], a["gains"], a["consts"], a["base"], a["curve"],
        a["state"], a["out"], a["buffer"],
        (data.qfrc_actuator, data.qfrc_constraint, data.qfrc_passive, data.qvel),
        data.xpos, data.energy, a["push"], a["platform_c"], a["wrench"],
    )  # fmt: skip
    return out
