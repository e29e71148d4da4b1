"""The full vibration model against textbook cases, the stiffness model and Pinocchio.

* a pinned-pinned tube, a clamped-free rod in traction and in torsion, from the
  element matrices alone (closed-form frequencies);
* the full model's stiffness, condensed onto the platform, is the vectorised
  stiffness model's ``K6`` (two assemblies of the same structure);
* a carriage on its actuator spring: rigid members, massless legs and platform;
* rigid members: the three finite modes are ``eig(k_a I, M_q)`` with ``M_q``
  from Pinocchio's ``crba`` through the closed-loop Jacobians;
* the Rayleigh quotient of each mode is its ``omega^2``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

import orthoglide_pin as og
from orthoglide_pin.elasticity import frame_modes as fm
from orthoglide_pin.elasticity.mass import (
    MemberMass,
    beam_mass,
    member_masses,
    platform_inertia,
    reflected_mass,
)
from orthoglide_pin.elasticity.members import Section, beam_stiffness
from orthoglide_pin.elasticity.modes import tool_mass
from orthoglide_pin.kinematics.closed_form import ik_and_jacobian

SEED = 20261201
#: Relative agreement of the element-matrix frequencies with the closed forms
#: (16 elements, cubic bending: the error falls as the fourth power).
TEXTBOOK_TOL = 2e-4
#: Relative agreement of two routes to the same matrices (rounding only).
EXACT_TOL = 1e-8
#: The same for traction and torsion (linear elements: the error falls as the
#: square; 64 elements, second mode).
ROD_TOL = 5e-4
#: Rayleigh quotient against the eigenvalue (the solver's rounding, 1e3 DOFs).
RAYLEIGH_TOL = 1e-8
#: Relative agreement of the rigid-member modes with ``eig(k_a I, M_q)``.
RIGID_TOL = 1e-8
#: Factor on the legs' and platform's masses that leaves the carriages alone.
LIGHT = 1e-4
#: Relative agreement then with ``k_a / m`` (the legs' mass left, 1e-4 of 5 kg).
LIGHT_TOL = 2e-4


def _chain(n: int, length: float, section: Section, member: MemberMass) -> tuple:
    """K and M of a straight beam along x cut into n elements (node DOFs stacked)."""
    size = 6 * (n + 1)
    k, m = np.zeros((size, size)), np.zeros((size, size))
    x, y, z = np.eye(3)
    ke = beam_stiffness(x, y, z, length / n, section)
    me = beam_mass(x, y, z, length / n, member)
    for e in range(n):
        sl = slice(6 * e, 6 * e + 12)
        k[sl, sl] += ke
        m[sl, sl] += me
    return k, m


def _solve(k: np.ndarray, m: np.ndarray, keep: np.ndarray, count: int) -> np.ndarray:
    w2 = scipy.linalg.eigh(k[np.ix_(keep, keep)], m[np.ix_(keep, keep)], eigvals_only=True)
    return np.sqrt(w2[:count]) / (2.0 * math.pi)


def test_pinned_pinned_tube_bends_at_the_textbook_frequencies() -> None:
    p = og.prototype()
    length, outer, wall = p.leg_length, p.bar_radius, p.bar_wall
    inner = outer - wall
    area, inertia = math.pi * (outer**2 - inner**2), math.pi * (outer**4 - inner**4) / 4.0
    section = Section(
        p.youngs_modulus * area, p.shear_modulus * 2 * inertia, p.youngs_modulus * inertia
    )
    mu = p.density * area
    member = MemberMass(mu, 0.0, 0.0)  # Euler-Bernoulli: no rotary inertia
    n = 16
    k, m = _chain(n, length, section, member)
    # Planar bending in x-y: keep v and theta_z, pin v at both ends.
    dofs = np.array([6 * i + d for i in range(n + 1) for d in (1, 5)])
    keep = dofs[(dofs != 1) & (dofs != 6 * n + 1)]
    f = _solve(k, m, keep, 3)
    f1 = math.pi / (2.0 * length**2) * math.sqrt(p.youngs_modulus * inertia / mu)
    np.testing.assert_allclose(f, f1 * np.array([1.0, 4.0, 9.0]), rtol=TEXTBOOK_TOL)
    assert 480.0 < f1 < 560.0  # the design notes' bar modes near 500 Hz


def test_clamped_free_rod_in_traction_and_torsion() -> None:
    p = og.prototype()
    length, radius = 0.3, 0.012
    area, polar = math.pi * radius**2, math.pi * radius**4 / 2.0
    section = Section(
        p.youngs_modulus * area, p.shear_modulus * polar, p.youngs_modulus * polar / 2
    )
    member = MemberMass(p.density * area, p.density * polar, 0.0)
    n = 64
    k, m = _chain(n, length, section, member)
    axial = np.array([6 * i for i in range(1, n + 1)])
    twist = axial + 3
    c_axial = math.sqrt(p.youngs_modulus / p.density)
    c_twist = math.sqrt(p.shear_modulus / p.density)
    expected = np.array([1.0, 3.0]) / (4.0 * length)
    np.testing.assert_allclose(_solve(k, m, axial, 2), c_axial * expected, rtol=ROD_TOL)
    np.testing.assert_allclose(_solve(k, m, twist, 2), c_twist * expected, rtol=ROD_TOL)


def _inputs(params: og.OrthoglideParams) -> tuple:
    table = og.inertia_table(params)
    return member_masses(params, table), platform_inertia(params, table), table


@pytest.fixture(scope="module")
def prototype_inputs() -> tuple:
    return _inputs(og.prototype())


def _designs() -> list[og.OrthoglideParams]:
    base = og.prototype()
    other = og.design_from_workspace(0.15, 0.5, 2.0).to_params(base)
    return [
        base,
        dataclasses.replace(other, bar_radius=0.012, bar_wall=0.002, actuator_stiffness=6e7),
    ]


def _points(params: og.OrthoglideParams, count: int) -> np.ndarray:
    cube = params.workspace
    rng = np.random.default_rng(SEED)
    return cube.q1 + cube.side * rng.uniform(0.0, 1.0, (count, 3))


@pytest.mark.parametrize("design", [0, 1])
def test_condensed_full_model_is_the_stiffness_model(design: int) -> None:
    params = _designs()[design]
    masses, plat, _ = _inputs(params)
    for point in _points(params, 3):
        mats = fm.frame_matrices(point, params, masses, plat, 1.0, segments=3)
        k = mats.K
        a, b = mats.platform, np.setdiff1d(np.arange(k.shape[0]), mats.platform)
        cond = k[np.ix_(a, a)] - k[np.ix_(a, b)] @ np.linalg.solve(
            k[np.ix_(b, b)], k[np.ix_(b, a)]
        )
        k6 = og.cartesian_stiffness(point, params).K6
        np.testing.assert_allclose(cond, k6, rtol=1e-7, atol=1e-7 * np.abs(k6).max())


def _rigid_modes(mats: fm.FrameMatrices, params: og.OrthoglideParams) -> np.ndarray:
    """omega^2 of the three mechanism modes: the members exactly rigid.

    The motions the members let free are the null space of their stiffness
    (``K`` without the actuator springs); the modes are those of ``K`` and
    ``M`` restricted to it.
    """
    k_members = mats.K.copy()
    k_members[mats.sliders, mats.sliders] -= params.actuator_stiffness
    w, v = np.linalg.eigh(k_members)
    assert np.all(np.abs(w[:3]) < 1e-6 * w[3])  # exactly a 3-DOF mechanism
    null = v[:, :3]
    return np.asarray(
        scipy.linalg.eigh(null.T @ mats.K @ null, null.T @ mats.M @ null, eigvals_only=True)
    )


def test_a_carriage_on_its_actuator_spring() -> None:
    params = og.prototype()
    drive = og.load_drive(str(og.example_drive_file()))
    carriage = og.inertia_table(params).kind("carriage")[0].mass + reflected_mass(drive)
    masses, plat, _ = _inputs(params)
    light = tuple(
        dataclasses.replace(m, **{f: LIGHT * getattr(m, f) for f in ("mu", "polar", "bending")})
        for m in masses
    )
    point = _points(params, 1)[0]
    mats = fm.frame_matrices(point, params, light, LIGHT * plat, carriage, segments=2)
    w2 = _rigid_modes(mats, params)
    expected = params.actuator_stiffness / carriage
    np.testing.assert_allclose(w2, expected, rtol=LIGHT_TOL)
    assert math.sqrt(expected) / (2 * math.pi) == pytest.approx(497.0, abs=1.0)


@pytest.mark.parametrize("design", [0, 1])
def test_rigid_members_give_eig_of_the_actuators_against_m_q(design: int) -> None:
    params = _designs()[design]
    masses, plat, table = _inputs(params)
    drive = og.load_drive(str(og.example_drive_file()))
    m_eq = reflected_mass(drive)
    carriage = table.kind("carriage")[0].mass + m_eq
    points = _points(params, 3)
    m_x = tool_mass(params, points)
    _, jac = ik_and_jacobian(points, params.leg_length)
    for point, mx, j in zip(points, m_x, jac, strict=True):
        m_q = j.T @ mx @ j + m_eq * np.eye(3)
        expected = scipy.linalg.eigh(params.actuator_stiffness * np.eye(3), m_q, eigvals_only=True)
        mats = fm.frame_matrices(point, params, masses, plat, carriage, segments=2)
        w2 = _rigid_modes(mats, params)
        np.testing.assert_allclose(w2, expected, rtol=RIGID_TOL)


def test_rayleigh_quotients_and_convergence(prototype_inputs: tuple) -> None:
    params = og.prototype()
    masses, plat, _ = prototype_inputs
    point = _points(params, 1)[0]
    w2, phi, mats = fm.frame_modes(point, params, masses, plat, 1.08, 6)
    for k in range(6):
        quotient = phi[:, k] @ mats.K @ phi[:, k] / (phi[:, k] @ mats.M @ phi[:, k])
        assert quotient == pytest.approx(w2[k], rel=RAYLEIGH_TOL)
    finer = fm.frame_matrices(point, params, masses, plat, 1.08, segments=2 * mats.segments)
    w2_fine, _ = fm.solve_modes(finer, 6)
    assert np.all(np.abs(np.sqrt(w2 / w2_fine) - 1.0) < fm.CONVERGENCE)
    assert mats.M.shape[0] == fm.model_size(mats.segments)
