"""The tool's deflection under the cutting force, checked against the frame FEA.

The elastostatic model's deflection ``C F`` under a milling force (the
revolution's mean, and its peak) is compared with the frame FEA's
(:func:`~orthoglide_pin.elasticity.frame_fea.frame_compliance`, PyNite, the
``[fea]`` extra) at Q1, Q2 and seeded points of the cube, on the prototype and
on the 340.75 mm leg design.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from elasticity._support import cube_points

import orthoglide_pin as og
from orthoglide_pin.machining.forces import milling_forces
from orthoglide_pin.machining.surface_error import (
    feed_frames,
    machine_compliance,
    surface_errors,
    tool_compliance,
    wall_sides,
)

SEED = 20261206
#: Agreement of the deflection with the frame FEA's, relative to its size: the
#: stiffness model's agreement with the FEA (tests/elasticity/test_stiffness.py).
FEA_TOL = 0.01
#: Exact relations (rotations, an isotropic compliance), relative.
EXACT_TOL = 1e-12
#: The other design: longer legs (its cube follows the design rule).
OTHER_LEG = 0.34075


def _designs() -> list[og.OrthoglideParams]:
    return [og.prototype(), og.prototype().replace(leg_length=OTHER_LEG)]


@pytest.mark.parametrize("design", [0, 1], ids=["prototype", "340.75 mm legs"])
def test_the_deflection_under_the_cutting_force_matches_the_frame_fea(design: int) -> None:
    pytest.importorskip("Pynite")
    from orthoglide_pin.elasticity.frame_fea import frame_compliance

    params = _designs()[design]
    points = cube_points(params, 3, SEED)
    cut = og.read_cut_file(og.shipped_cut_file())
    rng = np.random.default_rng(SEED)
    heading = rng.uniform(0.0, 2.0 * math.pi, points.shape[0])
    axes = og.design_axes(params)
    tangent = axes.to_world(np.stack([np.cos(heading), np.sin(heading), 0 * heading], axis=1))
    frames = feed_frames(tangent, axes.matrix[:, 2])
    e = cut.engagements[0]
    forces = milling_forces(1e-4, e.axial_depth, e.immersion(cut.tool.diameter), cut.tool,
                            cut.material)  # fmt: skip
    model = machine_compliance(points, params)
    for k, point in enumerate(points):
        fea = frame_compliance(point, params)[:3, :3]
        for load in (forces.mean[0], forces.at_peak[0]):
            world = frames[k] @ load
            ours, theirs = model[k] @ world, fea @ world
            assert np.linalg.norm(ours - theirs) < FEA_TOL * np.linalg.norm(theirs)


def test_feed_frames_are_right_handed_with_the_feed_along_x() -> None:
    rng = np.random.default_rng(SEED)
    tangent = rng.normal(size=(20, 3))
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    axis = og.ProgramAxes().matrix[:, 2]
    frames = feed_frames(tangent, axis)
    np.testing.assert_allclose(
        frames @ np.swapaxes(frames, 1, 2),
        np.broadcast_to(np.eye(3), frames.shape),
        atol=EXACT_TOL,
    )
    np.testing.assert_allclose(np.linalg.det(frames), 1.0, atol=EXACT_TOL)
    plane = tangent - np.outer(tangent @ axis, axis)
    np.testing.assert_allclose(
        np.einsum("ni,ni->n", frames[:, :, 0], plane),
        np.linalg.norm(plane, axis=1),
        atol=EXACT_TOL,
    )
    np.testing.assert_allclose(frames[:, :, 2], np.broadcast_to(axis, (20, 3)), atol=EXACT_TOL)
    plunge = feed_frames(np.broadcast_to(axis, (1, 3)), axis)[0]  # no feed in the plane
    np.testing.assert_allclose(plunge.T @ plunge, np.eye(3), atol=EXACT_TOL)


@pytest.mark.parametrize("milling", ["up", "down"])
def test_a_finishing_pass_pushes_the_tool_off_the_wall(milling: str) -> None:
    """Small radial width: the radial force pushes the tool away, material is left."""
    tool = og.Tool(0.01, 3, 0.5)
    material = og.shipped_materials()["aluminium_7075"]
    immersion = og.Engagement(0.002, 0.0005, milling).immersion(tool.diameter)
    forces = milling_forces(
        1e-4, 0.002, immersion, tool, material, keep_period=True, milling=milling
    )
    assert forces.over_period is not None and forces.at_wall is not None
    c = 1e-7 * np.eye(3)[None]  # isotropic: the deflection is the force times c
    frames = np.eye(3)[None]
    err = surface_errors(
        c, frames, wall_sides([milling]), forces.mean, forces.over_period, forces.at_wall
    )
    assert err.surface_static[0] > 0.0
    side = 1.0 if milling == "up" else -1.0
    assert err.surface_static[0] == pytest.approx(-side * 1e-7 * forces.mean[0, 1], rel=EXACT_TOL)
    assert err.feed_static[0] == pytest.approx(1e-7 * forces.mean[0, 0], rel=EXACT_TOL)
    normal = -side * 1e-7 * forces.over_period[0, :, 1]
    assert err.surface_peak[0] == normal[np.argmax(np.abs(normal))]
    assert abs(err.surface_peak[0]) >= abs(err.surface_static[0])
    wall = -side * 1e-7 * forces.at_wall[0, :, 1]
    assert err.surface_generated[0] == wall[np.argmax(np.abs(wall))]
    assert err.surface_generated[0] > 0.0  # the edge forces push the tool off the wall


def test_a_straight_edge_leaves_its_radial_edge_force_over_the_stiffness() -> None:
    """Zero helix, one tooth in: the wall is left K_re a / k off, up or down (isotropic k)."""
    tool = og.Tool(0.01, 3, 0.0)
    material = og.shipped_materials()["aluminium_7075"]
    for milling in ("up", "down"):
        immersion = og.Engagement(0.002, 0.0005, milling).immersion(tool.diameter)
        forces = milling_forces(
            1e-4, 0.002, immersion, tool, material, keep_period=True, milling=milling
        )
        assert forces.over_period is not None
        err = surface_errors(
            1e-7 * np.eye(3)[None], np.eye(3)[None], wall_sides([milling]), forces.mean,
            forces.over_period, forces.at_wall,
        )  # fmt: skip
        assert err.surface_generated[0] == pytest.approx(material.kre * 0.002 * 1e-7, rel=1e-7)


def test_the_tool_modes_add_their_static_compliance_along_their_axis() -> None:
    modes = (og.ToolMode(2000.0, 0.03, 2e7, "x"), og.ToolMode(2500.0, 0.03, 4e7, "y"))
    tool = og.Tool(0.01, 2, 0.0, modes)
    axes = og.ProgramAxes()  # the prototype's: X on +e2, Y on +e1
    c = tool_compliance(tool, axes)
    np.testing.assert_allclose(c, np.diag([1 / 4e7, 1 / 2e7, 0.0]), rtol=EXACT_TOL)
    point = np.zeros((1, 3))
    np.testing.assert_allclose(
        machine_compliance(point, None, c) - machine_compliance(point, None),
        c[None],
        atol=EXACT_TOL * 1e-6,
    )
