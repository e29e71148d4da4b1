"""What the servo loop follows: the plan sampled every period, with its feedforward, in chunks.

:func:`reference_chunks` samples the plan at every servo period
(:func:`~orthoglide_pin.planning.sampling.sample_chunks`) a chunk of periods
at a time: the slider positions to follow, the speeds and accelerations that
MuJoCo's integrator needs to land on them (:func:`integrator_motion`, carried
from one chunk to the next), and the feedforward torque through the
closed-loop inverse dynamics and the controller's drive model. The memory it
needs grows with the chunk, not with the program; the values are those of the
whole run sampled at once, to the last digit (each chunk sees the last
position of the one before and the first of the one after).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sampling import sample_chunks, sample_count
from orthoglide_pin.simulation.servo import ServoSettings
from orthoglide_pin.simulation.slider_drive import feedforward_torque

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ReferenceChunk:
    """The references of ``n`` consecutive servo periods.

    Attributes:
        columns: The plan sampled at those periods (the columns of
            :func:`~orthoglide_pin.planning.sampling.sample_plan`), each (n,).
        q_ref: Slider positions to follow [m], (n, 3).
        qd_ref: Slider speeds to follow [m/s], (n, 3) (with an encoder, the
            difference of the positions over a period, as the encoder reads).
        feedforward: Feedforward motor torques [N.m], (n, 3) (zero without
            the torque feedforward).
    """

    columns: dict[str, FloatArray]
    q_ref: FloatArray
    qd_ref: FloatArray
    feedforward: FloatArray


def run_periods(plan: Plan, period: float) -> int:
    """The servo periods of a run of ``plan``: every period, up to the last one in the plan."""
    total = sample_count(plan, period)
    if total < 2:
        return total
    last = min((total - 1) * period, plan.cycle_time)
    before = min((total - 2) * period, plan.cycle_time)
    # the plan's end between two periods: the run ends at the last period
    return total if math.isclose(last - before, period, rel_tol=1e-9) else total - 1


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
    a, v, _ = _integrator_chunk(q, period, substeps, None, None, np.zeros(q.shape[1:]))
    return a, v


def _integrator_chunk(
    q: FloatArray,
    period: float,
    substeps: int,
    before: FloatArray | None,
    after: FloatArray | None,
    v0: FloatArray,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`integrator_motion` of a chunk: its accelerations and speeds, and the next speed.

    ``before`` and ``after`` are the positions of the periods just before and
    just after the chunk (``None`` at the run's start and end), ``v0`` the speed
    at its first period (the recursion's carry, with several steps a period).
    """
    n = q.shape[0]
    v, a = np.zeros_like(q), np.zeros_like(q)
    ext = np.vstack([q] if after is None else [q, after[None, :]])
    step = np.diff(ext, axis=0)  # step[j] = q[j + 1] - q[j]
    if substeps == 1:  # c = 1: the speed is the last step over the period
        v[1:] = step[: n - 1] / period
        if before is not None:
            v[0] = (q[0] - before) / period
        nxt = step[n - 1] / period if after is not None else np.zeros_like(q[0])
        upper = np.vstack([v[1:], nxt[None, :]])
        a[: step.shape[0]] = (upper - v)[: step.shape[0]] / period
        return a, v, nxt
    c = (substeps + 1) / (2.0 * substeps)
    v[0] = v0
    speed = np.array(v0, dtype=float)
    for j in range(step.shape[0]):
        a[j] = (step[j] - v[j] * period) / (c * period * period)
        speed = v[j] + a[j] * period
        if j + 1 < n:
            v[j + 1] = speed
    return a, v, speed


def reference_chunks(
    plan: Plan,
    dyn: ClosedLoopDynamics,
    drive: Drive,
    settings: ServoSettings,
    substeps: int,
    chunk: int,
) -> Iterator[ReferenceChunk]:
    """The run's references, ``chunk`` periods at a time (see the module).

    Args:
        plan: The plan.
        dyn: Its machine's inverse dynamics.
        drive: The simulated drive (the controller believes in it, with the
            settings' model errors).
        settings: The servo settings.
        substeps: MuJoCo steps per period.
        chunk: Periods per chunk (>= 1).
    """
    period = settings.period
    n = run_periods(plan, period)
    pending: dict[str, FloatArray] | None = None
    before: FloatArray | None = None
    v0 = np.zeros(3)
    taken = 0
    # the plan's own forces are not needed: the feedforward is computed below
    for cols in sample_chunks(plan, dyn, period, chunk=chunk, forces=False):
        size = min(cols["t"].size, n - taken)
        if size <= 0:
            break
        taken += size
        cols = {k: v[:size] for k, v in cols.items()}
        if pending is not None:
            first = np.array([cols[f"q{i}"][0] for i in (1, 2, 3)])
            out, before, v0 = _finish(
                plan, dyn, drive, settings, substeps, pending, before, first, v0
            )
            yield out
        pending = cols
    if pending is not None:
        yield _finish(plan, dyn, drive, settings, substeps, pending, before, None, v0)[0]


def _finish(
    plan: Plan,
    dyn: ClosedLoopDynamics,
    drive: Drive,
    settings: ServoSettings,
    substeps: int,
    cols: dict[str, FloatArray],
    before: FloatArray | None,
    after: FloatArray | None,
    v0: FloatArray,
) -> tuple[ReferenceChunk, FloatArray, FloatArray]:
    """One chunk's references; the last position and the next speed, for the next chunk."""
    period = settings.period
    q_ref = np.column_stack([cols[f"q{i}"] for i in (1, 2, 3)])
    acc, qd_ref, v_next = _integrator_chunk(q_ref, period, substeps, before, after, v0)
    ff = np.zeros_like(q_ref)
    if settings.torque_feedforward:
        qd_plan = np.column_stack([cols[f"qd{i}"] for i in (1, 2, 3)])
        force = dyn.inverse_dynamics_sliders(q_ref, qd_plan, acc, gravity=plan.gravity).forces
        load = None
        if plan.wrench is not None:  # what the sliders balance of the wrench: no model error
            still = np.zeros_like(q_ref)
            load = dyn.inverse_dynamics_sliders(
                q_ref, still, still, wrench=plan.wrench, gravity=np.zeros(3)
            ).forces
        ff = feedforward_torque(
            drive,
            force,
            qd_ref,
            acc,
            mass_scale=1.0 + settings.mass_error,
            friction_scale=1.0 + settings.friction_error,
            load=load,
        )
    if settings.encoder_counts is not None:  # the speed read is a difference of counts
        ext = q_ref if before is None else np.vstack([before[None, :], q_ref])
        diff = np.diff(ext, axis=0) / period
        qd_ref = diff if before is not None else np.vstack([np.zeros((1, 3)), diff])
    return ReferenceChunk(cols, q_ref, qd_ref, ff), q_ref[-1].copy(), v_next
