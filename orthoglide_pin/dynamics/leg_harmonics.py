"""Each leg's dynamics as exact trigonometric polynomials of its two angles.

Leg ``i`` of the cut tree is a subtree of its own, rooted at its slider (a
prismatic joint on the ground), and its joints move with the three joint
functions ``f = (q, theta, phi)`` of :mod:`orthoglide_pin.kinematics.joint_motion`.
Projected onto them (the signed sums of
:data:`~orthoglide_pin.kinematics.joint_motion.LEG_JOINTS`), the joint torques
of a leg are::

    tau_f = M_f(theta, phi) f''
            + theta'^2 C_tt(theta, phi) + phi'^2 C_pp(theta, phi) + theta' phi' C_tp(theta, phi)
            + Gamma(theta, phi) g

* no slider value ``q``: sliding a leg along its axis changes neither its
  inertia nor its gravity torques;
* no slider rate ``q'`` in the velocity terms: the slider translates the whole
  leg at a constant speed (Galilean invariance);
* ``Gamma`` (3, 3) is linear in the gravity vector ``g``.

Every coefficient is a trigonometric polynomial of degree at most
:data:`DEGREE` in each angle. A body's placement is a product of fixed
placements and joint rotations; on every branch of a leg ``theta`` occurs
twice (base and end revolutes) and ``phi`` twice (bar a, base and tip), so the
entries of each body's position and rotation have degree 2 at most in each
angle. The mass matrix (``J^T I J``), its derivatives (the velocity terms)
and the gravity torques then have degree 4 at most.

A grid of ``2 DEGREE + 1`` angles per axis therefore determines them exactly:
the two-dimensional discrete Fourier transform of Pinocchio's values on it
gives the coefficients up to rounding. The values come from ``crba`` (the mass
matrix), ``rnea`` without gravity at the rates ``(theta', phi') = (1, 0), (0, 1),
(1, 1)`` (the velocity terms, polarised) and ``computeGeneralizedGravity``
with ``g = e_1, e_2, e_3``. Only the harmonics present are kept (those above
:data:`SELECT_TOL` of their group's largest value). On the Orthoglide they are
``(k_theta, k_phi) = (0, 0), (0, 1), (0, 2), (1, 1), (1, -1)``, so each
coefficient costs 9 products per point instead of one ``rnea`` pass.

:func:`leg_harmonics` checks the expansion against Pinocchio before it is used:
one ``rnea`` call with gravity at each of :data:`VERIFY_POINTS` random
configurations of the whole tree (random slider values, angles, rates,
accelerations and gravity), which also checks that the legs are independent.
A model that fails the check (a custom URDF of another structure) gets
``None``, and its callers use ``rnea`` at every point instead.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Final

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.kinematics.joint_motion import LEG_JOINTS, scatter

FloatArray = NDArray[np.float64]

#: Highest harmonic of either angle in the leg dynamics (see the module).
DEGREE: Final[int] = 4
#: Samples per angle: enough for every harmonic up to ``DEGREE``.
GRID: Final[int] = 2 * DEGREE + 1
#: A harmonic is kept when one of its coefficients exceeds this share of its
#: group's largest value (mass, velocity or gravity terms); rounding gives ~1e-16.
SELECT_TOL: Final[float] = 1e-12
#: Random configurations at which the expansion is checked against ``rnea``.
VERIFY_POINTS: Final[int] = 24
#: Largest difference accepted there, relative to the largest torque term.
VERIFY_TOL: Final[float] = 1e-11
#: Outputs per leg: mass matrix (3 x 3), velocity terms (3 x 3), gravity (3 x 3).
_MASS, _VELOCITY, _GRAVITY = slice(0, 9), slice(9, 18), slice(18, 27)
#: Joint-function rates ``(q', theta', phi')`` of the velocity rows (polarised).
_RATES: Final = ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 1.0, 1.0))

_CACHE: weakref.WeakKeyDictionary[ClosedLoopDynamics, LegHarmonics | None] = (
    weakref.WeakKeyDictionary()
)


@dataclass(frozen=True)
class LegHarmonics:
    """The exact trigonometric expansion of the three legs' dynamics.

    A coefficient ``y`` of leg ``l`` is ``sum_b basis_b(theta, phi) coef[l, b]``
    with ``basis = (1, cos h_1, sin h_1, cos h_2, ...)`` and
    ``h_j = k_theta theta + k_phi phi`` (:attr:`harmonics`).

    Attributes:
        harmonics: ``(k_theta, k_phi)`` of the kept harmonics but the constant, (K, 2).
        mass: ``M_f`` per leg and basis function [kg, kg.m, kg.m^2], (3, 2K + 1, 3, 3).
        velocity: ``(C_tt, C_pp, C_tp)`` per leg and basis function [N, N.m],
            (3, 2K + 1, 3 terms, 3 functions).
        gravity: ``Gamma`` per leg and basis function, response to a unit gravity
            along each world axis [kg, kg.m], (3, 2K + 1, 3 axes, 3 functions).
    """

    harmonics: NDArray[np.intp]
    mass: FloatArray
    velocity: FloatArray
    gravity: FloatArray

    def basis(
        self,
        cos_theta: FloatArray,
        sin_theta: FloatArray,
        cos_phi: FloatArray,
        sin_phi: FloatArray,
    ) -> FloatArray:
        """The basis functions at given angles, by products of ``e^(i theta)`` and ``e^(i phi)``.

        Args:
            cos_theta: ``cos theta`` per leg and point, shape (3, n).
            sin_theta: ``sin theta``, shape (3, n).
            cos_phi: ``cos phi``, shape (3, n).
            sin_phi: ``sin phi``, shape (3, n).

        Returns:
            ``(1, cos h_1, sin h_1, ...)``, shape (3, 2K + 1, n).
        """
        theta = _powers(cos_theta, sin_theta, int(self.harmonics[:, 0].max(initial=0)))
        phi = _powers(cos_phi, sin_phi, int(np.abs(self.harmonics[:, 1]).max(initial=0)))
        out = np.empty((cos_theta.shape[0], 1 + 2 * len(self.harmonics), cos_theta.shape[1]))
        out[:, 0] = 1.0
        for j, (kt, kp) in enumerate(self.harmonics.tolist()):
            (ar, ai), (br, bi) = theta[kt], phi[abs(kp)]
            if kp < 0:
                bi = -bi
            out[:, 2 * j + 1] = ar * br - ai * bi
            out[:, 2 * j + 2] = ar * bi + ai * br
        return out

    def coefficients(self, gravity: FloatArray) -> FloatArray:
        """Per leg, output and basis function: ``M_f`` (9), velocity terms (9), ``Gamma g`` (3).

        Args:
            gravity: Gravity [m/s^2], shape (3,).

        Returns:
            Shape (3, 21, 2K + 1), for :meth:`evaluate`.
        """
        n_legs, n_basis = self.mass.shape[:2]
        weight = np.einsum("lbaf,a->lbf", self.gravity, gravity)
        parts = (self.mass.reshape(n_legs, n_basis, 9), self.velocity.reshape(n_legs, n_basis, 9))
        return np.ascontiguousarray(np.concatenate([*parts, weight], axis=-1).transpose(0, 2, 1))

    def evaluate(
        self, basis: FloatArray, coefficients: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The leg dynamics at points, from :meth:`basis` and :meth:`coefficients`.

        Args:
            basis: Shape (3, 2K + 1, n).
            coefficients: Shape (3, 21, 2K + 1).

        Returns:
            Per leg: ``M_f`` (3, 3, 3, n), the velocity terms ``(C_tt, C_pp, C_tp)``
            (3, 3 terms, 3 functions, n) and the gravity torques ``Gamma g`` (3, 3, n).
        """
        values = coefficients @ basis
        n_legs, _, n = values.shape
        return (
            values[:, :9].reshape(n_legs, 3, 3, n),
            values[:, 9:18].reshape(n_legs, 3, 3, n),
            values[:, 18:],
        )


def _powers(
    cos: FloatArray, sin: FloatArray, top: int
) -> list[tuple[FloatArray | float, FloatArray | float]]:
    """``e^(i k a)`` as (real, imaginary) parts for ``k = 0 .. top``, by repeated products."""
    out: list[tuple[FloatArray | float, FloatArray | float]] = [(1.0, 0.0)]
    for _ in range(top):
        re, im = out[-1]
        out.append((re * cos - im * sin, re * sin + im * cos))
    return out


def leg_harmonics(dyn: ClosedLoopDynamics) -> LegHarmonics | None:
    """The checked expansion of ``dyn``'s legs (cached per dynamics), or ``None``.

    Args:
        dyn: The closed-loop dynamics whose Pinocchio model is expanded.

    Returns:
        The expansion, or ``None`` when it does not reproduce ``rnea`` (see the module).
    """
    if dyn not in _CACHE:
        model = pin.Model(dyn.closed_loop.model)
        expansion = _expand(model, dyn.leg_indices)
        _CACHE[dyn] = expansion if _agrees(expansion, model, dyn.leg_indices) else None
    return _CACHE[dyn]


def _projection(leg_indices: NDArray[np.intp], nv: int) -> FloatArray:
    """Joint torques to joint-function forces, leg by leg, shape (9, nv)."""
    proj = np.zeros((9, nv))
    for slot, (_, fn, sign) in enumerate(LEG_JOINTS):
        proj[3 * np.arange(3) + fn, leg_indices[:, slot]] += sign
    return proj


def _configuration(functions: FloatArray, leg_indices: NDArray[np.intp]) -> FloatArray:
    """The tree's joint vector of joint functions ``(3, 3)`` (leg, function)."""
    out: FloatArray = scatter(functions[None], leg_indices)[0]
    return out


def _sample(model: pin.Model, leg_indices: NDArray[np.intp]) -> FloatArray:
    """The 27 outputs per leg on the angle grid (the legs at once), shape (3, GRID, GRID, 27)."""
    data, nv = model.createData(), model.nv
    proj = _projection(leg_indices, nv)
    angles = 2.0 * np.pi * np.arange(GRID) / GRID
    f = np.zeros((GRID, GRID, 3, 3))  # (theta, phi, leg, function)
    f[..., 1], f[..., 2] = angles[:, None, None], angles[None, :, None]
    configurations = scatter(f.reshape(-1, 3, 3), leg_indices)
    rates = [_configuration(np.tile(r, (3, 1)), leg_indices) for r in _RATES]
    zero = np.zeros(nv)
    m = configurations.shape[0]
    mass, vel, grav = np.empty((m, nv, nv)), np.empty((m, 3, nv)), np.empty((m, 3, nv))
    model.gravity = pin.Motion.Zero()
    for k, q in enumerate(configurations):
        mass[k] = pin.crba(model, data, q)
        for row, r in enumerate(rates):
            vel[k, row] = pin.rnea(model, data, q, r, zero)
    for axis in range(3):
        model.gravity = pin.Motion(np.eye(3)[axis], np.zeros(3))
        for k, q in enumerate(configurations):
            grav[k, axis] = pin.computeGeneralizedGravity(model, data, q)
    model.gravity = pin.Motion.Zero()
    mass = np.triu(mass) + np.triu(mass, 1).transpose(0, 2, 1)  # crba fills the upper part
    m_f = (proj @ mass @ proj.T).reshape(m, 3, 3, 3, 3)
    vel, grav = (vel @ proj.T).reshape(m, 3, 3, 3), (grav @ proj.T).reshape(m, 3, 3, 3)
    vel[:, 2] -= vel[:, 0] + vel[:, 1]  # the cross term
    out = np.empty((3, m, 27))
    for leg in range(3):
        out[leg, :, _MASS] = m_f[:, leg, :, leg, :].reshape(m, 9)
    out[:, :, _VELOCITY] = vel.transpose(2, 0, 1, 3).reshape(3, m, 9)  # (leg, point, term, fn)
    out[:, :, _GRAVITY] = grav.transpose(2, 0, 1, 3).reshape(3, m, 9)  # (leg, point, axis, fn)
    return out.reshape(3, GRID, GRID, 27)


def _expand(model: pin.Model, leg_indices: NDArray[np.intp]) -> LegHarmonics:
    """The Fourier coefficients of the sampled outputs, the harmonics present kept."""
    values = _sample(model, leg_indices)
    spectrum = np.fft.fft2(values, axes=(1, 2)) / (GRID * GRID)
    orders = np.rint(np.fft.fftfreq(GRID, 1.0 / GRID)).astype(np.intp)
    floor = np.empty(27)
    for group in (_MASS, _VELOCITY, _GRAVITY):
        floor[group] = SELECT_TOL * max(float(np.abs(values[..., group]).max()), 1e-300)
    kept = [
        (i, j)
        for i, kt in enumerate(orders)
        for j, kp in enumerate(orders)
        if (kt > 0 or (kt == 0 and kp > 0)) and bool((np.abs(spectrum[:, i, j]) > floor).any())
    ]
    coef = np.empty((3, 1 + 2 * len(kept), 27))
    coef[:, 0] = spectrum[:, 0, 0].real
    for h, (i, j) in enumerate(kept):
        coef[:, 2 * h + 1] = 2.0 * spectrum[:, i, j].real
        coef[:, 2 * h + 2] = -2.0 * spectrum[:, i, j].imag
    harmonics = np.array([(orders[i], orders[j]) for i, j in kept], dtype=np.intp).reshape(-1, 2)
    n_basis = coef.shape[1]
    return LegHarmonics(
        harmonics=harmonics,
        mass=np.ascontiguousarray(coef[..., _MASS].reshape(3, n_basis, 3, 3)),
        velocity=np.ascontiguousarray(coef[..., _VELOCITY].reshape(3, n_basis, 3, 3)),
        gravity=np.ascontiguousarray(coef[..., _GRAVITY].reshape(3, n_basis, 3, 3)),
    )


def _agrees(expansion: LegHarmonics, model: pin.Model, leg_indices: NDArray[np.intp]) -> bool:
    """Whether the expansion gives ``rnea`` at random configurations of the whole tree."""
    rng = np.random.default_rng(20)
    m = VERIFY_POINTS
    f = np.stack(
        [rng.uniform(-0.5, 0.5, (m, 3)), *rng.uniform(-np.pi, np.pi, (2, m, 3))], axis=-1
    )  # (point, leg, function)
    rates, accelerations = rng.normal(size=(2, m, 3, 3))
    gravity = rng.normal(size=(m, 3)) * 10.0
    data, proj = model.createData(), _projection(leg_indices, model.nv)
    q, v, a = (scatter(x, leg_indices) for x in (f, rates, accelerations))
    tau = np.empty((m, model.nv))
    for k in range(m):
        model.gravity = pin.Motion(gravity[k], np.zeros(3))
        tau[k] = pin.rnea(model, data, q[k], v[k], a[k])
    model.gravity = pin.Motion.Zero()
    expected = (tau @ proj.T).reshape(m, 3, 3).transpose(1, 2, 0)  # (leg, function, point)
    cos, sin = np.cos(f[..., 1:]).T, np.sin(f[..., 1:]).T  # (angle, leg, point)
    basis = expansion.basis(cos[0], sin[0], cos[1], sin[1])
    mass, vel, _ = expansion.evaluate(basis, expansion.coefficients(np.zeros(3)))
    th, ph = rates[..., 1].T, rates[..., 2].T  # (leg, point)
    terms = (
        np.einsum("lfgn,ngl->lfn", mass, accelerations.transpose(0, 2, 1)),
        np.einsum("ltfn,tln->lfn", vel, np.stack([th * th, ph * ph, th * ph])),
        np.einsum("lbaf,lbn,na->lfn", expansion.gravity, basis, gravity),
    )
    scale = np.max([np.abs(t).max(axis=(0, 1)) for t in terms], axis=0)  # per point
    return bool(np.all(np.abs(sum(terms) - expected).max(axis=(0, 1)) <= VERIFY_TOL * scale))
