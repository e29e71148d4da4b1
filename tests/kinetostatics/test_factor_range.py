"""The factors over a machine's cube on a grid, judged by its criterion."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, lapack_factors

import orthoglide_pin as og

# the module itself (the package's ``factor_range`` attribute is the function)
factor_range_module = sys.modules["orthoglide_pin.kinetostatics.factor_range"]
#: Closed form against LAPACK at well-conditioned points.
SVD_RTOL = 1e-10


def _lapack_extremes(params: og.OrthoglideParams, n: int) -> tuple[float, float]:
    cube = params.workspace
    points = og.cube_grid(cube.q1, cube.side, n).points().reshape(-1, 3)
    f = lapack_factors(points, params.leg_length)
    return float(f[:, 0].min()), float(f[:, 2].max())


def test_the_prototype_misses_its_criterion_at_q2(params: og.OrthoglideParams) -> None:
    fr = og.factor_range(params, grid_points=11)
    lo, hi = _lapack_extremes(params, 11)
    assert fr.lowest == pytest.approx(lo, rel=SVD_RTOL)
    assert fr.highest == pytest.approx(hi, rel=SVD_RTOL)
    assert (round(fr.lowest, 4), round(fr.highest, 4)) == (0.4989, 2.0090)
    q2 = np.full(3, CUBE_CORNER + CUBE_SIDE)
    np.testing.assert_allclose(fr.lowest_at, q2, atol=1e-15)
    np.testing.assert_allclose(fr.highest_at, q2, atol=1e-15)
    assert (fr.psi_min, fr.psi_max) == (0.5, 2.0) and not fr.holds
    assert fr.verdict == "DOES NOT HOLD"
    assert fr.describe() == "[0.498888, 2.008957] on a 11^3 grid of the cube"
    # the same machine judged by a wider criterion
    wider = og.factor_range(params, grid_points=11, psi_min=0.45, psi_max=2.1)
    assert wider.holds and wider.lowest == fr.lowest


def test_another_design_meets_its_own_criterion() -> None:
    made = og.design_from_workspace(0.25, 0.4, 2.5, grid_points=5)
    params = made.to_params()
    fr = og.factor_range(params, grid_points=9)
    assert fr.holds and (fr.psi_min, fr.psi_max) == (0.4, 2.5)
    lo, hi = _lapack_extremes(params, 9)
    assert fr.lowest == pytest.approx(lo, rel=SVD_RTOL) and lo > 0.45  # 5/11 at Q2
    assert fr.highest == pytest.approx(2.5, rel=SVD_RTOL) == hi  # reached at Q1 and Q2
    # the design's own grid check reads the same extremes
    assert made.psi_min_found == fr.lowest and made.psi_max_found == pytest.approx(fr.highest)
    # a hand-written file: the same cube with a shorter leg breaks the criterion
    shorter = params.replace(leg_length=0.33)
    broken = og.factor_range(shorter, grid_points=9)
    assert not broken.holds and broken.highest > 2.5 + og.CRITERION_TOL


def test_a_point_out_of_reach_never_holds(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    real = factor_range_module.transmission_factor_map

    def spoiled(grid: og.Grid, leg: float) -> np.ndarray:
        out = real(grid, leg)
        out[1, 0, 2] = np.nan  # out of reach, say
        return out

    monkeypatch.setattr(factor_range_module, "transmission_factor_map", spoiled)
    fr = og.factor_range(params, grid_points=3, psi_min=1e-6, psi_max=1e6)
    assert not fr.holds and fr.highest == math.inf
    grid = og.cube_grid(params.workspace.q1, params.workspace.side, 3)
    np.testing.assert_array_equal(fr.highest_at, grid.points()[1, 0, 2])
    data = json.loads(json.dumps(fr.to_dict(), allow_nan=False))  # strict JSON
    assert data["highest"] is None and data["lowest"] == pytest.approx(fr.lowest)


def test_to_dict_is_strict_json(params: og.OrthoglideParams) -> None:
    data = json.loads(
        json.dumps(og.factor_range(params, grid_points=3).to_dict(), allow_nan=False)
    )
    assert data["holds"] is False and data["grid_points"] == 3
    assert data["tolerance"] == og.CRITERION_TOL and data["psi_max"] == 2.0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"grid_points": 1}, "grid_points"),
        ({"grid_points": 202}, "grid_points"),
        ({"grid_points": 2.5}, "grid_points"),
        ({"psi_min": 1.5}, "psi_min"),
        ({"psi_max": 0.9}, "psi_max"),
        ({"tol": 0.0}, "tol"),
        ({"tol": math.inf}, "tol"),
    ],
)
def test_bad_arguments_are_named(
    params: og.OrthoglideParams, kwargs: dict[str, object], name: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        og.factor_range(params, **kwargs)  # type: ignore[arg-type]
    assert info.value.name == name
    with pytest.raises(og.InvalidParameterError, match="params"):
        og.factor_range("prototype")  # type: ignore[arg-type]
