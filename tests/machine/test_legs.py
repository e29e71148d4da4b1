"""A built machine's per-leg geometry in the description."""

from __future__ import annotations

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machine.description import render_urdf, xacro_args
from orthoglide_pin.machine.legs import LegGeometry


def test_the_drawing_renders_the_drawing() -> None:
    params = og.prototype().replace(leg_length=0.33)
    plain = render_urdf(params, use_cache=False)
    assert render_urdf(params, legs=LegGeometry.drawing(0.33), use_cache=False) == plain


def test_arguments_in_each_legs_frame() -> None:
    axes = np.eye(3)
    axes[1] = [0.001, np.sqrt(1 - 0.001**2), 0.0]  # rail 2 tilted towards e1
    legs = LegGeometry(np.diag([1e-4, 0, 0]), axes, [0.31, 0.3101, 0.31])
    args = legs.xacro_args()
    assert args["leg1_offset"] == "0.0001 0 0"
    # leg 2's frame is (e2, e3, e1): the tilt towards e1 is its third component
    assert args["leg2_axis"] == f"{float(axes[1, 1])!r} 0 0.001"
    assert args["leg2_length"] == "0.3101"
    assert xacro_args(og.prototype(), legs)["leg3_axis"] == "1 0 0"


def test_the_cache_tells_built_machines_apart() -> None:
    params = og.prototype()
    legs = LegGeometry(np.zeros((3, 3)), np.eye(3), [0.31, 0.31, 0.3102])
    assert render_urdf(params, legs=legs) != render_urdf(params)
    assert 'xyz="0.3102 0 0"' in render_urdf(params, legs=legs)


@pytest.mark.parametrize(
    ("offsets", "axes", "lengths", "words"),
    [
        (np.full((3, 3), 0.1), np.eye(3), [0.31] * 3, "offsets"),
        (np.zeros((3, 3)), 2 * np.eye(3), [0.31] * 3, "unit vectors"),
        (np.zeros((3, 3)), np.eye(3)[[1, 0, 2]], [0.31] * 3, "within 0.2 rad"),
        (np.zeros((3, 3)), np.eye(3), [0.31, -1, 0.31], "positive"),
        (np.zeros((3, 3)), np.eye(3), [0.31, np.nan, 0.31], "lengths"),
        (np.zeros((2, 3)), np.eye(3), [0.31] * 3, "(3, 3)"),
    ],
)
def test_bad_legs_are_refused(offsets, axes, lengths, words: str) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        LegGeometry(offsets, axes, lengths)
    assert words in str(info.value)
