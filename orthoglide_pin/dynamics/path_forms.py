"""Slider forces along a geometric path as a function of the path speed.

Along a path ``p(s)`` (``s`` the arc length [m]) with tangent ``p' = dp/ds``
and curvature vector ``p'' = d2p/ds2``, the tool moves with ``v = p' s_dot`` and
``a = p' s_ddot + p'' s_dot^2``. Every joint function ``f`` of the legs
(:mod:`orthoglide_pin.kinematics.joint_motion`) follows with ``f_dot = f' s_dot``
and ``f_ddot = f' s_ddot + f'' s_dot^2``, where ``f' = R p'`` and
``f'' = R p'' + d2f/dP2 [p', p']`` (``R = df/dP``). The closed-loop inverse
dynamics (:mod:`orthoglide_pin.dynamics.inverse`), ``F = J^T (R^T tau_f - f_ext)``,
is then, exactly::

    F = a s_ddot + b s_dot^2 + c

with, leg by leg (:mod:`orthoglide_pin.dynamics.leg_harmonics` for ``tau_f``):

* ``a = J^T R^T M_f f'``: the inertia seen along the path [kg];
* ``b = J^T R^T (M_f f'' + C(f', f'))``: the centripetal and Coriolis part [kg/m];
* ``c = J^T (R^T Gamma g - f_ext)``: gravity and the tool wrench [N] (the
  static forces, :meth:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics.static_forces`).

The slider motion is ``q_dot = q' s_dot`` and ``q_ddot = q' s_ddot + q'' s_dot^2``
(the slider rows of ``f'`` and ``f''``). These are the inputs of a time-optimal
parametrisation along the path (phase-plane, TOPP-RA).

Two routes give the same forms:

* the leg expansion (the default): ``M_f``, ``C`` and ``Gamma`` from
  :func:`~orthoglide_pin.dynamics.leg_harmonics.leg_harmonics`, a few products
  per point, in one compiled loop over the points
  (:mod:`~orthoglide_pin.dynamics.forms_compiled`, numba, with the slider-limit
  and finiteness checks), or vectorised over the points in blocks of
  :data:`BLOCK` without numba and wherever a point fails a check (this array
  route then raises its error);
* ``rnea`` (:func:`path_forms_by_rnea`, the reference and the fallback for a
  model the expansion does not fit): three columns per point, batched in C++
  with ``rneaInParallel`` (``rnea(q, 0, f')`` and ``rnea(q, f', f'')`` without
  gravity, ``rnea(q, 0, 0)`` with it).
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import MAX_LENGTH, bounded_rows, float_array
from orthoglide_pin.dynamics.forms_compiled import AVAILABLE as COMPILED
from orthoglide_pin.dynamics.forms_compiled import forms_compiled
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics, _blocks, _wrench
from orthoglide_pin.dynamics.leg_harmonics import LegHarmonics, leg_harmonics
from orthoglide_pin.dynamics.motion_forms import Machine, as_dynamics
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import PARALLEL_TOL, SERIAL_TOL, ik_and_jacobian
from orthoglide_pin.kinematics.joint_motion import (
    LEG_AXES,
    MAX_CURVATURE,
    MAX_TANGENT,
    gather,
    leg_motion,
    path_motion,
    scatter,
)
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: For each world axis, the leg whose local ``y`` (resp. ``z``) axis it is (LEG_AXES).
_Y_LEG: Final = np.argsort(LEG_AXES[:, 1])
_Z_LEG: Final = np.argsort(LEG_AXES[:, 2])
_LEGS: Final = np.stack([_Y_LEG, _Z_LEG])
#: Slack on the slider values of path points [m]: a part program's points count as
#: inside up to 1e-9 m beyond the cube or a slider limit (they reach Q1 and Q2 only
#: to rounding); ten times that is still far below any physical meaning.
PATH_LIMIT_TOL: Final[float] = 1e-8
#: Points per block (keeps the temporaries in the cache, see the design notes).
BLOCK: Final[int] = 4096


@dataclass(frozen=True)
class PathForms:
    """Slider forces and motion along a geometric path ``p(s)``, ``s`` the arc length [m].

    At path speed ``s_dot`` [m/s] and acceleration ``s_ddot`` [m/s^2]::

        F = a * s_ddot + b * s_dot**2 + c            (each (N, 3) [N])
        q_dot = dq * s_dot,  q_ddot = dq * s_ddot + ddq * s_dot**2

    Attributes:
        q: Slider positions [m], shape (N, 3).
        dq: ``dq/ds`` [-], shape (N, 3).
        ddq: ``d2q/ds2`` [1/m], shape (N, 3).
        a: Force per unit ``s_ddot`` [kg] (N per m/s^2), shape (N, 3).
        b: Force per unit ``s_dot^2`` [kg/m] (N per (m/s)^2), shape (N, 3).
        c: Gravity and tool-wrench forces [N], shape (N, 3).
    """

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    a: FloatArray
    b: FloatArray
    c: FloatArray

    def forces(self, s_dot: ArrayLike, s_ddot: ArrayLike) -> FloatArray:
        """Slider forces at a path motion.

        Args:
            s_dot: Path speeds [m/s], shape (N,) or a number.
            s_ddot: Path accelerations [m/s^2], shape (N,) or a number.

        Returns:
            ``a s_ddot + b s_dot^2 + c`` [N], shape (N, 3).
        """
        sd, sdd = self._column("s_dot", s_dot), self._column("s_ddot", s_ddot)
        return np.asarray(self.a * sdd + self.b * (sd * sd) + self.c)

    def slider_motion(self, s_dot: ArrayLike, s_ddot: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Slider velocities [m/s] and accelerations [m/s^2] at a path motion, (N, 3) each.

        Args:
            s_dot: Path speeds [m/s], shape (N,) or a number.
            s_ddot: Path accelerations [m/s^2], shape (N,) or a number.
        """
        sd, sdd = self._column("s_dot", s_dot), self._column("s_ddot", s_ddot)
        return np.asarray(self.dq * sd), np.asarray(self.dq * sdd + self.ddq * (sd * sd))

    def _column(self, name: str, value: ArrayLike) -> FloatArray:
        """``value`` as a finite column (N, 1), or a number as (1, 1)."""
        n = self.q.shape[0]
        arr = float_array(value)
        if arr.shape not in ((), (n,)) or not np.isfinite(arr).all():
            raise InvalidParameterError(name, value, f"a finite number or {n} of them")
        return arr.reshape(-1, 1)


def path_forms(
    model: Machine,
    points: ArrayLike,
    tangents: ArrayLike,
    curvatures: ArrayLike,
    *,
    gravity: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
) -> PathForms:
    """The slider forces along a path as forms in the path speed (see the module).

    Exact: for any ``s_dot`` and ``s_ddot``, ``a s_ddot + b s_dot^2 + c`` is the
    closed-loop inverse dynamics (:meth:`ClosedLoopDynamics.inverse_dynamics`)
    at ``v = p' s_dot``, ``a = p' s_ddot + p'' s_dot^2`` to rounding.

    Args:
        model: The dynamics, a closed-loop model, or a machine's parameters
            (``None``: the prototype's; the dynamics of given parameters are
            kept for the next calls with them).
        points: Path points ``p(s)`` [m], world frame, shape (N, 3) or (3,).
        tangents: ``dp/ds`` [-] (unit vectors for the arc length), same shape,
            entries within ``+-MAX_TANGENT``.
        curvatures: ``d2p/ds2`` [1/m], same shape, within ``+-MAX_CURVATURE``.
        gravity: Gravity [m/s^2], shape (3,); the model's default when ``None``.
        wrench: External wrench on the tool, as for ``inverse_dynamics``:
            shape (3,), (6,), (N, 3) or (N, 6), force [N] then moment [N.m].

    Returns:
        The forms at the ``N`` points.

    Raises:
        InvalidParameterError: Bad model, shapes, non-finite or out-of-range
            values, or forms that are not finite.
        UnreachablePointError: A point beyond the slider limits (by more than
            ``PATH_LIMIT_TOL``) or out of reach.
        SingularConfigurationError: A serially singular point.
    """
    dyn, (p, t, k) = _validated(model, points, tangents, curvatures)
    w, g = _wrench(wrench, p.shape[0]), dyn.gravity_vector(gravity)
    expansion = leg_harmonics(dyn)
    if COMPILED and expansion is not None:
        params = dyn.closed_loop.params
        limits = (dyn.leg_length, params.slider_lower, params.slider_upper, PATH_LIMIT_TOL)
        got = forms_compiled(
            p, t, k, w[:, :3], expansion.coefficients(g), expansion.harmonics, _LEGS,
            (*limits, SERIAL_TOL, PARALLEL_TOL),
        )  # fmt: skip
        if got is not None:
            return PathForms(*got)
    _check_inside(dyn, p)  # the array route raises the error of a point that failed
    return _assemble(dyn, p, t, k, w, g, expansion)


def path_forms_by_rnea(
    model: Machine,
    points: ArrayLike,
    tangents: ArrayLike,
    curvatures: ArrayLike,
    *,
    gravity: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
) -> PathForms:
    """:func:`path_forms` by three batched ``rnea`` columns per point (the reference route).

    Same arguments, result and errors as :func:`path_forms`.
    """
    dyn, (p, t, k) = _validated(model, points, tangents, curvatures)
    _check_inside(dyn, p)
    w, g = _wrench(wrench, p.shape[0]), dyn.gravity_vector(gravity)
    return _assemble(dyn, p, t, k, w, g, None)


def _validated(
    model: Machine, points: ArrayLike, tangents: ArrayLike, curvatures: ArrayLike
) -> tuple[ClosedLoopDynamics, tuple[FloatArray, FloatArray, FloatArray]]:
    """The dynamics and the validated path rows."""
    dyn = _dynamics(model) if isinstance(model, OrthoglideParams) else as_dynamics(model, "model")
    p = bounded_rows("points", points, 3, MAX_LENGTH, "[m]")
    t = bounded_rows("tangents", tangents, 3, MAX_TANGENT, "[-]")
    k = bounded_rows("curvatures", curvatures, 3, MAX_CURVATURE, "[1/m]")
    if not p.shape == t.shape == k.shape:
        raise InvalidParameterError(
            "shapes", (p.shape, t.shape, k.shape), "points, tangents, curvatures of one shape"
        )
    return dyn, (p, t, k)


def _check_inside(dyn: ClosedLoopDynamics, p: FloatArray) -> None:
    """Refuse points beyond the slider limits (by more than ``PATH_LIMIT_TOL``) or reach."""
    check_slider_limits(dyn.closed_loop.params, p, hint=None, tol=PATH_LIMIT_TOL)


@functools.lru_cache(maxsize=4)
def _dynamics(params: OrthoglideParams) -> ClosedLoopDynamics:
    """The dynamics of a machine's parameters, kept for the next calls with them."""
    return as_dynamics(params)


def _assemble(
    dyn: ClosedLoopDynamics,
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    w: FloatArray,
    g: FloatArray,
    expansion: LegHarmonics | None,
) -> PathForms:
    """The forms block by block, by the expansion or (``None``) by ``rnea``."""
    n = p.shape[0]
    out = [np.empty((n, 3)) for _ in range(6)]
    coef = None if expansion is None else expansion.coefficients(g)
    with _one_blas_thread():
        for s in _blocks(n, BLOCK):
            if expansion is None or coef is None:  # both or neither
                block = _block_by_rnea(dyn, p[s], t[s], k[s], w[s], g)
            else:
                block = _block_by_expansion(
                    expansion, coef, p[s], t[s], k[s], w[s], dyn.leg_length
                )
            for dest, value in zip(out, block, strict=True):
                dest[s] = value
    _check_finite(out[3:], p)
    return PathForms(*out)


@functools.lru_cache(maxsize=1)
def _thread_pools() -> Any:
    """The thread pools of the loaded native libraries (found once: a scan of them)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextlib.contextmanager
def _one_blas_thread() -> Iterator[None]:
    """BLAS on one thread inside (threadpoolctl).

    Its products here are small (a few thousand points by a few dozen basis
    functions): more threads only wait for each other, and on a loaded machine
    they slowed the forms down by up to 7 times.
    """
    with _thread_pools().limit(limits=1, user_api="blas"):
        yield


_Block = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]


def _block_by_expansion(
    expansion: LegHarmonics,
    coef: FloatArray,
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    w: FloatArray,
    leg_length: float,
) -> _Block:
    """``(q, dq, ddq, a, b, c)`` of a block, leg by leg (rows of ``n`` numbers)."""
    motion = path_motion(p, t, k, leg_length)
    basis = expansion.basis(motion.cos_theta, motion.sin_theta, motion.cos_phi, motion.sin_phi)
    mass, vel, weight = expansion.evaluate(basis, coef)
    first, second = motion.first, motion.second  # (leg, function, n)
    th, ph = first[:, 1], first[:, 2]
    # tau_f per form (a, b, c), leg and function: M_f f', M_f f'' + C(f', f'), Gamma g
    tau = np.empty((3, *first.shape))
    tau[0] = mass[:, :, 0] * first[:, None, 0]
    tau[1] = mass[:, :, 0] * second[:, None, 0]
    for j in (1, 2):
        tau[0] += mass[:, :, j] * first[:, None, j]
        tau[1] += mass[:, :, j] * second[:, None, j]
    tau[1] += vel[:, 0] * (th * th)[:, None] + vel[:, 1] * (ph * ph)[:, None]
    tau[1] += vel[:, 2] * (th * ph)[:, None]
    tau[2] = weight
    # F = J^T R^T tau_f - J^T f_ext = tau_q + J^T (theta and phi gradients) - J^T f_ext: the
    # slider rows of R make J^-T, so their part is tau_q itself
    grad = motion.theta_gradient
    local_y = tau[:, :, 1] * grad[:, 0] + tau[:, :, 2] * motion.phi_gradient
    local_z = tau[:, :, 1] * grad[:, 1]  # (form, leg, n)
    # world axis m is the y axis of leg m - 1 and the z axis of leg m - 2 (LEG_AXES)
    world = local_y[:, _Y_LEG] + local_z[:, _Z_LEG]
    world[2] -= w[:, :3].T
    _, jac = ik_and_jacobian(p, leg_length)
    jt = np.ascontiguousarray(jac.transpose(1, 2, 0))  # (world, slider, n)
    forces = tau[:, :, 0] + world[:, 0, None] * jt[0]
    forces += world[:, 1, None] * jt[1]
    forces += world[:, 2, None] * jt[2]  # (form, slider, n)
    return (
        motion.slider.T,
        first[:, 0].T,
        second[:, 0].T,
        forces[0].T,
        forces[1].T,
        forces[2].T,
    )


def _block_by_rnea(
    dyn: ClosedLoopDynamics,
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    w: FloatArray,
    g: FloatArray,
) -> _Block:
    """``(q, dq, ddq, a, b, c)`` of a block by three ``rnea`` columns per point."""
    motion = leg_motion(p, t, np.zeros_like(t), dyn.leg_length)
    # f'' is affine in p'': add R p'' to the part of p' alone (no bound on p'' there)
    second = motion.accelerations + np.einsum("nlfw,nw->nlf", motion.gradients, k)
    idx = dyn.leg_indices
    q = scatter(motion.values, idx)
    v = scatter(motion.rates, idx)
    zero = np.zeros_like(q)
    inertial = dyn.engine((0.0, 0.0, 0.0)).rnea(
        np.concatenate([q, q]),
        np.concatenate([zero, v]),
        np.concatenate([v, scatter(second, idx)]),
    )
    weight = dyn.engine(g).rnea(q, zero, zero)
    n = q.shape[0]
    tau = (gather(inertial[:n], idx), gather(inertial[n:], idx), gather(weight, idx))
    tool = np.stack([np.einsum("nlf,nlfw->nw", x, motion.gradients) for x in tau], axis=1)
    tool[:, 2] -= w[:, :3]
    _, jac = ik_and_jacobian(p, dyn.leg_length)
    forces = tool @ jac  # J^T per form, (n, form, slider)
    return (
        motion.values[:, :, 0],
        motion.rates[:, :, 0],
        second[:, :, 0],
        forces[:, 0],
        forces[:, 1],
        forces[:, 2],
    )


def _check_finite(forms: list[FloatArray], points: FloatArray) -> None:
    """Refuse forms that are not finite (inputs too extreme for this machine)."""
    finite = np.logical_and.reduce([np.isfinite(f).all(axis=1) for f in forms])
    if not finite.all():
        row = int(np.argmin(finite))
        raise InvalidParameterError(
            "points, tangents, curvatures, wrench, gravity",
            f"non-finite forms at p = {tuple(points[row].tolist())}",
            "a path, wrench and gravity that give finite slider forces [N]",
        )
