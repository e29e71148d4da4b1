"""Slider forces and accelerations as affine-quadratic forms in the tool motion.

At a tool point ``P`` the slider forces are affine in the tool acceleration
``a`` and quadratic in the tool velocity ``v`` (the platform only translates;
``rnea`` is linear in the joint accelerations and quadratic in the joint
velocities, and these are linear in ``v``, with joint accelerations linear in
``a`` plus a quadratic term in ``v``)::

    F_i = m_i . a + v^T H_i v + c_i

with ``m_i`` the row ``i`` of the tool-space mass matrix seen by the sliders,
``H_i`` symmetric (3, 3) and ``c_i`` the gravity and external-wrench term. The
slider accelerations have the same form, ``q''_i = b_i . a + v^T K_i v``, with
``b_i`` the row ``i`` of ``J^-1``. :func:`requirement_forms` reads both from
the Pinocchio model of the cut tree, vectorised over points, through the joint
functions ``f = (q, theta, phi)`` of each leg
(:mod:`orthoglide_pin.kinematics.joint_motion`), whose gradients ``R = df/dP``
and Hessians ``d2f/dP2`` are in closed form (:func:`function_hessians`):

* the mass part from the joint-space mass matrix (``pinocchio.crba``) brought
  to the joint functions, ``M_f``: ``R^T M_f R a`` for the acceleration and
  ``R^T M_f d2f/dP2 [v, v]`` for the joint accelerations a velocity causes;
* the constant from ``computeGeneralizedGravity`` and the wrench, ``-J^T f``;
* the Coriolis and centrifugal part from three ``rnea`` rows without gravity
  nor acceleration. Each leg is a subtree of its own, so one row gives the
  three legs at once; and a leg's velocity term does not depend on its slider
  rate (the slider translates the whole leg at a constant speed: Galilean
  invariance), so it is a quadratic form in ``(theta', phi')`` with three
  coefficients, read from the rates ``(1, 0)``, ``(0, 1)`` and ``(1, 1)``.

These three model terms are functions of each leg's two angles only, and
trigonometric polynomials of them: they are evaluated from the legs' exact
expansion (:mod:`~orthoglide_pin.dynamics.leg_harmonics`), read once from the
same Pinocchio calls, and point by point from Pinocchio for a model that the
expansion does not fit.

Exact up to rounding; the tests check the forms against the black-box route
(10 inverse-dynamics evaluations per point, the coefficients polarised).

Over the independent balls ``|a| <= a_max`` and ``|v| <= v_max``, exactly::

    max y_i = a_max |m_i| + max(0, v_max^2 lambda_max(H_i)) + c_i
    min y_i = -a_max |m_i| + min(0, v_max^2 lambda_min(H_i)) + c_i

(:meth:`MotionForm.bounds`; :meth:`MotionForm.worst_motion` gives a motion that
attains the larger magnitude). The motor load torques of a drive
(:mod:`orthoglide_pin.drives.motor`) are linear combinations of the two forms, one per
efficiency case (:meth:`RequirementForms.torques`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_number, finite_rows, flag, instance_of
from orthoglide_pin.drives.motor import DriveTrain
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics, _blocks, _wrench
from orthoglide_pin.dynamics.leg_harmonics import leg_harmonics
from orthoglide_pin.dynamics.sym3 import extreme_eigenvalues
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import ik_and_jacobian
from orthoglide_pin.kinematics.joint_motion import (
    LEG_AXES,
    LEG_JOINTS,
    LegMotion,
    leg_motion,
    path_motion,
    scatter,
)
from orthoglide_pin.machine.closed_loop import ClosedLoopModel, as_model
from orthoglide_pin.machine.coerce import MODEL_ALLOWED, is_model
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Joint-function rates ``(q', theta', phi')`` of a leg in the three velocity
#: rows: ``theta'`` alone, ``phi'`` alone, both (see the module).
_CORIOLIS_RATES: Final = ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 1.0, 1.0))
#: Points per block (the block's mass matrices are held at once, 2.6 kB each).
BLOCK: Final[int] = 2048


@dataclass(frozen=True)
class MotionForm:
    """``y_i(a, v) = linear_i . a + v^T quadratic_i v + constant_i`` at ``N`` points.

    Attributes:
        linear: Rows ``m_i``, shape (N, 3, 3) (point, component, tool axis).
        quadratic: Symmetric ``H_i``, shape (N, 3, 3, 3).
        constant: ``c_i``, shape (N, 3).
    """

    linear: FloatArray
    quadratic: FloatArray
    constant: FloatArray

    def evaluate(self, velocity: ArrayLike, acceleration: ArrayLike) -> FloatArray:
        """The values at tool velocities [m/s] and accelerations [m/s^2], (N, 3) each."""
        n = self.constant.shape[0]
        v, a = _motion_rows("velocity", velocity, n), _motion_rows("acceleration", acceleration, n)
        quad = np.einsum("nk,nikl,nl->ni", v, self.quadratic, v)
        return np.asarray(np.einsum("nik,nk->ni", self.linear, a) + quad + self.constant)

    def combine(self, scale: float, other: MotionForm, other_scale: float) -> MotionForm:
        """``scale * self + other_scale * other`` (same points)."""
        scale, other_scale = (
            finite_number("scale", scale),
            finite_number("other_scale", other_scale),
        )
        other = instance_of("other", other, MotionForm, "a MotionForm")
        return MotionForm(
            scale * self.linear + other_scale * other.linear,
            scale * self.quadratic + other_scale * other.quadratic,
            scale * self.constant + other_scale * other.constant,
        )

    def bounds(self, v_max: float, a_max: float) -> tuple[FloatArray, FloatArray]:
        """Exact ``(min, max)`` over ``|v| <= v_max``, ``|a| <= a_max``, each (N, 3)."""
        v_max, a_max = _bound("v_max", v_max, "[m/s]"), _bound("a_max", a_max, "[m/s^2]")
        lam_min, lam_max = extreme_eigenvalues(self.quadratic)
        lin = a_max * np.linalg.norm(self.linear, axis=-1)
        upper = lin + v_max**2 * np.maximum(lam_max, 0.0) + self.constant
        lower = -lin + v_max**2 * np.minimum(lam_min, 0.0) + self.constant
        return lower, upper

    def worst_motion(self, v_max: float, a_max: float) -> tuple[FloatArray, FloatArray]:
        """A motion attaining the worst ``|y_i|``: velocities and accelerations (N, 3, 3).

        Entry ``[n, i]`` is the tool velocity [m/s] (resp. acceleration [m/s^2])
        at point ``n`` that gives component ``i`` its largest magnitude.
        """
        v_max, a_max = _bound("v_max", v_max, "[m/s]"), _bound("a_max", a_max, "[m/s^2]")
        lower, upper = self.bounds(v_max, a_max)
        lam, vec = np.linalg.eigh(self.quadratic)
        up = upper >= -lower
        norm = np.linalg.norm(self.linear, axis=-1, keepdims=True)
        unit = np.divide(self.linear, norm, out=np.zeros_like(self.linear), where=norm > 0.0)
        acc = np.where(up[..., None], a_max, -a_max) * unit
        use = np.where(up, lam[..., -1] > 0.0, lam[..., 0] < 0.0)
        direction = np.where(up[..., None], vec[..., :, -1], vec[..., :, 0])
        vel = np.where(use[..., None], v_max * direction, 0.0)
        return vel, acc


@dataclass(frozen=True)
class RequirementForms:
    """Slider forces and accelerations as forms in the tool motion, at ``N`` points.

    Attributes:
        points: Tool points [m], shape (N, 3).
        forces: Slider forces [N] (constant: gravity and external wrench).
        slider_accelerations: Slider accelerations [m/s^2] (linear part ``J^-1``).
        inverse_jacobian: ``J^-1``, shape (N, 3, 3).
    """

    points: FloatArray
    forces: MotionForm
    slider_accelerations: MotionForm
    inverse_jacobian: FloatArray

    def torques(self, train: DriveTrain) -> tuple[MotionForm, MotionForm]:
        """Motor load torques [N.m] without friction: ``(driving, back-driven)`` forms."""
        train = instance_of("train", train, DriveTrain, "a DriveTrain")
        r = train.lead / (2.0 * math.pi * train.gear_ratio)
        inertia = train.reflected_inertia / r
        acc = self.slider_accelerations
        return (
            self.forces.combine(r / train.efficiency, acc, inertia),
            self.forces.combine(r * train.efficiency, acc, inertia),
        )

    def slider_speed(self, v_max: float) -> FloatArray:
        """Largest slider speeds ``v_max |b_i|`` over ``|v| <= v_max`` [m/s], (N, 3)."""
        v_max = _bound("v_max", v_max, "[m/s]")
        return np.asarray(v_max * np.linalg.norm(self.inverse_jacobian, axis=-1))


def _bound(name: str, value: float, unit: str) -> float:
    """``value`` as a finite bound >= 0, else an error naming ``name``."""
    out = finite_number(name, value, unit)
    if out < 0.0:
        raise InvalidParameterError(name, value, f"a finite number >= 0 {unit}")
    return out


def _motion_rows(name: str, value: ArrayLike, n: int) -> FloatArray:
    """``value`` as ``n`` finite rows of three numbers (one per point), else an error naming it."""
    rows = finite_rows(name, value, 3)
    if rows.shape[0] != n:
        raise InvalidParameterError(f"{name}.shape", rows.shape, f"({n}, 3): one row per point")
    return rows


#: Everything that names a machine's dynamics (see :func:`as_dynamics`).
Machine = ClosedLoopDynamics | ClosedLoopModel | OrthoglideParams | None


def as_dynamics(machine: Machine, name: str = "machine") -> ClosedLoopDynamics:
    """The inverse dynamics of ``machine``: itself, that of a model or of parameters.

    The rule of :mod:`orthoglide_pin.machine.coerce`, with the dynamics added.

    Args:
        machine: A ``ClosedLoopDynamics``, a ``ClosedLoopModel``,
            ``OrthoglideParams``, or ``None`` for the prototype.
        name: The argument's name, for the error message.

    Raises:
        InvalidParameterError: Naming ``name`` and the type received.
    """
    if isinstance(machine, ClosedLoopDynamics):
        return machine
    if machine is not None and not (is_model(machine) or isinstance(machine, OrthoglideParams)):
        allowed = f"a ClosedLoopDynamics, {MODEL_ALLOWED}, not {type(machine).__name__}"
        raise InvalidParameterError(name, machine, allowed)
    return ClosedLoopDynamics(as_model(machine, name))


def requirement_forms(
    machine: Machine,
    points: ArrayLike,
    *,
    wrench: ArrayLike | None = None,
    gravity: ArrayLike | None = None,
    check_limits: bool = True,
) -> RequirementForms:
    """Extract the forms of the slider forces and accelerations (see the module).

    Args:
        machine: Inverse dynamics, a closed-loop model, parameters, or
            ``None`` for the prototype (see :func:`as_dynamics`).
        points: Tool points [m], shape (N, 3) or (3,).
        wrench: Constant external wrench on the tool (as
            :meth:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics.inverse_dynamics`).
        gravity: Gravity [m/s^2], shape (3,); the dynamics' default when ``None``.
        check_limits: Refuse points beyond the machine's slider limits, as
            ``orthoglide ik`` does (``False``: compute there anyway).

    Returns:
        The forms at the points.

    Raises:
        InvalidParameterError: Bad points, wrench or gravity.
        UnreachablePointError, SingularConfigurationError: A point out of reach
            (of a leg, or of the sliders within their limits).
    """
    dyn, p = as_dynamics(machine), finite_rows("points", points, 3, "[m]")
    if flag("check_limits", check_limits):
        check_slider_limits(dyn.closed_loop.params, p)
    w = _wrench(wrench, p.shape[0])
    g = dyn.gravity_vector(gravity)
    parts = [_forms(dyn, p[s], w[s], g) for s in _blocks(p.shape[0], BLOCK)]
    f_lin, f_quad, f_const, a_lin, a_quad = (
        x[0] if len(x) == 1 else np.concatenate(x) for x in zip(*parts, strict=True)
    )
    forces = MotionForm(f_lin, f_quad, f_const)
    sliders = MotionForm(a_lin, a_quad, np.zeros_like(p))
    return RequirementForms(p, forces, sliders, a_lin.copy())


def _forms(
    dyn: ClosedLoopDynamics, p: FloatArray, w: FloatArray, g: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Coefficients of the force and slider-acceleration forms at points ``p`` (see module).

    Returns:
        The force form (linear (n, 3, 3), quadratic (n, 3, 3, 3), constant
        (n, 3)), then the slider-acceleration form (linear, quadratic).
    """
    n, length = p.shape[0], dyn.leg_length
    zero = np.zeros_like(p)
    motion = leg_motion(p, zero, zero, length)
    grads = motion.gradients  # (n, leg, function, world)
    hess = function_hessians(p, length)  # (n, leg, function, world, world)
    m_f, weight, y = _leg_terms(dyn, p, motion, g)
    r = grads.reshape(n, 9, 3)
    rt = r.transpose(0, 2, 1)
    t = rt @ m_f  # R^T M_f, (n, 3, 9)
    tool_mass = t @ r
    quad = t @ hess.reshape(n, 9, 9)  # (n, 3, 3 * 3)
    # per leg and term (theta'^2, phi'^2, theta' phi'): its tool force and its outer
    # product of d(theta)/dP, d(phi)/dP, then summed over the legs and terms
    coeff = y.transpose(1, 2, 0, 3) @ grads  # (n, leg, term, world)
    theta, phi = grads[:, :, 1, :, None], grads[:, :, 2, None, :]
    outer = np.empty((n, 3, 3, 3, 3))
    outer[:, :, 0] = theta * theta.transpose(0, 1, 3, 2)
    outer[:, :, 1] = phi.transpose(0, 1, 3, 2) * phi
    outer[:, :, 2] = theta * phi
    outer[:, :, 2] += outer[:, :, 2].transpose(0, 1, 3, 2)
    quad += coeff.reshape(n, 9, 3).transpose(0, 2, 1) @ outer.reshape(n, 9, 9)
    tool_weight = (rt @ weight[:, :, None])[:, :, 0] - w[:, :3]
    _, jac = ik_and_jacobian(p, length)
    jt = jac.transpose(0, 2, 1)
    return (
        jt @ tool_mass,
        (jt @ quad).reshape(n, 3, 3, 3),
        (jt @ tool_weight[:, :, None])[:, :, 0],
        np.ascontiguousarray(grads[:, :, 0, :]),
        np.ascontiguousarray(hess[:, :, 0]),
    )


def _leg_terms(
    dyn: ClosedLoopDynamics, p: FloatArray, motion: LegMotion, g: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The model's terms at points ``p``, brought to the joint functions of the legs.

    From the legs' expansion (:mod:`~orthoglide_pin.dynamics.leg_harmonics`)
    when the model has one, else from Pinocchio point by point.

    Returns:
        ``M_f`` (n, 9, 9), the gravity torques (n, 9), and the velocity terms
        per rate pair ``(theta'^2, phi'^2, theta' phi' / 2)``, (3, n, leg, function).
    """
    n = p.shape[0]
    expansion = leg_harmonics(dyn)
    if expansion is not None:
        angles = path_motion(p, np.zeros_like(p), np.zeros_like(p), dyn.leg_length)
        basis = expansion.basis(angles.cos_theta, angles.sin_theta, angles.cos_phi, angles.sin_phi)
        mass, vel, weight = expansion.evaluate(basis, expansion.coefficients(g))
        m_f = np.zeros((n, 9, 9))
        for leg in range(3):
            m_f[:, 3 * leg : 3 * leg + 3, 3 * leg : 3 * leg + 3] = mass[leg].transpose(2, 0, 1)
        y = vel.transpose(1, 3, 0, 2).copy()  # (term, n, leg, function)
        y[2] *= 0.5
        return m_f, weight.transpose(2, 0, 1).reshape(n, 9), y
    idx = dyn.leg_indices
    q = scatter(motion.values, idx)
    nv = q.shape[1]
    proj = np.zeros((9, nv))  # joint torques to joint-function forces, leg by leg
    for slot, (_, fn, sign) in enumerate(LEG_JOINTS):
        proj[3 * np.arange(3) + fn, idx[:, slot]] += sign
    # mass matrix and gravity torques, point by point, on the engine with gravity g
    engine = dyn.engine(g)
    model, data = engine.model, engine.data
    mass_q, weight_q = np.empty((n, nv, nv)), np.empty((n, nv))
    for k in range(n):
        mass_q[k] = pin.crba(model, data, q[k])
        weight_q[k] = pin.computeGeneralizedGravity(model, data, q[k])
    m_pt = (mass_q.reshape(n * nv, nv) @ proj.T).reshape(n, nv, 9)  # M P^T (P M, transposed)
    m_f = (m_pt.transpose(0, 2, 1).reshape(n * 9, nv) @ proj.T).reshape(n, 9, 9)
    # velocity terms: three rnea rows per point, the three legs at once
    rates = np.broadcast_to(np.asarray(_CORIOLIS_RATES)[:, None, None, :], (3, n, 3, 3))
    v = scatter(rates.reshape(3 * n, 3, 3), idx)
    tau = dyn.engine((0.0, 0.0, 0.0)).rnea(np.tile(q, (3, 1)), v, np.zeros_like(v))
    y = (tau @ proj.T).reshape(3, n, 3, 3)  # rates, point, leg, function
    y[2] = 0.5 * (y[2] - y[0] - y[1])  # the cross term
    return m_f, weight_q @ proj.T, y


def function_hessians(points: FloatArray, leg_length: float) -> FloatArray:
    """Second derivatives of the joint functions in the tool point.

    In the leg frame only ``(y, z)`` enter. With ``a = -(y, z) / eta`` the
    gradient of ``eta`` and ``b`` that of ``theta`` (in ``(y, z)``):
    ``d2q = (I + a a^T) / eta``,
    ``d2theta = (-z (I + a a^T) / eta + y (e_y b^T + b e_y^T)) / c^2`` and
    ``d2phi = y / c^3`` on ``(y, y)`` (notation of
    :mod:`orthoglide_pin.kinematics.joint_motion`).

    Args:
        points: Tool points [m], shape (n, 3), checked.
        leg_length: Leg length ``L`` [m].

    Returns:
        ``d2f/dP2`` per point, leg and function ``(q, theta, phi)``, in world
        axes [1/m, rad/m^2], shape (n, 3, 3, 3, 3).
    """
    y, z = points[:, LEG_AXES[:, 1]], points[:, LEG_AXES[:, 2]]  # (n, leg)
    c2 = leg_length * leg_length - y * y
    eta = np.sqrt(c2 - z * z)
    ay, az = -y / eta, -z / eta
    qyy, qyz, qzz = (1.0 + ay * ay) / eta, ay * az / eta, (1.0 + az * az) / eta
    by, bz = z * ay / c2, (z * az - eta) / c2
    blocks = (
        (qyy, qyz, qzz),
        ((-z * qyy + 2.0 * y * by) / c2, (-z * qyz + y * bz) / c2, -z * qzz / c2),
        (y / (c2 * np.sqrt(c2)), np.zeros_like(y), np.zeros_like(y)),
    )
    out = np.zeros((points.shape[0], 3, 3, 3, 3))
    for leg in range(3):
        iy, iz = LEG_AXES[leg, 1], LEG_AXES[leg, 2]
        for fn, (hyy, hyz, hzz) in enumerate(blocks):
            out[:, leg, fn, iy, iy] = hyy[:, leg]
            out[:, leg, fn, iy, iz] = out[:, leg, fn, iz, iy] = hyz[:, leg]
            out[:, leg, fn, iz, iz] = hzz[:, leg]
    return out
