"""Velocity projections of the closed chain, and the singularities they reveal.

With ``K`` the 21 x 18 constraint Jacobian (columns of the sliders ``a`` and of
the passive joints ``p``) and ``J_tool`` the 3 x 18 linear tool Jacobian:

* :func:`velocity_map`: ``G = [I; -K_p^+ K_a]`` (``v = G v_a``), defined while
  the sliders fix the passive joints (``rank K_p = 15``); it is not at a
  parallel singularity;
* :func:`inverse_jacobian`: ``J^-1``, the slider part of the solution of
  ``[K; J_tool] v = [0; p_dot]`` for the three unit ``p_dot`` (24 rows, rank 18
  off serial singularities); it is defined at parallel singularities, so that
  :func:`orthoglide_pin.kinematics.singularity.check_inverse_jacobian` can
  judge any configuration with the closed form's thresholds.

Every rank decision uses the relative singular-value threshold ``rank_tol``.
The tool point named in an error is computed only when one is raised.
:class:`JacobianMixin` gives :class:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel`
its ``velocity_map``, ``inverse_jacobian`` and ``jacobian``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.kinematics.singularity import MAX_CONDITION, check_inverse_jacobian

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]


def _rank(s: FloatArray, rank_tol: float) -> int:
    return int(np.sum(s > rank_tol * s[0])) if s.size and s[0] > 0.0 else 0


def velocity_map(
    k: FloatArray,
    actuated: IndexArray,
    passive: IndexArray,
    rank_tol: float,
    point: Callable[[], FloatArray],
) -> FloatArray:
    """``G`` with ``v = G v_a``, shape (nv, 3).

    Raises:
        SingularConfigurationError: ``kind="parallel"`` when ``rank K_p`` is
            below the number of passive joints.
    """
    u, s, vt = np.linalg.svd(k[:, passive], full_matrices=False)
    rank = _rank(s, rank_tol)
    if rank < passive.size:
        why = (
            f"the sliders do not fix the passive joints (rank {rank} of "
            f"{passive.size} of the passive constraint Jacobian)"
        )
        raise SingularConfigurationError(point(), None, "parallel", why)
    g = np.zeros((k.shape[1], 3))
    g[actuated] = np.eye(3)
    g[passive] = -(vt.T / s) @ (u.T @ k[:, actuated])
    return g


def inverse_jacobian(
    k: FloatArray,
    j_tool: FloatArray,
    actuated: IndexArray,
    rank_tol: float,
    point: Callable[[], FloatArray],
) -> FloatArray:
    """``J^-1`` (``q_dot = J^-1 p_dot``), shape (3, 3).

    Raises:
        SingularConfigurationError: ``kind="serial"`` (the leg whose slider
            moves most) when ``[K; J_tool]`` loses rank: a slider moves with
            the tool fixed.
    """
    stacked = np.vstack([k, j_tool])
    u, s, vt = np.linalg.svd(stacked, full_matrices=False)
    rank = _rank(s, rank_tol)
    if rank < stacked.shape[1]:
        leg = int(np.argmax(np.abs(vt[-1, actuated]))) + 1
        why = (
            f"a slider moves with the tool fixed (rank {rank} of {stacked.shape[1]} "
            "of [K; J_tool])"
        )
        raise SingularConfigurationError(point(), leg, "serial", why)
    v = (vt.T / s) @ u[-3:].T  # right-hand side [0; I]: the last three rows of u^T
    return np.ascontiguousarray(v[actuated])


#: Relative singular-value threshold of the rank decisions (as the loop closure's).
RANK_TOL = 1e-9


class JacobianMixin:
    """``velocity_map``, ``inverse_jacobian`` and ``jacobian`` of the closed-loop model.

    Uses the model's ``model``, ``data``, ``actuated``, ``passive``,
    ``tool_frame`` and ``constraint_residual_and_jacobian``.
    """

    model: pin.Model
    data: pin.Data
    actuated: IndexArray
    passive: IndexArray
    tool_frame: int

    def constraint_residual_and_jacobian(self, q: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Stacked loop-closure residual and its Jacobian (see the model)."""
        raise NotImplementedError

    def _projected(self, q: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``K`` (21, 18) and the linear tool Jacobian ``J_tool`` (3, 18) at ``q``."""
        _, k = self.constraint_residual_and_jacobian(q)
        j_tool = pin.getFrameJacobian(
            self.model, self.data, self.tool_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )[:3]
        return k, np.asarray(j_tool, dtype=float)

    def _tool_point(self) -> FloatArray:
        """Tool position at the joints last computed [m], shape (3,)."""
        pin.updateFramePlacements(self.model, self.data)
        return np.array(self.data.oMf[self.tool_frame].translation)

    def velocity_map(self, q: ArrayLike) -> FloatArray:
        """The map ``G`` with ``v = G v_a`` on the closed chain, shape (18, 3).

        ``q`` must be assembled (see :meth:`solve`).

        Raises:
            SingularConfigurationError: ``kind="parallel"`` when the sliders do
                not fix the passive joints (:func:`velocity_map`).
        """
        k = self._projected(q)[0]
        return velocity_map(k, self.actuated, self.passive, RANK_TOL, self._tool_point)

    def inverse_jacobian(self, q: ArrayLike) -> FloatArray:
        """Inverse Jacobian ``J^-1`` (``q_dot = J^-1 p_dot``) by projection, shape (3, 3).

        Defined at parallel singularities, where ``J`` is not
        (:func:`inverse_jacobian`). ``q`` must be assembled.

        Raises:
            SingularConfigurationError: ``kind="serial"`` when a slider can move
                with the tool fixed.
        """
        k, j_tool = self._projected(q)
        return inverse_jacobian(k, j_tool, self.actuated, RANK_TOL, self._tool_point)

    def jacobian(self, q: ArrayLike, *, max_condition: float = MAX_CONDITION) -> FloatArray:
        """Tool Jacobian ``J = J_tool G`` (``p_dot = J q_dot``) by projection, shape (3, 3).

        ``q`` must be assembled (see :meth:`solve`). ``J_tool`` is the linear
        part of the tool frame's Jacobian in world axes along the cut tree.
        The configuration is first judged from :meth:`inverse_jacobian` with
        the closed form's thresholds
        (:func:`orthoglide_pin.kinematics.singularity.check_inverse_jacobian`).

        Args:
            q: Assembled configuration [m, rad], shape (18,).
            max_condition: Largest condition number of ``J`` accepted.

        Raises:
            SingularConfigurationError: A serial or parallel singularity (the
                closed form's ``SERIAL_TOL``, ``PARALLEL_TOL``), or a condition
                number beyond ``max_condition``.
        """
        k, j_tool = self._projected(q)
        point = self._tool_point
        j_inv = inverse_jacobian(k, j_tool, self.actuated, RANK_TOL, point)
        check_inverse_jacobian(j_inv, point(), max_condition=max_condition)
        g = velocity_map(k, self.actuated, self.passive, RANK_TOL, point)
        return np.asarray(j_tool @ g, dtype=float)
