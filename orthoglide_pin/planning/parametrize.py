"""Time-optimal parametrisation of a section, rest to rest, with TOPP-RA.

TOPP-RA (Pham and Pham, IEEE T-RO 2018; the ``toppra`` package, extra
``[plan]``) finds, on a grid ``s_0 < ... < s_N`` of the path, the fastest
squared speeds ``x_i = s_dot(s_i)^2`` under constraints linear in
``(u, x)``, with ``u = s_ddot`` constant on each interval (so that
``x_{i+1} = x_i + 2 (s_{i+1} - s_i) u_i``). The rows of
:mod:`orthoglide_pin.planning.limits` are handed to it as one array per
coefficient on the whole grid, in its *interpolation* discretisation: each
interval's ``u`` also meets the constraints of the interval's end point.
Speed limits are bounds on ``x``. Its two passes run in closed form, stage by
stage (:mod:`~orthoglide_pin.planning.reachability`); a problem they cannot
settle goes to toppra's own ``seidel`` solver (a ``LinearConstraint`` whose
parameters are computed once, no Python call per point).

When a limit depends on the speed itself (friction, the speed-torque curve),
its majorant is built around the previous pass's profile and the section is
planned again, :data:`PASSES` times in all; a section planned again after its
verification (:class:`SectionInput` ``previous``) starts from the plan it
replaces and takes one pass. Between grid points the motion is
exact: ``x`` is linear in ``s``, hence
``t(s) = t_i + (sqrt(x(s)) - sqrt(x_i)) / u_i``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._lazy import optional_import
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning.limits import (
    TRUST,
    X_CAP,
    PlanLimits,
    Scales,
    flat_rows,
    joined_scales,
    speed_bound,
    speed_bound_dq,
)
from orthoglide_pin.planning.reach_compiled import AVAILABLE
from orthoglide_pin.planning.reachability import reach
from orthoglide_pin.planning.run_batch import joined_at_lengths, time_laws
from orthoglide_pin.planning.verify_compiled import intervals

FloatArray = NDArray[np.float64]

#: Passes of the planner when a limit depends on the speed.
PASSES: Final[int] = 2
#: Gap between sections laid end to end in one problem [m].
GAP: Final[float] = 1e-6
#: Speeds below this are rest [m/s].
REST_SPEED: Final[float] = 1e-12


@dataclass(frozen=True)
class SectionPlan:
    """The time law of one section: ``s_dot^2`` on the grid, ``s_ddot`` per interval.

    Attributes:
        s: Grid arc lengths [m], (n,).
        x: Squared path speeds [(m/s)^2], (n,).
        u: Path accelerations on each interval [m/s^2], (n - 1,).
        t: Times at the grid points from the section's start [s], (n,).
    """

    s: FloatArray
    x: FloatArray
    u: FloatArray
    t: FloatArray

    @property
    def duration(self) -> float:
        """The section's duration [s]."""
        return float(self.t[-1])

    def at_lengths(
        self, s: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
        """Time [s], speed [m/s], acceleration [m/s^2] and interval at arc lengths ``s``."""
        i = np.clip(intervals(self.s, s), 0, self.u.size - 1)
        ds = s - self.s[i]
        u = self.u[i]
        x = np.maximum(self.x[i] + 2.0 * u * ds, 0.0)
        sd = np.sqrt(x)
        sd0 = np.sqrt(self.x[i])
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where(np.abs(u) > 0.0, (sd - sd0) / u, ds / sd0)
        dt = np.where(ds > 0.0, dt, 0.0)
        return np.asarray(self.t[i] + dt), sd, np.asarray(u, dtype=np.float64), i

    def at_times(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Arc length [m], speed [m/s] and acceleration [m/s^2] at times ``t`` [s]."""
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, self.u.size - 1)
        tau = np.clip(t - self.t[i], 0.0, None)
        u = self.u[i]
        sd0 = np.sqrt(self.x[i])
        sd = np.maximum(sd0 + u * tau, 0.0)
        s = np.minimum(self.s[i] + sd0 * tau + 0.5 * u * tau * tau, self.s[i + 1])
        return s, sd, u


def laws_at(
    laws: list[SectionPlan], lengths: list[FloatArray]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Time [s], speed [m/s] and acceleration [m/s^2] of each law at its arc lengths, end to end.

    The numbers of :meth:`SectionPlan.at_lengths` of each law, in one compiled
    pass (:func:`~orthoglide_pin.planning.run_batch.joined_at_lengths`); law by
    law without numba, or when a law is not a plain :class:`SectionPlan` (a
    smoothed one, under a jerk limit).
    """
    if not AVAILABLE or len(laws) == 1 or any(type(law) is not SectionPlan for law in laws):
        parts = [law.at_lengths(s)[:3] for law, s in zip(laws, lengths, strict=True)]
        t, sd, u = (np.concatenate([p[j] for p in parts]) for j in range(3))
        return t, sd, u
    big = [np.concatenate([getattr(law, n) for law in laws]) for n in ("s", "x", "u", "t")]
    return joined_at_lengths(
        (big[0], big[1], big[2], big[3]), [law.s.size for law in laws], lengths
    )


def _toppra() -> Any:
    toppra = optional_import("toppra", "plan", "planning a program")
    logging.getLogger("toppra").setLevel(logging.ERROR)
    return toppra


def _solve(
    s: FloatArray,
    a: FloatArray,
    b: FloatArray,
    c: FloatArray,
    x_bound: FloatArray,
    *,
    confirm: bool = True,
) -> FloatArray | None:
    """TOPP-RA's squared speeds from rest to rest, or ``None`` when infeasible.

    The stages in closed form (:func:`~orthoglide_pin.planning.reachability.reach`);
    a problem they cannot settle goes to toppra's own solver when ``confirm``
    (sections laid end to end do not: each is then planned alone, and confirmed).
    """
    _toppra()  # the extra is required either way
    x = reach(s, a, b, c, x_bound)
    if x is not None:
        x[[0, -1]] = 0.0
        return x
    return _solve_by_toppra(s, a, b, c, x_bound) if confirm else None


def _solve_by_toppra(
    s: FloatArray, a: FloatArray, b: FloatArray, c: FloatArray, x_bound: FloatArray
) -> FloatArray | None:
    """:func:`_solve` by toppra's ``seidel`` solver (one call per stage)."""
    toppra = _toppra()
    from toppra.constraint import (
        DiscretizationType,
        LinearConstraint,
        canlinear_colloc_to_interpolate,
    )
    from toppra.interpolator import AbstractGeometricPath

    class _Path(AbstractGeometricPath):  # type: ignore[misc]
        def __call__(self, ss: Any, order: int = 0) -> FloatArray:
            return np.zeros((np.size(ss), 1))

        @property
        def dof(self) -> int:
            return 1

        @property
        def path_interval(self) -> FloatArray:
            return np.array([s[0], s[-1]])

    class _Rows(LinearConstraint):  # type: ignore[misc]
        def __init__(self) -> None:
            super().__init__()
            self.dof = 1
            self.identical = True
            self.discretization_type = DiscretizationType.Interpolation
            m = a.shape[1]
            xb = np.stack([np.zeros_like(x_bound), x_bound], axis=1)
            ai, bi, ci, fi, gi, _, _ = canlinear_colloc_to_interpolate(
                a, b, c, np.eye(m), np.ones(m), None, None, s, identical=True
            )
            self.params = (ai, bi, ci, fi, gi, None, xb)

        def compute_constraint_params(self, path: Any, gridpoints: Any, *args: Any) -> Any:
            return self.params

    algorithm = toppra.algorithm.TOPPRA([_Rows()], _Path(), gridpoints=s, solver_wrapper="seidel")
    try:
        _, sd, _ = algorithm.compute_parameterization(0.0, 0.0)
    except ZeroDivisionError:  # toppra's seidel solver on a stage with an empty set
        return None
    if sd is None or not np.all(np.isfinite(sd)):
        # Infeasible, or the solver broke down (seen across the tiny gap between
        # sections laid end to end): the caller plans the sections one by one.
        return None
    x = np.asarray(sd, dtype=float) ** 2
    x[[0, -1]] = 0.0
    return x


def time_law(s: FloatArray, x: FloatArray) -> SectionPlan:
    """The section's time law from squared speeds on the grid (exact between points)."""
    ds = np.diff(s)
    u = np.diff(x) / (2.0 * ds)
    sd = np.sqrt(np.maximum(x, 0.0))
    dt = 2.0 * ds / np.maximum(sd[:-1] + sd[1:], REST_SPEED)
    return SectionPlan(s, x, u, np.concatenate([[0.0], np.cumsum(dt)]))


@dataclass(frozen=True)
class SectionInput:
    """What the planner needs of one section.

    Attributes:
        s: Grid arc lengths [m], (n,).
        forms: Path forms at the grid points.
        feed: Path-speed cap at each point [m/s] (``inf`` on rapid moves), (n,).
        scales: Tightening factors from earlier verifications.
        previous: Squared path speeds of an earlier plan of the section [(m/s)^2],
            (n,), or ``None``: the speed-dependent limits start from them.
    """

    s: FloatArray
    forms: PathForms
    feed: FloatArray
    scales: Scales
    previous: FloatArray | None = None


def first_bounds(
    inp: SectionInput, limits: PlanLimits, again: bool, bound: FloatArray | None = None
) -> tuple[FloatArray, FloatArray, FloatArray, int]:
    """A section's speed bound, first majorant, first guess and number of passes.

    The speed-dependent bounds are taken around a guess of the squared speeds
    (a quarter of the bound), re-taken around each pass's plan (:data:`PASSES`
    under motor torque). ``again``: a plan tightened after its verification,
    whose majorants start from its earlier plan (``inp.previous``), as a second
    pass would, so one pass suffices. ``bound``: the speed bound when already
    computed.

    Returns:
        ``(bound, x_high, x0, passes)``: squared speeds [m^2/s^2], shape (n,) each.
    """
    if bound is None:
        bound = np.minimum(speed_bound(limits, inp.forms, inp.feed, inp.scales), X_CAP)
    if again and inp.previous is not None:
        x0 = np.asarray(inp.previous).copy()
        return bound, narrowed(bound, x0), x0, 1
    return bound, bound.copy(), 0.25 * bound, PASSES if limits.limits_torque else 1


def narrowed(bound: FloatArray, x: FloatArray) -> FloatArray:
    """The majorant of the next pass: the bound, capped at :data:`TRUST` x the plan's peak."""
    return np.minimum(bound, TRUST * max(float(np.max(x)), 1e-12))


def plan_sections(inputs: list[SectionInput], limits: PlanLimits) -> list[SectionPlan | None]:
    """The time-optimal laws of sections, each from rest to rest, in one TOPP-RA problem.

    The sections' grids are laid end to end, :data:`GAP` apart, with ``x = 0``
    imposed at each section's ends, so that one call plans them all (a
    program of many short sections pays TOPP-RA's set-up once). If that
    problem is infeasible, each section is planned alone to find which.
    Everything is computed on the sections laid end to end (the speed bounds,
    the rows, each pass's majorants, the time laws), with the numbers of a
    section planned alone.

    Returns:
        Each section's law, ``None`` for a section no motion can make.
    """
    if not inputs:
        return []
    sizes = [i.s.size for i in inputs]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
    names = ("q", "dq", "ddq", "a", "b", "c")
    if len(inputs) == 1:
        forms, feed, s_cat = inputs[0].forms, inputs[0].feed, inputs[0].s
        scales = inputs[0].scales
    else:
        forms = PathForms(*(np.concatenate([getattr(i.forms, n) for i in inputs]) for n in names))
        feed, s_cat = (np.concatenate([getattr(i, n) for i in inputs]) for n in ("feed", "s"))
        scales = joined_scales([i.scales for i in inputs], sizes)
    bound = np.minimum(speed_bound_dq(limits, forms.dq, feed, scales), X_CAP)
    again = limits.limits_torque and all(i.previous is not None for i in inputs)
    if again:
        x0 = np.concatenate([np.asarray(i.previous) for i in inputs])
        x_high, passes = _narrowed_all(bound, x0, starts), 1
    else:
        x_high, x0 = bound.copy(), 0.25 * bound
        passes = PASSES if limits.limits_torque else 1
    s_all = _laid_end_to_end(s_cat, starts, sizes)
    x: FloatArray | None = None
    for _ in range(passes):
        a, b, c = flat_rows(limits, forms, x_high, x0, scales, sizes)
        xb = x_high.copy()
        xb[starts], xb[starts + np.asarray(sizes) - 1] = 0.0, 0.0
        x = _solve(s_all, a, b, c, xb, confirm=len(inputs) == 1)
        if x is None:
            if len(inputs) == 1:
                return [None]
            return [
                None if (law := plan_sections([i], limits)[0]) is None else law for i in inputs
            ]
        x = np.maximum(x, 0.0)
        x[starts], x[starts + np.asarray(sizes) - 1] = 0.0, 0.0
        if limits.limits_torque:
            x0 = x.copy()
            x_high = _narrowed_all(bound, x, starts)
    assert x is not None
    return [SectionPlan(*law) for law in time_laws(s_cat, x, sizes, REST_SPEED)]


def _laid_end_to_end(s: FloatArray, starts: NDArray[np.intp], sizes: list[int]) -> FloatArray:
    """Grids laid end to end from ``0``, :data:`GAP` apart, (m,)."""
    first = s[starts]
    length = s[starts + np.asarray(sizes) - 1] - first
    start = np.concatenate([[0.0], np.cumsum(length + GAP)[:-1]])
    return np.asarray(s + np.repeat(start - first, sizes))


def _narrowed_all(bound: FloatArray, x: FloatArray, starts: NDArray[np.intp]) -> FloatArray:
    """:func:`narrowed` of every section laid end to end (their peaks apart)."""
    peak = TRUST * np.maximum(np.maximum.reduceat(x, starts), 1e-12)
    return np.minimum(bound, np.repeat(peak, np.diff(np.append(starts, x.size))))


def _solve_joined(
    grids: list[FloatArray],
    parts: list[tuple[FloatArray, FloatArray, FloatArray]],
    x_high: list[FloatArray],
) -> list[FloatArray] | None:
    """Squared speeds of sections planned end to end (see :func:`plan_sections`)."""
    offsets, start = [], 0.0
    for s in grids:
        offsets.append(start - s[0])
        start += float(s[-1] - s[0]) + GAP
    s_all = np.concatenate([s + o for s, o in zip(grids, offsets, strict=True)])
    a, b, c = (np.concatenate(col) for col in zip(*parts, strict=True))
    bound = []
    for xh in x_high:
        xb = xh.copy()
        xb[[0, -1]] = 0.0
        bound.append(xb)
    x = _solve(s_all, a, b, c, np.concatenate(bound), confirm=len(grids) == 1)
    if x is None:
        return None
    cuts = np.cumsum([g.size for g in grids])[:-1]
    out = np.split(np.maximum(x, 0.0), cuts)
    for part in out:
        part[[0, -1]] = 0.0
    return out
