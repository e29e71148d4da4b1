"""Forward dynamics of the closed chain and its mechanical energy.

Forward dynamics (slider forces in, joint accelerations out) runs Pinocchio's
``constraintDynamics`` on the cut tree with the five loop closures as rigid
constraints (``convertToRigidConstraintModel``, expressed ``LOCAL``, Baumgarte
gains zero). It is the independent check of the inverse dynamics
(:mod:`orthoglide_pin.dynamics.inverse`) and a simulation step.

The cut tree is loaded exactly as described: every body with a joint carries
its physical mass (the platform is shared in thirds by the three end revolutes,
see the description), so the tree's joint-space mass matrix is positive
definite and ``constraintDynamics`` factors it. The constraint Jacobian has 21
rows of rank 15 (over-constrained machine): the constraint forces are not
unique, the accelerations are. The proximal solver (``ProximalSettings`` with
``mu > 0``) handles the redundant rows.

Energies: ``E = 1/2 v^T M(q) v`` (``computeKineticEnergy``) and the potential
``V = -sum_b m_b g . c_b`` (``computePotentialEnergy`` with the model's gravity
set to ``g``), both in [J].
"""

from __future__ import annotations

from typing import Final

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import MAX_WRENCH, bounded_rows, finite_rows
from orthoglide_pin.dynamics.inverse import _wrench
from orthoglide_pin.dynamics.motion_forms import Machine, as_dynamics
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]

#: Proximal regularisation of ``constraintDynamics`` (redundant constraint rows).
PROX_MU: Final[float] = 1e-6
#: Proximal iterations (the accelerations converge to 1e-13 in about 5).
PROX_ITERATIONS: Final[int] = 50
#: Requested accuracy of the proximal iterations.
PROX_ACCURACY: Final[float] = 1e-12


class ForwardDynamics:
    """Joint accelerations of the closed chain for given slider forces.

    Args:
        dynamics: The closed-loop dynamics (model and default gravity), or
            the model or parameters to build them from (see
            :func:`~orthoglide_pin.dynamics.motion_forms.as_dynamics`); the
            prototype's when ``None``.
        gravity: Gravity [m/s^2], shape (3,); the dynamics' default when ``None``.

    Attributes:
        model: The Pinocchio model of the cut tree, with that gravity.
        data: Its data.
        gravity: Gravity used [m/s^2], shape (3,).
    """

    def __init__(self, dynamics: Machine = None, gravity: ArrayLike | None = None) -> None:
        dynamics = as_dynamics(dynamics, "dynamics")
        self.dynamics = dynamics
        self.gravity = dynamics.gravity_vector(gravity)
        self.model = pin.Model(dynamics.pinocchio_model(self.gravity))
        self.data = self.model.createData()
        self._constraints = pin.StdVec_RigidConstraintModel()
        for cm in dynamics.closed_loop.constraint_models:
            rigid = pin.convertToRigidConstraintModel(self.model, cm, pin.ReferenceFrame.LOCAL)
            rigid.m_baumgarte_parameters.Kp = 0.0
            rigid.m_baumgarte_parameters.Kd = 0.0
            self._constraints.append(rigid)
        self._datas = pin.StdVec_RigidConstraintData()
        for rigid in self._constraints:
            self._datas.append(rigid.createData())
        pin.initConstraintDynamics(self.model, self.data, self._constraints, self._datas)

    def accelerations(
        self,
        q: ArrayLike,
        v: ArrayLike,
        forces: ArrayLike,
        *,
        wrench: ArrayLike | None = None,
    ) -> FloatArray:
        """Joint accelerations for slider forces (``constraintDynamics``).

        Args:
            q: Assembled configurations [m, rad], shape (N, 18).
            v: Constraint-consistent joint velocities [m/s, rad/s], shape (N, 18).
            forces: Actuator forces along the sliders [N], shape (N, 3).
            wrench: External wrench on the tool (force [N], moment [N.m], world
                axes, exerted by the environment), as in
                :meth:`ClosedLoopDynamics.inverse_dynamics`.

        Returns:
            Joint accelerations [m/s^2, rad/s^2], shape (N, 18).

        Raises:
            InvalidParameterError: Bad shapes, non-finite values, forces beyond
                ``MAX_WRENCH`` [N], or accelerations that would not be finite.
        """
        cl = self.dynamics.closed_loop
        qs, vs = finite_rows("q", q, cl.nv), finite_rows("v", v, cl.nv)
        fs = bounded_rows("forces", forces, 3, MAX_WRENCH, "[N]")
        if not qs.shape[0] == vs.shape[0] == fs.shape[0]:
            shapes = (qs.shape, vs.shape, fs.shape)
            raise InvalidParameterError("shapes", shapes, "q, v and forces with N rows each")
        w = _wrench(wrench, qs.shape[0])
        m, d = self.model, self.data
        lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        out = np.empty_like(qs)
        for k in range(qs.shape[0]):
            tau = np.zeros(cl.nv)
            tau[cl.actuated] = fs[k]
            if np.any(w[k]):
                pin.computeJointJacobians(m, d, qs[k])
                tau += pin.getFrameJacobian(m, d, cl.tool_frame, lwa).T @ w[k]
            settings = pin.ProximalSettings(PROX_ACCURACY, PROX_ACCURACY, PROX_MU, PROX_ITERATIONS)
            out[k] = pin.constraintDynamics(
                m, d, qs[k], vs[k], tau, self._constraints, self._datas, settings
            )
        if not np.isfinite(out).all():
            bad = int(np.argmin(np.isfinite(out).all(axis=1)))
            raise InvalidParameterError(
                "q, v, forces",
                f"non-finite accelerations at row {bad}",
                "a state and forces that give finite joint accelerations",
            )
        return out


def mechanical_energy(
    dynamics: Machine,
    q: ArrayLike,
    v: ArrayLike,
    *,
    gravity: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Kinetic and potential energy of the machine along ``N`` states.

    Args:
        dynamics: The closed-loop dynamics, or the model or parameters to
            build them from (``None``: the prototype's).
        q: Configurations [m, rad], shape (N, 18).
        v: Joint velocities [m/s, rad/s], shape (N, 18).
        gravity: Gravity [m/s^2], shape (3,); the default one when ``None``.

    Returns:
        ``(E, V)`` [J], each shape (N,): ``E = 1/2 v^T M v`` and
        ``V = -sum_b m_b g . c_b`` (zero at the world origin).

    Raises:
        InvalidParameterError: Bad shapes or non-finite values.
    """
    dynamics = as_dynamics(dynamics, "dynamics")
    nv = dynamics.closed_loop.nv
    qs, vs = finite_rows("q", q, nv), finite_rows("v", v, nv)
    if qs.shape != vs.shape:
        raise InvalidParameterError("shapes", (qs.shape, vs.shape), "q and v of one shape")
    eng = dynamics.engine(gravity)
    m, d = eng.model, eng.data
    kinetic = np.array(
        [pin.computeKineticEnergy(m, d, qk, vk) for qk, vk in zip(qs, vs, strict=True)]
    )
    potential = np.array([pin.computePotentialEnergy(m, d, qk) for qk in qs])
    return kinetic, potential
