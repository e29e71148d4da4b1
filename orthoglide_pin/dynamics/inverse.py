"""Closed-loop inverse dynamics: actuator forces along the sliders for a tool motion.

Two routes give the same result (tested against each other):

* ``"closed-form"`` (the default, fast): every joint's ``q``, ``v`` and ``a``
  come from the tool motion in closed form (:mod:`orthoglide_pin.kinematics.joint_motion`),
  so the loops are closed exactly without a solver. Pinocchio's ``rnea`` gives
  the cut tree's joint torques ``tau`` (N, 18), batched in C++ with
  ``rneaInParallel``. The closed chain has ``v = Q' P'`` with ``Q' = dq/dP``
  and ``P' = J q_a'``, so ``v = G q_a'`` with ``G = Q' J`` and, by virtual work,
  ``F = G^T tau = J^T (Q'^T tau - f_ext)``.
* ``"projection"`` (the reference, per point): the design-notes method on the
  Pinocchio model: warm-started loop closure, ``G = [I; -K_p^+ K_a]``,
  ``a = G a_a - [0; K_p^+ gamma]`` with ``gamma`` the constraint drift at
  ``(q, v, 0)``, and ``F = G^T (rnea(q, v, a) - J_tool^T w_ext)`` with the 6D
  tool Jacobian.

Conventions:

* **Gravity** is a vector in the machine (world) frame [m/s^2], a parameter of
  every call. Default :data:`DEFAULT_GRAVITY`: on the prototype ``e3`` points
  **down** (the vertical slider sits above the platform and the tool points
  along ``+e3`` towards the table), so ``g = (0, 0, +9.81)``.
* **External wrench** ``w_ext = (f, m)``: exerted **by the environment on the
  tool** (e.g. the cutting force), at the tool point, in world axes: force
  ``f`` [N], moment ``m`` [N.m]. The actuators balance it, so a force ``f``
  adds ``-J^T f`` to the slider forces. The platform does not rotate, so a
  pure moment loads the structure and the joints but no actuator.
* **Forces** ``F_i`` [N] are exerted by actuator ``i`` on its carriage along
  ``+e_i``; their power is ``F . q_a'``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    MAX_ACCELERATION,
    MAX_SPEED,
    MAX_WRENCH,
    bounded_rows,
    choice,
    finite_rows,
    first_index,
    gravity_vector,
)
from orthoglide_pin.dynamics.inertia import assumptions as inertia_assumptions
from orthoglide_pin.exceptions import InvalidParameterError, SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import ik_and_jacobian, inverse_kinematics
from orthoglide_pin.kinematics.joint_motion import (
    LEG_JOINTS,
    gather,
    leg_motion,
    scatter,
    tool_motion_from_sliders,
)
from orthoglide_pin.machine.closed_loop import RANK_TOL, ClosedLoopModel, as_model
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Default gravity in the machine frame [m/s^2]: ``e3`` points down (see module).
DEFAULT_GRAVITY: Final = (0.0, 0.0, 9.81)
#: The gravity convention, as printed in reports.
GRAVITY_ASSUMPTION: Final = (
    "gravity (0, 0, +9.81) m/s^2 in the machine frame by default: e3 points down "
    "(vertical slider above the platform, tool along +e3 towards the table)"
)
#: Inverse-dynamics routes.
METHODS: Final = ("closed-form", "projection")
#: Points per block of the closed-form route (keeps temporaries small).
BLOCK: Final[int] = 8192
_MAX_ENGINES: Final[int] = 16


@dataclass(frozen=True)
class DynamicsResult:
    """Closed-loop inverse dynamics along ``N`` points.

    Attributes:
        forces: Actuator forces along the sliders [N], shape (N, 3).
        q: Configuration of every joint of the cut tree [m, rad], shape (N, 18).
        v: Joint velocities [m/s, rad/s], shape (N, 18).
        a: Joint accelerations [m/s^2, rad/s^2], shape (N, 18).
        p: Tool points [m], shape (N, 3).
        p_dot: Tool velocities [m/s], shape (N, 3).
        p_ddot: Tool accelerations [m/s^2], shape (N, 3).
        slider_positions: Slider values [m], shape (N, 3).
        slider_velocities: Slider velocities [m/s], shape (N, 3).
        slider_accelerations: Slider accelerations [m/s^2], shape (N, 3).
        wrench: External wrench on the tool (force [N], moment [N.m]), shape (N, 6).
        gravity: Gravity used [m/s^2], shape (3,).
        method: The route, ``"closed-form"`` or ``"projection"``.
    """

    forces: FloatArray
    q: FloatArray
    v: FloatArray
    a: FloatArray
    p: FloatArray
    p_dot: FloatArray
    p_ddot: FloatArray
    slider_positions: FloatArray
    slider_velocities: FloatArray
    slider_accelerations: FloatArray
    wrench: FloatArray
    gravity: FloatArray
    method: str


class _Engine:
    """A Pinocchio model with one gravity, its data and its batch pool."""

    def __init__(self, model: pin.Model, gravity: FloatArray) -> None:
        self.model = pin.Model(model)
        self.model.gravity = pin.Motion(np.asarray(gravity, dtype=float), np.zeros(3))
        self.data = self.model.createData()
        self.pool = pin.ModelPool(self.model, 1) if hasattr(pin, "rneaInParallel") else None

    def rnea(self, q: FloatArray, v: FloatArray, a: FloatArray) -> FloatArray:
        """Joint torques of the cut tree, row by row [N, N.m], shape (N, nv)."""
        if self.pool is not None:
            out: FloatArray = np.empty((q.shape[1], q.shape[0]), order="F")
            pin.rneaInParallel(1, self.pool, q.T, v.T, a.T, out)
            return np.asarray(out.T)
        m, d = self.model, self.data
        return np.array([pin.rnea(m, d, qk, vk, ak) for qk, vk, ak in zip(q, v, a, strict=True)])


class ClosedLoopDynamics:
    """Inverse dynamics of the closed-loop Orthoglide.

    Args:
        model: The closed-loop model, or the parameters to build it from; the
            prototype's when ``None``.
        gravity: Default gravity [m/s^2], shape (3,), machine frame.

    Attributes:
        closed_loop: The closed-loop model (kinematics, constraints).
        gravity: Default gravity [m/s^2], shape (3,).
        leg_indices: Velocity index of each joint of
            :data:`orthoglide_pin.kinematics.joint_motion.LEG_JOINTS`, per leg, shape (3, 6).
    """

    def __init__(
        self,
        model: ClosedLoopModel | OrthoglideParams | None = None,
        *,
        gravity: ArrayLike = DEFAULT_GRAVITY,
    ) -> None:
        self.closed_loop = as_model(model, "model")
        self.gravity = _gravity(gravity)
        pm = self.closed_loop.model
        self.leg_indices = np.array(
            [
                [pm.joints[pm.getJointId(f"leg{i}_{suffix}")].idx_v for suffix, _, _ in LEG_JOINTS]
                for i in (1, 2, 3)
            ],
            dtype=np.intp,
        )
        self._engines: dict[tuple[float, ...], _Engine] = {}

    # ----------------------------------------------------------------- set-up
    @property
    def leg_length(self) -> float:
        """Leg length ``L`` [m]."""
        return float(self.closed_loop.params.leg_length)

    def gravity_vector(self, gravity: ArrayLike | None = None) -> FloatArray:
        """``gravity`` validated, or the default one [m/s^2], shape (3,)."""
        if gravity is None:
            return np.array(self.gravity, dtype=np.float64)
        return _gravity(gravity)

    def engine(self, gravity: ArrayLike | None = None) -> _Engine:
        """The Pinocchio model (a copy with that gravity), data and pool; cached."""
        g = self.gravity_vector(gravity)
        key = tuple(float(x) for x in g)
        if key not in self._engines:
            if len(self._engines) >= _MAX_ENGINES:  # many gravities: keep memory bounded
                self._engines.clear()
            self._engines[key] = _Engine(self.closed_loop.model, g)
        return self._engines[key]

    def pinocchio_model(self, gravity: ArrayLike | None = None) -> pin.Model:
        """The cut tree's Pinocchio model with ``model.gravity`` set to ``gravity``."""
        return self.engine(gravity).model

    def assumptions(self) -> list[str]:
        """Inertial model and gravity assumptions, one sentence per line, for reports."""
        lines = inertia_assumptions(self.closed_loop.params)
        if tuple(self.gravity) == DEFAULT_GRAVITY:
            return [*lines, GRAVITY_ASSUMPTION[0].upper() + GRAVITY_ASSUMPTION[1:] + "."]
        g = ", ".join(f"{x:g}" for x in self.gravity)
        return [*lines, f"Gravity ({g}) m/s^2 in the machine frame (given)."]

    # -------------------------------------------------------- inverse dynamics
    def inverse_dynamics(
        self,
        p: ArrayLike,
        p_dot: ArrayLike,
        p_ddot: ArrayLike,
        *,
        wrench: ArrayLike | None = None,
        gravity: ArrayLike | None = None,
        method: str = "closed-form",
    ) -> DynamicsResult:
        """Actuator forces and the motion of every joint for a tool motion.

        Args:
            p: Tool points [m], shape (N, 3) or (3,).
            p_dot: Tool velocities [m/s], same shape, entries within
                ``+-MAX_SPEED`` (:mod:`orthoglide_pin._validation`).
            p_ddot: Tool accelerations [m/s^2], same shape, within ``+-MAX_ACCELERATION``.
            wrench: External wrench on the tool (see module), shape (3,), (6,),
                (N, 3) or (N, 6): force [N] then moment [N.m], within
                ``+-MAX_WRENCH``; none by default.
            gravity: Gravity [m/s^2], shape (3,), of magnitude at most
                ``MAX_GRAVITY``; the default one when ``None``.
            method: ``"closed-form"`` (fast) or ``"projection"`` (reference).

        Returns:
            The forces and the constraint-consistent joint motion.

        Raises:
            InvalidParameterError: Bad shapes, non-finite or out-of-range values,
                unknown method, or actuator forces that are not finite.
            UnreachablePointError, SingularConfigurationError: A point out of
                reach or singular.
            NoAssemblyError: The projection route cannot close the loops.
        """
        pts, vel, acc = (
            finite_rows("p", p, 3),
            bounded_rows("p_dot", p_dot, 3, MAX_SPEED, "[m/s]"),
            bounded_rows("p_ddot", p_ddot, 3, MAX_ACCELERATION, "[m/s^2]"),
        )
        if not pts.shape == vel.shape == acc.shape:
            raise InvalidParameterError(
                "shapes", (pts.shape, vel.shape, acc.shape), "p, p_dot, p_ddot of one shape"
            )
        w = _wrench(wrench, pts.shape[0])
        g = self.gravity_vector(gravity)
        method = choice("method", method, METHODS)
        if method == "closed-form":
            parts = [
                self._closed_form(pts[s], vel[s], acc[s], w[s], g)
                for s in _blocks(pts.shape[0], BLOCK)
            ]
            forces, q, v, a = (np.concatenate(x) for x in zip(*parts, strict=True))
        elif method == "projection":
            forces, q, v, a = self._projection(pts, vel, acc, w, g)
        else:
            raise InvalidParameterError("method", method, "one of " + ", ".join(METHODS))
        _check_forces(forces, pts)
        act = self.closed_loop.actuated
        return DynamicsResult(
            forces=forces,
            q=q,
            v=v,
            a=a,
            p=pts,
            p_dot=vel,
            p_ddot=acc,
            slider_positions=q[:, act],
            slider_velocities=v[:, act],
            slider_accelerations=a[:, act],
            wrench=w,
            gravity=g,
            method=method,
        )

    def inverse_dynamics_sliders(
        self,
        q: ArrayLike,
        q_dot: ArrayLike,
        q_ddot: ArrayLike,
        *,
        wrench: ArrayLike | None = None,
        gravity: ArrayLike | None = None,
        method: str = "closed-form",
    ) -> DynamicsResult:
        """As :meth:`inverse_dynamics`, for a slider motion (working assembly mode).

        Args:
            q: Slider values [m], shape (N, 3) or (3,).
            q_dot: Slider velocities [m/s], same shape.
            q_ddot: Slider accelerations [m/s^2], same shape.
            wrench: External wrench on the tool, as :meth:`inverse_dynamics`.
            gravity: Gravity [m/s^2], shape (3,).
            method: ``"closed-form"`` or ``"projection"``.

        Returns:
            The forces and the joint motion.

        Raises:
            NoAssemblyError: Slider values without assembly (and as
                :meth:`inverse_dynamics`).
        """
        rows = (
            finite_rows("q", q, 3),
            bounded_rows("q_dot", q_dot, 3, MAX_SPEED, "[m/s]"),
            bounded_rows("q_ddot", q_ddot, 3, MAX_ACCELERATION, "[m/s^2]"),
        )
        p, pd, pdd = tool_motion_from_sliders(*rows, self.leg_length)
        return self.inverse_dynamics(p, pd, pdd, wrench=wrench, gravity=gravity, method=method)

    def static_forces(
        self,
        p: ArrayLike,
        *,
        wrench: ArrayLike | None = None,
        gravity: ArrayLike | None = None,
    ) -> FloatArray:
        """Actuator forces holding the machine still at tool points [N], shape (N, 3)."""
        pts = finite_rows("p", p, 3)
        zero = np.zeros_like(pts)
        return self.inverse_dynamics(pts, zero, zero, wrench=wrench, gravity=gravity).forces

    def _closed_form(
        self, p: FloatArray, pd: FloatArray, pdd: FloatArray, w: FloatArray, g: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        motion = leg_motion(p, pd, pdd, self.leg_length)
        idx = self.leg_indices
        q = scatter(motion.values, idx)
        v = scatter(motion.rates, idx)
        a = scatter(motion.accelerations, idx)
        tau = self.engine(g).rnea(q, v, a)
        tool_force = np.einsum("nlf,nlfw->nw", gather(tau, idx), motion.gradients)  # Q'^T tau
        _, J = ik_and_jacobian(p, self.leg_length)
        forces = np.einsum("nwk,nw->nk", J, tool_force - w[:, :3])
        return forces, q, v, a

    def _projection(
        self, p: FloatArray, pd: FloatArray, pdd: FloatArray, w: FloatArray, g: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        cl, eng = self.closed_loop, self.engine(g)
        pm, pdata, tool = cl.model, cl.data, cl.tool_frame
        act, pas = cl.actuated, cl.passive
        lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        q_act = inverse_kinematics(p, self.leg_length)
        n, nv = p.shape[0], cl.nv
        forces = np.empty((n, 3))
        qs, vs, accs = (np.empty((n, nv)) for _ in range(3))
        last: FloatArray | None = None
        for k in range(n):
            q = last = cl.solve(q_act[k], last).q
            _, K = cl.constraint_residual_and_jacobian(q)  # also the joint Jacobians
            kp_pinv = np.linalg.pinv(K[:, pas], rcond=RANK_TOL)
            G = np.zeros((nv, 3))
            G[act] = np.eye(3)
            G[pas] = -kp_pinv @ K[:, act]
            j_tool = pin.getFrameJacobian(pm, pdata, tool, lwa)
            j_lin = j_tool[:3] @ G
            try:
                j_inv = np.linalg.inv(j_lin)
            except np.linalg.LinAlgError:
                why = "the tool Jacobian of the closed chain is singular"
                raise SingularConfigurationError(p[k], None, "parallel", why) from None
            v = G @ (j_inv @ pd[k])
            # The drift gamma: Pinocchio's constraint acceleration at (q, v, 0) (pin 4.1
            # leaves constraint_acceleration_biais_term at zero after calc).
            pin.forwardKinematics(pm, pdata, q, v, np.zeros(nv))
            for cm, cd in zip(cl.constraint_models, cl.constraint_datas, strict=True):
                cm.calc(pm, pdata, cd)
            gamma = np.concatenate(
                [cd.constraint_acceleration_error for cd in cl.constraint_datas]
            )
            a_drift = np.zeros(nv)
            a_drift[pas] = -kp_pinv @ gamma
            pin.forwardKinematics(pm, pdata, q, v, a_drift)
            tool_drift = pin.getFrameClassicalAcceleration(pm, pdata, tool, lwa).linear
            a = G @ (j_inv @ (pdd[k] - tool_drift)) + a_drift
            tau = pin.rnea(eng.model, eng.data, q, v, a) - j_tool.T @ w[k]
            forces[k], qs[k], vs[k], accs[k] = G.T @ tau, q, v, a
        return forces, qs, vs, accs


def _wrench(value: ArrayLike | None, n: int) -> FloatArray:
    """External wrench rows (force [N], moment [N.m]), shape (n, 6)."""
    out = np.zeros((n, 6))
    if value is None:
        return out
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        arr = np.empty((0, 0))
    ok = arr.ndim in (1, 2) and arr.shape[-1] in (3, 6) and arr.shape[:-1] in ((), (n,))
    if not ok or not np.all(np.isfinite(arr)):
        allowed = (
            f"finite numbers of shape (3,), (6,), ({n}, 3) or ({n}, 6): force [N], moment [N.m]"
        )
        raise InvalidParameterError("wrench", getattr(arr, "shape", value), allowed)
    over = np.abs(arr) > MAX_WRENCH
    if over.any():
        bad = float(arr.reshape(-1)[first_index(over)])
        raise InvalidParameterError("wrench", bad, f"values within +-{MAX_WRENCH:g} [N, N.m]")
    out[:, : arr.shape[-1]] = arr
    return out


def _gravity(value: ArrayLike) -> FloatArray:
    """Gravity [m/s^2], shape (3,), of magnitude at most ``MAX_GRAVITY``."""
    return gravity_vector(value)


def _check_forces(forces: FloatArray, points: FloatArray) -> None:
    """Refuse non-finite actuator forces (an input too extreme for this machine)."""
    finite = np.isfinite(forces).all(axis=1)
    if not finite.all():
        idx = first_index(~finite)
        raise InvalidParameterError(
            "p, p_dot, p_ddot, wrench, gravity",
            f"non-finite forces at p = {tuple(points[idx].tolist())}",
            "a motion, wrench, gravity and machine masses that give finite actuator "
            "forces [N] (smaller values, or a point farther from singularities)",
        )


def _blocks(n: int, size: int) -> list[slice]:
    return [slice(start, min(start + size, n)) for start in range(0, n, size)]
