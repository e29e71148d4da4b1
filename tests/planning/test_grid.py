"""The grid that follows the motion: cycle times against dense phase-plane optima.

The references here take another route than the planner: the exact path is
sampled every :data:`REF_STEP` or finer, and the largest acceleration, then
the largest deceleration, are integrated forwards from rest and backwards
from rest under each limit evaluated exactly at the sample's speed (the
speed-torque curve and the friction included, no affine bound), below the
largest speed each point can hold (found by bisection). The planner must come
within :data:`OPTIMUM_TOL` of that time, and never beat it by more than the
reference's own discretisation (:data:`REF_TOL`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.dynamics.motion_forms import as_dynamics
from orthoglide_pin.dynamics.path_forms import path_forms
from orthoglide_pin.planning import example_program_text, read_program
from orthoglide_pin.planning.controller import with_controller
from orthoglide_pin.planning.grid import switch_points, switch_points_of
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.verify import USE_TOL

pytest.importorskip("toppra")

#: The planner's cycle time over the reference's, at most [-].
OPTIMUM_TOL = 0.01
#: The planner may beat the dense reference by this share (its own discretisation) [-].
REF_TOL = 0.002
#: Largest spacing of the reference's samples [m].
REF_STEP = 5e-5
#: Fewest samples of a reference section [-].
REF_MIN = 800
#: A reference point this close to its largest speed follows that speed [-].
ON_CAP = 1.0 - 1e-9
SLIDERS = PlanLimits(slider_speed=1.0, slider_acceleration=15.0)


@pytest.fixture(scope="module")
def motors() -> PlanLimits:
    return PlanLimits(drive=load_drive(str(example_drive_file())))


def _u_range(
    limits: PlanLimits, f: dict[str, np.ndarray], x: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The path accelerations the limits allow at points of squared speeds ``x``, (n,) each."""
    n = x.size
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    dq, ddq = f["dq"], f["ddq"]

    def within(alpha, beta, low, high, where) -> None:  # low <= alpha u + beta <= high
        nonlocal lo, hi
        with np.errstate(divide="ignore", invalid="ignore"):
            flat = np.abs(alpha) < 1e-300
            a, b = (low - beta) / alpha, (high - beta) / alpha
            bad = where & flat & ((beta < low) | (beta > high))
            use = where & ~flat
            lo = np.where(use, np.maximum(lo, np.minimum(a, b)), lo)
            hi = np.where(use, np.minimum(hi, np.maximum(a, b)), hi)
            lo, hi = np.where(bad, np.inf, lo), np.where(bad, -np.inf, hi)

    if limits.slider_acceleration is not None:
        acc = limits.slider_acceleration
        for j in range(3):
            within(dq[:, j], ddq[:, j] * x, -acc, acc, np.ones(n, dtype=bool))
    if limits.drive is not None and limits.limits_torque:
        train = limits.drive.train
        r = train.lead / (2.0 * math.pi * train.gear_ratio)
        k = 2.0 * math.pi * train.gear_ratio / train.lead
        inertia = train.reflected_inertia * k
        drive_e, back_e = 1.0 / train.efficiency, train.efficiency
        for j in range(3):
            w = k * dq[:, j] * np.sqrt(x)
            fric, avail = train.friction(w), limits.available_torque(w)
            fwd, bwd = w > 0.0, w < 0.0
            rest = ~fwd & ~bwd
            # the load torque is max(driving, back-driven) moving forwards, min backwards
            rows = (
                (drive_e, fwd | rest, True), (back_e, fwd | bwd, True),
                (back_e, fwd | bwd, False), (drive_e, bwd | rest, False),
            )  # fmt: skip
            for e, where, upper in rows:
                alpha = r * e * f["a"][:, j] + inertia * dq[:, j]
                beta = r * e * (f["b"][:, j] * x + f["c"][:, j]) + inertia * ddq[:, j] * x + fric
                if upper:
                    within(
                        alpha,
                        beta,
                        -np.inf,
                        avail,
                        where & (fwd | rest) | where & bwd & (e == back_e),
                    )
                else:
                    within(
                        alpha,
                        beta,
                        -avail,
                        np.inf,
                        where & (bwd | rest) | where & fwd & (e == back_e),
                    )
    return lo, hi


def _caps(limits: PlanLimits, forms: dict[str, np.ndarray], feed: np.ndarray) -> np.ndarray:
    """The largest squared speed each point can hold, by bisection, (n,)."""
    top = np.minimum(feed**2, 1e4)
    dq = np.abs(forms["dq"]).max(axis=1)
    if limits.slider_speed is not None:
        top = np.minimum(top, (limits.slider_speed / dq) ** 2)
    if limits.motor_speed is not None:
        assert limits.drive is not None
        k = float(limits.drive.train.motor_speed(1.0))
        top = np.minimum(top, (limits.motor_speed / (k * dq)) ** 2)
    lo, hi = np.zeros_like(top), top.copy()
    ok = np.less_equal(*_u_range(limits, forms, top))
    for _ in range(90):
        mid = 0.5 * (lo + hi)
        feasible = np.less_equal(*_u_range(limits, forms, mid))
        lo, hi = np.where(feasible, mid, lo), np.where(feasible, hi, mid)
    return np.where(ok, top, lo)


def _step(x: float, dx: float, cap: float, cap_next: float) -> float:
    """The next squared speed: the ramp below the next cap; on the cap, at least held."""
    low = min(x, cap_next) if x >= ON_CAP * cap else 0.0  # on the largest speed: slides along
    return min(cap_next, max(x + dx, low))


def reference_time(text: str, limits: PlanLimits, params) -> float:
    """The dense phase-plane optimum of a program's sections, rest to rest [s]."""
    dyn = as_dynamics(params)
    path = build_path(with_controller(read_program(text)))  # the path the planner follows
    total = 0.0
    for sec in path.sections:
        if not sec.pieces:
            total += sec.dwell
            continue
        n = max(REF_MIN, math.ceil(sec.length / REF_STEP)) + 1
        s = np.linspace(0.0, sec.length, n)
        ends = s[1] * 0.5 ** np.arange(1, 60)  # geometric towards each rest
        s = np.unique(np.concatenate([s, ends, sec.length - ends]))
        n = s.size
        k = np.clip(np.searchsorted(sec.offsets, s, side="right") - 1, 0, len(sec.pieces) - 1)
        p, dp, ddp = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
        for j in np.unique(k):
            sel = k == j
            p[sel], dp[sel], ddp[sel] = sec.pieces[j].evaluate(s[sel] - sec.offsets[j])
        pf = path_forms(dyn, p, dp, ddp, gravity=dyn.gravity_vector(None))
        forms = {name: getattr(pf, name) for name in ("dq", "ddq", "a", "b", "c")}
        feeds = np.array([math.inf if pc.feed is None else pc.feed for pc in sec.pieces])[k]
        cap = _caps(limits, forms, feeds)
        x_f, x_b = np.zeros(n), np.zeros(n)
        h = np.diff(s)
        rows = [{key: v[i : i + 1] for key, v in forms.items()} for i in range(n)]
        for i in range(n - 1):
            u = _u_range(limits, rows[i], x_f[i : i + 1])[1][0]
            x_f[i + 1] = _step(x_f[i], 2.0 * h[i] * u, cap[i], cap[i + 1])
        for i in range(n - 1, 0, -1):
            u = _u_range(limits, rows[i], x_b[i : i + 1])[0][0]
            x_b[i - 1] = _step(x_b[i], -2.0 * h[i - 1] * u, cap[i], cap[i - 1])
        sd = np.sqrt(np.minimum(x_f, x_b))
        total += float(np.sum(2.0 * h / np.maximum(sd[:-1] + sd[1:], 1e-300))) + sec.dwell
    return total


def _against_reference(text: str, limits: PlanLimits, params) -> float:
    plan = program = plan_program(read_program(text), params, limits)
    assert max(program.worst.values()) <= 1.0 + USE_TOL, program.worst
    ref = reference_time(text, limits, params)
    ratio = plan.cycle_time / ref
    assert 1.0 - REF_TOL <= ratio <= 1.0 + OPTIMUM_TOL, (plan.cycle_time, ref)
    return ratio


@pytest.mark.parametrize("feed", [1, 600, 60000])
def test_a_line_from_rest_is_optimal_under_slider_limits(feed: int, params) -> None:
    length = 1.0 if feed == 1 else 30.0
    _against_reference(f"G1 X{length} F{feed}\n", SLIDERS, params)


def test_thirty_mm_at_f6000_takes_the_optimum(params) -> None:
    plan = plan_program(read_program("G1 X30 F6000\n"), params, SLIDERS)
    # the slider runs along its axis: 30 mm at 0.1 m/s, ramps of 0.1 / 15 s at each end
    assert plan.cycle_time == pytest.approx(0.03 / 0.1 + 0.1 / 15.0, rel=1e-3)


@pytest.mark.parametrize("feed", [600, 60000])
def test_a_line_from_rest_is_optimal_under_motor_torque(feed: int, params, motors) -> None:
    _against_reference(f"G1 X30 Y10 F{feed}\n", motors, params)


@pytest.mark.slow
def test_an_arc_is_optimal(params, motors) -> None:
    text = "G1 X20 F12000\nG3 X0 Y20 I-20 J0\n"
    _against_reference(text, SLIDERS, params)
    _against_reference(text, motors, params)


@pytest.mark.slow
@pytest.mark.parametrize("which", ["sliders", "motors"])
def test_the_pocket_is_optimal(which: str, params, motors) -> None:
    limits = SLIDERS if which == "sliders" else motors
    # the shipped pocket's first passes: the plunge, then blended zig-zag lines
    head = "\n".join(example_program_text("pocket").splitlines()[:20]) + "\n"
    _against_reference(head, limits, params)


def test_switch_points_land_where_the_ramp_meets_the_cap() -> None:
    # one row: u <= 10 (a = 0.1), and a cap x <= 1 on a grid of 2 mm from rest
    s = np.array([0.0, 2e-3, 4e-3])
    x = np.array([0.0, 0.04, 1.0])
    a = np.array([[0.1], [0.1], [0.1]])
    zero = np.zeros((3, 1))
    added = switch_points(s, x, (a, zero, zero), np.ones(3))
    # from x = 0.04 at 2 mm, x = 1 is reached after 0.96 / 20 = 48 mm: no switch; from rest,
    # the ramp fills the first interval exactly (x = 2 * 10 * 2e-3 = 0.04): nothing to add
    assert added.size == 0
    slow = np.array([0.0, 0.01, 1.0])
    added = switch_points(s, slow, (a, zero, zero), np.ones(3))
    assert added.size == 1 and 0.0 < added[0] < 2e-3


def test_switch_points_of_sections_together_are_those_of_each() -> None:
    rng = np.random.default_rng(4)
    items = []
    for n in (3, 7, 2, 12):
        s = np.cumsum(rng.uniform(1e-4, 2e-3, n)) - 1e-4
        x = rng.uniform(0.0, 1.0, n)
        x[[0, -1]] = 0.0
        abc = (rng.uniform(0.05, 0.2, (n, 2)), rng.uniform(0.0, 0.5, (n, 2)), np.zeros((n, 2)))
        items.append((s, x, abc, rng.uniform(0.5, 1.5, n)))
    together = switch_points_of(items)
    assert any(p.size for p in together)
    for mine, item in zip(together, items, strict=True):
        np.testing.assert_array_equal(mine, switch_points(*item))
