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

A tool wrench of the plan is a constant load: the plan's inverse dynamics and
the feedforward balance it, and MuJoCo applies it to the platform
(``xfrc_applied``, at the platform's centre of mass in world axes, its moment
moved there from the tool point at every period).

The run starts at rest at the program's start point (every joint from the
closed-loop model) and records, at each period, the tool point (the ``tool``
body's origin), the sliders, the torques, and the energy account that MuJoCo
keeps: its kinetic and potential energy, the work of the actuators and the
power lost in friction, damping and the loops' compliance. It ends at the
last servo period of the plan.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._lazy import optional_import
from orthoglide_pin._validation import instance_of, optional_callable, positive_number
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.motion_forms import as_dynamics
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.digest import check_design
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.simulation.engine import compile_mjcf, joint_order
from orthoglide_pin.simulation.mjcf import EQUALITY_SOLREF, TIMESTEP, mjcf_text
from orthoglide_pin.simulation.reference import (
    ReferenceChunk,
    reference_chunks,
    run_periods,
)
from orthoglide_pin.simulation.reference import integrator_motion as integrator_motion
from orthoglide_pin.simulation.servo import ServoSettings, servo_gains
from orthoglide_pin.simulation.slider_drive import (
    drive_terms,
    plant_terms,
    slider_ratio,
    torque_curve,
)
from orthoglide_pin.simulation.stepping import LoopInputs, Stepper

FloatArray = NDArray[np.float64]

#: Servo periods sampled, stepped and handed on at once by :func:`simulate_chunks` [-].
CHUNK_PERIODS: Final[int] = 16_384


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


def simulate(
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None = None,
    drive: Drive | None = None,
    settings: ServoSettings | None = None,
    *,
    progress: Callable[[int, int], None] | None = None,
) -> SimulationRun:
    """Run a plan in MuJoCo under servo control (see the module), the whole run in memory.

    :func:`simulate_chunks` gives the same run a chunk at a time, in bounded memory.

    Args:
        plan: The plan (:func:`~orthoglide_pin.planning.plan.plan_program`) of
            this machine, without a calibration. Its tool wrench, if any, acts
            on the simulated tool, and the feedforward includes it.
        machine: The inverse dynamics or the parameters of the machine the plan
            was made for; the prototype when ``None``.
        drive: The simulated drive, whose motor data limit the torque; the
            plan's drive when ``None``. The controller believes in this drive,
            with the settings' model errors.
        settings: The servo settings; the defaults (``pid_ff`` at 4 kHz) when ``None``.
        progress: Called with (periods simulated, periods) as the run goes, or ``None``.

    Returns:
        The run.

    Raises:
        InvalidParameterError: Wrong arguments, a plan with a calibration, or a
            servo rate that cannot sample the plan (fewer than
            :data:`~orthoglide_pin.simulation.servo.MIN_PERIODS_PER_BLOCK` periods
            per block that takes time) or would make more than
            :data:`~orthoglide_pin.simulation.servo.MAX_PERIODS` periods.
        DesignMismatchError: The plan was made for another design.
        MissingExtraError: MuJoCo is not installed (``[sim]``).
    """
    parts = list(simulate_chunks(plan, machine, drive, settings, progress=progress, bounded=False))
    first = parts[0]
    fields: dict[str, Any] = {
        f.name: np.concatenate([getattr(p, f.name) for p in parts])
        for f in dataclasses.fields(SimulationRun)
        if f.name not in ("settings", "timestep", "drive")
    }
    return dataclasses.replace(first, **fields)


def simulate_chunks(
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None = None,
    drive: Drive | None = None,
    settings: ServoSettings | None = None,
    *,
    progress: Callable[[int, int], None] | None = None,
    chunk: int = CHUNK_PERIODS,
    bounded: bool = True,
) -> Iterator[SimulationRun]:
    """:func:`simulate`'s run, ``chunk`` consecutive periods at a time (the same values).

    The memory it needs grows with ``chunk``, not with the program: the plan is
    sampled, the feedforward computed and MuJoCo stepped one chunk at a time.
    Each chunk's ``work`` and ``losses`` count from the run's start.

    Args:
        plan: As :func:`simulate`.
        machine: As :func:`simulate`.
        drive: As :func:`simulate`.
        settings: As :func:`simulate`.
        progress: As :func:`simulate`.
        chunk: Periods per chunk (>= 1).
        bounded: Whether the run is streamed (no limit on its periods); with
            ``False``, at most :data:`~orthoglide_pin.simulation.servo.MAX_PERIODS`
            periods (the run held in memory).

    Raises:
        As :func:`simulate` (before the first chunk).
    """
    progress = optional_callable("progress", progress, "a function of (done, total), or None")
    chunk = int(positive_number("chunk", chunk, "a number of periods >= 1"))
    start = _start(plan, machine, drive, settings, capped=not bounded)
    return _chunks(start, progress, chunk)


def _chunks(
    start: _Start, progress: Callable[[int, int], None] | None, chunk: int
) -> Iterator[SimulationRun]:
    stepper = Stepper(
        start.mujoco, start.model, start.data, start.constants, progress, start.periods
    )
    timestep = float(start.model.opt.timestep)
    for ref in start.references(chunk):
        out = stepper.run(ref.q_ref, ref.qd_ref, ref.feedforward)
        cols = ref.columns
        yield SimulationRun(
            t=cols["t"],
            p=out["p"],
            p_ref=np.column_stack([cols["x"], cols["y"], cols["z"]]),
            q=out["q"],
            q_ref=ref.q_ref,
            qd=out["qd"],
            torque=out["torque"],
            feedforward=ref.feedforward,
            available=out["available"],
            saturated=out["saturated"] > 0.5,
            energy=out["energy"],
            work=out["work"],
            losses=out["losses"],
            settings=start.settings,
            timestep=timestep,
            drive=start.drive,
        )


@dataclass(frozen=True)
class Prepared:
    """A simulation ready to step: MuJoCo's model and data at the start, and the loop's inputs.

    Attributes:
        mujoco: The ``mujoco`` module. model: Its model. data: Its data, at the start state.
        inputs: The loop's inputs. reference: The plan sampled every servo period
            (:func:`~orthoglide_pin.planning.sampling.sample_plan`'s columns).
        settings: The servo settings. drive: The simulated drive.
    """

    mujoco: Any
    model: Any
    data: Any
    inputs: LoopInputs
    reference: dict[str, FloatArray]
    settings: ServoSettings
    drive: Drive


@dataclass(frozen=True)
class _Start:
    """MuJoCo at the start state, the loop's constant inputs, and how to sample the references."""

    mujoco: Any
    model: Any
    data: Any
    constants: LoopInputs
    settings: ServoSettings
    drive: Drive
    plan: Plan
    dyn: ClosedLoopDynamics
    periods: int

    def references(self, chunk: int) -> Iterator[ReferenceChunk]:
        """The references, ``chunk`` periods at a time (:func:`reference_chunks`)."""
        return reference_chunks(
            self.plan, self.dyn, self.drive, self.settings, self.constants.substeps, chunk
        )


def prepare(
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None = None,
    drive: Drive | None = None,
    settings: ServoSettings | None = None,
) -> Prepared:
    """Everything :func:`simulate` computes before its loop, in batch (same arguments)."""
    start = _start(plan, machine, drive, settings, capped=True)
    parts = list(start.references(max(start.periods, 1)))
    ref = {k: np.concatenate([p.columns[k] for p in parts]) for k in parts[0].columns}
    inputs = dataclasses.replace(
        start.constants,
        q_ref=np.concatenate([p.q_ref for p in parts]),
        qd_ref=np.concatenate([p.qd_ref for p in parts]),
        feedforward=np.concatenate([p.feedforward for p in parts]),
    )
    return Prepared(
        start.mujoco, start.model, start.data, inputs, ref, start.settings, start.drive
    )


def _start(
    plan: Plan,
    machine: ClosedLoopDynamics | OrthoglideParams | None,
    drive: Drive | None,
    settings: ServoSettings | None,
    *,
    capped: bool,
) -> _Start:
    """Check the arguments, build MuJoCo's model at the start state and the loop's constants."""
    plan = instance_of("plan", plan, Plan, "a Plan (plan_program)")
    dyn = as_dynamics(machine)
    if plan.design is not None:  # the plan of this machine
        check_design(plan.design, dyn.closed_loop.params, "the plan", redo="plan it again")
    if drive is None:
        drive = plan.limits.drive if plan.limits.drive is not None else Drive()
    drive = instance_of("drive", drive, Drive, "a Drive (load_drive)")
    settings = instance_of(
        "settings",
        ServoSettings() if settings is None else settings,
        ServoSettings,
        "ServoSettings",
    )
    if plan.calibration is not None:
        raise InvalidParameterError("plan", "with a calibration", "a plan without calibration")
    timed = sum(1 for block in plan.blocks if block.end > block.start)
    settings.check_sampling(plan.cycle_time, timed, capped=capped)  # before anything is built
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
    start = plan.path.program.start
    state = dyn.inverse_dynamics(start, np.zeros(3), np.zeros(3))
    order = joint_order(model, dyn.closed_loop.model)
    data.qpos[:] = state.q[0][order]
    data.qvel[:] = 0.0
    q0 = np.array([data.qpos[model.joint(f"leg{i}_slider").qposadr[0]] for i in (1, 2, 3)])
    wrench = None if plan.wrench is None else np.asarray(plan.wrench, dtype=float)
    constants = _loop_inputs(dyn, drive, settings, substeps, q0, wrench)
    periods = run_periods(plan, period)
    return _Start(mujoco, model, data, constants, settings, drive, plan, dyn, periods)


def _loop_inputs(
    dyn: ClosedLoopDynamics,
    drive: Drive,
    settings: ServoSettings,
    substeps: int,
    q0: FloatArray,
    wrench: FloatArray | None,
) -> LoopInputs:
    """Everything the stepping loop needs that does not vary with the period (no references)."""
    k = slider_ratio(drive.train)
    gains = servo_gains(settings, slider_masses(dyn, q0, drive))
    counts = settings.encoder_counts
    resolution = None if counts is None else 2.0 * math.pi / (k * counts)
    speeds, torques, peak = torque_curve(drive)
    train = drive.train
    empty = np.zeros((0, 3))
    return LoopInputs(
        q_ref=empty,
        qd_ref=empty,
        feedforward=empty,
        kp=np.asarray(gains.kp, dtype=float),
        kd=np.asarray(gains.kd, dtype=float),
        ki=np.asarray(gains.ki, dtype=float),
        period=settings.period,
        substeps=substeps,
        resolution=resolution,
        ratio=k,
        efficiency=train.efficiency,
        reflected_inertia=train.reflected_inertia,
        coulomb=train.coulomb_torque,
        viscous=train.viscous_coefficient,
        base=plant_terms(drive, np.ones(3, dtype=bool)),
        speeds=speeds,
        torques=torques,
        peak=peak,
        wrench=wrench,
    )
