"""The legs' dynamics as trigonometric polynomials, against Pinocchio at random configurations."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

import orthoglide_pin as og
from orthoglide_pin.dynamics import leg_harmonics as lh

#: Expansion against Pinocchio, relative to the largest value compared (rounding).
RTOL = 1e-12
#: The harmonics ``(k_theta, k_phi)`` of the Orthoglide's legs, but the constant.
ORTHOGLIDE_HARMONICS = [[0, 1], [0, 2], [1, 1], [1, -1]]


@pytest.fixture(scope="module", params=["prototype", "other"])
def machine(request: pytest.FixtureRequest) -> og.ClosedLoopDynamics:
    if request.param == "prototype":
        return og.ClosedLoopDynamics()
    params = og.prototype().replace(leg_length=0.35, platform_offset=0.03, spindle_mass=2.5)
    return og.ClosedLoopDynamics(og.ClosedLoopModel(params))


def _random_functions(rng: np.random.Generator) -> np.ndarray:
    """Joint functions (leg, (q, theta, phi)) anywhere: the tree has no loops to close."""
    return np.stack([rng.uniform(-0.3, 0.3, 3), *rng.uniform(-np.pi, np.pi, (2, 3))], axis=-1)


def _evaluate(
    expansion: lh.LegHarmonics, f: np.ndarray, gravity: np.ndarray
) -> tuple[np.ndarray, ...]:
    cos, sin = np.cos(f[:, 1:]).T[..., None], np.sin(f[:, 1:]).T[..., None]
    basis = expansion.basis(cos[0], sin[0], cos[1], sin[1])
    mass, vel, weight = expansion.evaluate(basis, expansion.coefficients(gravity))
    return mass[..., 0], vel[..., 0], weight[..., 0]


def test_each_coefficient_is_pinocchios(machine: og.ClosedLoopDynamics) -> None:
    """Mass matrix (crba), velocity terms (rnea) and gravity torques, one by one."""
    expansion = lh.leg_harmonics(machine)
    assert expansion is not None
    model = pin.Model(machine.closed_loop.model)
    data, idx = model.createData(), machine.leg_indices
    proj = lh._projection(idx, model.nv)
    rng = np.random.default_rng(41)
    for _ in range(10):
        f, gravity = _random_functions(rng), rng.normal(size=3) * 9.81
        mass, vel, weight = _evaluate(expansion, f, gravity)
        q = lh._configuration(f, idx)
        full = pin.crba(model, data, q)
        m_f = proj @ (np.triu(full) + np.triu(full, 1).T) @ proj.T
        blocks = np.zeros((9, 9))
        for leg in range(3):
            blocks[3 * leg : 3 * leg + 3, 3 * leg : 3 * leg + 3] = mass[leg]
        np.testing.assert_allclose(blocks, m_f, rtol=0, atol=RTOL * np.abs(m_f).max())
        # velocity terms at random rates, the slider rates included (they add none)
        rates = rng.normal(size=(3, 3))
        model.gravity = pin.Motion.Zero()
        tau = proj @ pin.rnea(model, data, q, lh._configuration(rates, idx), np.zeros(model.nv))
        th, ph = rates[:, 1], rates[:, 2]
        quad = np.einsum("lt,ltf->lf", np.stack([th * th, ph * ph, th * ph], -1), vel)
        np.testing.assert_allclose(quad.reshape(9), tau, rtol=0, atol=RTOL * np.abs(tau).max())
        model.gravity = pin.Motion(gravity, np.zeros(3))
        grav = proj @ pin.computeGeneralizedGravity(model, data, q)
        np.testing.assert_allclose(weight.reshape(9), grav, rtol=0, atol=RTOL * np.abs(grav).max())


def test_the_orthoglide_needs_four_harmonics(machine: og.ClosedLoopDynamics) -> None:
    expansion = lh.leg_harmonics(machine)
    assert expansion is not None
    assert expansion.harmonics.tolist() == ORTHOGLIDE_HARMONICS
    assert expansion.mass.shape == (3, 9, 3, 3)
    # the slider's own row: the whole leg's mass, constant [kg]
    model = machine.closed_loop.model
    leg_mass = [
        sum(
            model.inertias[j].mass for j in range(1, model.njoints) if model.joints[j].idx_v in row
        )
        for row in machine.leg_indices.tolist()
    ]
    assert leg_mass[0] > leg_mass[1] + 1.0  # leg 1 carries the platform in the cut tree
    np.testing.assert_allclose(expansion.mass[:, 0, 0, 0], leg_mass, rtol=1e-12)
    np.testing.assert_allclose(expansion.mass[:, 1:, 0, 0], 0.0, atol=1e-12)


def test_a_finer_grid_finds_nothing_beyond_the_degree(
    machine: og.ClosedLoopDynamics, monkeypatch: pytest.MonkeyPatch
) -> None:
    """On 13 x 13 angles (exact to degree 6) every harmonic above 4 vanishes: no aliasing."""
    monkeypatch.setattr(lh, "GRID", 13)
    values = lh._sample(pin.Model(machine.closed_loop.model), machine.leg_indices)
    spectrum = np.abs(np.fft.fft2(values, axes=(1, 2))) / 13**2
    orders = np.abs(np.rint(np.fft.fftfreq(13, 1.0 / 13))).astype(int)
    high = (orders[:, None] > lh.DEGREE) | (orders[None, :] > lh.DEGREE)
    assert spectrum[:, high].max() <= 1e-13 * np.abs(values).max()
    # and the grid of the expansion gives the same coefficients
    coarse = lh._expand(pin.Model(machine.closed_loop.model), machine.leg_indices)
    monkeypatch.setattr(lh, "GRID", 9)
    assert coarse.harmonics.tolist() == lh.leg_harmonics(machine).harmonics.tolist()  # type: ignore[union-attr]


def test_the_check_catches_a_wrong_expansion(machine: og.ClosedLoopDynamics) -> None:
    model = pin.Model(machine.closed_loop.model)
    good = lh._expand(model, machine.leg_indices)
    assert lh._agrees(good, model, machine.leg_indices)
    # one harmonic short
    short = dataclasses.replace(
        good,
        harmonics=good.harmonics[:-1],
        mass=good.mass[:, :-2],
        velocity=good.velocity[:, :-2],
        gravity=good.gravity[:, :-2],
    )
    assert not lh._agrees(short, model, machine.leg_indices)
    # the largest coefficient of a harmonic off by a part in 1e9
    mass = good.mass.copy()
    mass[:, 1:].flat[np.argmax(np.abs(mass[:, 1:]))] *= 1.0 + 1e-9
    assert not lh._agrees(dataclasses.replace(good, mass=mass), model, machine.leg_indices)


def test_the_expansion_is_kept_per_dynamics(machine: og.ClosedLoopDynamics) -> None:
    fresh = og.ClosedLoopDynamics(machine.closed_loop)
    before = fresh.closed_loop.model.gravity.linear.copy()
    assert lh.leg_harmonics(fresh) is lh.leg_harmonics(fresh) is not None
    # it works on a copy: the machine's model keeps its gravity
    np.testing.assert_array_equal(fresh.closed_loop.model.gravity.linear, before)
    np.testing.assert_array_equal(fresh.engine().model.gravity.linear, fresh.gravity)
