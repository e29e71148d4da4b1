"""Beam elements against the textbook local matrix and beam formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import cube_points

import orthoglide_pin as og
from orthoglide_pin.elasticity.members import (
    Section,
    bar_section,
    beam_stiffness,
    link_section,
    member_nodes,
)

SEED = 11
E, G = 70.0e9, 26.0e9
TOL = 1e-12
#: Node positions [m] and axis cosines against the Pinocchio model.
GEOMETRY_TOL = 1e-12


def _textbook(length: float, s: Section, ei_z: float) -> np.ndarray:
    """Local 12x12 Euler-Bernoulli matrix (Przemieniecki), DOFs u v w tx ty tz per end."""
    L, ea, gj, ei_y = length, s.EA, s.GJ, s.EI
    k = np.zeros((12, 12))

    def put(i: int, j: int, v: float) -> None:
        k[i, j] = k[j, i] = v

    put(0, 0, ea / L), put(6, 6, ea / L), put(0, 6, -ea / L)
    put(3, 3, gj / L), put(9, 9, gj / L), put(3, 9, -gj / L)
    for ei, (v, r, sign) in ((ei_z, (1, 5, 1.0)), (ei_y, (2, 4, -1.0))):
        a, b = 12 * ei / L**3, 6 * ei / L**2
        put(v, v, a), put(v + 6, v + 6, a), put(v, v + 6, -a)
        put(v, r, sign * b), put(v, r + 6, sign * b)
        put(v + 6, r, -sign * b), put(v + 6, r + 6, -sign * b)
        put(r, r, 4 * ei / L), put(r + 6, r + 6, 4 * ei / L), put(r, r + 6, 2 * ei / L)
    return k


@pytest.mark.parametrize("release", [False, True])
def test_world_form_is_the_rotated_textbook_matrix(release: bool) -> None:
    rng = np.random.default_rng(SEED)
    rot, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    rot *= np.sign(np.linalg.det(rot))
    x, y, z = rot.T
    section = bar_section(0.01, 0.0015, E, G)
    length = 0.31
    k = beam_stiffness(x, y, z, length, section, release_z=release)
    t = np.kron(np.eye(4), rot)  # local -> world, block-diagonal
    expected = t @ _textbook(length, section, 0.0 if release else section.EI) @ t.T
    np.testing.assert_allclose(k, expected, atol=TOL * np.abs(expected).max())


def test_cantilever_formulas() -> None:
    """Clamped at a, loaded at b: tip deflection F L^3 / 3EI, twist T L / GJ."""
    section = link_section(0.012, E, G)
    length = 0.04
    k = beam_stiffness(np.eye(3)[0], np.eye(3)[1], np.eye(3)[2], length, section)
    compliance = np.linalg.inv(k[6:, 6:])
    ei = E * math.pi * 0.012**4 / 4
    assert compliance[1, 1] == pytest.approx(length**3 / (3 * ei), rel=1e-12)
    assert compliance[3, 3] == pytest.approx(length / (G * 2 * math.pi * 0.012**4 / 4))
    assert compliance[0, 0] == pytest.approx(length / (E * math.pi * 0.012**2))
    # Six rigid-body modes.
    assert np.sum(np.linalg.eigvalsh(k) > 1e-6 * np.abs(k).max()) == 6


def test_sections() -> None:
    tube = bar_section(0.01, 0.0015, E, G)
    assert math.isclose(tube.EA, E * math.pi * (0.01**2 - 0.0085**2), rel_tol=1e-12)
    assert math.isclose(tube.GJ, G * math.pi * (0.01**4 - 0.0085**4) / 2, rel_tol=1e-12)
    solid = bar_section(0.01, 0.01, E, G)
    assert solid == link_section(0.01, E, G)


def test_member_nodes_are_the_descriptions_joints(model: og.ClosedLoopModel) -> None:
    """Node positions and joint axes against the Pinocchio model of the URDF."""
    import pinocchio as pin

    points = cube_points(4, seed=SEED)
    nodes = member_nodes(points, model.params)
    joints = {
        "C": "base_revolute",
        "A0": "bar_a_base",
        "B0": "bar_b_base",
        "A1": "bar_a_tip",
        "D": "end_revolute",
    }
    for k, point in enumerate(points):
        q = model.configuration(point)
        pin.forwardKinematics(model.model, model.data, q)
        pin.updateFramePlacements(model.model, model.data)
        for i in range(3):
            for node, joint in joints.items():
                oMi = model.data.oMi[model.model.getJointId(f"leg{i + 1}_{joint}")]
                np.testing.assert_allclose(nodes[node][k, i], oMi.translation, atol=GEOMETRY_TOL)
            tip = model.data.oMf[model.model.getFrameId(f"leg{i + 1}_bar_b_tip")]
            np.testing.assert_allclose(nodes["B1"][k, i], tip.translation, atol=GEOMETRY_TOL)
            for joint, axis, key in (("bar_a_base", 2, "normal"), ("base_revolute", 1, "axis")):
                rot = model.data.oMi[model.model.getJointId(f"leg{i + 1}_{joint}")].rotation
                cos = abs(float(rot[:, axis] @ nodes[key][k, i]))
                assert cos == pytest.approx(1.0, abs=GEOMETRY_TOL)
