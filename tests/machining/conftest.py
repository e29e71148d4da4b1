"""The machining tests' plans: a short contour on the prototype and on the 340.75 mm legs."""

from __future__ import annotations

import pytest
from machining._support import LIMITS, PROGRAM

import orthoglide_pin as og


@pytest.fixture(scope="session", params=[0.31, 0.34075], ids=["prototype", "340.75 mm legs"])
def planned(request: pytest.FixtureRequest) -> tuple[og.OrthoglideParams, og.Plan]:
    params = og.prototype().replace(leg_length=request.param)
    program = og.read_program(PROGRAM, axes=og.design_axes(params))
    return params, og.plan_program(program, params, LIMITS)
