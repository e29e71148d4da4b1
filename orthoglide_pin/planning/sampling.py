"""A plan sampled in time: the columns of ``trajectory.csv``.

:func:`sample_plan` evaluates the plan every ``dt`` seconds (and at its end):
the tool point and path speed from each section's exact time law, then the
slider motion and forces by the closed-loop inverse dynamics and, with a
drive, the motor torques (:func:`~orthoglide_pin.drives.motor.motor_demand`).
During a dwell the tool rests at the dwell's point.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import number_in, size_within
from orthoglide_pin.drives.motor import motor_demand
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.machine.digest import check_design
from orthoglide_pin.planning.calibrated import slider_motion
from orthoglide_pin.planning.plan import Plan

FloatArray = NDArray[np.float64]

#: The columns of ``trajectory.csv``, SI units (``tau`` only with a drive).
COLUMNS: Final = (
    "t", "x", "y", "z", "path_speed", "q1", "q2", "q3", "qd1", "qd2", "qd3",
    "qdd1", "qdd2", "qdd3", "F1", "F2", "F3", "tau1", "tau2", "tau3",
)  # fmt: skip
#: Most samples written [-] (a cycle of 1000 s at 1 ms).
MAX_SAMPLES: Final[int] = 1_000_000
#: Range of the sampling step [s]: a servo period of 1 MHz to 10 Hz.
MIN_DT: Final[float] = 1e-6
MAX_DT: Final[float] = 0.1


def sampling_step(name: str, dt: object) -> float:
    """``dt`` as a sampling step in ``[MIN_DT, MAX_DT]`` [s].

    Raises:
        InvalidParameterError: Naming ``name`` and the range.
    """
    return number_in(name, dt, MIN_DT, MAX_DT, "[s]")


def sample_plan(plan: Plan, dyn: ClosedLoopDynamics, dt: float) -> dict[str, FloatArray]:
    """The plan every ``dt`` [s]: column name -> values (see :data:`COLUMNS`).

    Raises:
        InvalidParameterError: A ``dt`` outside ``[MIN_DT, MAX_DT]``, or more than
            :data:`MAX_SAMPLES` samples (counted before any is made).
        DesignMismatchError: The plan was made for another design than ``dyn``'s.
    """
    dt = sampling_step("dt", dt)
    if plan.design is not None:  # the plan of this machine
        check_design(plan.design, dyn.closed_loop.params, "the plan", redo="plan it again")
    span = plan.cycle_time / dt
    size_within("dt", dt, span + 1.0, MAX_SAMPLES, f"samples over {plan.cycle_time:.6g} s")
    count = int(np.floor(span)) + 1
    t: FloatArray = np.arange(count, dtype=np.float64) * dt
    if t[-1] < plan.cycle_time:
        t = np.append(t, plan.cycle_time)
    n = t.size
    p, dp, ddp = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
    sd, sdd = np.zeros(n), np.zeros(n)
    last = plan.path.program.start.copy()
    p[:] = last
    for r in plan.sections:
        sec = r.section
        end = r.start + r.duration
        if r.plan is not None:
            mask = (t >= r.start) & (t <= end)
            s, v, a = r.plan.at_times(t[mask] - r.start)
            k = np.clip(np.searchsorted(sec.offsets, s, side="right") - 1, 0, len(sec.pieces) - 1)
            pp, d1, d2 = np.zeros((s.size, 3)), np.zeros((s.size, 3)), np.zeros((s.size, 3))
            for j in np.unique(k):
                sel = k == j
                pp[sel], d1[sel], d2[sel] = sec.pieces[j].evaluate(s[sel] - sec.offsets[j])
            p[mask], dp[mask], ddp[mask], sd[mask], sdd[mask] = pp, d1, d2, v, a
            piece = sec.pieces[-1]
            last = piece.evaluate(np.array([piece.length]))[0][0]
        later = t > end
        p[later] = last
        sd[later], sdd[later] = 0.0, 0.0
    vel = dp * sd[:, None]
    acc = dp * sdd[:, None] + ddp * (sd * sd)[:, None]
    res = dyn.inverse_dynamics(p, vel, acc, wrench=plan.wrench, gravity=plan.gravity)
    q, qd, qdd = res.slider_positions, res.slider_velocities, res.slider_accelerations
    if plan.calibration is not None:  # the commands that move the real tool along the path
        q, qd, qdd = slider_motion(plan.calibration, p, vel, acc)
    out: dict[str, FloatArray] = {
        "t": t,
        "x": p[:, 0],
        "y": p[:, 1],
        "z": p[:, 2],
        "path_speed": sd,
    }
    for i in range(3):
        out[f"q{i + 1}"] = q[:, i]
        out[f"qd{i + 1}"] = qd[:, i]
        out[f"qdd{i + 1}"] = qdd[:, i]
        out[f"F{i + 1}"] = res.forces[:, i]
    drive = plan.limits.drive
    if drive is not None:
        demand = motor_demand(res.forces, qd, qdd, drive.train)
        for i in range(3):
            out[f"tau{i + 1}"] = demand.torque[:, i]
    return out


def csv_text(columns: dict[str, FloatArray], order: tuple[str, ...] = COLUMNS) -> str:
    """The columns as CSV text: a header, then one row per sample (10 significant digits).

    Args:
        columns: Column name -> values, each (n,).
        order: The columns to write, in this order; the names absent from
            ``columns`` are left out (the planned trajectory's :data:`COLUMNS`
            by default).

    Returns:
        The CSV text.
    """
    import io

    names = [c for c in order if c in columns]
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([columns[c] for c in names]),
        fmt="%.10g",
        delimiter=",",
        header=",".join(names),
        comments="",
    )
    return buf.getvalue()
