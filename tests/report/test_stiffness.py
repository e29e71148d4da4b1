"""The report's stiffness section against the model, and where it shows."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_json

import orthoglide_pin as og
from orthoglide_pin.report.stiffness import (
    stiffness_dict,
    stiffness_figure,
    stiffness_html,
    stiffness_section,
)


@pytest.fixture(scope="module")
def section(params: og.OrthoglideParams) -> og.report.stiffness.StiffnessSection:
    q1 = np.asarray(params.workspace.q1)
    return stiffness_section(
        params, q1, params.workspace.side, cutting_force=250.0, resolution=9, cube_resolution=5
    )


def test_figures_are_the_model(
    params: og.OrthoglideParams, section: og.report.stiffness.StiffnessSection
) -> None:
    data = stiffness_dict(section)
    json.dumps(data, allow_nan=False)
    point = np.array(data["worst_point"])
    k = og.cartesian_stiffness(point, params).K
    assert data["min_stiffness"] == pytest.approx(np.linalg.eigvalsh(k)[0], rel=1e-9)
    assert data["max_deflection"] == pytest.approx(250.0 / data["min_stiffness"], rel=1e-9)
    # The corner Q2, far from the sliders, is the softest point of the prototype cube.
    np.testing.assert_allclose(point, np.asarray(params.workspace.q2), atol=1e-12)
    assert [s["label"] for s in data["slices"]] == [
        "z = lower face",
        "z = centre",
        "z = upper face",
    ]
    assert min(s["min_stiffness"] for s in data["slices"]) >= data["min_stiffness"] - 1e-6
    facts = data["assumptions"]
    assert facts["youngs_modulus"] == params.youngs_modulus
    assert facts["actuator_stiffness"] == params.actuator_stiffness


def test_page_and_figure(section: og.report.stiffness.StiffnessSection) -> None:
    png = stiffness_figure(section)
    assert png.startswith(b"\x89PNG")
    page = stiffness_html(section, "<img>")
    assert "GPa" in page and "N/um" in page and "revolutes" in page and "<img>" in page


@pytest.mark.usefixtures("no_drawing")
def test_report_command_carries_the_section(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = str(tmp_path) + "/report"
    data = run_json(
        capsys, "report", "--out", out, "--quiet", "--resolution", "3",
        "--cube-resolution", "2", "--cutting-force", "50",
    )  # fmt: skip
    assert data["stiffness"]["cutting_force"] == 50.0
    saved = json.loads(Path(data["json"]).read_text())
    assert saved["stiffness"]["min_stiffness"] == pytest.approx(data["stiffness"]["min_stiffness"])
    assert "Stiffness of the tool" in Path(data["report"]).read_text()
