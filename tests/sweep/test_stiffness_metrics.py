"""Stiffness metrics of a design against the stiffness model itself."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from conftest import PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.kinetostatics.stiffness_maps import DEFAULT_CUTTING_FORCE
from orthoglide_pin.sweep.metrics import evaluate_design
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

EXACT_TOL = 1e-9


def _row(**axes: float) -> dict[str, Any]:
    spec = SweepSpec(axes=tuple(SweepAxis(k, (v,)) for k, v in axes.items()), grid=5)
    return evaluate_design(spec.designs()[0])


def test_prototype_row_is_the_stiffness_map() -> None:
    row = _row(leg_length=PROTOTYPE_LEG)
    assert row["status"] == "ok", row["error"]
    params = og.prototype().replace(
        workspace_corner=[row[f"cube_corner_{a}"] for a in "xyz"], workspace_side=row["cube_side"]
    )
    grid = og.cube_grid(params.workspace.q1, params.workspace.side, 5)
    smap = og.stiffness_map(grid, params)
    assert row["min_stiffness"] == pytest.approx(smap.min_stiffness.min(), rel=EXACT_TOL)
    assert row["max_deflection"] == pytest.approx(
        DEFAULT_CUTTING_FORCE / row["min_stiffness"], rel=EXACT_TOL
    )
    centre = og.cartesian_stiffness(params.workspace.center, params).K
    assert row["centre_stiffness"] == pytest.approx(np.linalg.eigvalsh(centre)[0], rel=EXACT_TOL)


def test_thicker_bars_are_stiffer() -> None:
    thin = _row(leg_length=PROTOTYPE_LEG)
    thick = _row(leg_length=PROTOTYPE_LEG, bar_radius=0.015, bar_wall=0.003)
    assert thick["min_stiffness"] > thin["min_stiffness"]
    assert thick["centre_stiffness"] > thin["centre_stiffness"]
