"""The prescribed cube (orthoglide_pin.machine.cube) and the prototype's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og

#: Corner arithmetic on numbers of 0.1 m: rounding only.
EXACT_RTOL = 1e-15


def test_the_prototype_holds_the_papers_cube(params: og.OrthoglideParams) -> None:
    cube = params.workspace
    assert cube == og.Cube((CUBE_CORNER,) * 3, CUBE_SIDE)
    np.testing.assert_array_equal(cube.q1, np.full(3, -PROTOTYPE_LEG / math.sqrt(18.0)))
    np.testing.assert_allclose(cube.q2 - cube.q1, CUBE_SIDE, rtol=EXACT_RTOL)
    np.testing.assert_allclose(cube.center, cube.q1 + 0.1, rtol=EXACT_RTOL)
    assert params.derived_limits == ("slider_lower", "slider_upper")
    assert cube.describe() == "200 mm cube, lowest corner Q1 (-73.07, -73.07, -73.07) mm"


def test_the_cube_in_words_and_in_json() -> None:
    cube = og.Cube((-0.05, -0.06, 0.0), 0.12)
    assert cube.describe() == "120 mm cube, lowest corner Q1 (-50.00, -60.00, 0.00) mm"
    assert cube.to_dict() == {"corner": [-0.05, -0.06, 0.0], "side": 0.12}
    np.testing.assert_allclose(cube.q2, [0.07, 0.06, 0.12], rtol=EXACT_RTOL)
    cube.q1[0] = 1.0  # a fresh array each time: the cube stays as it was
    assert cube.q1[0] == -0.05
    with pytest.raises(AttributeError):
        cube.side = 0.3  # type: ignore[misc]
