"""Compliance ellipsoids in the viewer: the image of the unit force ball."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import cube_points, run

import orthoglide_pin as og
from orthoglide_pin.viewer import Viewer, overlays

ROOT = "/meshcat/orthoglide"
SHAPE_RTOL = 1e-9


def test_compliance_ellipsoids_are_the_displacements_under_unit_forces(
    model: og.ClosedLoopModel,
) -> None:
    v = Viewer(model)
    points = cube_points(4, seed=7)
    scale = 0.01
    ells = v.add_ellipsoids(points, "compliance", scale=scale)
    compliance = og.cartesian_stiffness(points, model.params).compliance[:, :3, :3]
    shape = compliance / overlays.COMPLIANCE_UNIT
    for k, p in enumerate(points):
        m = v.scene.transform(f"{ROOT}/ellipsoids/{k}")
        assert m is not None
        np.testing.assert_allclose(m[:3, 3], p)
        a = m[:3, :3]
        assert np.linalg.det(a) > 0
        # The drawn ellipsoid {a u : |u| <= 1} is {scale * C f : |f| <= 1}.
        np.testing.assert_allclose(a @ a.T, scale**2 * shape[k] @ shape[k], rtol=SHAPE_RTOL)
        assert ells.condition[k] == pytest.approx(np.linalg.cond(compliance[k]), rel=SHAPE_RTOL)


def test_compliance_ellipsoids_follow_the_machine(params: og.OrthoglideParams) -> None:
    stiff = params.replace(
        youngs_modulus=2 * params.youngs_modulus, shear_modulus=2 * params.shear_modulus
    )
    point = np.array([[0.01, 0.02, -0.03]])
    soft_axes = overlays.ellipsoids(point, stiff.leg_length, "compliance", params).axes
    stiff_axes = overlays.ellipsoids(point, stiff.leg_length, "compliance", stiff).axes
    assert np.all(stiff_axes < soft_axes)


def test_view_command_accepts_compliance(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = f"{tmp_path}/view.html"
    code, text, err = run(
        capsys, "view", "--ellipsoids", "grid", "--grid", "2", "--ellipsoid-kind", "compliance",
        "--static", out,
    )  # fmt: skip
    assert code == 0, err
    assert "compliance" in text
