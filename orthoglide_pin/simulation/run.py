"""A planned program run in MuJoCo under servo control: :func:`simulate`.

The machine is the MJCF of the design (:mod:`~orthoglide_pin.simulation.mjcf`)
with the simulated drive; MuJoCo's step is the servo period or a divisor of
it, at most :data:`~orthoglide_pin.simulation.mjcf.TIMESTEP`. The plan
(:func:`~orthoglide_pin.planning.plan.plan_program`) is sampled at every servo
period (:func:`~orthoglide_pin.planning.sampling.sample_plan`): the slider
positions and speeds to follow and, through the closed-loop inverse dynamics
and the controller's drive model, the feedforward torque, taken as the mean
of its values at both ends of the period that holds it. At each period:

1. the encoder reads the slider positions (:class:`~orthoglide_pin.simulation.servo.Encoder`);
2. the controller (:mod:`~orthoglide_pin.simulation.servo`) asks a motor torque,
   which is cut to the torque available at the motor's speed (the peak torque
   and the speed-torque curve: that period counts as saturated);
3. the drive turns it into slider force with the screw's efficiency in the
   direction the power flows (:mod:`~orthoglide_pin.simulation.slider_drive`),
   held over the period.

The run starts at rest at the program's start point (every joint from the
closed-loop model) and records, at each period, the tool point (the ``tool``
body's origin), the sliders, the torques, and the energy account that MuJoCo
keeps: its kinetic and potential energy, the work of the actuators and the
power lost in friction, damping and the loops' compliance. It ends at the
last servo period of the plan.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._lazy import optional_import
from orthoglide_pin._validation import instance_of
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.motion_forms import as_dynamics
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sampling import sample_plan
from orthoglide_pin.simulation.engine import compile_mjcf, joint_order
from orthoglide_pin.simulation.mjcf import EQUALITY_SOLREF, TIMESTEP, mjcf_text
from orthoglide_pin.simulation.servo import Encoder, PositionLoop, ServoSettings, servo_gains
from orthoglide_pin.simulation.slider_drive import (
    drive_terms,
    feedforward_torque,
    plant_terms,
    slider_ratio,
    torque_curve,
)

FloatArray = NDArray[np.float64]
SLIDERS = ("leg1_slider", "leg2_slider", "leg3_slider")


@dataclass(frozen=True)
class SimulationRun:
    """A program run in MuJoCo, sampled at every servo period (``N`` samples).

    Attributes:
        t: Times [s], (N,).
        p: Tool points [m], (N, 3). p_ref: Planned tool points [m], (N, 3).
        q: Slider positions [m], (N, 3). q_ref: Planned ones [m], (N, 3).
        qd: Slider speeds [m/s], (N, 3).
        torque: Motor torques applied over the period that starts there [N.m], (N, 3).
        feedforward: The feedforward part of the torque asked [N.m], (N, 3).
        available: Torque available at the motor's speed [N.m], (N, 3) (``inf``: no limit).
        saturated: Whether the torque asked was cut, (N, 3).
        energy: MuJoCo's kinetic plus potential energy [J], (N,).
        work: Work of the actuators since the start [J], (N,).
        losses: Energy lost since the start (friction, damping, loops) [J], (N,).
        settings: The servo settings. timestep: MuJoCo's step [s].
        drive: The simulated drive.
    """

    t: FloatArray
    p: FloatArray
    p_ref: FloatArray
    q: FloatArray
    q_ref: FloatArray
    qd: FloatArray
    torque: FloatArray
    feedforward: FloatArray
    available: FloatArray
    saturated: NDArray[np.bool_]
    energy: FloatArray
    work: FloatArray
    losses: FloatArray
    settings: ServoSettings
    timestep: float
    drive: Drive

    @property
    def tracking_error(self) -> FloatArray:
        """Slider position errors ``q - q_ref`` [m], (N, 3)."""
        return np.asarray(self.q - self.q_ref)

    @property
    def saturation_time(self) -> FloatArray:
        """Time each motor spent saturated [s], (3,)."""
        return np.asarray(self.saturated.sum(axis=0) * self.settings.period, dtype=float)

    @property
    def any_saturation_time(self) -> float:
        """Time at least one motor spent saturated [s]."""
        return float(self.saturated.any(axis=1).sum() * self.settings.period)


def slider_masses(dyn: ClosedLoopDynamics, q: FloatArray, drive: Drive) -> FloatArray:
    """Mass each slider moves at slider values ``q`` [kg], (3,).

    The diagonal of the closed-loop mass matrix in slider coordinates (from
    the inverse dynamics of unit slider accelerations) plus the rotor's armature.
    """
    qs = np.repeat(np.asarray(q, dtype=float)[None, :], 4, axis=0)
    acc = np.vstack([np.zeros(3), np.eye(3)])
    forces = dyn.inverse_dynamics_sliders(qs, np.zeros_like(qs), acc).forces
    mass = np.diag(forces[1:] - forces[0])
    return np.asarray(mass + float(drive_terms(drive)["armature"] or 0.0))


def integrator_motion(
    q: FloatArray, period: float, substeps: int
) -> tuple[FloatArray, FloatArray]:
    """Accelerations and speeds that MuJoCo's integrator needs to land on ``q`` every period.

    MuJoCo's semi-implicit Euler with ``m`` steps ``h = period / m`` per period
    and an acceleration ``a`` held over it moves a slider by
    ``v T + c a T^2`` with ``c = (m + 1) / (2 m)`` while its speed grows by
    ``a T``. From rest at ``q[0]``, the accelerations ``a_n`` that land it on
    ``q[n + 1]`` and the speeds ``v_n`` it has at each period follow one from
    the other (``c >= 1/2``: the recursion does not grow). They differ from
    the plan's own by ``O(T)``; the plan's are what the exact motion has.

    Args:
        q: Slider positions every period [m], (N, 3), at rest at both ends.
        period: The servo period ``T`` [s].
        substeps: MuJoCo steps per period ``m``.

    Returns:
        ``(a, v)``: accelerations [m/s^2] held over each period and speeds
        [m/s] at each period, each (N, 3) (the last acceleration is zero).
    """
    c = (substeps + 1) / (2.0 * substeps)
    n = q.shape[0]
    v, a = np.zeros_like(q), np.zeros_like(q)
    step = np.diff(q, axis=0)
    if substeps == 1:  # c = 1: the speed is the last step over the period
        v[1:] = step / period
        a[:-1] = np.diff(v, axis=0) / period
        return a, v
    for j in range(n - 1):
        a[j] = (step[j] - v[j] * period) / (c * period * period)
        v[j + 1] = v[j] + a[j] * period
    return a, v


def _reference(plan: Plan, dyn: ClosedLoopDynamics, period: float) -> dict[str, FloatArray]:
    cols = sample_plan(plan, dyn, period)
    n = cols["t"].size
    if n > 1 and not math.isclose(cols["t"][-1] - cols["t"][-2], period, rel_tol=1e-9):
        n -= 1  # the plan's end between two periods: the run ends at the last period
    return {k: v[:n] for k, v in cols.items()}


def simulate(
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None = None,
    drive: Drive | None = None,
    settings: ServoSettings | None = None,
) -> SimulationRun:
    """Run a plan in MuJoCo under servo control (see the module).

    Args:
        plan: The plan (:func:`~orthoglide_pin.planning.plan.plan_program`) of
            this machine, without a tool wrench or a calibration.
        machine: The inverse dynamics or the parameters of the machine the plan
            was made for; the prototype when ``None``.
        drive: The simulated drive, whose motor data limit the torque; the
            plan's drive when ``None``. The controller believes in this drive,
            with the settings' model errors.
        settings: The servo settings; the defaults (``pid_ff`` at 4 kHz) when ``None``.

    Returns:
        The run.

    Raises:
        InvalidParameterError: Wrong arguments, or a plan with a wrench or a calibration.
        MissingExtraError: MuJoCo is not installed (``[sim]``).
    """
    plan = instance_of("plan", plan, Plan, "a Plan (plan_program)")
    dyn = as_dynamics(machine)
    if drive is None:
        drive = plan.limits.drive if plan.limits.drive is not None else Drive()
    drive = instance_of("drive", drive, Drive, "a Drive (load_drive)")
    settings = instance_of(
        "settings",
        ServoSettings() if settings is None else settings,
        ServoSettings,
        "ServoSettings",
    )
    if plan.wrench is not None or plan.calibration is not None:
        raise InvalidParameterError(
            "plan", "with a wrench or a calibration", "a plan without a tool wrench or calibration"
        )
    mujoco = optional_import("mujoco", "sim", "the simulation")
    model = compile_mjcf(mjcf_text(dyn.closed_loop.params, drive, gravity=plan.gravity))
    model.actuator_ctrllimited[:] = 0  # the motor's curve limits the torque, below
    model.actuator_forcelimited[:] = 0
    period = settings.period
    substeps = max(1, math.ceil(period / TIMESTEP - 1e-9))
    model.opt.timestep = period / substeps
    model.eq_solref[:, 0] = EQUALITY_SOLREF[0] * model.opt.timestep / TIMESTEP  # twice the step
    model.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    data = mujoco.MjData(model)
    ref = _reference(plan, dyn, period)
    q_ref = np.column_stack([ref[f"q{i}"] for i in (1, 2, 3)])
    acc, qd_ref = integrator_motion(q_ref, period, substeps)
    ff = np.zeros_like(q_ref)
    if settings.torque_feedforward:
        force = dyn.inverse_dynamics_sliders(
            q_ref, np.column_stack([ref[f"qd{i}"] for i in (1, 2, 3)]), acc, gravity=plan.gravity
        ).forces
        ff = feedforward_torque(
            drive,
            force,
            qd_ref,
            acc,
            mass_scale=1.0 + settings.mass_error,
            friction_scale=1.0 + settings.friction_error,
        )
    start = plan.path.program.start
    state = dyn.inverse_dynamics(start, np.zeros(3), np.zeros(3))
    order = joint_order(model, dyn.closed_loop.model)
    data.qpos[:] = state.q[0][order]
    data.qvel[:] = 0.0
    return _run(mujoco, model, data, dyn, drive, settings, substeps, ref, q_ref, qd_ref, ff)


def _run(
    mujoco: Any,
    model: Any,
    data: Any,
    dyn: ClosedLoopDynamics,
    drive: Drive,
    settings: ServoSettings,
    substeps: int,
    ref: dict[str, FloatArray],
    q_ref: FloatArray,
    qd_ref: FloatArray,
    ff: FloatArray,
) -> SimulationRun:
    """The stepping loop (see the module)."""
    n = q_ref.shape[0]
    dofs = np.array([model.joint(name).dofadr[0] for name in SLIDERS], dtype=np.intp)
    qadr = np.array([model.joint(name).qposadr[0] for name in SLIDERS], dtype=np.intp)
    tool = model.body("tool").id
    k = slider_ratio(drive.train)
    to_torque = 1.0 / (k * drive.train.efficiency)
    q0 = np.array(data.qpos[qadr])
    gains = servo_gains(settings, slider_masses(dyn, q0, drive))
    period = settings.period
    loops = [
        PositionLoop(float(gains.kp[i]), float(gains.kd[i]), float(gains.ki[i]), period)
        for i in range(3)
    ]
    counts = settings.encoder_counts
    resolution = None if counts is None else 2.0 * math.pi / (k * counts)
    encoders = [Encoder(resolution, period, float(q0[i])) for i in range(3)]
    if counts is not None:  # the speed read is a difference of counts: so is its reference
        qd_ref = np.vstack([np.zeros((1, 3)), np.diff(q_ref, axis=0) / period])
    out = {name: np.zeros((n, 3)) for name in ("p", "q", "qd", "torque", "available")}
    saturated = np.zeros((n, 3), dtype=bool)
    energy, work, losses = np.zeros(n), np.zeros(n), np.zeros(n)
    speeds, torques, peak = torque_curve(drive)
    train = drive.train
    inertia_k, coulomb = train.reflected_inertia * k, train.coulomb_torque
    viscous = train.viscous_coefficient
    base = plant_terms(drive, np.ones(3, dtype=bool))
    eta = train.efficiency
    frozen, driving, factor = [False] * 3, [True] * 3, [eta] * 3
    w_total = l_total = 0.0
    step = float(model.opt.timestep)
    qpos, qvel, qacc, ctrl = data.qpos, data.qvel, data.qacc, data.ctrl
    xpos, mj_energy = data.xpos, data.energy  # views: MuJoCo's buffers do not move
    f_act, f_con, f_pas = data.qfrc_actuator, data.qfrc_constraint, data.qfrc_passive
    armature, frictionloss, damping = model.dof_armature, model.dof_frictionloss, model.dof_damping
    curve_w, curve_t = speeds.tolist(), torques.tolist()
    armature[dofs], frictionloss[dofs], damping[dofs] = base  # every motor drives at rest

    def available(w: float) -> float:  # numpy.interp(w, speeds, torques, right=0), min peak
        i = bisect.bisect_right(curve_w, w)
        if i >= len(curve_w):
            top = curve_t[-1] if w == curve_w[-1] else 0.0
        else:
            w0, w1, t0, t1 = curve_w[i - 1], curve_w[i], curve_t[i - 1], curve_t[i]
            top = t0 if math.isinf(w1) else t0 + (t1 - t0) * (w - w0) / (w1 - w0)
        return min(top, peak)

    slider_q, slider_v = [int(i) for i in qadr], [int(i) for i in dofs]
    q_ref_l, qd_ref_l, ff_l = q_ref.tolist(), qd_ref.tolist(), ff.tolist()
    for j in range(n):
        torque, avail = [0.0] * 3, [0.0] * 3
        for i in range(3):
            q, qd = float(qpos[slider_q[i]]), float(qvel[slider_v[i]])
            read_q, read_qd = encoders[i].read(q, qd)
            asked = ff_l[j][i] + to_torque * loops[i].force(
                q_ref_l[j][i] - read_q, qd_ref_l[j][i] - read_qd, frozen[i]
            )
            w = k * qd
            a = available(abs(w))
            t = min(max(asked, -a), a)
            frozen[i] = abs(asked) > a
            friction = coulomb * math.copysign(1.0, w) * (w != 0.0) + viscous * w
            into_screw = t - inertia_k * float(qacc[slider_v[i]]) - friction
            now = into_screw * qd >= 0.0
            if now != driving[i]:  # the power changed direction: eta^s changes
                driving[i] = now
                factor[i] = eta if now else 1.0 / eta
                scale = factor[i] / eta
                armature[slider_v[i]] = scale * base[0][i]
                frictionloss[slider_v[i]] = scale * base[1][i]
                damping[slider_v[i]] = scale * base[2][i]
            ctrl[i] = factor[i] * k * t
            torque[i], avail[i] = t, a
            out["q"][j, i], out["qd"][j, i] = q, qd
        mujoco.mj_step1(model, data)
        out["p"][j] = xpos[tool]
        out["torque"][j], out["available"][j] = torque, avail
        saturated[j] = frozen
        energy[j] = mj_energy[0] + mj_energy[1]
        work[j], losses[j] = w_total, l_total
        for sub in range(substeps):
            v0 = qvel.copy()
            if sub == 0:
                mujoco.mj_step2(model, data)
            else:
                mujoco.mj_step(model, data)
            mid = (0.5 * step) * (v0 + qvel)  # the displacement at the mean speed
            w_total += float(np.dot(f_act, mid))
            l_total -= float(np.dot(f_con, mid) + np.dot(f_pas, mid))
    return SimulationRun(
        t=ref["t"],
        p=out["p"],
        p_ref=np.column_stack([ref["x"], ref["y"], ref["z"]]),
        q=out["q"],
        q_ref=q_ref,
        qd=out["qd"],
        torque=out["torque"],
        feedforward=ff,
        available=out["available"],
        saturated=saturated,
        energy=energy,
        work=work,
        losses=losses,
        settings=settings,
        timestep=float(model.opt.timestep),
        drive=drive,
    )
