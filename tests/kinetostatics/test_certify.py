"""Certified workspace: verdicts, counterexamples and enclosures, each checked by another route."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, lapack_factors

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.certify import (
    CERTIFY_TOL,
    certify,
    certify_cube,
)

# the module itself (the package's ``certify`` attribute is the function)
certify_module = sys.modules["orthoglide_pin.kinetostatics.certify"]

#: The paper's design: a 200 mm cube, factors in [0.5, 2] (leg 310.58 mm).
PAPER = og.design_from_workspace(0.2, 0.5, 2.0, grid_points=2)
#: Points per edge of the grids the enclosures must contain.
GRID = 41
#: Rounding of the closed form against LAPACK (well-conditioned points).
SVD_TOL = 1e-10


def _grid_factors(L: float, corner: np.ndarray, side: float) -> np.ndarray:
    points = og.cube_grid(corner, side, GRID).points().reshape(-1, 3)
    return lapack_factors(points, L)


def _assert_counterexample(cert: og.Certification) -> None:
    """Inside the cube, and out of the bounds by the closed form and by LAPACK."""
    p = cert.counterexample
    assert p is not None and cert.counterexample_factors is not None
    assert np.all(p >= cert.corner) and np.all(p <= cert.corner + cert.side)
    for factors in (
        og.transmission_factors(p, cert.leg_length),
        lapack_factors(p, cert.leg_length),
    ):
        assert factors[0] < cert.psi_min or factors[2] > cert.psi_max
    np.testing.assert_allclose(
        cert.counterexample_factors, og.transmission_factors(p, cert.leg_length), rtol=SVD_TOL
    )


def test_the_paper_design_is_certified_for_slightly_wider_bounds() -> None:
    cert = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.499, 2.001)
    assert cert.certified and cert.status == "certified"
    assert cert.counterexample is None
    lo, hi = cert.factor_bounds
    assert lo >= 0.499 and hi <= 2.001 and cert.margin > 0.0
    # tight: Q2 reaches 0.5 and Q1 reaches 2 exactly (design method), closed forms
    assert 0.5 - CERTIFY_TOL <= lo <= 0.5 + SVD_TOL
    assert 2.0 - SVD_TOL <= hi <= 2.0 + CERTIFY_TOL
    assert cert.tight and cert.boxes > 8


def test_the_paper_design_is_not_certified_for_slightly_narrower_bounds() -> None:
    cert = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.501, 1.999)
    assert not cert.certified and cert.status == "violated"
    _assert_counterexample(cert)
    assert "outside [0.501, 1.999]" in cert.reason


def test_a_210_mm_cube_with_the_310_mm_leg_is_not_certified() -> None:
    corner = np.full(3, CUBE_CORNER)
    cert = certify_cube(PROTOTYPE_LEG, corner, 0.21, 0.5, 2.0)
    assert not cert.certified and cert.status == "violated"
    _assert_counterexample(cert)
    # its enclosure still holds the factors of the whole cube, tightly
    f = _grid_factors(PROTOTYPE_LEG, corner, 0.21)
    lo, hi = cert.factor_bounds
    assert lo <= f[:, 0].min() <= lo + CERTIFY_TOL
    assert hi - CERTIFY_TOL <= f[:, 2].max() <= hi


@pytest.mark.parametrize(
    ("L", "corner", "side"),
    [
        (PAPER.leg_length, PAPER.cube_corner, 0.2),  # the paper's design
        (PROTOTYPE_LEG, np.full(3, CUBE_CORNER), CUBE_SIDE),  # the prototype: 310 mm
        (0.25, np.array([-0.02, -0.09, 0.01]), 0.12),  # off the diagonal
    ],
)
def test_the_enclosure_contains_every_factor_of_a_fine_grid(
    L: float, corner: np.ndarray, side: float
) -> None:
    cert = certify_cube(L, corner, side, 0.1, 10.0)
    assert cert.certified
    f = _grid_factors(L, corner, side)
    lo, hi = cert.factor_bounds
    assert np.all(f >= lo) and np.all(f <= hi)
    # the extremes are at corners of these cubes (on the grid): tight to the tolerance
    assert f[:, 0].min() - lo <= CERTIFY_TOL and hi - f[:, 2].max() <= CERTIFY_TOL


def test_another_design_widened_bounds_and_the_lower_bound_never_reached() -> None:
    # the paper's claim for [1/3, 3]: both corners reach 3, and 1/3 is never reached
    made = og.design_from_workspace(0.15, 1.0 / 3.0, 3.0, grid_points=2)
    cert = made.certify()
    assert cert.certified
    lo, hi = cert.factor_bounds
    assert lo > 0.4 and abs(hi - 3.0) <= CERTIFY_TOL  # 3 / 7 = 0.4286 at Q2 (closed form)
    assert lo == pytest.approx(3.0 / 7.0, abs=CERTIFY_TOL)
    narrower = certify_cube(made.leg_length, made.cube_corner, 0.15, 0.2, 2.99)
    assert narrower.status == "violated"
    _assert_counterexample(narrower)


def test_the_design_cube_itself_reaches_its_bounds_exactly() -> None:
    # Q1 and Q2 sit on the bounds: no proof with a margin, and no violation either
    cert = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.5, 2.0)
    assert cert.status == "undecided" and not cert.certified
    assert cert.counterexample is None
    assert -CERTIFY_TOL < cert.margin < 0.0


def test_a_cube_meeting_a_singularity() -> None:
    L = 0.3
    # partly out of reach of leg 1: a point with non-finite factors is a counterexample
    out = certify_cube(L, [0.0, 0.2, 0.2], 0.05, 1e-3, 1e3)
    assert out.status == "violated" and "out of reach or singular" in out.reason
    assert not np.isfinite(og.transmission_factors(out.counterexample, L, check=False)).all()
    # 5 mm from the serial surface of leg 1, unresolved at a coarse depth: huge factors
    # keep the enclosure of J^-1 from proving it regular, and the reason says so
    near = certify_cube(L, [0.0, 0.2, 0.2], 0.0121, 1e-12, 1e12, max_depth=2)
    assert near.status == "singular" and "singular surface" in near.reason
    assert near.counterexample is None
    assert near.factor_bounds[1] == math.inf
    text = json.dumps(near.to_dict(), allow_nan=False)  # strict JSON
    assert json.loads(text)["factor_bounds"][1] is None


def test_certify_defaults_to_the_machines_cube(params: og.OrthoglideParams) -> None:
    default = certify(params, psi_min=0.498, psi_max=2.01)
    explicit = certify_cube(params.leg_length, np.full(3, CUBE_CORNER), CUBE_SIDE, 0.498, 2.01)
    assert default.factor_bounds == explicit.factor_bounds and default.certified
    np.testing.assert_allclose(default.corner, CUBE_CORNER)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"psi_min": 2.0, "psi_max": 1.0}, "psi_min"),
        ({"side": -0.1}, "side"),
        ({"corner": [0.0, 0.0]}, "corner"),
        ({"leg_length": math.nan}, "leg_length"),
        ({"tol": 0.0}, "tol"),
        ({"max_boxes": 0}, "max_boxes"),
    ],
)
def test_bad_input_names_the_value(kwargs: dict[str, object], name: str) -> None:
    args: dict[str, object] = {
        "leg_length": 0.3,
        "corner": [0.0, 0.0, 0.0],
        "side": 0.1,
        "psi_min": 0.5,
        "psi_max": 2.0,
    }
    args.update(kwargs)
    with pytest.raises(InvalidParameterError, match=name):
        certify_cube(**args)  # type: ignore[arg-type]


def test_the_box_budget_leaves_it_undecided() -> None:
    cert = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.4999, 2.0001, max_boxes=20)
    assert cert.status == "undecided" and "budget" in cert.reason
    f = _grid_factors(PAPER.leg_length, PAPER.cube_corner, 0.2)
    assert cert.factor_bounds[0] <= f[:, 0].min() and f[:, 2].max() <= cert.factor_bounds[1]
    assert certify_module.MAX_BOXES > 20


def test_the_axis_permutations_of_a_diagonal_cube_change_nothing_but_the_work() -> None:
    # one orbit of boxes per permutation on the diagonal; a corner off the diagonal
    # by 1 nm takes the plain route through every box
    plain_corner = PAPER.cube_corner + np.array([0.0, 0.0, 1e-9])
    fast = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.499, 2.001)
    plain = certify_cube(PAPER.leg_length, plain_corner, 0.2, 0.499, 2.001)
    assert fast.certified and plain.certified
    np.testing.assert_allclose(fast.factor_bounds, plain.factor_bounds, atol=CERTIFY_TOL)
    assert 2 * fast.boxes < plain.boxes
