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
``b_i`` the row ``i`` of ``J^-1``. :func:`requirement_forms` extracts both from
the closed-loop inverse dynamics
(:class:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics`), vectorised over points,
with 10 evaluations per point, the fewest that determine the 10 coefficients
of each form: unit accelerations with ``v = 0`` and no gravity give ``m_i``;
unit velocities with ``a = 0`` give the diagonal of ``H_i`` and the
polarisation ``H_kl = (f(e_k + e_l) - H_kk - H_ll) / 2`` the rest; a static
call with gravity and wrench gives ``c_i``. Exact up to rounding.

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
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows
from orthoglide_pin.drives.motor import DriveTrain
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: The pairs of tool axes of the polarisation.
_PAIRS: Final = ((0, 1), (0, 2), (1, 2))
#: Dynamic evaluations per point: 3 unit accelerations, 3 unit velocities, 3 pairs.
_ROWS: Final = 9


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
        v, a = np.asarray(velocity, dtype=float), np.asarray(acceleration, dtype=float)
        quad = np.einsum("nk,nikl,nl->ni", v, self.quadratic, v)
        return np.asarray(np.einsum("nik,nk->ni", self.linear, a) + quad + self.constant)

    def combine(self, scale: float, other: MotionForm, other_scale: float) -> MotionForm:
        """``scale * self + other_scale * other`` (same points)."""
        return MotionForm(
            scale * self.linear + other_scale * other.linear,
            scale * self.quadratic + other_scale * other.quadratic,
            scale * self.constant + other_scale * other.constant,
        )

    def bounds(self, v_max: float, a_max: float) -> tuple[FloatArray, FloatArray]:
        """Exact ``(min, max)`` over ``|v| <= v_max``, ``|a| <= a_max``, each (N, 3)."""
        lam = np.linalg.eigvalsh(self.quadratic)
        lin = a_max * np.linalg.norm(self.linear, axis=-1)
        upper = lin + v_max**2 * np.maximum(lam[..., -1], 0.0) + self.constant
        lower = -lin + v_max**2 * np.minimum(lam[..., 0], 0.0) + self.constant
        return lower, upper

    def worst_motion(self, v_max: float, a_max: float) -> tuple[FloatArray, FloatArray]:
        """A motion attaining the worst ``|y_i|``: velocities and accelerations (N, 3, 3).

        Entry ``[n, i]`` is the tool velocity [m/s] (resp. acceleration [m/s^2])
        at point ``n`` that gives component ``i`` its largest magnitude.
        """
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
        r = train.lead / (2.0 * math.pi * train.gear_ratio)
        inertia = train.reflected_inertia / r
        acc = self.slider_accelerations
        return (
            self.forces.combine(r / train.efficiency, acc, inertia),
            self.forces.combine(r * train.efficiency, acc, inertia),
        )

    def slider_speed(self, v_max: float) -> FloatArray:
        """Largest slider speeds ``v_max |b_i|`` over ``|v| <= v_max`` [m/s], (N, 3)."""
        return np.asarray(v_max * np.linalg.norm(self.inverse_jacobian, axis=-1))


def as_dynamics(machine: ClosedLoopDynamics | OrthoglideParams | None) -> ClosedLoopDynamics:
    """The inverse dynamics of ``machine``: itself, a machine's parameters, or the prototype."""
    if isinstance(machine, ClosedLoopDynamics):
        return machine
    if machine is None:
        return ClosedLoopDynamics()
    if isinstance(machine, OrthoglideParams):
        from orthoglide_pin.machine.closed_loop import ClosedLoopModel

        return ClosedLoopDynamics(ClosedLoopModel(machine))
    raise InvalidParameterError("machine", machine, "ClosedLoopDynamics, OrthoglideParams or None")


def requirement_forms(
    machine: ClosedLoopDynamics | OrthoglideParams | None,
    points: ArrayLike,
    *,
    wrench: ArrayLike | None = None,
    gravity: ArrayLike | None = None,
    check_limits: bool = True,
) -> RequirementForms:
    """Extract the forms of the slider forces and accelerations (see the module).

    Args:
        machine: Inverse dynamics, parameters, or ``None`` for the prototype.
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
    if check_limits:
        check_slider_limits(dyn.closed_loop.params, p)
    n, eye = p.shape[0], np.eye(3)
    dirs = [*eye, *(eye[k] + eye[m] for k, m in _PAIRS)]
    acc = np.zeros((_ROWS, n, 3))
    vel = np.zeros((_ROWS, n, 3))
    acc[:3] = eye[:, None, :]
    vel[3:] = np.asarray(dirs)[:, None, :]
    rows = np.broadcast_to(p, (_ROWS, n, 3)).reshape(-1, 3)
    res = dyn.inverse_dynamics(rows, vel.reshape(-1, 3), acc.reshape(-1, 3), gravity=(0, 0, 0))
    still = np.zeros_like(p)
    const = dyn.inverse_dynamics(p, still, still, wrench=wrench, gravity=gravity).forces

    def form(values: FloatArray, constant: FloatArray) -> MotionForm:
        y = values.reshape(_ROWS, n, 3)
        quad = np.empty((n, 3, 3, 3))
        for k in range(3):
            quad[:, :, k, k] = y[3 + k]
        for j, (k, m) in enumerate(_PAIRS):
            quad[:, :, k, m] = quad[:, :, m, k] = 0.5 * (y[6 + j] - y[3 + k] - y[3 + m])
        return MotionForm(np.ascontiguousarray(y[:3].transpose(1, 2, 0)), quad, constant)

    forces = form(res.forces, const)
    sliders = form(res.slider_accelerations, np.zeros_like(p))
    return RequirementForms(p, forces, sliders, sliders.linear.copy())
