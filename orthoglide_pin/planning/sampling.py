"""A plan sampled in time: the columns of ``trajectory.csv``.

:func:`sample_plan` evaluates the plan every ``dt`` seconds (and at its end):
the tool point and path speed from each section's exact time law, then the
slider motion and forces by the closed-loop inverse dynamics and, with a
drive, the motor torques (:func:`~orthoglide_pin.drives.motor.motor_demand`).
During a dwell the tool rests at the dwell's point. The pieces of a chunk's
samples are evaluated together
(:func:`~orthoglide_pin.planning.sample_batch.evaluate_pieces`: the corner
blends' arc length inverted in one compiled loop with numba, in arrays
without it); a simulation, which computes its own feedforward, samples the
motion without the forces (``forces=False``).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import number_in, positive_number, size_within
from orthoglide_pin.drives.motor import motor_demand
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.kinematics.joint_motion import leg_motion, scatter
from orthoglide_pin.machine.digest import check_design
from orthoglide_pin.planning.calibrated import slider_motion
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sample_batch import evaluate_pieces

FloatArray = NDArray[np.float64]

#: The columns of ``trajectory.csv``, SI units (``tau`` only with a drive).
COLUMNS: Final = (
    "t", "x", "y", "z", "path_speed", "q1", "q2", "q3", "qd1", "qd2", "qd3",
    "qdd1", "qdd2", "qdd3", "F1", "F2", "F3", "tau1", "tau2", "tau3",
)  # fmt: skip
#: The sampling step when none is given, while it fits :data:`MAX_SAMPLES` [s].
DEFAULT_DT: Final[float] = 0.001
#: Most samples of a plan held in memory (:func:`sample_plan`), and of a plan
#: sampled without a given step (:func:`auto_dt`) [-].
MAX_SAMPLES: Final[int] = 1_000_000
#: Samples computed at once by :func:`sample_chunks` [-].
CHUNK_SAMPLES: Final[int] = 50_000
#: Range of a given sampling step [s]: a servo period of 1 MHz to 10 Hz.
MIN_DT: Final[float] = 1e-6
MAX_DT: Final[float] = 0.1


def sampling_step(name: str, dt: object) -> float:
    """``dt`` as a sampling step in ``[MIN_DT, MAX_DT]`` [s].

    Raises:
        InvalidParameterError: Naming ``name`` and the range.
    """
    return number_in(name, dt, MIN_DT, MAX_DT, "[s]")


def auto_dt(cycle_time: float) -> float:
    """The sampling step of a plan when none is given [s] (see the module).

    :data:`DEFAULT_DT` while it gives at most :data:`MAX_SAMPLES` samples, else
    the smallest step of the series 1, 2, 5 x 10^k s that does.
    """
    cycle = max(float(cycle_time), 0.0)
    if np.floor(cycle / DEFAULT_DT) + 1 <= MAX_SAMPLES:
        return DEFAULT_DT
    scale = 10.0 ** np.floor(np.log10(cycle / (MAX_SAMPLES - 1)))
    for mantissa in (1.0, 2.0, 5.0, 10.0):
        step = float(mantissa * scale)
        if np.floor(cycle / step) + 1 <= MAX_SAMPLES:
            return step
    return float(20.0 * scale)  # not reached: 10 x scale always fits


def sample_count(plan: Plan, dt: float) -> int:
    """The number of samples of ``plan`` every ``dt`` [s], its end included."""
    count = int(np.floor(plan.cycle_time / dt)) + 1
    return count + (1 if (count - 1) * dt < plan.cycle_time else 0)


def sample_plan(
    plan: Plan, dyn: ClosedLoopDynamics, dt: float | None = None
) -> dict[str, FloatArray]:
    """The plan every ``dt`` [s] (:func:`auto_dt` when ``None``): column name -> values.

    The columns are those of :data:`COLUMNS`; :func:`sample_chunks` gives the
    same samples a chunk at a time, in bounded memory.

    Raises:
        InvalidParameterError: A ``dt`` outside ``[MIN_DT, MAX_DT]``, or more than
            :data:`MAX_SAMPLES` samples (counted before any is made).
        DesignMismatchError: The plan was made for another design than ``dyn``'s.
    """
    dt = auto_dt(plan.cycle_time) if dt is None else sampling_step("dt", dt)
    if plan.design is not None:  # the plan of this machine
        check_design(plan.design, dyn.closed_loop.params, "the plan", redo="plan it again")
    grid = np.floor(plan.cycle_time / dt) + 1.0  # the grid's samples (then the end)
    size_within("dt", dt, grid, MAX_SAMPLES, f"samples over {plan.cycle_time:.6g} s")
    parts = list(sample_chunks(plan, dyn, dt, chunk=MAX_SAMPLES + 1))
    return {name: np.concatenate([c[name] for c in parts]) for name in parts[0]}


def sample_chunks(
    plan: Plan,
    dyn: ClosedLoopDynamics,
    dt: float,
    *,
    chunk: int = CHUNK_SAMPLES,
    forces: bool = True,
) -> Iterator[dict[str, FloatArray]]:
    """The plan every ``dt`` [s], ``chunk`` samples at a time (the columns of :func:`sample_plan`).

    With ``forces=False`` the columns ``F1..F3`` and ``tau1..tau3`` are left
    out and the sliders' motion comes from the kinematics alone (the same
    values, without the cost of the inverse dynamics): what a simulation
    that computes its own feedforward needs.

    Raises:
        InvalidParameterError: A bad ``dt`` or ``chunk``.
        DesignMismatchError: The plan was made for another design than ``dyn``'s.
    """
    if plan.design is not None:  # the plan of this machine
        check_design(plan.design, dyn.closed_loop.params, "the plan", redo="plan it again")
    dt = positive_number("dt", dt, "a time step > 0 [s]")
    chunk = int(positive_number("chunk", chunk, "a number of samples >= 1"))
    total = sample_count(plan, dt)
    starts = np.array([r.start for r in plan.sections])
    ends = np.array([r.start + r.duration for r in plan.sections])
    after = []  # where the tool rests after each section
    last = plan.path.program.start.copy()
    for r in plan.sections:
        if r.plan is not None:
            piece = r.section.pieces[-1]
            last = piece.evaluate(np.array([piece.length]))[0][0]
        after.append(last)
    for first in range(0, total, chunk):
        t = np.arange(first, min(first + chunk, total), dtype=np.float64) * dt
        t[t > plan.cycle_time] = plan.cycle_time  # the last sample: the end
        yield _columns(plan, dyn, t, starts, ends, after, forces)


def _columns(
    plan: Plan,
    dyn: ClosedLoopDynamics,
    t: FloatArray,
    starts: FloatArray,
    ends: FloatArray,
    after: list[FloatArray],
    forces: bool,
) -> dict[str, FloatArray]:
    """The columns at the times ``t`` (increasing) [s] (``F``, ``tau`` with ``forces``)."""
    n = t.size
    p, dp, ddp = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
    sd, sdd = np.zeros(n), np.zeros(n)
    before = int(np.searchsorted(ends, t[0], side="left")) - 1  # ended before the chunk
    p[:] = plan.path.program.start if before < 0 else after[before]
    stop = int(np.searchsorted(starts, t[-1], side="right"))
    # the samples on pieces, evaluated together once every section has placed them
    rows: list[NDArray[np.intp]] = []
    which: list[NDArray[np.intp]] = []
    local: list[FloatArray] = []
    pieces: list[Piece] = []
    for k in range(max(before, 0), stop):
        r = plan.sections[k]
        sec = r.section
        end = r.start + r.duration
        if r.plan is not None:
            mask = (t >= r.start) & (t <= end)
            s, v, a = r.plan.at_times(t[mask] - r.start)
            j_of = np.clip(
                np.searchsorted(sec.offsets, s, side="right") - 1, 0, len(sec.pieces) - 1
            )
            used, inverse = np.unique(j_of, return_inverse=True)
            rows.append(np.flatnonzero(mask))
            which.append(inverse.reshape(-1) + len(pieces))
            local.append(s - sec.offsets[j_of])
            pieces.extend(sec.pieces[j] for j in used.tolist())
            sd[mask], sdd[mask] = v, a
        later = t > end
        p[later] = after[k]
        dp[later], ddp[later] = 0.0, 0.0
        sd[later], sdd[later] = 0.0, 0.0
    if rows:
        pp, d1, d2 = evaluate_pieces(pieces, np.concatenate(which), np.concatenate(local))
        first = 0
        for at in rows:  # in the sections' order: a sample at a boundary takes the later
            part = slice(first, first + at.size)
            p[at], dp[at], ddp[at] = pp[part], d1[part], d2[part]
            first += at.size
    vel = dp * sd[:, None]
    acc = dp * sdd[:, None] + ddp * (sd * sd)[:, None]
    res = None
    if forces:
        res = dyn.inverse_dynamics(p, vel, acc, wrench=plan.wrench, gravity=plan.gravity)
        q, qd, qdd = res.slider_positions, res.slider_velocities, res.slider_accelerations
    else:  # the sliders' motion alone: the closed form's own, without its dynamics
        motion = leg_motion(p, vel, acc, dyn.leg_length)
        act = dyn.closed_loop.actuated
        q, qd, qdd = (
            scatter(f, dyn.leg_indices)[:, act]
            for f in (motion.values, motion.rates, motion.accelerations)
        )
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
        if res is not None:
            out[f"F{i + 1}"] = res.forces[:, i]
    drive = plan.limits.drive
    if drive is not None and res is not None:
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
