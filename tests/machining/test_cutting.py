"""The cut file and the cutting conditions."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin.machining.cutting import (
    RPM_PER_RAD_S,
    CutConditions,
    Engagement,
    Material,
    Tool,
    ToolMode,
    cut_conditions,
    read_cut_file,
    shipped_cut_file,
    shipped_materials,
)

#: Exactness of the closed-form immersion angles [rad].
ANGLE_TOL = 1e-12

BASE = {
    "tool": {"diameter": 0.01, "teeth": 2},
    "material": "aluminium_7075",
    "engagement": {"axial_depth": 0.002, "radial_width": 0.005},
}


def _with(**changes: object) -> dict[str, object]:
    data = dict(BASE)
    data.update(changes)
    return data


def test_the_shipped_cut_file_reads_in_si() -> None:
    cut = read_cut_file(shipped_cut_file())
    assert cut.tool.diameter == 0.01 and cut.tool.teeth == 3
    assert cut.spindle_speed == pytest.approx(12000 / RPM_PER_RAD_S)
    assert cut.material.name == "aluminium_7075" and "Altintas" in cut.material.source
    assert len(cut.tool.modes) == 2 and cut.tool.modes[1].direction == "y"
    assert cut.engagement_at(1) is cut.engagement_at(10_000) is cut.engagements[0]


def test_every_shipped_material_names_its_source() -> None:
    materials = shipped_materials()
    assert {"aluminium_7075", "aluminium_6061", "benchmark"} <= set(materials)
    for material in materials.values():
        assert len(material.source) > 40
    assert materials["benchmark"].kt == 6e8


@pytest.mark.parametrize(
    ("milling", "width", "expected"),
    [
        ("up", 0.01, (0.0, math.pi)),
        ("down", 0.01, (0.0, math.pi)),
        ("up", 0.005, (0.0, math.pi / 2)),
        ("down", 0.005, (math.pi / 2, math.pi)),
        ("up", 0.0025, (0.0, math.acos(0.5))),
        ("down", 0.0025, (math.acos(-0.5), math.pi)),
    ],
)
def test_immersion_angles_follow_altintas(
    milling: str, width: float, expected: tuple[float, float]
) -> None:
    start, exit_ = Engagement(0.002, width, milling).immersion(0.01)
    assert start == pytest.approx(expected[0], abs=ANGLE_TOL)
    assert exit_ == pytest.approx(expected[1], abs=ANGLE_TOL)


def test_engagements_by_line_ranges_and_the_default() -> None:
    data = _with(
        engagement=[
            {"axial_depth": 0.001, "radial_width": 0.01, "lines": [5, 9]},
            {"axial_depth": 0.002, "radial_width": 0.002, "milling": "up"},
            {"axial_depth": 0.003, "radial_width": 0.003, "lines": [12, 12]},
        ],
        spindle_speed="program",
    )
    cut = cut_conditions(data)
    assert cut.spindle_speed is None
    assert cut.engagement_at(5).axial_depth == cut.engagement_at(9).axial_depth == 0.001
    assert cut.engagement_at(12).axial_depth == 0.003
    assert cut.engagement_at(4).milling == "up" and cut.engagement_at(10).axial_depth == 0.002
    only = CutConditions(cut.tool, cut.material, (Engagement(0.001, 0.001, lines=(2, 3)),))
    assert only.engagement_at(1) is None and only.engagement_at(3) is not None


def test_an_inline_material() -> None:
    data = _with(material={"name": "mine", "kt": 1e9, "kr": 3e8, "source": "my tests"})
    material = cut_conditions(data).material
    assert material == Material("mine", 1e9, 3e8, source="my tests")


@pytest.mark.parametrize(
    ("data", "words"),
    [
        (_with(tool={"diameter": 10, "teeth": 2}), "did you mean 0.01"),
        (_with(tool={"diameter": 0.01, "teeth": 2, "helix_angle": 30}), "did you mean 0.523599"),
        (_with(tool={"diameter": 0.01, "teeth": 2.0}), "teeth=2.0"),
        (_with(tool={"diameter": 0.01}), "tool.teeth"),
        (_with(material={"kt": 796, "kr": 168}), "did you mean 7.96e+08"),
        (_with(material="unobtainium"), "one of 'aluminium_7075'"),
        (_with(engagement={"axial_depth": 0.002, "radial_width": 0.02}), "at most the tool"),
        (
            _with(engagement={"axial_depth": 0.002, "radial_width": 0.005, "milling": "climb"}),
            "milling='climb'",
        ),
        (_with(spindle_speed=0), "spindle_speed=0"),
        (_with(spindle_speed="12000 rpm"), "or program (its S)"),
        (_with(modal_damping=2), "did you mean 0.02"),
        (_with(feed=1), "cut file key='feed'"),
        (
            _with(
                engagement=[
                    {"axial_depth": 0.002, "radial_width": 0.005, "lines": [3, 8]},
                    {"axial_depth": 0.002, "radial_width": 0.005, "lines": [8, 9]},
                ]
            ),
            "ranges that do not overlap",
        ),
        (
            _with(engagement={"axial_depth": 0.002, "radial_width": 0.005, "lines": [9, 3]}),
            "1 <= first <= last",
        ),
        ({"tool": BASE["tool"], "material": "benchmark"}, "engagement section"),
    ],
)
def test_bad_values_are_named_in_one_line(data: dict[str, object], words: str) -> None:
    with pytest.raises(og.CutConditionsError, match=None) as info:
        cut_conditions(data)
    message = str(info.value)
    assert words in message and "\n" not in message
    assert isinstance(info.value, og.OrthoglideError)


def test_bad_yaml_is_located_and_not_quoted(tmp_path: Path) -> None:
    path = tmp_path / "cut.yaml"
    path.write_text("tool: {diameter: 0.01, teeth: 2\nmaterial: secret-words\n")
    with pytest.raises(og.CutConditionsError, match="line 2, column") as info:
        read_cut_file(path)
    assert "secret" not in str(info.value)
    path.write_bytes(b"tool: \x00\n")
    with pytest.raises(og.CutConditionsError, match="not a text file"):
        read_cut_file(path)
    with pytest.raises(og.CutConditionsError, match="readable file"):
        read_cut_file(tmp_path / "missing.yaml")


def test_the_api_checks_its_values() -> None:
    with pytest.raises(og.CutConditionsError, match="direction='z'"):
        ToolMode(1000.0, 0.02, 1e7, "z")
    with pytest.raises(og.CutConditionsError, match="teeth=0"):
        Tool(0.01, 0)
    tool = Tool(0.01, 2)
    with pytest.raises(og.CutConditionsError, match="at least one Engagement"):
        CutConditions(tool, shipped_materials()["benchmark"], ())
    with pytest.raises(og.CutConditionsError, match="spindle_speed"):
        CutConditions(tool, shipped_materials()["benchmark"], (Engagement(1e-3, 1e-3),), -1.0)
