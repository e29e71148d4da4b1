"""The stepping loop against a plain implementation of the same servo period, step by step."""

from __future__ import annotations

import bisect
import math
from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.simulation.run import Prepared, prepare
from orthoglide_pin.simulation.servo import Encoder, PositionLoop
from orthoglide_pin.simulation.stepping import BLOCK, run_loop

pytest.importorskip("mujoco")
pytest.importorskip("toppra")

DRIVE = og.load_drive(str(og.example_drive_file()))
#: The loop and the plain implementation agree to rounding, relative to each quantity's size [-].
SAME = 1e-12
#: Periods compared: past one block of the energy account.
PERIODS = BLOCK + 500
PROGRAM = "G21 G90 G17\nG1 X10 Y5 Z-5 F3000\nG2 X10 Y5 I-5 J0\nG0 X0 Y0 Z0\nM30\n"


def _plain(ready: Prepared, periods: int) -> dict[str, Any]:
    """The servo periods written plainly: numpy per period, the servo classes, np.interp."""
    mujoco, model, data, inputs = ready.mujoco, ready.model, ready.data, ready.inputs
    names = ("leg1_slider", "leg2_slider", "leg3_slider")
    dofs = [model.joint(n).dofadr[0] for n in names]
    qadr = [model.joint(n).qposadr[0] for n in names]
    tool, platform = model.body("tool").id, model.body("platform").id
    k, eta, period = inputs.ratio, inputs.efficiency, inputs.period
    loops = [PositionLoop(inputs.kp[i], inputs.kd[i], inputs.ki[i], period) for i in range(3)]
    encoders = [Encoder(inputs.resolution, period, float(data.qpos[qadr[i]])) for i in range(3)]
    base = np.array(inputs.base)
    for i in range(3):
        model.dof_armature[dofs[i]], model.dof_frictionloss[dofs[i]] = base[0, i], base[1, i]
        model.dof_damping[dofs[i]] = base[2, i]
    frozen, driving = np.zeros(3, dtype=bool), np.ones(3, dtype=bool)
    out: dict[str, Any] = {key: [] for key in ("p", "q", "qd", "torque", "available", "energy")}
    out["work"], out["losses"] = [], []
    work = losses = 0.0
    h = model.opt.timestep
    for j in range(periods):
        q, qd = data.qpos[qadr].copy(), data.qvel[dofs].copy()
        w = k * qd
        a = np.minimum(np.interp(np.abs(w), inputs.speeds, inputs.torques, right=0.0), inputs.peak)
        t = np.zeros(3)
        for i in range(3):
            read_q, read_qd = encoders[i].read(float(q[i]), float(qd[i]))
            force = loops[i].force(
                inputs.q_ref[j, i] - read_q, inputs.qd_ref[j, i] - read_qd, bool(frozen[i])
            )
            asked = inputs.feedforward[j, i] + (1.0 / (k * eta)) * force
            t[i] = np.clip(asked, -a[i], a[i])
            frozen[i] = abs(asked) > a[i]
        friction = inputs.coulomb * np.sign(w) + inputs.viscous * w
        into = t - inputs.reflected_inertia * k * data.qacc[dofs] - friction
        now = into * qd >= 0.0
        for flip in np.flatnonzero(now != driving):
            scale = (eta if now[flip] else 1.0 / eta) / eta  # eta^s over the MJCF's eta
            model.dof_armature[dofs[flip]] = scale * base[0, flip]
            model.dof_frictionloss[dofs[flip]] = scale * base[1, flip]
            model.dof_damping[dofs[flip]] = scale * base[2, flip]
        driving = now
        data.ctrl[:] = np.where(driving, eta, 1.0 / eta) * k * t
        mujoco.mj_step1(model, data)
        if inputs.wrench is not None:
            f, m = inputs.wrench[:3], inputs.wrench[3:]
            arm = data.xpos[tool] - data.xipos[platform]
            data.xfrc_applied[platform] = np.concatenate([f, m + np.cross(arm, f)])
        out["p"].append(data.xpos[tool].copy())
        out["energy"].append(data.energy.sum())
        out["work"].append(work)
        out["losses"].append(losses)
        for sub in range(inputs.substeps):
            v0 = data.qvel.copy()
            (mujoco.mj_step2 if sub == 0 else mujoco.mj_step)(model, data)
            mid = 0.5 * h * (v0 + data.qvel)
            work += data.qfrc_actuator @ mid
            losses -= (data.qfrc_constraint + data.qfrc_passive) @ mid
        for key, value in (("q", q), ("qd", qd), ("torque", t), ("available", a)):
            out[key].append(value)
    return {key: np.array(value) for key, value in out.items()}


@pytest.mark.parametrize(
    ("case", "settings", "wrench"),
    [
        ("default", og.ServoSettings(), None),
        (
            "weak motor, encoder, 3 steps a period",
            og.ServoSettings(rate=1500.0, encoder_counts=4096),
            None,
        ),
        (
            "wrench, model errors, longer legs",
            og.ServoSettings(mass_error=0.1, friction_error=-0.2),
            (30.0, -20.0, 15.0, 1.0, 0.5, -2.0),
        ),
    ],
)
def test_the_loop_is_the_plain_servo_period(
    case: str, settings: og.ServoSettings, wrench: Any
) -> None:
    params = og.prototype().replace(leg_length=0.36, bar_mass=0.7) if "legs" in case else None
    dyn = og.ClosedLoopDynamics(og.ClosedLoopModel(params))
    drive = DRIVE
    if "weak" in case:
        drive = og.Drive(
            DRIVE.train,
            og.MotorData(name="weak", peak_torque=1.5, speed_torque_curve=((0, 1.5), (5000, 1.0))),
        )
    plan = og.plan_program(
        og.read_program(PROGRAM), dyn, og.PlanLimits(drive=DRIVE), wrench=wrench
    )
    ready = prepare(plan, dyn, drive, settings)
    assert ready.inputs.substeps == (3 if "3 steps" in case else 1)
    fast = run_loop(*_fields(ready))
    n = min(PERIODS, fast["q"].shape[0])
    plain = _plain(prepare(plan, dyn, drive, settings), n)
    if "weak" in case:
        assert fast["saturated"][:n].any()  # the curve cuts the torque in the periods compared
    for key in ("p", "q", "qd", "torque", "available", "energy", "work", "losses"):
        scale = max(1.0, float(np.abs(plain[key]).max()))
        assert np.abs(fast[key][:n] - plain[key]).max() <= SAME * scale, key


def _fields(ready: Prepared) -> tuple[Any, Any, Any, Any]:
    return ready.mujoco, ready.model, ready.data, ready.inputs


def test_curve_segments_are_numpy_interp() -> None:
    """The scalar interpolation of the loop is ``numpy.interp`` with ``right=0``, peak-capped."""
    from orthoglide_pin.simulation.stepping import _segments

    speeds, torques = np.array([0.0, 100.0, 400.0, 600.0]), np.array([3.0, 3.0, 2.0, 0.5])
    curve_w, w0, t0, dt, dw = _segments(speeds, torques)
    rng = np.random.default_rng(1)
    for s in np.concatenate([rng.uniform(0.0, 700.0, 200), speeds]):
        g = bisect.bisect_right(curve_w, s)
        top = (
            (t0[g] + dt[g] * (s - w0[g]) / dw[g])
            if g < len(curve_w)
            else (torques[-1] if s == speeds[-1] else 0.0)
        )
        assert math.isclose(top, np.interp(s, speeds, torques, right=0.0), abs_tol=1e-15)
