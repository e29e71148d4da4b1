"""The plan sampled for the cut: which samples cut; the program's spindle speed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from machining._support import CUT, DT

import orthoglide_pin as og
from orthoglide_pin.machining.plan_samples import cut_samples, program_spindle_speed


def test_only_the_feed_moves_in_the_plane_cut(
    planned: tuple[og.OrthoglideParams, og.Plan],
) -> None:
    _, plan = planned
    s = cut_samples(plan, og.cut_conditions(CUT), DT)
    assert set(np.unique(s.line[s.cutting])) <= {3, 4, 5, 6}
    assert {4, 5, 6} <= set(np.unique(s.line[s.cutting]))
    assert not s.cutting[np.isin(s.line, [2, 7])].any()  # the rapids
    plunge = s.line == 3
    assert (~s.cutting[plunge]).sum() > 0.9 * plunge.sum()  # along the tool: drilling
    only = og.cut_conditions({**CUT, "engagement": {**CUT["engagement"], "lines": [5, 5]}})
    s5 = cut_samples(plan, only, DT)
    assert set(np.unique(s5.line[s5.cutting])) == {5}


def test_the_program_s_word_is_its_spindle_speed() -> None:
    assert program_spindle_speed("G21\nG0 X1 S12000 (S5 in a comment)\nM3 S12000\n") == (
        pytest.approx(12000 * 2 * math.pi / 60)
    )
    assert program_spindle_speed("G1 X1 F100\n") is None
    with pytest.raises(og.CutConditionsError, match="line 1 says S100, line 2 S200"):
        program_spindle_speed("S100\nS200\n")
    with pytest.raises(og.CutConditionsError, match="spindle_speed=0"):
        program_spindle_speed("M3 S0\n")
