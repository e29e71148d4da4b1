"""The criterion a machine carries: its bounds, its one tolerance rule, the prototype's truth."""

from __future__ import annotations

import inspect
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, lapack_factors

import orthoglide_pin as og
from orthoglide_pin.machine import criterion, params
from orthoglide_pin.machine.criterion import CRITERION_TOL, check_bounds, within

#: The prototype's factors over its 200 mm cube, as every text of the package states them.
STATED = "[0.4989, 2.0090]"
#: The leg the design method gives for that cube and [0.5, 2], as stated [mm].
STATED_LEG = "310.58 mm"
README = Path(__file__).resolve().parents[2] / "README.md"


def _prototype_factors() -> tuple[float, float]:
    """The extremes over the prototype's cube, proven (interval arithmetic) and tight."""
    cert = og.certify(og.prototype(), psi_min=0.1, psi_max=10.0, tol=1e-6)
    assert cert.certified and cert.tight
    enclosure = "[{:.4f}, {:.4f}]".format(*cert.factor_bounds)
    assert enclosure == "[{:.4f}, {:.4f}]".format(*cert.attained)  # proven to 4 decimals
    return cert.attained


def test_the_stated_figures_are_the_computed_ones() -> None:
    lo, hi = _prototype_factors()
    assert f"[{lo:.4f}, {hi:.4f}]" == STATED
    # another route: LAPACK on a grid of the cube (its corner Q2 holds both extremes)
    points = og.cube_grid(np.full(3, CUBE_CORNER), CUBE_SIDE, 21).points().reshape(-1, 3)
    f = lapack_factors(points, PROTOTYPE_LEG)
    assert f[:, 0].min() == pytest.approx(lo, rel=1e-10)
    assert f[:, 2].max() == pytest.approx(hi, rel=1e-10)
    np.testing.assert_allclose(
        points[np.argmax(f[:, 2])], np.full(3, CUBE_CORNER + CUBE_SIDE), atol=1e-15
    )
    exact = og.design_from_workspace(CUBE_SIDE, *og.PAPER_BOUNDS, grid_points=2).leg_length
    assert f"{1e3 * exact:.2f} mm" == STATED_LEG
    assert round(1e3 * exact) == 1e3 * PROTOTYPE_LEG + 1  # rounded to 310 mm, not 311


def test_every_text_on_the_prototype_tells_the_truth() -> None:
    texts = {
        "prototype()": inspect.getdoc(og.prototype) or "",
        "machine.params": params.__doc__ or "",
        "machine.criterion": criterion.__doc__ or "",
        "README": README.read_text(),
    }
    for where, text in texts.items():
        flat = " ".join(text.split())
        assert STATED in flat and STATED_LEG in flat, where
    # the prototype's criterion is [0.5, 2], and it does not hold over its cube
    assert og.prototype().psi_min == 0.5 and og.prototype().psi_max == 2.0
    assert not og.factor_range(og.prototype()).holds


def test_the_rule_is_the_bounds_widened_by_the_tolerance() -> None:
    lo, hi = 0.4, 2.5
    inside = [lo - 0.5 * CRITERION_TOL, 1.0, hi + 0.5 * CRITERION_TOL]
    outside = [lo - 1.5 * CRITERION_TOL, 1.0, hi + 1.5 * CRITERION_TOL]
    assert within(inside[0], 1.0, lo, hi) and within(1.0, inside[2], lo, hi)
    assert not within(outside[0], 1.0, lo, hi) and not within(1.0, outside[2], lo, hi)
    # per point, singular (inf) or out of reach (NaN) never meets it
    got = within([0.5, 0.5, math.nan, 0.5], [2.0, math.inf, 2.0, 2.6], lo, hi)
    assert got.tolist() == [True, False, False, False]
    assert within(0.39, 1.0, lo, hi, tol=0.02)  # another tolerance


def test_bounds_are_checked_by_name() -> None:
    assert check_bounds(0.5, 2) == (0.5, 2.0)
    assert check_bounds("0.4", "2.5") == (0.4, 2.5)
    for lo, hi, name in [
        (1.0, 2.0, "psi_min"),
        (0.0, 2.0, "psi_min"),
        (math.nan, 2.0, "psi_min"),
        (None, 2.0, "psi_min"),
        (0.5, 1.0, "psi_max"),
        (0.5, math.inf, "psi_max"),
        (0.5, [2.0], "psi_max"),
    ]:
        with pytest.raises(og.InvalidParameterError) as info:
            check_bounds(lo, hi)
        assert info.value.name == name
    with pytest.raises(og.InvalidParameterError, match="--psi MAX"):
        check_bounds(0.5, 0.9, names=("--psi MIN", "--psi MAX"))
