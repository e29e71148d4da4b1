"""The largest certified cube around the design method's cube."""

from __future__ import annotations

import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.largest_cube import SIDE_RESOLUTION, largest_certified_side

#: The paper's design: a 200 mm cube, factors in [0.5, 2] (leg 310.58 mm).
PAPER = og.design_from_workspace(0.2, 0.5, 2.0, grid_points=2)


def test_largest_certified_side() -> None:
    # the design's cube meets its bounds exactly at Q1 and Q2: with the criterion's
    # tolerance (the rule certify applies) it is certified itself, and the largest
    # certified side is found to within the resolution around it
    centre = (PAPER.q1 + PAPER.q2) / 2
    assert og.certify_cube(PAPER.leg_length, centre - 0.1, 0.2, 0.5, 2.0).certified
    for guess in (0.2, 0.15, 0.23):  # a short or long guess widens the bracket
        side = largest_certified_side(PAPER.leg_length, centre, 0.5, 2.0, guess=guess)
        assert abs(side - 0.2) < SIDE_RESOLUTION, guess
        assert og.certify_cube(PAPER.leg_length, centre - side / 2, side, 0.5, 2.0).certified
        wider = side + SIDE_RESOLUTION
        cert = og.certify_cube(PAPER.leg_length, centre - wider / 2, wider, 0.5, 2.0)
        assert cert.status == "violated", guess


def test_another_design_and_the_sides_around_the_answer() -> None:
    made = og.design_from_workspace(0.15, 0.6, 1.5, grid_points=2)
    centre = (made.q1 + made.q2) / 2
    side = largest_certified_side(made.leg_length, centre, 0.6, 1.5, guess=0.15, resolution=1e-3)
    assert 0.15 - 1e-3 <= side < 0.15 + 1e-3
    inside = og.certify_cube(made.leg_length, centre - side / 2, side, 0.6, 1.5)
    assert inside.certified
    wider = side + 1e-3
    outside = og.certify_cube(made.leg_length, centre - wider / 2, wider, 0.6, 1.5)
    assert outside.status == "violated"


def test_bad_resolution() -> None:
    with pytest.raises(InvalidParameterError, match="resolution"):
        largest_certified_side(0.3, [0, 0, 0], 0.5, 2.0, guess=0.1, resolution=-1.0)
