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
    low, high = cert.proven_bounds  # the criterion widened by the tolerance (the rule)
    for factors in (
        og.transmission_factors(p, cert.leg_length),
        lapack_factors(p, cert.leg_length),
    ):
        assert factors[0] < low or factors[2] > high
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


def test_the_design_cube_is_certified_within_the_tolerance_of_the_rule() -> None:
    # Q1 and Q2 sit on the bounds: the rule's tolerance makes the proof possible,
    # the margin is measured to the widened bounds, and a finer tolerance that the
    # boxes cannot resolve leaves it undecided (never certified, never violated)
    cert = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.5, 2.0)
    assert cert.status == "certified" and cert.certified and cert.tight
    assert cert.proven_bounds == (0.5 - CERTIFY_TOL, 2.0 + CERTIFY_TOL)
    lo, hi = cert.factor_bounds
    assert 0.5 - CERTIFY_TOL <= lo <= 0.5 + SVD_TOL and 2.0 - SVD_TOL <= hi <= 2.0 + CERTIFY_TOL
    assert 0.0 <= cert.margin == pytest.approx(min(lo - 0.4999, 2.0001 - hi), abs=1e-15)
    assert "within 0.0001 of [0.5, 2]" in cert.reason
    fine = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.5, 2.0, tol=1e-12)
    assert fine.status == "undecided" and "resolution" in fine.reason
    assert fine.counterexample is None and fine.margin < 0.0


def test_a_proof_with_an_unreachable_tolerance_is_still_a_proof() -> None:
    # The prototype is far inside [0.4, 2.5]: a tolerance of 1e-8 on the enclosure
    # is not reached at the depth limit, which makes it loose, not undecided
    corner = np.full(3, CUBE_CORNER)
    cert = certify_cube(PROTOTYPE_LEG, corner, CUBE_SIDE, 0.4, 2.5, tol=1e-8)
    assert cert.status == "certified" and cert.certified
    assert cert.margin > 0.09 and not cert.tight
    assert "not refined to the tolerance" in cert.reason
    loose = certify_cube(PROTOTYPE_LEG, corner, CUBE_SIDE, 0.4, 2.5)
    assert loose.certified and loose.tight
    assert cert.margin == pytest.approx(loose.margin, abs=CERTIFY_TOL)
    # the enclosure holds the factors of a fine grid all the same (another route)
    f = _grid_factors(PROTOTYPE_LEG, corner, CUBE_SIDE)
    assert cert.factor_bounds[0] <= f[:, 0].min() and f[:, 2].max() <= cert.factor_bounds[1]


def test_a_violation_smaller_than_the_tolerance_is_no_violation() -> None:
    # the rule: [psi_min - tol, psi_max + tol]; the paper's design exceeds 1.9999 by 1e-4
    near = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.5, 1.99995)
    assert near.certified
    far = certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.5, 1.9998)
    assert far.status == "violated"
    f = lapack_factors(far.counterexample, PAPER.leg_length)
    assert f[2] > 1.9998 + CERTIFY_TOL


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


def test_certify_defaults_to_the_machines_criterion(params: og.OrthoglideParams) -> None:
    # the prototype carries the paper's [0.5, 2], which its 310 mm legs miss
    own = certify(params)
    assert (own.psi_min, own.psi_max) == (0.5, 2.0) and own.status == "violated"
    wider = params.replace(psi_min=0.498, psi_max=2.01)
    again = certify(wider)
    assert (again.psi_min, again.psi_max) == (0.498, 2.01) and again.certified
    explicit = certify_cube(params.leg_length, np.full(3, CUBE_CORNER), CUBE_SIDE, 0.498, 2.01)
    assert again.factor_bounds == explicit.factor_bounds
    # another design: its file's bounds are the ones certified
    made = og.design_from_workspace(0.15, 0.6, 1.5, grid_points=2).to_params()
    cert = certify(made)
    assert (cert.psi_min, cert.psi_max) == (0.6, 1.5) and cert.certified


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
