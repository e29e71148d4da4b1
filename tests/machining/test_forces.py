"""Altintas' milling force model against its closed forms and an independent integration.

Full immersion (a slot, ``phi_st = 0``, ``phi_ex = pi``), zero helix: the mean
over a revolution of

    F_x = -(K_tc h + K_te) cos(phi) - (K_rc h + K_re) sin(phi),
    F_y = (K_tc h + K_te) sin(phi) - (K_rc h + K_re) cos(phi),  h = f_t sin(phi),

summed over N teeth of axial depth a, is ``(N a / 2 pi)`` times its integral
over ``[0, pi]``; with ``int sin cos = 0``, ``int cos = 0``,
``int sin^2 = pi / 2`` and ``int sin = 2``:

    mean F_x = -N a K_rc f_t / 4 - N a K_re / pi,
    mean F_y = N a K_tc f_t / 4 + N a K_te / pi,
    mean F_z = -(N a K_ac f_t / pi + N a K_ae / 2)   (the axial force pulls the tool down).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machining.forces import DISCS, STEPS, milling_forces

SEED = 20261206
#: The closed-form mean of the module against the test's formula (the same
#: integral written twice: round-off only), relative.
CLOSED_FORM_TOL = 1e-12
#: The mean of the sampled revolution against the closed form, relative to the
#: force's size: the sampled period (STEPS angles, DISCS discs) misses part of
#: the jumps of the edge forces at entry and exit.
SAMPLED_MEAN_TOL = 0.02
#: The force at the wall: the edge is taken 1e-9 rad inside the cut, relative.
WALL_TOL = 1e-7
#: The sampled force against a brute-force integration of the same model, relative.
BRUTE_FORCE_TOL = 1e-9

MATERIAL = og.Material("test", kt=7.0e8, kr=2.1e8, ka=1.5e8, kte=2.4e4, kre=3.1e4, kae=1.2e3)


def slot_mean(teeth: int, depth: float, feed: float, m: og.Material) -> np.ndarray:
    """The closed-form slot mean of the module docstring [N]."""
    n, a, f = teeth, depth, feed
    return np.array(
        [
            -n * a * m.kr * f / 4 - n * a * m.kre / math.pi,
            n * a * m.kt * f / 4 + n * a * m.kte / math.pi,
            -(n * a * m.ka * f / math.pi + n * a * m.kae / 2),
        ]
    )


@pytest.mark.parametrize("teeth", [1, 2, 4])
def test_the_slot_mean_is_the_closed_form(teeth: int) -> None:
    rng = np.random.default_rng(SEED + teeth)
    feed, depth = rng.uniform(2e-5, 2e-4, 5), rng.uniform(5e-4, 5e-3, 5)
    tool = og.Tool(0.012, teeth, 0.0)
    forces = milling_forces(feed, depth, (0.0, math.pi), tool, MATERIAL, keep_period=True)
    expected = np.stack(
        [slot_mean(teeth, a, f, MATERIAL) for a, f in zip(depth, feed, strict=True)]
    )
    scale = np.abs(expected).max()
    np.testing.assert_allclose(forces.mean, expected, rtol=0, atol=CLOSED_FORM_TOL * scale)
    assert forces.over_period is not None
    sampled = forces.over_period.mean(axis=1)
    assert np.abs(sampled - expected).max() < SAMPLED_MEAN_TOL * scale


@pytest.mark.parametrize("helix", [0.0, 0.5236, 0.7])
def test_the_mean_does_not_depend_on_the_helix(helix: float) -> None:
    """The helix shifts each disc's phase only: the revolution's mean stays."""
    tool = og.Tool(0.01, 3, helix)
    immersion = [(0.0, 1.2), (2.0, math.pi), (0.0, math.pi)]
    forces = milling_forces(1e-4, 0.004, immersion, tool, MATERIAL, keep_period=True)
    assert forces.over_period is not None
    scale = np.abs(forces.mean).max()
    assert np.abs(forces.over_period.mean(axis=1) - forces.mean).max() < SAMPLED_MEAN_TOL * scale


def _brute_force(
    phi: float, f: float, a: float, st: float, ex: float, tool: og.Tool
) -> np.ndarray:
    """The same model, one edge element at a time (loops, no vectorisation)."""
    total = np.zeros(3)
    discs = 12
    for k in range(discs):
        z = (k + 0.5) * a / discs
        for j in range(tool.teeth):
            angle = (
                phi
                + 2 * math.pi * j / tool.teeth
                - z * math.tan(tool.helix_angle) * 2 / tool.diameter
            ) % (2 * math.pi)
            if not st <= angle <= ex:
                continue
            h = f * math.sin(angle)
            dft = (MATERIAL.kt * h + MATERIAL.kte) * a / discs
            dfr = (MATERIAL.kr * h + MATERIAL.kre) * a / discs
            dfa = (MATERIAL.ka * h + MATERIAL.kae) * a / discs
            total += [
                -dft * math.cos(angle) - dfr * math.sin(angle),
                dft * math.sin(angle) - dfr * math.cos(angle),
                -dfa,
            ]
    return total


def test_the_sampled_force_is_the_model_element_by_element() -> None:
    tool = og.Tool(0.01, 3, 0.5)
    st, ex = og.Engagement(0.003, 0.002, "down").immersion(tool.diameter)
    forces = milling_forces(1.2e-4, 0.003, (st, ex), tool, MATERIAL, keep_period=True)
    assert forces.over_period is not None
    scale = forces.peak[0]
    for i in (0, 17, 40, STEPS - 1):
        expected = _brute_force(float(forces.angles[i]), 1.2e-4, 0.003, st, ex, tool)
        got = forces.over_period[0, i]
        assert np.abs(got - expected).max() <= BRUTE_FORCE_TOL * scale
    size = np.linalg.norm(forces.over_period[0], axis=1)
    assert forces.peak[0] == size.max()
    np.testing.assert_array_equal(forces.at_peak[0], forces.over_period[0, np.argmax(size)])


def test_no_engagement_no_force_and_bad_values() -> None:
    tool = og.Tool(0.01, 2)
    forces = milling_forces([0.0, 1e-4], [0.0, 0.002], [(0.0, 0.0), (0.0, 0.0)], tool, MATERIAL)
    np.testing.assert_array_equal(forces.mean, 0.0)
    np.testing.assert_array_equal(forces.peak, 0.0)
    with pytest.raises(og.InvalidParameterError, match="feed_per_tooth"):
        milling_forces([-1e-4], 0.002, (0.0, math.pi), tool, MATERIAL)
    with pytest.raises(og.InvalidParameterError, match="immersion"):
        milling_forces(1e-4, 0.002, (2.0, 1.0), tool, MATERIAL)


@pytest.mark.parametrize("milling", ["up", "down"])
def test_the_force_as_a_straight_edge_generates_the_wall_is_its_edge_force(milling: str) -> None:
    """Zero helix, one tooth in the cut: at the wall the chip is nil, the edge forces act.

    Up milling generates the wall at phi = 0: F = (-K_te a, -K_re a, -K_ae a);
    down milling at phi = pi: F = (K_te a, K_re a, -K_ae a).
    """
    tool = og.Tool(0.01, 3, 0.0)
    immersion = og.Engagement(0.002, 0.0005, milling).immersion(tool.diameter)
    depth = 0.002
    forces = milling_forces([1e-4, 3e-5], depth, immersion, tool, MATERIAL, milling=milling)
    sign = -1.0 if milling == "up" else 1.0
    m = MATERIAL
    expected = np.array([sign * m.kte * depth, sign * m.kre * depth, -m.kae * depth])
    assert forces.at_wall is not None and forces.at_wall.shape == (2, DISCS, 3)
    np.testing.assert_allclose(forces.at_wall, np.broadcast_to(expected, (2, DISCS, 3)),
                               rtol=WALL_TOL)  # fmt: skip
    with pytest.raises(og.InvalidParameterError, match="milling"):
        milling_forces(1e-4, depth, immersion, tool, MATERIAL, milling="climb")
