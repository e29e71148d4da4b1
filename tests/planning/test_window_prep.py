"""A window prepared from the one before it: the same samples and path forms as alone."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning import read_program, window_prep
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.path import build_path
from orthoglide_pin.planning.window_prep import Prepared, WindowSetting, prepare

LIMITS = PlanLimits(
    slider_speed=1.0, slider_acceleration=15.0, drive=load_drive(str(example_drive_file()))
)
#: Planning-grid spacing of the test [m].
STEP = 2e-3


def _program(seed: int = 5) -> str:
    """Blended short lines over a wave, an arc and a helix among them, one section."""
    rng = np.random.default_rng(seed)
    lines, x = ["G21 G90 G64 P0.01", "G0 X-20 Y0 Z10", "F2400"], -20.0
    for k in range(240):
        x += rng.uniform(0.1, 0.45)
        lines.append(f"G1 X{x:.4f} Y{np.sin(x / 3.0):.4f} Z{10 + 2 * np.cos(x / 5.0):.4f}")
        if k in (60, 150):  # a quarter turn up and back down: arcs inside the windows
            y = np.sin(x / 3.0)
            lines.append(f"G3 X{x + 2:.4f} Y{y + 2:.4f} Z10.5 I0 J2")
            lines.append(f"G2 X{x + 4:.4f} Y{y:.4f} Z10 I2 J0")
            x += 4.0
            lines.append(f"G1 X{x + 0.2:.4f} Y{np.sin(x / 3.0):.4f} Z10")
            x += 0.2
    return "\n".join(lines) + "\n"


def _setting(text: str, params: og.OrthoglideParams) -> WindowSetting:
    path = build_path(read_program(text))
    section = max(path.sections, key=lambda sec: len(sec.pieces))
    blocks = path.program.blocks
    lines = np.array([blocks[p.block].line for p in section.pieces], dtype=np.intp)
    dyn = og.ClosedLoopDynamics(params)
    g = dyn.gravity_vector()
    return WindowSetting(section, lines, dyn, LIMITS, g, None, STEP, None, 8)


def _same(a: Prepared, b: Prepared) -> None:
    for name in ("s", "p", "dp", "ddp", "piece"):
        np.testing.assert_array_equal(getattr(a.fine, name), getattr(b.fine, name), err_msg=name)
        np.testing.assert_array_equal(getattr(a.grid, name), getattr(b.grid, name), err_msg=name)
    for name in ("q", "dq", "ddq", "a", "b", "c"):
        np.testing.assert_array_equal(getattr(a.fine_forms, name), getattr(b.fine_forms, name))
        np.testing.assert_array_equal(getattr(a.inp.forms, name), getattr(b.inp.forms, name))
    np.testing.assert_array_equal(a.fine_lines, b.fine_lines)
    np.testing.assert_array_equal(a.fine_feed, b.fine_feed)
    np.testing.assert_array_equal(a.inp.feed, b.inp.feed)
    np.testing.assert_array_equal(a.inp.s, b.inp.s)


def test_a_window_prepared_from_the_one_before_is_the_window_alone(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    evaluated: list[int] = []  # samples given path forms, each call
    real = window_prep.section_forms

    def counted(dyn, grids, g, w):
        evaluated.append(sum(x.s.size for x in grids))
        return real(dyn, grids, g, w)

    monkeypatch.setattr(window_prep, "section_forms", counted)
    st = _setting(_program(), params)
    count = len(st.section.pieces)
    assert count > 200 and any(p.v is not None for p in st.section.pieces)  # arcs among them
    first = prepare(st, 0, 170)
    assert any(p.v is not None for p in st.section.pieces[120:170])  # in the shared pieces
    for lo, hi in ((120, 230), (169, count), (0, 171)):
        taken, alone = prepare(st, lo, hi, first), prepare(st, lo, hi)
        _same(taken, alone)
        assert taken.fine.s.size == alone.fine.s.size > 0
        shared = int(np.searchsorted(alone.fine.piece, 170 - lo))  # samples of pieces lo:170
        assert evaluated[-2:] == [alone.fine.s.size - shared, alone.fine.s.size]
    # windows that do not overlap it (or that it reaches past) are prepared alone
    _same(prepare(st, 170, 200, first), prepare(st, 170, 200))
    _same(prepare(st, 10, 150, first), prepare(st, 10, 150))


def test_the_new_pieces_are_still_checked_inside_the_workspace(
    params: og.OrthoglideParams,
) -> None:
    """A window whose new pieces leave the cube is refused, its line named."""
    lines = _program().splitlines()
    lines.append("G1 X400 Y0 Z10")  # far out of the cube, in the last window only
    st = _setting("\n".join(lines) + "\n", params)
    count = len(st.section.pieces)
    first = prepare(st, 0, count - 5)
    with pytest.raises(ProgramError, match=f"line {len(lines)}") as caught:
        prepare(st, count - 20, count, first)
    assert "outside" in str(caught.value)
