"""The largest certified cube around the design method's cube."""

from __future__ import annotations

import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.largest_cube import SIDE_RESOLUTION, largest_certified_side

#: The paper's design: a 200 mm cube, factors in [0.5, 2] (leg 310.58 mm).
PAPER = og.design_from_workspace(0.2, 0.5, 2.0, grid_points=2)


def test_largest_certified_side() -> None:
    centre = (PAPER.q1 + PAPER.q2) / 2
    side = largest_certified_side(PAPER.leg_length, centre, 0.5, 2.0, guess=0.2)
    assert 0.2 - SIDE_RESOLUTION <= side < 0.2
    far = largest_certified_side(PAPER.leg_length, centre, 0.5, 2.0, guess=0.15)
    assert 0.2 - SIDE_RESOLUTION <= far < 0.2  # a short guess widens the bracket
    high = largest_certified_side(PAPER.leg_length, centre, 0.5, 2.0, guess=0.23)
    assert 0.2 - SIDE_RESOLUTION <= high < 0.2


def test_another_design_and_the_sides_around_the_answer() -> None:
    made = og.design_from_workspace(0.15, 0.6, 1.5, grid_points=2)
    centre = (made.q1 + made.q2) / 2
    side = largest_certified_side(made.leg_length, centre, 0.6, 1.5, guess=0.15, resolution=1e-3)
    assert 0.15 - 1e-3 <= side < 0.15
    inside = og.certify_cube(made.leg_length, centre - side / 2, side, 0.6, 1.5)
    assert inside.certified
    wider = side + 1e-3
    outside = og.certify_cube(made.leg_length, centre - wider / 2, wider, 0.6, 1.5)
    assert outside.status == "violated"


def test_bad_resolution() -> None:
    with pytest.raises(InvalidParameterError, match="resolution"):
        largest_certified_side(0.3, [0, 0, 0], 0.5, 2.0, guess=0.1, resolution=-1.0)
