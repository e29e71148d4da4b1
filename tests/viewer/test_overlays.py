"""One colour scale for the legend and every ellipsoid, the one following the tool included."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, cube_points, run

import orthoglide_pin as og
from orthoglide_pin.viewer import Viewer, overlays

ROOT = "/meshcat/orthoglide"
#: Colour resolution of a material (0xRRGGBB rounding).
COLOR_TOL = 0.5 / 255 + 1e-6
EXACT_TOL = 1e-12
#: A point of small condition number (about 1.35), inside the prototype's cube [m].
MIDDLE = np.array([0.02, 0.03, 0.04])


def line_to_q2(n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """From home to Q2 in 1 s: the condition number grows from 1 to about 4."""
    t = np.linspace(0.0, 1.0, n)
    q2 = np.full(3, CUBE_CORNER + CUBE_SIDE)
    return t, t[:, None] * q2


def follower_track(viewer: Viewer) -> np.ndarray:
    """The colour keyframes of the ellipsoid that follows the tool, shape (F, 3)."""
    command = viewer.scene.animation()
    assert command is not None
    (clip,) = [
        a["clip"] for a in command["animations"] if a["path"] == f"{ROOT}/follower/<object>"
    ]
    (t,) = [t for t in clip["tracks"] if t["name"] == ".material.color"]
    return np.array([k["value"] for k in t["keys"]], dtype=float)


def static_colors(viewer: Viewer) -> np.ndarray:
    """Material colours of the ellipsoids of ``add_ellipsoids``, in order, shape (N, 3)."""
    by_path: dict[str, Any] = {
        c["path"]: c["object"]["materials"][0]["color"]
        for c in viewer.scene.commands()
        if c["type"] == "set_object" and "/ellipsoids/" in c["path"]
    }
    n = len(by_path)
    return np.array(
        [
            [(by_path[f"{ROOT}/ellipsoids/{k}"] >> s & 255) / 255 for s in (16, 8, 0)]
            for k in range(n)
        ]
    )


def test_the_follower_widens_the_legend_to_its_own_values(model: og.ClosedLoopModel) -> None:
    viewer = Viewer(model)
    ells = viewer.add_ellipsoids(MIDDLE)
    assert viewer.scene.legend is not None
    assert viewer.scene.legend["max"] == pytest.approx(ells.condition[0], rel=EXACT_TOL)
    before = static_colors(viewer)
    viewer.play(line_to_q2())
    follower = viewer.follower
    assert follower is not None
    legend = viewer.scene.legend
    assert legend is not None and viewer.color_scale is not None
    # The legend covers every condition number drawn: nothing is clamped.
    assert legend["min"] == 1.0
    assert legend["max"] == pytest.approx(follower.condition.max(), rel=EXACT_TOL)
    assert follower.condition.max() == pytest.approx(4.0, rel=2e-2)  # Q2 (paper: 0.5 and 2)
    assert not legend["max_label"].startswith(">=")
    assert "following the tool" in legend["title"] and "ellipsoids" in legend["title"]
    # The follower's colours are the legend's colormap at its values, within its range.
    lo, hi, cmap = legend["min"], legend["max"], legend["colormap"]
    track = follower_track(viewer)
    np.testing.assert_allclose(
        track, overlays.colors(follower.condition, lo, hi, cmap), atol=EXACT_TOL
    )
    t = (follower.condition - lo) / (hi - lo)
    assert (t >= 0.0).all() and (t <= 1.0 + EXACT_TOL).all()
    # "cool" is cyan (0, 1, 1) to magenta (1, 0, 1): red is t, green 1 - t.
    np.testing.assert_allclose(track[:, 0], t, atol=1e-2)
    np.testing.assert_allclose(track[:, 0] + track[:, 1], 1.0, atol=1e-2)
    # The still ellipsoid was recoloured on the wider scale: less magenta than before.
    after = static_colors(viewer)
    np.testing.assert_allclose(
        after, overlays.colors(ells.condition, lo, hi, cmap), atol=COLOR_TOL
    )
    assert after[0, 0] < before[0, 0] - 0.1


def test_ellipsoids_drawn_after_the_animation_recolour_the_follower(
    model: og.ClosedLoopModel,
) -> None:
    viewer = Viewer(model)
    viewer.play(line_to_q2(), colormap="viridis")
    follower = viewer.follower
    assert follower is not None
    q1 = np.full(3, CUBE_CORNER)
    viewer.add_ellipsoids(np.stack([q1, MIDDLE]), colormap="viridis")
    legend = viewer.scene.legend
    assert legend is not None and legend["colormap"] == "viridis"
    assert legend["max"] == pytest.approx(follower.condition.max(), rel=EXACT_TOL)
    np.testing.assert_allclose(
        follower_track(viewer),
        overlays.colors(follower.condition, 1.0, legend["max"], "viridis"),
        atol=EXACT_TOL,
    )
    # The animation still plays, once per scene, last.
    kinds = [c["type"] for c in viewer.scene.commands()]
    assert kinds.count("set_animation") == 1 and kinds[-1] == "set_animation"
    viewer.clear_ellipsoids()
    legend = viewer.scene.legend
    assert legend is not None
    assert legend["title"] == "condition number [-] of the velocity ellipsoid following the tool"


def test_a_fixed_range_clamps_and_says_so(model: og.ClosedLoopModel) -> None:
    viewer = Viewer(model)
    viewer.add_ellipsoids(MIDDLE, vmin=1.0, vmax=2.5)
    viewer.play(line_to_q2())
    follower = viewer.follower
    assert follower is not None and follower.condition.max() > 2.5
    legend = viewer.scene.legend
    assert legend is not None
    assert (legend["min"], legend["max"]) == (1.0, 2.5)
    assert legend["max_label"] == ">= 2.5" and legend["min_label"] == "1"
    track = follower_track(viewer)
    end = overlays.colors([2.5], 1.0, 2.5, overlays.COLORMAP)[0]
    beyond = follower.condition >= 2.5
    np.testing.assert_allclose(track[beyond], np.broadcast_to(end, track[beyond].shape))
    # No colour outside the colormap's range: each is a colour of the bar.
    stops = overlays.colors(np.linspace(1.0, 2.5, 1001), 1.0, 2.5, overlays.COLORMAP)
    nearest = np.abs(track[:, None, :] - stops[None]).max(axis=-1).min(axis=1)
    assert nearest.max() < 2e-3


def test_no_ellipsoid_no_colour_bar(model: og.ClosedLoopModel) -> None:
    viewer = Viewer(model)
    viewer.play(line_to_q2(), follow=None)
    assert viewer.color_scale is None and viewer.follower is None
    legend = viewer.scene.legend
    assert legend is not None and "stops" not in legend
    with pytest.raises(og.InvalidParameterError, match="colormap"):
        viewer.play(line_to_q2(), colormap="no-such-map")


def test_color_scale_covers_or_clamps() -> None:
    scale = overlays.ColorScale.covering([1.2, 1.7])
    assert (scale.vmin, scale.vmax, scale.fixed) == (1.0, 1.7, False)
    fixed = overlays.ColorScale.covering([1.2], vmax=1.5)
    assert fixed.fixed and (fixed.vmin, fixed.vmax) == (1.0, 1.5)
    np.testing.assert_allclose(fixed.rgb([9.0]), fixed.rgb([1.5]))


#: Compliance ellipsoids against the stiffness model, relative.
COMPLIANCE_RTOL = 1e-9


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
        np.testing.assert_allclose(a @ a.T, scale**2 * shape[k] @ shape[k], rtol=COMPLIANCE_RTOL)
        assert ells.condition[k] == pytest.approx(
            np.linalg.cond(compliance[k]), rel=COMPLIANCE_RTOL
        )
    assert v.scene.legend is not None
    title = v.scene.legend["title"]  # the model's assumptions go with the drawing
    assert "compliance" in title and "70 GPa" in title and "100 N/um" in title


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
