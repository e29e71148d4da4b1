"""Long sections planned in windows: the same plan as whole, verified, from any start."""

from __future__ import annotations

import itertools
import threading

import numpy as np
import pytest

import orthoglide_pin.planning.plan as plan_module
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning import read_program, windows
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.reachability import reach
from orthoglide_pin.planning.verify import USE_TOL

pytest.importorskip("toppra")

SLIDERS = PlanLimits(slider_speed=1.0, slider_acceleration=15.0)
#: Windowed and whole plans' cycle times agree within this share (look-ahead long enough).
AGREE_RTOL = 1e-4
#: Blocks of the test program.
BLOCKS = 300
#: The rapid override of the windowed rapid moves [-].
RAPID = 0.4
#: Blocks of the rapid test program (still planned in windows).
RAPID_BLOCKS = 150


def _relief(blocks: int, feed: float, seed: int = 3) -> str:
    """Short blended G1 blocks (0.1 to 0.45 mm) over a relief, one section."""
    rng = np.random.default_rng(seed)
    lines, x = ["G21 G90 G64 P0.01", "G0 X-20 Y0 Z10", f"F{feed:g}"], -20.0
    for _ in range(blocks):
        x += rng.uniform(0.1, 0.45)
        lines.append(f"G1 X{x:.4f} Y{np.sin(x / 3.0):.4f} Z{10 + 2 * np.cos(x / 5.0):.4f}")
    return "\n".join(lines) + "\n"


@pytest.fixture
def small_windows(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(windows, "WINDOW_POINTS", 400)
    monkeypatch.setattr(windows, "LOOK_AHEAD_POINTS", 200)
    monkeypatch.setattr(windows, "WINDOWED_ABOVE", 800)
    _unrefined(monkeypatch)  # every plan here on its first grid: windows and whole alike


def _unrefined(m: pytest.MonkeyPatch) -> None:
    """Whole sections keep their first grid, as windows do (planning.grid refines whole ones)."""
    m.setattr(plan_module, "refine_grid", lambda moving, grids, inputs, *rest: (grids, inputs))


def _whole(monkeypatch: pytest.MonkeyPatch, prog, params, limits, **options):
    """The plan of the same program with every section planned whole, on the same grid."""
    with monkeypatch.context() as m:
        m.setattr(windows, "WINDOWED_ABOVE", 10**9)
        _unrefined(m)
        return plan_program(prog, params, limits, **options)


def test_windowed_plan_agrees_with_the_whole(small_windows, monkeypatch, params) -> None:
    prog = read_program(_relief(BLOCKS, 3000))
    drive = PlanLimits(
        slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(str(example_drive_file()))
    )
    for limits in (SLIDERS, drive):
        plan = plan_program(prog, params, limits)
        whole = _whole(monkeypatch, prog, params, limits)
        assert plan.sections[-1].motion is None  # the relief, planned in windows
        assert whole.sections[-1].motion is not None  # planned whole
        assert plan.cycle_time == pytest.approx(whole.cycle_time, rel=AGREE_RTOL)
        assert plan.grid_points == whole.grid_points
        law = plan.sections[-1].plan
        assert law is not None and np.all(np.diff(law.s) > 0.0)  # windows joined once
        assert max(plan.worst.values()) <= 1.0 + USE_TOL
        assert plan.worst.keys() == whole.worst.keys()
        times = [(b.start, b.end) for b in plan.blocks]
        assert all(a[1] <= b[0] + 1e-9 for a, b in itertools.pairwise(times))


def test_short_look_ahead_is_slower_never_over(small_windows, monkeypatch, params) -> None:
    """A look-ahead shorter than the braking distance: slower than whole, still verified."""
    monkeypatch.setattr(windows, "LOOK_AHEAD_POINTS", 8)
    prog = read_program(_relief(BLOCKS, 60000))
    plan = plan_program(prog, params, SLIDERS)
    whole = _whole(monkeypatch, prog, params, SLIDERS)
    assert plan.cycle_time >= whole.cycle_time * (1.0 - 1e-9)
    assert max(plan.worst.values()) <= 1.0 + USE_TOL


def test_reach_from_a_start_speed() -> None:
    """``start`` is kept when the path can brake from it, refused when it cannot."""
    s = np.linspace(0.0, 0.1, 51)
    a = np.tile([1.0, -1.0], (s.size, 1))  # |u| <= 1
    zeros = np.zeros_like(a)
    bound = np.full(s.size, 1.0)
    x = reach(s, a, zeros, zeros, bound, start=0.1)
    assert x is not None and x[0] == pytest.approx(0.1) and x[-1] == pytest.approx(0.0)
    assert np.all(np.abs(np.diff(x) / (2 * np.diff(s))) <= 1.0 + 1e-9)
    assert reach(s, a, zeros, zeros, bound, start=0.5) is None  # 0.1 m cannot brake from it


def test_a_window_that_cannot_start_makes_the_previous_one_stop(
    small_windows, monkeypatch, params
) -> None:
    """No window can start moving: each one before it ends at rest, still in windows."""
    real = windows.plan_window
    monkeypatch.setattr(
        windows,
        "plan_window",
        lambda inp, lim, start, cache=None: None if start > 0 else real(inp, lim, start, cache),
    )
    prog = read_program(_relief(BLOCKS, 3000))
    plan = plan_program(prog, params, SLIDERS)
    whole = _whole(monkeypatch, prog, params, SLIDERS)
    assert plan.sections[-1].motion is None  # still in windows
    assert max(plan.worst.values()) <= 1.0 + USE_TOL
    assert plan.cycle_time > whole.cycle_time  # it stops between windows
    law = plan.sections[-1].plan
    assert law is not None and np.count_nonzero(law.x[1:-1] == 0.0) >= 1


def test_a_windowed_rapid_section_follows_the_rapid_override(
    small_windows, monkeypatch, params
) -> None:
    """Blended G0 blocks planned in windows: capped by the override as when planned whole."""
    text = _relief(RAPID_BLOCKS, 3000).replace("G1 ", "G0 ")
    prog = read_program(text)
    calls: list[tuple[int, int]] = []
    slow = plan_program(
        prog, params, SLIDERS, rapid_override=RAPID, progress=lambda d, t: calls.append((d, t))
    )
    full = plan_program(prog, params, SLIDERS)
    whole = _whole(monkeypatch, prog, params, SLIDERS, rapid_override=RAPID)
    law, law_whole, law_full = (p.sections[-1].plan for p in (slow, whole, full))
    assert law is not None and law_whole is not None and law_full is not None
    assert slow.sections[-1].motion is None  # planned in windows
    assert slow.sections[-1].section.pieces[0].feed is None  # a rapid section
    top = np.sqrt(law.x.max())  # the override's cap, as when planned whole
    assert top == pytest.approx(np.sqrt(law_whole.x.max()), rel=AGREE_RTOL)
    assert top < 0.8 * np.sqrt(law_full.x.max())
    assert slow.cycle_time >= whole.cycle_time * (1.0 - 1e-9)
    assert max(slow.worst.values()) <= 1.0 + USE_TOL
    done = [d for d, _ in calls]
    assert done == sorted(done) and len(calls) > 3  # told window by window
    assert calls[-1] == (len(prog.blocks), len(prog.blocks))


def _pool_threads() -> set[threading.Thread]:
    return {t for t in threading.enumerate() if t.name.startswith("ThreadPoolExecutor")}


def test_the_next_window_prepared_beside_leaves_no_thread(small_windows, params) -> None:
    """Planned with the next window prepared on a second thread: no thread outlives it."""
    prog = read_program(_relief(BLOCKS, 3000))
    before = _pool_threads()
    plan = plan_program(prog, params, SLIDERS)
    assert plan.sections[-1].motion is None  # in windows
    assert _pool_threads() == before


@pytest.mark.parametrize("error", [ProgramError(7, "a later window"), KeyboardInterrupt()])
def test_an_error_while_the_next_window_is_prepared_stops_the_plan(
    small_windows, monkeypatch, params, error
) -> None:
    """An error in a later window's preparation, or an interrupt, ends the plan and its thread."""
    real = windows._prepare

    def prepare(st, lo, hi, *before):
        if lo > 0:
            raise error
        return real(st, lo, hi, *before)

    monkeypatch.setattr(windows, "_prepare", prepare)
    before = _pool_threads()
    with pytest.raises(type(error)):
        plan_program(read_program(_relief(BLOCKS, 3000)), params, SLIDERS)
    assert _pool_threads() == before
