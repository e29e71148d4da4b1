"""Slider forces along a geometric path as forms in the path speed and acceleration.

Along a tool path ``p(s)`` parametrised by its arc length ``s`` [m], the tool
moves with ``v = p' s_dot`` and ``a = p' s_ddot + p'' s_dot^2``. The slider
forces are affine in the tool acceleration and quadratic in its velocity
(:mod:`orthoglide_pin.dynamics.motion_forms`, ``F_i = m_i . a + v^T H_i v + c_i``),
so along the path they are affine in ``(s_ddot, s_dot^2)``::

    F_i = a_i s_ddot + b_i s_dot^2 + c_i
    a_i = m_i . p'      b_i = m_i . p'' + p'^T H_i p'      c_i = c_i

and the slider motion is ``q_dot = q' s_dot``, ``q_ddot = q' s_ddot + q'' s_dot^2``
with ``q' = J^-1 p'`` and ``q''_i = b_i . p'' + p'^T K_i p'`` (the slider
acceleration form). These are the coefficients a time-optimal planner needs
at every grid point of the path (:mod:`orthoglide_pin.planning.parametrize`).

This module reads them from :func:`~orthoglide_pin.dynamics.motion_forms.requirement_forms`,
one batch for the whole path; it is exact up to rounding (the tests compare it
with :meth:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics.inverse_dynamics`
point by point).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows
from orthoglide_pin.dynamics.motion_forms import Machine, as_dynamics, requirement_forms
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PathForms:
    """Slider forces along a geometric path ``p(s)``, ``s`` the arc length [m].

    ``F = a * s_ddot + b * s_dot**2 + c`` (each (N, 3) [N]);
    ``q_dot = dq * s_dot``, ``q_ddot = dq * s_ddot + ddq * s_dot**2``.

    Attributes:
        q: Slider positions [m], shape (N, 3).
        dq: ``dq/ds`` [-], shape (N, 3).
        ddq: ``d2q/ds2`` [1/m], shape (N, 3).
        a: Force per unit path acceleration [kg] (N per m/s^2 of ``s_ddot``), (N, 3).
        b: Force per unit squared path speed [kg/m] (N per (m/s)^2), (N, 3).
        c: Force at rest [N] (gravity and tool wrench), (N, 3).
    """

    q: FloatArray
    dq: FloatArray
    ddq: FloatArray
    a: FloatArray
    b: FloatArray
    c: FloatArray

    def forces(self, s_dot: ArrayLike, s_ddot: ArrayLike) -> FloatArray:
        """Slider forces [N], (N, 3), at path speeds [m/s] and accelerations [m/s^2], (N,)."""
        sd = np.asarray(s_dot, dtype=float)[:, None]
        sdd = np.asarray(s_ddot, dtype=float)[:, None]
        return np.asarray(self.a * sdd + self.b * sd * sd + self.c)


def path_forms(
    model: Machine,
    points: ArrayLike,
    tangents: ArrayLike,
    curvatures: ArrayLike,
    *,
    gravity: ArrayLike | None = None,
    wrench: ArrayLike | None = None,
) -> PathForms:
    """The coefficients of the slider forces and motion along a path (see the module).

    Args:
        model: The inverse dynamics, a closed-loop model, or a machine's
            parameters (``None``: the prototype's; see
            :func:`~orthoglide_pin.dynamics.motion_forms.as_dynamics`).
        points: Path points ``p(s)`` [m], world frame, shape (N, 3).
        tangents: ``dp/ds`` [-], shape (N, 3) (unit vectors for an arc-length path).
        curvatures: ``d2p/ds2`` [1/m], shape (N, 3).
        gravity: Gravity [m/s^2], shape (3,); the model's when ``None``.
        wrench: Tool wrench (force [N], moment [N.m]), shape (6,), (3,), (N, 6)
            or (N, 3), as :meth:`ClosedLoopDynamics.inverse_dynamics`.

    Returns:
        The forms at the ``N`` points.

    Raises:
        InvalidParameterError: Bad shapes or values.
        UnreachablePointError, SingularConfigurationError: A point out of reach.
    """
    dyn = as_dynamics(model, "model")
    p = finite_rows("points", points, 3, "[m]")
    t = finite_rows("tangents", tangents, 3, "[-]")
    k = finite_rows("curvatures", curvatures, 3, "[1/m]")
    if not p.shape == t.shape == k.shape:
        raise InvalidParameterError(
            "shapes", (p.shape, t.shape, k.shape), "points, tangents, curvatures of one shape"
        )
    forms = requirement_forms(dyn, p, wrench=wrench, gravity=gravity, check_limits=False)
    f, acc = forms.forces, forms.slider_accelerations
    a = np.einsum("nik,nk->ni", f.linear, t)
    b = np.einsum("nik,nk->ni", f.linear, k) + np.einsum("nk,nikl,nl->ni", t, f.quadratic, t)
    dq = np.einsum("nik,nk->ni", acc.linear, t)
    ddq = np.einsum("nik,nk->ni", acc.linear, k) + np.einsum("nk,nikl,nl->ni", t, acc.quadratic, t)
    q = inverse_kinematics(p, dyn.leg_length)
    return PathForms(q=q, dq=dq, ddq=ddq, a=a, b=b, c=np.array(f.constant))
