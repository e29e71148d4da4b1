"""The stepping loop of a simulation: servo periods, the drive and MuJoCo's steps.

:func:`~orthoglide_pin.simulation.run.simulate` prepares everything that does
not depend on the simulated state as arrays, in batch (:class:`LoopInputs`:
the references, the feedforward torques, the gains, the speed-torque curve's
segments); :func:`run_loop` then does, at every servo period, only what
depends on MuJoCo's state, with plain floats: per slider, the encoder
(:class:`~orthoglide_pin.simulation.servo.Encoder`), the position loop
(:class:`~orthoglide_pin.simulation.servo.PositionLoop`), the torque cut by the
speed-torque curve (:func:`~orthoglide_pin.simulation.slider_drive.available_torque`),
the screw's efficiency in the direction the power flows (the joint's armature,
friction loss and damping rewritten only when it changes), and the actuator's
control; then the tool wrench's moment moved to the platform's centre of mass;
then MuJoCo's steps. The energy account (the actuators' work and the losses at
the mean speed of every step) is reduced in batch from the generalised forces
and speeds recorded at every step, by blocks of :data:`BLOCK` steps. With
numba, the periods run in one compiled loop that calls MuJoCo's steps itself
(:mod:`~orthoglide_pin.simulation.stepping_compiled`: the same arithmetic in
the same order, the same values to the last digit).
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.simulation import stepping_compiled as sc

FloatArray = NDArray[np.float64]

#: MuJoCo steps whose forces and speeds are kept before the energy account reduces them.
BLOCK: Final[int] = 4096
#: Whether the loop runs compiled when it can
#: (:mod:`~orthoglide_pin.simulation.stepping_compiled`: numba and MuJoCo's C library).
COMPILED: bool = True


@dataclass(frozen=True)
class LoopInputs:
    """What the loop needs, computed before it (``N`` servo periods).

    Attributes:
        q_ref: Slider positions to follow [m], (N, 3).
        qd_ref: Slider speeds to follow [m/s], (N, 3).
        feedforward: Feedforward motor torques [N.m], (N, 3).
        kp: Position gains [N/m], (3,). kd: Speed gains [N.s/m], (3,).
        ki: Integral gains [N/(m.s)], (3,).
        period: Servo period [s]. substeps: MuJoCo steps per period.
        resolution: Encoder's slider travel per count [m], or ``None`` (exact).
        ratio: Motor radians per metre of slider ``k`` [rad/m].
        efficiency: The screw's efficiency ``eta`` [-].
        reflected_inertia: Rotor and screw inertia ``J`` [kg.m^2].
        coulomb: Motor's Coulomb friction torque [N.m]. viscous: Its viscous
            coefficient [N.m.s/rad].
        base: The slider joints' armature [kg], friction loss [N] and damping
            [N.s/m] while the motor drives, each (3,).
        speeds: The speed-torque curve's speeds [rad/s]. torques: Its torques
            [N.m]. peak: The peak torque [N.m] (``inf``: none).
        wrench: The tool wrench (force [N], moment [N.m] at the tool point, world
            axes), (6,), or ``None``.
    """

    q_ref: FloatArray
    qd_ref: FloatArray
    feedforward: FloatArray
    kp: FloatArray
    kd: FloatArray
    ki: FloatArray
    period: float
    substeps: int
    resolution: float | None
    ratio: float
    efficiency: float
    reflected_inertia: float
    coulomb: float
    viscous: float
    base: tuple[FloatArray, FloatArray, FloatArray]
    speeds: FloatArray
    torques: FloatArray
    peak: float
    wrench: FloatArray | None


def _segments(speeds: FloatArray, torques: FloatArray) -> tuple[list[float], ...]:
    """The curve by ``bisect_right`` index: start speed, start torque, rises of torque and speed.

    Index 0 (below the first speed) and the segments that end at an infinite
    speed are flat (rise 0 over 1): the torque is the start torque exactly.
    """
    w, t = speeds.tolist(), torques.tolist()
    w0, t0, dt, dw = [0.0], [t[0]], [0.0], [1.0]
    for i in range(1, len(w)):
        flat = math.isinf(w[i])
        w0.append(w[i - 1])
        t0.append(t[i - 1])
        dt.append(0.0 if flat else t[i] - t[i - 1])
        dw.append(1.0 if flat else w[i] - w[i - 1])
    return w, w0, t0, dt, dw


def run_loop(
    mujoco: Any,
    model: Any,
    data: Any,
    inputs: LoopInputs,
    progress: Callable[[int, int], None] | None = None,
) -> dict[str, FloatArray]:
    """Run the ``N`` servo periods of ``inputs`` from MuJoCo's present state (see the module).

    Args:
        mujoco: The ``mujoco`` module.
        model: MuJoCo's model (its slider joints' armature, friction loss and
            damping are rewritten as the power changes direction).
        data: MuJoCo's data, at the start state.
        inputs: The loop's inputs.
        progress: Called with (periods run, ``N``) about every 1 % of the run, or ``None``.

    Returns:
        :meth:`Stepper.run`'s columns for the ``N`` periods.
    """
    stepper = Stepper(mujoco, model, data, inputs, progress, inputs.q_ref.shape[0])
    return stepper.run(inputs.q_ref, inputs.qd_ref, inputs.feedforward)


class Stepper:
    """The servo loop run a chunk of periods at a time, its state kept between chunks.

    Args:
        mujoco: The ``mujoco`` module.
        model: MuJoCo's model (its slider joints' armature, friction loss and
            damping are rewritten as the power changes direction).
        data: MuJoCo's data, at the start state.
        inputs: The loop's inputs; only those that do not vary with the period are read
            (the references and the feedforward come with each chunk).
        progress: Called with (periods run, ``total``) about every 1 % of the run, or ``None``.
        total: The periods of the whole run (for ``progress``).
    """

    def __init__(
        self,
        mujoco: Any,
        model: Any,
        data: Any,
        inputs: LoopInputs,
        progress: Callable[[int, int], None] | None = None,
        total: int = 0,
    ) -> None:
        names = ("leg1_slider", "leg2_slider", "leg3_slider")
        self.mujoco, self.model, self.data, self.inputs = mujoco, model, data, inputs
        self.slider_q = [int(model.joint(name).qposadr[0]) for name in names]
        self.slider_v = [int(model.joint(name).dofadr[0]) for name in names]
        self.tool, self.platform = model.body("tool").id, model.body("platform").id
        res = inputs.resolution
        self.last = (
            [0.0] * 3 if res is None else [round(data.qpos[a] / res) * res for a in self.slider_q]
        )
        eta = inputs.efficiency
        self.integral, self.frozen, self.driving = [0.0] * 3, [False] * 3, [True] * 3
        self.factor = [eta] * 3
        self.thrust = [f * inputs.ratio for f in self.factor]  # eta^s k: force per torque
        self.base = [b.tolist() for b in inputs.base]
        self.curve = _segments(inputs.speeds, inputs.torques)
        armature, frictionloss = model.dof_armature, model.dof_frictionloss
        for i in range(3):  # every motor drives at rest
            v = self.slider_v[i]
            armature[v], frictionloss[v] = self.base[0][i], self.base[1][i]
            model.dof_damping[v] = self.base[2][i]
        if inputs.wrench is not None:
            data.xfrc_applied[self.platform][:3] = inputs.wrench[:3]
        self.record = _Record(model, data, inputs.substeps, self.tool)
        self.progress, self.total, self.done = progress, int(total), 0
        self.funcs = sc.library(mujoco) if COMPILED else None

    def run(
        self, q_ref: FloatArray, qd_ref: FloatArray, feedforward: FloatArray
    ) -> dict[str, FloatArray]:
        """Run the next ``n`` periods, whose references and feedforward are given, each (n, 3).

        Returns:
            ``p`` (n, 3) tool points [m]; ``q``, ``qd`` (n, 3) slider positions and
            speeds; ``torque``, ``available`` (n, 3) [N.m]; ``saturated`` (n, 3) as
            0/1; ``energy``, ``work``, ``losses`` (n,) [J] (since the run's start), as
            :class:`~orthoglide_pin.simulation.run.SimulationRun` has them.
        """
        if self.funcs is not None:
            return self._run_compiled(q_ref, qd_ref, feedforward)
        mujoco, model, data, inputs = self.mujoco, self.model, self.data, self.inputs
        n, substeps, period = q_ref.shape[0], inputs.substeps, inputs.period
        slider_q, slider_v = self.slider_q, self.slider_v
        k, eta = inputs.ratio, inputs.efficiency
        to_torque = 1.0 / (k * eta)
        kp, kd, ki = inputs.kp.tolist(), inputs.kd.tolist(), inputs.ki.tolist()
        res = inputs.resolution
        last, integral, frozen = self.last, self.integral, self.frozen
        driving, factor, thrust = self.driving, self.factor, self.thrust
        inertia_k, coulomb, viscous = inputs.reflected_inertia * k, inputs.coulomb, inputs.viscous
        base = self.base
        curve_w, seg_w, seg_t, seg_dt, seg_dw = self.curve
        top_i, last_w = len(curve_w), curve_w[-1]
        last_t, peak = float(inputs.torques[-1]), inputs.peak
        qpos, qvel, qacc, ctrl = data.qpos, data.qvel, data.qacc, data.ctrl
        tool_x, platform_c = data.xpos[self.tool], data.xipos[self.platform]
        armature, frictionloss = model.dof_armature, model.dof_frictionloss
        damping = model.dof_damping
        push = data.xfrc_applied[self.platform]
        fx = fy = fz = mx = my = mz = 0.0
        if inputs.wrench is not None:
            fx, fy, fz, mx, my, mz = inputs.wrench.tolist()
        size = 3 * n
        out_t, out_a, out_s = [0.0] * size, [0.0] * size, [False] * size
        out_q, out_qd = [0.0] * size, [0.0] * size
        record = self.record
        rows, parts, block, c = record.rows, record.parts, len(record.rows), 0
        cat = np.concatenate
        # flat lists of floats: no object per period for the garbage collector to walk
        q_ref_l, qd_ref_l = q_ref.ravel().tolist(), qd_ref.ravel().tolist()
        ff_l = feedforward.ravel().tolist()
        step1, step2, step = mujoco.mj_step1, mujoco.mj_step2, mujoco.mj_step
        progress, done, total = self.progress, self.done, self.total
        tell = max(1, total // 100) if progress is not None else total + n + 1
        for j in range(n):
            if (done + j) % tell == 0 and progress is not None:
                progress(done + j, total)
            o = 3 * j
            for i in range(3):
                q, qd = qpos.item(slider_q[i]), qvel.item(slider_v[i])
                out_q[o + i], out_qd[o + i] = q, qd
                if res is None:
                    read_q, read_qd = q, qd
                else:
                    read_q = round(q / res) * res
                    read_qd = (read_q - last[i]) / period
                    last[i] = read_q
                error = q_ref_l[o + i] - read_q
                if not frozen[i]:  # anti-windup: no integral after a saturated period
                    integral[i] += error * period
                force = kp[i] * error + kd[i] * (qd_ref_l[o + i] - read_qd) + ki[i] * integral[i]
                asked = ff_l[o + i] + to_torque * force
                w = k * qd
                s = w if w >= 0.0 else -w
                g = bisect.bisect_right(curve_w, s)
                if g < top_i:
                    top = seg_t[g] + seg_dt[g] * (s - seg_w[g]) / seg_dw[g]
                else:  # beyond the curve: no torque (its last point included)
                    top = last_t if s == last_w else 0.0
                a = top if top < peak else peak
                t = a if asked > a else (-a if asked < -a else asked)
                frozen[i] = asked > a or asked < -a
                friction = (coulomb if w > 0.0 else (-coulomb if w < 0.0 else 0.0)) + viscous * w
                now = (t - inertia_k * qacc.item(slider_v[i]) - friction) * qd >= 0.0
                if now != driving[i]:  # the power changed direction: eta^s changes
                    driving[i] = now
                    factor[i] = eta if now else 1.0 / eta
                    thrust[i] = factor[i] * k
                    scale, v = factor[i] / eta, slider_v[i]
                    armature[v] = scale * base[0][i]
                    frictionloss[v] = scale * base[1][i]
                    damping[v] = scale * base[2][i]
                ctrl[i] = thrust[i] * t
                out_t[o + i], out_a[o + i], out_s[o + i] = t, a, frozen[i]
            step1(model, data)
            if inputs.wrench is not None:  # the moment about the platform's centre of mass
                x = tool_x.tolist()
                rx, ry, rz = (
                    x[0] - platform_c.item(0),
                    x[1] - platform_c.item(1),
                    x[2] - platform_c.item(2),
                )
                push[3] = mx + (ry * fz - rz * fy)
                push[4] = my + (rz * fx - rx * fz)
                push[5] = mz + (rx * fy - ry * fx)
            step2(model, data)
            cat(parts, out=rows[c])
            c += 1
            if c == block:
                c = record.reduce(c)
            for _ in range(substeps - 1):
                step(model, data)
                cat(parts, out=rows[c])
                c += 1
                if c == block:
                    c = record.reduce(c)
        record.reduce(c)
        self.done = done + n
        if progress is not None and self.done >= total:
            progress(self.done, total)
        shape = (n, 3)
        return {
            **record.take(n),
            "q": np.array(out_q).reshape(shape),
            "qd": np.array(out_qd).reshape(shape),
            "torque": np.array(out_t).reshape(shape),
            "available": np.array(out_a).reshape(shape),
            "saturated": np.array(out_s, dtype=float).reshape(shape),
        }

    def _run_compiled(
        self, q_ref: FloatArray, qd_ref: FloatArray, feedforward: FloatArray
    ) -> dict[str, FloatArray]:
        """:meth:`run` by the compiled loop (:func:`~.stepping_compiled.run_compiled`)."""
        assert self.funcs is not None
        inputs, record, data = self.inputs, self.record, self.data
        n, k, eta = q_ref.shape[0], inputs.ratio, inputs.efficiency
        res = inputs.resolution
        curve_w = self.curve[0]
        consts = [0.0] * 13
        consts[sc.PERIOD], consts[sc.RESOLUTION] = inputs.period, math.nan if res is None else res
        consts[sc.RATIO], consts[sc.EFFICIENCY], consts[sc.TO_TORQUE] = k, eta, 1.0 / (k * eta)
        consts[sc.INERTIA_K] = inputs.reflected_inertia * k
        consts[sc.COULOMB], consts[sc.VISCOUS] = inputs.coulomb, inputs.viscous
        consts[sc.LAST_T], consts[sc.PEAK] = float(inputs.torques[-1]), inputs.peak
        consts[sc.LAST_W], consts[sc.SUBSTEPS] = curve_w[-1], float(inputs.substeps)
        consts[sc.WRENCH] = 0.0 if inputs.wrench is None else 1.0
        lists = (self.last, self.integral, self.frozen, self.driving, self.factor, self.thrust)
        state = np.array(lists, dtype=float)
        out = np.zeros((5, n, 3))
        arrays: dict[str, Any] = {
            "index": np.array(
                [self.slider_q, self.slider_v, [self.tool, self.platform, 0]], dtype=np.intp
            ),
            "refs": np.ascontiguousarray(np.stack([q_ref, qd_ref, feedforward]), dtype=float),
            "gains": np.array([inputs.kp, inputs.kd, inputs.ki], dtype=float),
            "consts": np.array(consts),
            "base": np.array(self.base, dtype=float),
            "curve": np.array(self.curve, dtype=float),
            "state": state,
            "out": out,
            "buffer": record.buffer,
            "push": data.xfrc_applied[self.platform],
            "platform_c": data.xipos[self.platform],
            "wrench": np.zeros(6) if inputs.wrench is None else np.asarray(inputs.wrench, float),
        }
        progress, done, total = self.progress, self.done, self.total
        tell = max(1, total // 100) if progress is not None else total + n + 1
        j = sub = c = 0
        while j < n:
            if sub == 0 and (done + j) % tell == 0 and progress is not None:
                progress(done + j, total)
            arrays["stop"] = min(n, j + tell - (done + j) % tell)
            j, sub, c = sc.run_compiled(self.funcs, self.model, data, (j, sub, c), arrays)
            if c == BLOCK:
                c = record.reduce(c)
        record.reduce(c)
        self.last[:], self.integral[:] = state[0].tolist(), state[1].tolist()
        self.frozen[:] = [bool(x) for x in state[2]]
        self.driving[:] = [bool(x) for x in state[3]]
        self.factor[:], self.thrust[:] = state[4].tolist(), state[5].tolist()
        self.done = done + n
        if progress is not None and self.done >= total:
            progress(self.done, total)
        return {
            **record.take(n),
            "q": out[0],
            "qd": out[1],
            "torque": out[2],
            "available": out[3],
            "saturated": out[4],
        }


class _Record:
    """What MuJoCo's steps leave, one row a step, reduced by blocks of at most :data:`BLOCK` rows.

    A row holds, after the step: the actuator, constraint and passive
    generalised forces (those of the step's start state), the speeds reached,
    and the tool point and the energy of the start state. Over a step ``h``
    the displacement is taken at the mean speed, ``(h / 2) (v_before + v_after)``:
    the work is the actuator forces' power over it, the losses minus the
    constraint and passive forces' (friction, damping, the loops' compliance).
    A period's tool point and energy are those of its first step; its work and
    losses, the sums over the steps before it.
    """

    def __init__(self, model: Any, data: Any, substeps: int, tool: int) -> None:
        nv = model.nv
        self.parts = (
            data.qfrc_actuator,
            data.qfrc_constraint,
            data.qfrc_passive,
            data.qvel,
            data.xpos[tool],
            data.energy,
        )
        self.buffer = np.zeros((BLOCK, 4 * nv + 5))
        self.rows = list(self.buffer)  # views, made once
        self.h, self.m, self.nv, self.steps = float(model.opt.timestep), substeps, nv, 0
        self.col_p = 4 * nv
        self.v = np.array(data.qvel)
        self.totals = [0.0, 0.0]  # work and losses before the next step
        self.chunks: dict[str, list[FloatArray]] = {k: [] for k in ("dw", "dl", "p", "energy")}

    def reduce(self, count: int) -> int:
        """Reduce the first ``count`` rows; returns the next row to fill (0)."""
        if count == 0:
            return 0
        nv, rows = self.nv, self.buffer[:count]
        after = rows[:, 3 * nv : 4 * nv]
        before = np.vstack([self.v[None, :], after[:-1]])
        mid = (0.5 * self.h) * (before + after)
        out = self.chunks
        out["dw"].append(np.einsum("ij,ij->i", rows[:, :nv], mid))
        out["dl"].append(
            -np.einsum("ij,ij->i", rows[:, nv : 2 * nv] + rows[:, 2 * nv : 3 * nv], mid)
        )
        first = rows[(self.steps + np.arange(count)) % self.m == 0]
        out["p"].append(first[:, self.col_p : self.col_p + 3])
        out["energy"].append(first[:, self.col_p + 3] + first[:, self.col_p + 4])
        self.v = after[-1].copy()
        self.steps += count
        return 0

    def take(self, n: int) -> dict[str, FloatArray]:
        """The ``n`` periods reduced since the last call.

        Returns:
            ``p`` (n, 3), ``energy``, ``work``, ``losses`` (n,), as :meth:`Stepper.run`.
        """
        out = {k: np.concatenate(v) if v else np.zeros(0) for k, v in self.chunks.items()}
        for v in self.chunks.values():
            v.clear()
        sums = []
        for i, key in enumerate(("dw", "dl")):  # one running sum, in the steps' order
            total = np.concatenate([[self.totals[i]], out[key]]).cumsum()
            sums.append(np.asarray(total[: -1 : self.m][:n]))
            self.totals[i] = float(total[-1])
        return {
            "p": out["p"].reshape(-1, 3)[:n],
            "energy": out["energy"][:n],
            "work": sums[0],
            "losses": sums[1],
        }
