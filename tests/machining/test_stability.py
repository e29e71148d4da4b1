"""Stability where the tool is: lobes that move with the machine's modes, a map, a margin.

* Scaling: a modal model whose frequencies are all multiplied by ``s`` at
  the same stiffnesses and damping has the same lobes at ``s`` times the speeds
  (the delayed equations in the time ``s t``).
* On the prototype with the shipped cut file, the lowest mode falls from
  213 Hz at home to 108 Hz at Q2: the lobes' highest pocket at home sits where
  the tooth frequency is the lowest mode's, and at Q2 that pocket is gone and
  the lowest limit falls.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machining.frf import ModalModel
from orthoglide_pin.machining.stability import limit_depth_map, stability_lobes
from orthoglide_pin.machining.stability_path import (
    feed_angles,
    program_blocks,
    stability_margin_along,
)
from orthoglide_pin.machining.stability_sd import critical_depths_sd

RPM = 2.0 * math.pi / 60.0
#: Lobes of the scaled model against the original's at scaled speeds, relative.
SCALING_TOL = 1e-6
#: The home pocket's tooth frequency against the lowest mode, relative.
POCKET_TOL = 0.05
#: The map's and the margin's limits against the lobes at the same speed, relative.
SAME_LIMIT_TOL = 1e-9
#: The map (bracketed from a grid of depths) against the lobes (bracketed from
#: the zero-order limit): the same limit within the refinement's tolerance, relative.
MAP_VS_LOBES_TOL = 0.01


@pytest.fixture(scope="module")
def cut() -> og.CutConditions:
    return og.read_cut_file(og.shipped_cut_file())


def test_lobes_scale_with_the_frequencies(cut: og.CutConditions) -> None:
    lobes = stability_lobes(cut, speeds=np.linspace(3000.0, 9000.0, 13) * RPM, zero_order=False)
    model, s = lobes.model, 0.5
    slow = ModalModel(model.frequencies * s, model.damping, model.masses / s**2, model.shapes)
    from orthoglide_pin.machining.stability import milling_process

    process = milling_process(cut, cut.engagements[0])
    again = critical_depths_sd(slow, process, lobes.speeds * s)
    original = critical_depths_sd(model, process, lobes.speeds)
    assert np.allclose(again, original, rtol=SCALING_TOL)


def test_lobes_move_with_the_tool(cut: og.CutConditions) -> None:
    params = og.prototype()
    speeds = np.linspace(1000.0, 12000.0, 45) * RPM
    home = stability_lobes(cut, (0.0, 0.0, 0.0), speeds=speeds, zero_order=False)
    q2 = stability_lobes(cut, params.workspace.q2, speeds=speeds, zero_order=False)
    teeth = cut.tool.teeth
    pocket = int(np.argmax(np.where(np.isfinite(home.depths), home.depths, 1.0)))
    tooth = teeth * speeds[pocket] / (2.0 * math.pi)
    assert tooth == pytest.approx(home.model.frequencies[0], rel=POCKET_TOL)
    assert q2.model.frequencies[0] < 0.55 * home.model.frequencies[0]
    assert q2.depths[pocket] < 0.2 * home.depths[pocket]  # the pocket moved away
    assert q2.minimum < 0.6 * home.minimum
    payload = home.to_dict()
    assert len(payload["speeds_rpm"]) == speeds.size
    assert payload["minimum_depth_mm"] == pytest.approx(home.minimum * 1e3)


def test_map_and_margin_agree_with_the_lobes(cut: og.CutConditions) -> None:
    points = np.array([[0.0, 0.0, 0.0], [0.02, 0.01, -0.03], [0.05, 0.05, 0.05]])
    assert cut.spindle_speed is not None
    limits = limit_depth_map(cut, points)
    for point, limit in zip(points, limits, strict=True):
        lobe = stability_lobes(cut, point, speeds=[cut.spindle_speed], zero_order=False)
        assert limit == pytest.approx(lobe.depths[0], rel=MAP_VS_LOBES_TOL)
    margin = stability_margin_along(points, cut, angles=np.zeros(3))
    depth = cut.engagements[0].axial_depth
    assert np.allclose(margin.margin, limits / depth, rtol=SAME_LIMIT_TOL)
    assert margin.worst == int(np.argmin(limits))


def test_margin_by_lines_and_feed(cut: og.CutConditions) -> None:
    data = {
        "tool": {"diameter": 0.01, "teeth": 3, "helix_angle": 0.5},
        "material": "aluminium_7075",
        "engagement": [
            {"axial_depth": 0.002, "radial_width": 0.001, "milling": "down", "lines": [2, 3]}
        ],
        "spindle_speed": 12000,
    }
    conditions = og.cut_conditions(data)
    points = np.array([[0.0, 0.0, 0.0], [0.0, 0.01, 0.0], [0.01, 0.01, 0.0]])
    margin = stability_margin_along(points, conditions, lines=[1, 2, 3])
    assert math.isnan(margin.margin[0]) and np.all(np.isfinite(margin.margin[1:]))
    assert margin.stable[0]
    # world e1 is program Y, e2 program X on the prototype
    assert feed_angles(points).tolist() == pytest.approx([0.0, 0.0, math.pi / 2])


def test_bad_arguments_are_named(cut: og.CutConditions) -> None:
    with pytest.raises(og.InvalidParameterError, match="point"):
        stability_lobes(cut, (0.0, 0.0))
    with pytest.raises(og.InvalidParameterError, match="speeds"):
        stability_lobes(cut, speeds=[-1.0])
    with pytest.raises(og.InvalidParameterError, match="conditions"):
        stability_lobes("cut.yaml")  # type: ignore[arg-type]
    no_speed = og.cut_conditions({**_data(), "spindle_speed": "program"})
    with pytest.raises(og.InvalidParameterError, match="spindle_speed"):
        limit_depth_map(no_speed, [[0.0, 0.0, 0.0]])


def _data() -> dict[str, object]:
    return {
        "tool": {"diameter": 0.01, "teeth": 3},
        "material": "aluminium_7075",
        "engagement": {"axial_depth": 0.002, "radial_width": 0.001, "milling": "down"},
    }


def test_program_blocks(cut: og.CutConditions) -> None:
    text = "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-2 F600\nG1 X10 F3000\nG3 X10 Y0 I0 J5\nG1 Y-10\n"
    params = og.prototype()
    axes = og.design_axes(params)
    points, lines, angles = program_blocks(og.read_program(text, axes=axes), axes)
    assert lines.tolist() == [4, 5, 6]  # the plunge (line 3) does not cut sideways
    assert points[0] == pytest.approx(axes.to_world([0.005, 0.0, -0.002]))  # world frame
    # along +X; a full counter-clockwise circle from its bottom: +X; then -Y
    assert angles.tolist() == pytest.approx([0.0, 0.0, -math.pi / 2])
    margin = stability_margin_along(points, cut, lines=lines, angles=angles, params=params)
    assert margin.margin.shape == (3,) and np.all(margin.margin > 0.0)
    empty = stability_margin_along(np.zeros((0, 3)), cut)
    assert empty.margin.size == 0 and empty.worst == -1
