"""Tests of the design from a prescribed workspace (orthoglide_pin.kinetostatics.design)."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, jacobian
from orthoglide_pin.kinetostatics import design as design_module
from orthoglide_pin.kinetostatics.design import (
    WorkspaceDesign,
    design_from_workspace,
    diagonal_factors,
    prototype_cube,
)

# the module itself (the package's ``factor_range`` attribute is the function)
factor_range_module = sys.modules["orthoglide_pin.kinetostatics.factor_range"]

#: The paper's prototype (section 4): cube side [m], bounds, leg [m], stroke [m], ratio.
SIDE = 0.2
BOUNDS = (0.5, 2.0)
PAPER_LEG = 0.3106
PAPER_STROKE = 0.2570
PAPER_RATIO = 0.78
#: The paper's figures are rounded: leg and stroke to 0.1 mm, the ratio to 0.01.
PAPER_LENGTH_TOL = 5e-5
PAPER_RATIO_TOL = 5e-3
#: Closed-form identities and rounding of the factors on the grid.
EXACT_TOL = 1e-12
#: Factors by LAPACK vs the bounds on an independent grid (rounding only).
GRID_TOL = 1e-9
#: The Pinocchio closed-loop model vs the closed form [m] or dimensionless.
MODEL_TOL = 1e-9
#: Slider range by brute force on a face grid of 401^2 points [m].
RANGE_TOL = 1e-6
#: Admissible bound pairs: the paper's, wider, narrower, asymmetric both ways.
ADMISSIBLE = [(0.5, 2.0), (1 / 3, 3.0), (0.6, 1.5), (0.5, 3.0), (0.8, 4.0), (0.2, 1.25)]


@pytest.fixture(scope="module")
def prototype_design() -> WorkspaceDesign:
    return design_from_workspace(SIDE, *BOUNDS)


def lapack_factors(points: np.ndarray, leg: float) -> np.ndarray:
    return np.linalg.svd(jacobian(points, leg), compute_uv=False)[..., ::-1]


def test_reproduces_the_paper_prototype(prototype_design: WorkspaceDesign) -> None:
    d = prototype_design
    assert d.leg_length == pytest.approx(PAPER_LEG, abs=PAPER_LENGTH_TOL)
    assert d.stroke == pytest.approx(PAPER_STROKE, abs=PAPER_LENGTH_TOL)
    assert d.ratio == pytest.approx(PAPER_RATIO, abs=PAPER_RATIO_TOL)
    # [0.5, 2]: Q1 where 2 is reached (t = -L/sqrt(18)), Q2 where both are (t = L/sqrt(6))
    leg = d.leg_length
    np.testing.assert_allclose(d.q1, np.full(3, -leg / math.sqrt(18.0)), rtol=EXACT_TOL)
    np.testing.assert_allclose(d.q2, np.full(3, leg / math.sqrt(6.0)), rtol=EXACT_TOL)
    expected_leg = SIDE / (1 / math.sqrt(6.0) + 1 / math.sqrt(18.0))
    assert leg == pytest.approx(expected_leg, rel=EXACT_TOL)
    np.testing.assert_array_equal(d.cube_corner, d.q1)
    np.testing.assert_allclose(d.q2 - d.q1, SIDE, rtol=EXACT_TOL)
    np.testing.assert_allclose(d.factors_q1, [0.8, 0.8, 2.0], rtol=EXACT_TOL)
    np.testing.assert_allclose(d.factors_q2, [0.5, 2.0, 2.0], rtol=EXACT_TOL)


def test_bounds_hold_on_the_grid_and_are_reached_at_q1_q2(
    prototype_design: WorkspaceDesign,
) -> None:
    d = prototype_design
    assert d.bounds_hold
    assert d.grid_points == design_module.VERIFY_POINTS
    assert d.psi_min_found == pytest.approx(BOUNDS[0], rel=EXACT_TOL)
    assert d.psi_max_found == pytest.approx(BOUNDS[1], rel=EXACT_TOL)
    for where in (d.psi_min_at, d.psi_max_at):
        assert min(np.abs(where - d.q1).max(), np.abs(where - d.q2).max()) < EXACT_TOL
    # an independent grid, factors by LAPACK
    g = np.linspace(d.q1[0], d.q2[0], 25)
    points = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    s = lapack_factors(points, d.leg_length)
    assert s.min() >= BOUNDS[0] - GRID_TOL
    assert s.max() <= BOUNDS[1] + GRID_TOL


def test_stroke_is_the_slider_range_over_the_whole_cube(prototype_design: WorkspaceDesign) -> None:
    d = prototype_design
    # q_i is monotonic in p_i: its extremes lie on the faces p_i = lo and p_i = hi
    g = np.linspace(d.q1[0], d.q2[0], 401)
    a, b = (m.reshape(-1) for m in np.meshgrid(g, g, indexing="ij"))
    faces = [np.stack([np.full_like(a, c), a, b], axis=-1) for c in (d.q1[0], d.q2[0])]
    q = inverse_kinematics(np.concatenate(faces), d.leg_length)[:, 0]  # leg 1, by symmetry
    assert q.min() == pytest.approx(d.slider_limits[0], abs=RANGE_TOL)
    assert q.max() == pytest.approx(d.slider_limits[1], abs=RANGE_TOL)
    assert d.stroke == pytest.approx(d.slider_limits[1] - d.slider_limits[0], rel=EXACT_TOL)
    # the extremes are not both at Q1 / Q2
    q_ref = inverse_kinematics(np.stack([d.q1, d.q2]), d.leg_length)[:, 0]
    assert q_ref[1] - q_ref[0] < d.stroke - 0.01


@pytest.mark.parametrize("bounds", ADMISSIBLE)
def test_any_admissible_bounds(bounds: tuple[float, float]) -> None:
    lo, hi = bounds
    d = design_from_workspace(SIDE, lo, hi, grid_points=41)
    assert d.bounds_hold
    assert d.q2[0] - d.q1[0] == pytest.approx(SIDE, rel=EXACT_TOL)
    assert d.q1[0] < 0.0 < d.q2[0]
    # The first bound reached on each side of home along the diagonal (paper eqs.)
    for point in (d.q1, d.q2):
        along, twice = diagonal_factors(point[0], d.leg_length)
        reached = [v for v in (along, twice) if min(abs(v - lo), abs(v - hi)) < EXACT_TOL]
        assert reached, (along, twice)
    s = lapack_factors(np.stack([d.q1, d.q2]), d.leg_length)
    np.testing.assert_allclose(s, np.stack([d.factors_q1, d.factors_q2]), rtol=1e-9)
    # between home and Q1 / Q2 every factor stays strictly inside the bounds
    t = np.concatenate([np.linspace(d.q1[0], 0, 50)[1:], np.linspace(0, d.q2[0], 50)[:-1]])
    inner = lapack_factors(t[:, None] * np.ones(3), d.leg_length)
    assert inner.min() > lo and inner.max() < hi
    # the extremes over the whole cube are those of Q1 and Q2 (the paper's claim)
    assert d.psi_min_found == pytest.approx(s.min(), rel=EXACT_TOL)
    assert d.psi_max_found == pytest.approx(s.max(), rel=EXACT_TOL)


def test_a_failed_verification_is_reported(monkeypatch: pytest.MonkeyPatch) -> None:
    real = factor_range_module.transmission_factor_map

    def spoiled(grid: og.Grid, leg: float) -> np.ndarray:
        out = real(grid, leg)
        out[1, 2, 3] = np.nan  # a point out of reach, say
        return out

    monkeypatch.setattr(factor_range_module, "transmission_factor_map", spoiled)
    d = design_from_workspace(SIDE, *BOUNDS, grid_points=11)
    assert not d.bounds_hold
    assert d.psi_max_found == math.inf
    grid = og.cube_grid(d.cube_corner, SIDE, 11)
    np.testing.assert_array_equal(d.psi_max_at, grid.points()[1, 2, 3])


@pytest.mark.parametrize(("shift", "holds"), [(0.5, True), (1.5, False)])
def test_the_grid_check_applies_the_tolerance_of_the_criterion(
    monkeypatch: pytest.MonkeyPatch, shift: float, holds: bool
) -> None:
    # a factor beyond the bound by half the tolerance passes, by 1.5 times it fails:
    # the rule certify applies (orthoglide_pin.machine.criterion.within)
    real = factor_range_module.transmission_factor_map

    def raised(grid: og.Grid, leg: float) -> np.ndarray:
        out = real(grid, leg)
        out[0, 0, 0, 2] = BOUNDS[1] + shift * og.CRITERION_TOL
        return out

    monkeypatch.setattr(factor_range_module, "transmission_factor_map", raised)
    d = design_from_workspace(SIDE, *BOUNDS, grid_points=5)
    assert d.bounds_hold is holds
    assert d.psi_max_found == BOUNDS[1] + shift * og.CRITERION_TOL


@pytest.mark.parametrize(
    ("side", "lo", "hi", "name"),
    [
        (SIDE, 1.0, 2.0, "psi_min"),
        (SIDE, 1.2, 2.0, "psi_min"),
        (SIDE, 0.0, 2.0, "psi_min"),
        (SIDE, 0.5, 1.0, "psi_max"),
        (SIDE, 0.5, 0.8, "psi_max"),
        (SIDE, 0.5, math.inf, "psi_max"),
        (0.0, 0.5, 2.0, "side"),
        (-0.2, 0.5, 2.0, "side"),
        (math.nan, 0.5, 2.0, "side"),
        ("big", 0.5, 2.0, "side"),
    ],
)
def test_impossible_inputs(side: object, lo: float, hi: float, name: str) -> None:
    with pytest.raises(InvalidParameterError) as info:
        design_from_workspace(side, lo, hi)  # type: ignore[arg-type]
    assert info.value.name == name


def test_to_params_and_model(prototype_design: WorkspaceDesign) -> None:
    d = prototype_design
    params = d.to_params()
    assert params.leg_length == d.leg_length
    assert (params.slider_lower, params.slider_upper) == d.slider_limits
    # the design's cube is the machine's workspace, and the limits stay derived from it
    assert params.workspace == og.Cube(tuple(d.cube_corner.tolist()), d.cube_side)
    assert params.derived_limits == ("slider_lower", "slider_upper")
    base = og.prototype().replace(spindle_mass=3.5, psi_min=0.3)
    assert d.to_params(base).spindle_mass == 3.5
    assert (d.to_params(base).psi_min, d.to_params(base).psi_max) == BOUNDS
    assert d.urdf() == og.render_urdf(params)
    model = d.model()  # URDF rendered and closed-loop model loaded in one call
    assert model.params == params
    assembly = model.solve(inverse_kinematics(d.q2, d.leg_length))
    np.testing.assert_allclose(assembly.tool_position, d.q2, atol=MODEL_TOL)
    assert model.mobility(assembly.q) == 3
    J = model.jacobian(assembly.q)
    np.testing.assert_allclose(J, jacobian(d.q2, d.leg_length), atol=MODEL_TOL)
    s = np.linalg.svd(J, compute_uv=False)
    assert s.min() == pytest.approx(BOUNDS[0], rel=MODEL_TOL)


@pytest.mark.parametrize(("lo", "hi"), ADMISSIBLE)
def test_every_admissible_design_becomes_a_machine(lo: float, hi: float) -> None:
    """Through the Pinocchio model of the designed machine, Q1 and Q2 each reach a bound."""
    d = design_from_workspace(SIDE, lo, hi, grid_points=21)
    model = d.model()
    for corner in (d.q1, d.q2):
        q = model.solve(inverse_kinematics(corner, d.leg_length)).q
        s = np.linalg.svd(model.jacobian(q), compute_uv=False)
        assert lo - MODEL_TOL <= s.min() and s.max() <= hi + MODEL_TOL
        assert min(abs(s.min() - lo), abs(s.max() - hi)) < MODEL_TOL


def test_to_dict_is_json(prototype_design: WorkspaceDesign) -> None:
    data = json.loads(json.dumps(prototype_design.to_dict()))
    for key in ("leg_length", "stroke", "slider_limits", "q1", "q2", "ratio"):
        assert key in data
    assert data["bounds_hold"] is True


def test_prototype_cube() -> None:
    corner, side = prototype_cube(og.prototype())
    L = og.prototype().leg_length
    np.testing.assert_array_equal(corner, np.full(3, -L / math.sqrt(18.0)))
    assert side == SIDE
    # the prototype's slider limits are the range over that cube
    lo, hi = og.slider_range_over_cube(L, corner, side)
    assert (lo, hi) == (og.prototype().slider_lower, og.prototype().slider_upper)
    # another leg keeps the cube (it is part of the machine); the limits follow the leg
    longer = og.prototype().replace(leg_length=0.4)
    longer_corner, longer_side = prototype_cube(longer)
    np.testing.assert_array_equal(longer_corner, corner)
    assert longer_side == SIDE
    assert (longer.slider_lower, longer.slider_upper) == og.slider_range_over_cube(
        0.4, corner, SIDE
    )
    assert longer.stroke < og.prototype().stroke  # a longer leg: less slider travel


def test_the_designed_machine_carries_its_criterion() -> None:
    # another design than the paper's: its bounds become the machine's and its file's
    d = design_from_workspace(0.25, 0.4, 2.5, grid_points=5)
    params = d.to_params()
    assert (params.psi_min, params.psi_max) == (0.4, 2.5)
    again = og.OrthoglideParams.from_yaml(params.to_yaml())
    assert again == params and (again.psi_min, again.psi_max) == (0.4, 2.5)
    assert params.replace(leg_length=0.36).psi_max == 2.5  # replace() keeps the criterion
    # the certification of the design and of its machine are one statement
    assert og.certify(params).to_dict() | {"seconds": 0} == d.certify().to_dict() | {"seconds": 0}


def test_the_prototype_note_says_why_its_cube_misses_its_criterion() -> None:
    from orthoglide_pin.kinetostatics.design import prototype_note

    note = prototype_note(og.prototype())
    exact = design_from_workspace(SIDE, *BOUNDS, grid_points=2).leg_length
    assert note is not None and f"{1e3 * exact:.2f} mm" in note and "310.58 mm" in note
    assert "310 mm" in note
    # any other machine, or another criterion: no note
    assert prototype_note(og.prototype().replace(leg_length=exact)) is None
    assert prototype_note(og.prototype().replace(psi_max=2.1)) is None
    assert prototype_note(og.prototype().replace(workspace_side=0.19)) is None
    with pytest.raises(InvalidParameterError, match="params"):
        prototype_note("prototype")  # type: ignore[arg-type]
