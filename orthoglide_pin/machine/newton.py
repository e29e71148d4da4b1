"""Newton's method for the loop closure: results, step operators, the inner loop, paths.

:class:`LoopNewton` closes the loops of a cut tree for slider values already
set in ``q``: Newton's method on the passive joints, ``dq_p = -K_p^+ r`` with
``r`` the stacked constraint residual and ``K_p`` the passive columns of its
Jacobian, least squares with an explicit rank tolerance. The operator
``-K_p^+`` is kept while it contracts the residual fast (simplified Newton:
each further iteration is one forward-kinematics pass), and the caller may
pass the operators of an earlier nearby solution.

The results of the solves are :class:`Assembly` (one configuration) and
:class:`PathAssembly` (rows of them). :class:`LoopNewton` is the inner path of
:class:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel`
(which checks the inputs once, at its public entries): no input checks, one
preallocated residual buffer, and the residual read straight from the views
Pinocchio keeps on its constraint data (``constraint_position_error`` is
updated in place by ``calc``), so that one residual costs one
forward-kinematics pass, the ``calc`` of each closure and one copy.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from orthoglide_pin.machine import projection

FloatArray = NDArray[np.float64]
#: The step operator ``-K_p^+`` (15, 21) and the passive velocity map ``-K_p^+ K_a`` (15, 3).
Operator = tuple[FloatArray, FloatArray]

#: Loop-closure residual accepted by default (max-norm) [m, rad].
CLOSURE_TOL: Final = 1e-12
#: Relative singular-value threshold used for every rank decision.
RANK_TOL: Final = projection.RANK_TOL
#: Newton iterations before the closure is declared failed.
MAX_ITERATIONS: Final = 50
#: Largest Newton step on the passive joints [rad]: keeps the solver on its branch.
MAX_STEP: Final = 0.35
#: Residual ratio (Euclidean norms) between two iterations above which the step
#: operator is computed again (below it, the operator of an earlier point keeps
#: contracting).
CONTRACTION: Final = 0.05
#: Iterations past which a solve leaves the operators of its solution (not the
#: reused ones) for the next warm start.
REFRESH_AFTER: Final = 3
#: Earlier solutions extrapolated to start a solve on a path (cubic extrapolation).
NODES: Final = 4


@dataclass(frozen=True)
class Assembly:
    """A solved configuration of the closed-loop model.

    Attributes:
        q: Configuration of all 18 joints [m, rad], shape (18,).
        residual: Max-norm of the loop-closure residual at ``q`` [m, rad].
        iterations: Newton iterations used.
        tool_position: Tool tip in the world frame [m], shape (3,).
    """

    q: FloatArray
    residual: float
    iterations: int
    tool_position: FloatArray


@dataclass(frozen=True)
class PathAssembly:
    """Solved configurations along ``N`` rows of slider values.

    The result of :meth:`ClosedLoopModel.solve_many`.

    Attributes:
        q: Configurations of all 18 joints [m, rad], shape (N, 18).
        residual: Max-norm of the loop-closure residual per row [m, rad], shape (N,).
        iterations: Newton iterations per row, shape (N,).
        tool_position: Tool tips in the world frame [m], shape (N, 3).
    """

    q: FloatArray
    residual: FloatArray
    iterations: NDArray[np.intp]
    tool_position: FloatArray

    def __len__(self) -> int:
        return int(self.q.shape[0])


def pinv_rank(a: FloatArray, rtol: float = RANK_TOL) -> tuple[FloatArray, int]:
    """Pseudo-inverse with an explicit relative rank tolerance, and the rank."""
    u, s, vt = np.linalg.svd(a, full_matrices=False)
    rank = int(np.sum(s > rtol * s[0])) if s.size and s[0] > 0 else 0
    inv = (vt[:rank].T / s[:rank]) @ u[:, :rank].T
    return inv, rank


def step_matrix(k_p: FloatArray) -> FloatArray:
    """The least-squares step operator ``-K_p^+`` on the passive joints, shape (15, 21).

    ``K_p`` (21 x 15) has full column rank away from singularities, so the
    normal equations give it through one Cholesky factorisation. The
    diagonal of the factor estimates the singular values of ``K_p``: when its
    spread passes ``1 / RANK_TOL`` (or the factorisation fails) the
    rank-revealing pseudo-inverse takes over.
    """
    normal = k_p.T @ k_p
    try:
        chol = np.linalg.cholesky(normal)
    except np.linalg.LinAlgError:
        chol = None
    if chol is not None:
        diag = np.diagonal(chol)
        if diag.min() > RANK_TOL * diag.max():
            return np.asarray(-np.linalg.solve(normal, k_p.T), dtype=float)
    k_pinv, _ = pinv_rank(k_p)
    return np.asarray(-k_pinv, dtype=float)


def path_extrapolation(rows: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """Where and how a solve on a path starts from the earlier solutions extrapolated.

    Row ``k`` may start from the Lagrange extrapolation, in the chord length
    of the slider values, of the solutions of the ``NODES`` rows before it.
    It does (``smooth[k]``) when the same extrapolation of those rows predicts
    row ``k`` to within a tenth of the last step: the path is smooth there, so
    the first-order predictor that follows corrects a small slider offset only.

    Args:
        rows: Slider values [m], shape (N, 3).

    Returns:
        ``(weights (N, NODES), smooth (N,))``.
    """
    n = rows.shape[0]
    weights, smooth = np.zeros((n, NODES)), np.zeros(n, dtype=bool)
    if n <= NODES:
        return weights, smooth
    steps = np.linalg.norm(np.diff(rows, axis=0), axis=1)
    chord = np.concatenate([[0.0], np.cumsum(steps)])
    # nodes[k - NODES] holds the chord of rows k - NODES .. k - 1; x that of row k
    nodes = np.lib.stride_tricks.sliding_window_view(chord[:-1], NODES)
    x = chord[NODES:, None]
    gaps = nodes[:, :, None] - nodes[:, None, :]  # t_j - t_i
    eye = np.eye(NODES, dtype=bool)
    later = np.tril(np.ones((NODES, NODES), dtype=bool), -1)  # j > i
    ok = np.all((gaps > 0.0) | ~later, axis=(1, 2))
    ok &= steps[NODES - 1 :] > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        num = np.where(eye, 1.0, x[:, None, :] - nodes[:, None, :])
        den = np.where(eye, 1.0, gaps)
        w = np.prod(num / den, axis=2)
    window = np.lib.stride_tricks.sliding_window_view(rows[:-1], NODES, axis=0)  # (N-m, 3, m)
    off = rows[NODES:] - np.einsum("km,kcm->kc", w, window)
    step = rows[NODES:] - rows[NODES - 1 : -1]
    ok &= np.einsum("kc,kc->k", off, off) <= 0.01 * np.einsum("kc,kc->k", step, step)
    ok &= np.isfinite(w).all(axis=1)
    weights[NODES:] = np.where(ok[:, None], w, 0.0)
    smooth[NODES:] = ok
    return weights, smooth


class LoopNewton:
    """The loop-closure iteration on one Pinocchio model and its constraints.

    Args:
        model: Pinocchio model of the cut tree.
        data: Its data (scratch space, shared with the caller).
        pairs: ``(constraint model, constraint data)`` per closure.
        actuated: Velocity indices of the sliders, shape (3,).
        passive: Velocity indices of the passive joints, shape (15,).
    """

    def __init__(
        self,
        model: pin.Model,
        data: pin.Data,
        pairs: Sequence[tuple[Any, Any]],
        actuated: NDArray[np.intp],
        passive: NDArray[np.intp],
    ) -> None:
        self.model, self.data = model, data
        self.actuated, self.passive = actuated, passive
        self._calcs = [(cm.calc, cd) for cm, cd in pairs]
        self._jacobians = [(cm.jacobian, cd) for cm, cd in pairs]
        # Views on Pinocchio's residual vectors: calc updates them in place.
        self._errors = [cd.constraint_position_error for _, cd in pairs]
        self._rows = sum(e.shape[0] for e in self._errors)
        self._r = np.empty(self._rows)

    def residual(self, q: FloatArray) -> FloatArray:
        """Stacked residual at ``q`` [m, rad], shape (21,), in a buffer reused by the next call."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q)
        for calc, cd in self._calcs:
            calc(model, data, cd)
        return np.concatenate(self._errors, out=self._r)

    def operator(self, q: FloatArray) -> Operator:
        """At ``q``: ``-K_p^+`` (15, 21) and ``-K_p^+ K_a`` (15, 3).

        The second is the passive block of the velocity map ``G``.
        """
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        for calc, cd in self._calcs:
            calc(model, data, cd)
        k = np.vstack([jac(model, data, cd) for jac, cd in self._jacobians])
        step = step_matrix(k[:, self.passive])
        return step, step @ k[:, self.actuated]

    def close(
        self, q: FloatArray, tol: float, max_iterations: int, operator: Operator | None
    ) -> tuple[bool, float, int, Operator | None]:
        """Close the loops from ``q`` (modified in place; sliders already set).

        Args:
            q: Start configuration [m, rad], shape (18,); the solution on return.
            tol: Residual (max-norm) to reach [m, rad].
            max_iterations: Iteration budget.
            operator: Operators of a nearby solution to start with, or ``None``.

        Returns:
            ``(converged, residual [m, rad], iterations, operators)``; on
            success the operators are those to reuse from the solution, and
            the joint placements in ``data`` are those of ``q``.
        """
        passive = self.passive
        tol2, loose2 = tol * tol, self._rows * tol * tol
        max_step2 = MAX_STEP * MAX_STEP
        last = math.inf
        res = math.inf
        for it in range(max_iterations + 1):
            r = self.residual(q)
            ss = float(r @ r)
            # the Euclidean norm decides unless it lies within sqrt(21) of tol
            if ss <= tol2 or (ss <= loose2 and float(np.abs(r).max()) <= tol):
                if operator is None or it > REFRESH_AFTER:
                    operator = self.operator(q)  # the operators of this point
                return True, float(np.abs(r).max()), it, operator
            if it == max_iterations or not math.isfinite(ss):
                res = float(np.abs(r).max()) if math.isfinite(ss) else math.inf
                break
            if operator is None or ss > CONTRACTION * CONTRACTION * last:
                # Newton: the operator at this point (simplified Newton while
                # the reused one still contracts fast).
                operator = self.operator(q)
            step = operator[0] @ r
            if float(step @ step) > max_step2:
                norm = float(np.abs(step).max())
                if norm > MAX_STEP:
                    step *= MAX_STEP / norm
            q[passive] += step
            last = ss
        return False, res, max_iterations, operator

    def worst_closure(self) -> int:
        """Index of the closure with the largest residual at the last evaluation."""
        return int(np.argmax([np.abs(e).max() for e in self._errors]))
