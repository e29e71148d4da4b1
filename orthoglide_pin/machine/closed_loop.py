"""The closed-loop Pinocchio model of the Orthoglide.

The URDF is a cut tree (18 one-degree-of-freedom joints): leg 1 carries the
platform, each parallelogram has one bar left open at its tip, and legs 2 and 3
end in a closure frame. :class:`ClosedLoopModel` wraps the Pinocchio model, its
data and one Pinocchio constraint model per loop closure:

* 3 :class:`pinocchio.PointAnchorConstraintModel` (the parallelograms, 3 rows
  each, one of them redundant for a planar parallelogram);
* 2 :class:`pinocchio.FrameAnchorConstraintModel` (legs 2 and 3 onto the
  platform, 6 rows each).

The stacked constraint residual ``r(q)`` has 21 rows and the constraint
Jacobian ``K = dr/dq`` is 21 x 18 with rank 15 away from singularities, so the
mobility is ``18 - 15 = 3``: the machine is over-constrained, which is why
every solve below is a rank-revealing least-squares solve.

Loop closure (:meth:`ClosedLoopModel.solve`) is Newton's method on the passive
joints only, ``dq_p = -K_p^+ r`` with an explicit rank tolerance
(:mod:`orthoglide_pin.machine.newton`). The operator ``-K_p^+`` is kept while
it contracts the residual fast (simplified Newton: each further iteration is
one forward-kinematics pass), and a solve started from the last solution
reuses its operators, predicting the passive joints to first order first
(``dq_p = -K_p^+ K_a dq_a``); along a path this makes a warm solve a few
forward-kinematics passes. The answer is the same (the residual reaches the
same tolerance). :meth:`ClosedLoopModel.solve_many` runs those warm solves
along rows of slider values with the inputs checked once. The velocity
map of the closed chain is ``v = G v_a`` with ``G = [I; -K_p^+ K_a]`` (rows in
the tree's order), and the tool Jacobian is ``J = J_tool G`` (linear part,
world axes), so that ``p_dot = J q_dot`` [m/s per m/s].

Every method takes the configuration it works on as an explicit argument; the
wrapped ``data`` is scratch space only.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, finite_vector, positive_number, text
from orthoglide_pin.exceptions import (
    DescriptionError,
    InvalidParameterError,
    NoAssemblyError,
)
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, leg_vectors
from orthoglide_pin.machine import projection
from orthoglide_pin.machine.coerce import MODEL_ALLOWED, URDF_TEXT, as_params
from orthoglide_pin.machine.description import LoopSpec, load_loops, render_urdf
from orthoglide_pin.machine.loading import load_model
from orthoglide_pin.machine.newton import (
    CLOSURE_TOL,
    MAX_ITERATIONS,
    NODES,
    LoopNewton,
    Operator,
    path_extrapolation,
    pinv_rank,
)
from orthoglide_pin.machine.newton import RANK_TOL as RANK_TOL  # re-exported here, as are
from orthoglide_pin.machine.newton import Assembly as Assembly  # the results of the solves
from orthoglide_pin.machine.newton import PathAssembly as PathAssembly
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]


class ClosedLoopModel(projection.JacobianMixin):
    """Pinocchio model of the Orthoglide with all its loops closed.

    Args:
        params: Machine parameters; the prototype when ``None``.
        urdf: A URDF string to use instead of rendering ``params`` (it must
            follow the description's naming, see ``orthoglide_loops.yaml``).

    Attributes:
        params: The machine parameters.
        urdf: The URDF text the model was built from.
        model: The Pinocchio model of the cut tree.
        data: Pinocchio data (scratch space).
        loops: The loop and actuation data of the description.
        constraint_models: One Pinocchio constraint model per closure, in the
            order of ``loops.closures``.
        constraint_datas: Their data.
        actuated: Velocity indices of the three sliders, shape (3,).
        passive: Velocity indices of the 15 passive joints, shape (15,).
        tool_frame: Frame index of the tool tip.
        platform_frame: Frame index of the platform.
    """

    def __init__(self, params: OrthoglideParams | None = None, *, urdf: str | None = None) -> None:
        self.params = as_params(params)
        self.urdf = render_urdf(self.params) if urdf is None else text("urdf", urdf, URDF_TEXT)
        self.model = load_model(self.urdf)
        self.data = self.model.createData()
        self.loops: LoopSpec = load_loops()
        self.constraint_models: list[
            pin.PointAnchorConstraintModel | pin.FrameAnchorConstraintModel
        ]
        self.constraint_models = [
            self._constraint(c.kind, c.frame1, c.frame2) for c in self.loops.closures
        ]
        self.constraint_datas = [c.createData() for c in self.constraint_models]
        self._pairs = list(zip(self.constraint_models, self.constraint_datas, strict=True))
        # The last solution, its step operator -K_p^+ and passive velocity map
        # -K_p^+ K_a, reused by a solve warm-started from that solution.
        self._warm: tuple[FloatArray, Operator] | None = None
        self._operator: Operator | None = None
        self._last: tuple[float, int] = (0.0, 0)  # residual and iterations of the last solve
        joint_ids = [self._joint_id(name) for name in self.loops.actuated_joints]
        self.actuated = np.array([self.model.joints[j].idx_v for j in joint_ids], dtype=np.intp)
        self.passive = np.setdiff1d(np.arange(self.model.nv), self.actuated).astype(np.intp)
        self._newton = LoopNewton(self.model, self.data, self._pairs, self.actuated, self.passive)
        self.tool_frame = self._frame_id(self.loops.tool_frame)
        self.platform_frame = self._frame_id(self.loops.platform_frame)
        # Per leg: v indices of slider, base revolute, bar a base, bar a tip,
        # end revolute, bar b base.
        suffixes = (
            "slider",
            "base_revolute",
            "bar_a_base",
            "bar_a_tip",
            "end_revolute",
            "bar_b_base",
        )
        self._leg_indices = [
            [self.model.joints[self._joint_id(f"leg{i}_{s}")].idx_v for s in suffixes]
            for i in (1, 2, 3)
        ]
        if self.model.nq != self.model.nv:
            raise DescriptionError("every joint of the description must have nq = nv = 1")

    # ------------------------------------------------------------------ set-up
    def _frame_id(self, name: str) -> int:
        if not self.model.existFrame(name):
            raise DescriptionError(f"frame {name!r} not found in the URDF", name)
        return int(self.model.getFrameId(name))

    def _joint_id(self, name: str) -> int:
        if not self.model.existJointName(name):
            raise DescriptionError(f"joint {name!r} not found in the URDF", name)
        return int(self.model.getJointId(name))

    def _constraint(
        self, kind: str, frame1: str, frame2: str
    ) -> pin.PointAnchorConstraintModel | pin.FrameAnchorConstraintModel:
        f1 = self.model.frames[self._frame_id(frame1)]
        f2 = self.model.frames[self._frame_id(frame2)]
        cls = pin.PointAnchorConstraintModel if kind == "point" else pin.FrameAnchorConstraintModel
        return cls(self.model, f1.parentJoint, f1.placement, f2.parentJoint, f2.placement)

    @property
    def nv(self) -> int:
        """Number of joints of the cut tree (18)."""
        return int(self.model.nv)

    @property
    def constraint_size(self) -> int:
        """Number of stacked constraint rows (21)."""
        return sum(int(c.residualSize()) for c in self.constraint_models)

    def neutral(self) -> FloatArray:
        """The home configuration (isotropic point): every joint at 0, shape (18,)."""
        return np.asarray(pin.neutral(self.model), dtype=float)

    # -------------------------------------------------------------- constraints
    def constraint_residual_and_jacobian(self, q: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Stacked loop-closure residual and its Jacobian at ``q``.

        Args:
            q: Configuration [m, rad], shape (18,).

        Returns:
            ``(r, K)``: residual [m, rad], shape (21,), and the Pinocchio
            constraint Jacobian, shape (21, 18). ``K`` is exactly ``dr/dq`` for
            the point anchors everywhere and for the frame anchors on the
            closed manifold (``r = 0``).
        """
        q = self._check_q(q)
        pin.computeJointJacobians(self.model, self.data, q)
        for cm, cd in zip(self.constraint_models, self.constraint_datas, strict=True):
            cm.calc(self.model, self.data, cd)
        r = np.concatenate([cd.constraint_position_error for cd in self.constraint_datas])
        k = np.vstack(
            [
                cm.jacobian(self.model, self.data, cd)
                for cm, cd in zip(self.constraint_models, self.constraint_datas, strict=True)
            ]
        )
        return r, k

    def constraint_rank(self, q: ArrayLike) -> int:
        """Rank of the 21 x 18 constraint Jacobian at ``q`` (15 off singularities)."""
        _, k = self.constraint_residual_and_jacobian(q)
        return pinv_rank(k)[1]

    def mobility(self, q: ArrayLike) -> int:
        """Degrees of freedom of the closed chain at ``q``: ``18 - rank(K)`` (3)."""
        return self.nv - self.constraint_rank(q)

    def passive_rank(self, q: ArrayLike) -> int:
        """Rank of the passive columns of ``K`` (15 when the sliders fix everything)."""
        _, k = self.constraint_residual_and_jacobian(q)
        return pinv_rank(k[:, self.passive])[1]

    # -------------------------------------------------------------- loop closure
    def solve(
        self,
        q_actuated: ArrayLike,
        q_init: ArrayLike | None = None,
        *,
        tol: float = CLOSURE_TOL,
        max_iterations: int = MAX_ITERATIONS,
    ) -> Assembly:
        """Close every loop for given slider values.

        Newton's method on the 15 passive joints, started from ``q_init``
        (warm start) or from the home configuration (cold start).

        Args:
            q_actuated: Slider values [m], shape (3,).
            q_init: Initial configuration [m, rad], shape (18,); its slider
                entries are replaced by ``q_actuated``.
            tol: Residual (max-norm) to reach [m, rad].
            max_iterations: Iteration budget.

        Returns:
            The assembled configuration.

        Raises:
            InvalidParameterError: On non-finite or wrongly shaped input.
            NoAssemblyError: If the loops cannot be closed.
        """
        qa = finite_vector("q_actuated", q_actuated, 3, "[m] (slider values)")
        tol, max_iterations = self._check_budget(tol, max_iterations)
        q = self.neutral() if q_init is None else self._check_q(q_init, "q_init").copy()
        warm = self._warm
        operator = None
        if q_init is not None and warm is not None and np.array_equal(q, warm[0]):
            operator = warm[1]  # started from the last solution: reuse its operators
        q = self._close(qa, q, tol, max_iterations, operator)
        return Assembly(q, self._last[0], self._last[1], self._tool())

    def solve_many(
        self,
        q_actuated: ArrayLike,
        q_init: ArrayLike | None = None,
        *,
        tol: float = CLOSURE_TOL,
        max_iterations: int = MAX_ITERATIONS,
    ) -> PathAssembly:
        """Close every loop along rows of slider values, each solve warm-started from the last.

        The solutions of :meth:`solve` called row after row with the previous
        solution as ``q_init`` (the first row from ``q_init``, or from home), to
        the same residual tolerance, with the inputs checked once. Where the
        rows follow a smooth path, each solve starts from the last solutions
        extrapolated (:func:`~orthoglide_pin.machine.newton.path_extrapolation`),
        which leaves about one Newton step, one forward-kinematics pass, per row.

        Args:
            q_actuated: Slider values [m], shape (N, 3) or (3,).
            q_init: Start of the first solve [m, rad], shape (18,).
            tol: Residual (max-norm) to reach [m, rad].
            max_iterations: Iteration budget per row.

        Returns:
            The configurations, one row per row of ``q_actuated``.

        Raises:
            InvalidParameterError: On non-finite or wrongly shaped input.
            NoAssemblyError: At the first row whose loops cannot be closed.
        """
        rows = finite_rows("q_actuated", q_actuated, 3, "[m] (slider values)")
        tol, max_iterations = self._check_budget(tol, max_iterations)
        q = self.neutral() if q_init is None else self._check_q(q_init, "q_init").copy()
        n = rows.shape[0]
        qs, tools = np.empty((n, self.nv)), np.empty((n, 3))
        residuals, iterations = np.empty(n), np.empty(n, dtype=np.intp)
        warm = self._warm
        operator = None
        if q_init is not None and warm is not None and np.array_equal(q, warm[0]):
            operator = warm[1]
        weights, smooth = path_extrapolation(rows)
        for k in range(n):
            if smooth[k] and operator is not None:
                q = weights[k] @ qs[k - NODES : k]  # start from the extrapolated solutions
            q = self._close(rows[k], q, tol, max_iterations, operator)
            operator = self._operator
            qs[k], tools[k] = q, self._tool()
            residuals[k], iterations[k] = self._last
        return PathAssembly(qs, residuals, iterations, tools)

    def _check_budget(self, tol: float, max_iterations: int) -> tuple[float, int]:
        tol = positive_number("tol", tol, "a positive residual [m, rad]")
        if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)):
            raise InvalidParameterError("max_iterations", max_iterations, "an integer >= 0")
        if max_iterations < 0:
            raise InvalidParameterError("max_iterations", max_iterations, "an integer >= 0")
        return tol, int(max_iterations)

    def _close(
        self,
        qa: FloatArray,
        q: FloatArray,
        tol: float,
        max_iterations: int,
        operator: Operator | None,
    ) -> FloatArray:
        """Solve from ``q`` (a checked copy, modified) with the sliders at ``qa``.

        With ``operator`` (the operators of the solution ``q``) the passive
        joints are first predicted along the closed chain,
        ``dq_p = -K_p^+ K_a dq_a``. The solution is remembered, with its
        operators, for a warm start from it; ``self._last`` holds its residual
        and iteration count, and the joint placements in ``data`` are its own.
        """
        if operator is not None:
            q[self.passive] += operator[1] @ (qa - q[self.actuated])
        q[self.actuated] = qa
        ok, res, iterations, operator = self._newton.close(q, tol, max_iterations, operator)
        if not ok or operator is None:
            name = self.loops.closures[self._newton.worst_closure()].name
            raise NoAssemblyError(
                qa,
                f"loop closure did not converge (residual {res:.3g} at closure {name} "
                f"after {max_iterations} iterations)",
                leg=int(name[3]) if name.startswith("leg") else None,
                residual=res,
            )
        self._warm = (q.copy(), operator)
        self._operator, self._last = operator, (res, iterations)
        return q

    def _tool(self) -> FloatArray:
        """Tool position [m] from the joint placements in ``data``, shape (3,)."""
        return np.array(
            pin.updateFramePlacement(self.model, self.data, self.tool_frame).translation
        )

    def configuration(self, points: ArrayLike) -> FloatArray:
        """Closed-form configuration of every joint for tool points (working mode).

        In the frame of leg ``i`` (``x_l = e_i``, ``y_l = e_(i+1)``,
        ``z_l = e_(i+2)``) the leg vector ``u = c_i - b_i`` (norm ``L``) is
        ``L (cos(theta) cos(phi), sin(phi), -sin(theta) cos(phi))`` where
        ``theta`` turns the leg about ``y_l`` and ``phi`` opens the
        parallelogram about the turned ``z_l``. Hence ``theta = atan2(-u_z, u_x)``,
        ``phi = asin(u_y / L)``; the end link stays parallel to the base link
        (``-phi`` at the tip of bar a, ``phi`` at the base of bar b) and the end
        revolute undoes the base one (``-theta``), so the platform keeps its
        orientation.

        Args:
            points: Tool points [m], shape (3,) or (..., 3).

        Returns:
            Configurations [m, rad], shape (18,) or (..., 18); each closes every
            loop exactly (the solver is not needed, see :meth:`solve`).

        Raises:
            UnreachablePointError, SingularConfigurationError: As
                :func:`orthoglide_pin.kinematics.closed_form.inverse_kinematics`.
        """
        length = self.params.leg_length
        q_act = inverse_kinematics(points, length)
        legs = leg_vectors(points, length)  # (..., 3 legs, 3 world components)
        out = np.zeros((*q_act.shape[:-1], self.nv))
        for i, idx in enumerate(self._leg_indices):
            u = legs[..., i, :]
            ux, uy, uz = u[..., i], u[..., (i + 1) % 3], u[..., (i + 2) % 3]
            theta = np.arctan2(-uz, ux)
            phi = np.arcsin(np.clip(uy / length, -1.0, 1.0))
            out[..., idx[0]] = q_act[..., i]
            out[..., idx[1]] = theta
            out[..., idx[2]] = phi
            out[..., idx[3]] = -phi
            out[..., idx[4]] = -theta
            out[..., idx[5]] = phi
        return out

    # ---------------------------------------------------------------- kinematics
    def tool_position(self, q: ArrayLike) -> FloatArray:
        """Tool tip position in the world frame [m], shape (3,)."""
        q = self._check_q(q)
        pin.framesForwardKinematics(self.model, self.data, q)
        return np.array(self.data.oMf[self.tool_frame].translation)

    def platform_rotation(self, q: ArrayLike) -> FloatArray:
        """Orientation of the platform in the world frame, shape (3, 3)."""
        q = self._check_q(q)
        pin.framesForwardKinematics(self.model, self.data, q)
        return np.array(self.data.oMf[self.platform_frame].rotation)

    def platform_orientation_error(self, q: ArrayLike) -> float:
        """Rotation angle of the platform away from the world axes [rad]."""
        return float(np.linalg.norm(pin.log3(self.platform_rotation(q))))

    def _check_q(self, q: ArrayLike, name: str = "q") -> FloatArray:
        return finite_vector(name, q, self.model.nq, "[m, rad] (a configuration)")


def as_model(value: object, name: str = "model") -> ClosedLoopModel:
    """The closed-loop model: ``value`` itself, or the model of those parameters.

    The rule of :mod:`orthoglide_pin.machine.coerce` for the entry points that
    work on the model.

    Args:
        value: A ``ClosedLoopModel``, ``OrthoglideParams``, or ``None`` (the
            prototype's model).
        name: The argument's name, for the error message.

    Raises:
        InvalidParameterError: Naming ``name`` and the type received.
    """
    if isinstance(value, ClosedLoopModel):
        return value
    if value is not None and not isinstance(value, OrthoglideParams):
        allowed = f"{MODEL_ALLOWED}, not {type(value).__name__}"
        raise InvalidParameterError(name, value, allowed)
    return ClosedLoopModel(value)
