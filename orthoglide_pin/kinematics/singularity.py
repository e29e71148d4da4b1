"""Singular and near-singular configurations, judged from ``J^-1`` by any route.

Row ``i`` of ``J^-1`` (paper eq. 2) is ``u_i L / eta_i``: the unit leg
direction ``u_i`` scaled by ``L / eta_i``, where ``eta_i / L`` is the cosine of
the angle between leg ``i`` and its slider. So ``J^-1`` alone, whichever way it
was computed (the closed form, or the Pinocchio projection of
:meth:`orthoglide_pin.machine.closed_loop.ClosedLoopModel.inverse_jacobian`),
gives the closed form's own singularity measures:

* serial: ``eta_i / L = 1 / |row_i| <= SERIAL_TOL`` (a leg orthogonal to its
  slider; ``J`` loses rank);
* parallel: ``|det(u_1, u_2, u_3)| < PARALLEL_TOL`` with ``u_i`` the
  normalised rows (coplanar legs; ``J^-1`` loses rank);
* near-singular: the condition number ``cond(J) = cond(J^-1)`` (ratio of the
  extreme singular values) beyond :data:`MAX_CONDITION`. Past it a velocity
  or a force derived from ``J`` has lost at least 6 of its 16 significant
  digits, and the machine stiffness or speed there is of no practical use.

Both routes of the Jacobian and of the kinetostatic indices call
:func:`check_inverse_jacobian`, so they refuse the same configurations with
the same :class:`~orthoglide_pin.exceptions.SingularConfigurationError`.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import first_index, float_array, points_array, positive_number
from orthoglide_pin.exceptions import InvalidParameterError, SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import PARALLEL_TOL, SERIAL_TOL

FloatArray = NDArray[np.float64]

#: Largest condition number ``sigma_3 / sigma_1`` of ``J`` accepted by the
#: Jacobian and the kinetostatic indices (both routes). The prototype's cube
#: stays below 4.
MAX_CONDITION: Final[float] = 1e6


def singularity_measures(j_inv: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The closed form's singularity measures, read from ``J^-1``.

    Args:
        j_inv: Inverse Jacobians, shape ``(3, 3)`` or ``(..., 3, 3)``.

    Returns:
        ``(cosines, det, condition)``: ``eta_i / L`` per leg, shape ``(..., 3)``
        (0 where a row is not finite); ``det(u_1, u_2, u_3)`` of the
        normalised rows, shape ``(...)``; ``cond(J^-1)``, shape ``(...)``
        (``inf`` where ``J^-1`` is singular or not finite).
    """
    m = float_array(j_inv)
    if m.ndim < 2 or m.shape[-2:] != (3, 3):
        raise InvalidParameterError("J_inv.shape", m.shape, "an array of shape (..., 3, 3)")
    finite = np.asarray(np.isfinite(m).all(axis=(-2, -1)))
    safe = np.where(finite[..., np.newaxis, np.newaxis], m, 0.0)
    with np.errstate(all="ignore"):
        norms = np.linalg.norm(safe, axis=-1)
        cosines = np.where(norms > 0.0, 1.0 / norms, 0.0)
        cosines = np.where(finite[..., np.newaxis], cosines, 0.0)
        det = np.linalg.det(safe * cosines[..., np.newaxis])
        s = np.linalg.svd(safe, compute_uv=False)
        condition = np.where(finite & (s[..., -1] > 0.0), s[..., 0] / s[..., -1], np.inf)
    return cosines, np.asarray(det), np.asarray(condition)


def check_inverse_jacobian(
    j_inv: ArrayLike, points: ArrayLike, *, max_condition: float = MAX_CONDITION
) -> None:
    """Raise for the first singular or near-singular configuration.

    Args:
        j_inv: Inverse Jacobians, shape ``(3, 3)`` or ``(..., 3, 3)``.
        points: The tool points they belong to [m], shape ``(3,)`` or
            ``(..., 3)`` (named in the error).
        max_condition: Largest condition number accepted.

    Raises:
        SingularConfigurationError: ``kind="serial"`` (with the leg) when
            ``eta_i / L <= SERIAL_TOL``; ``kind="parallel"`` when
            ``|det(u_1, u_2, u_3)| < PARALLEL_TOL``; beyond ``max_condition``,
            the kind whose measure is the smaller.
    """
    max_condition = positive_number("max_condition", max_condition)
    cosines, det, condition = singularity_measures(j_inv)
    pts = points_array(points, "points").reshape(-1, 3)
    cos2, det1, cond1 = cosines.reshape(-1, 3), np.abs(det).reshape(-1), condition.reshape(-1)
    if pts.shape[0] not in (1, cos2.shape[0]):
        raise InvalidParameterError("points.shape", pts.shape, f"one point, or {cos2.shape[0]}")
    serial = np.asarray((cos2 <= SERIAL_TOL).any(axis=1))
    parallel = ~(det1 >= PARALLEL_TOL)
    near = ~(cond1 <= max_condition)
    bad = serial | parallel | near
    if not bad.any():
        return
    idx = first_index(bad)
    point = pts[idx if pts.shape[0] > 1 else 0]
    leg = int(np.argmin(cos2[idx])) + 1
    if serial[idx]:
        why = f"the leg is orthogonal to its slider (eta / L = {cos2[idx, leg - 1]:.3g})"
        raise SingularConfigurationError(point, leg, "serial", why)
    if parallel[idx]:
        why = f"coplanar legs (|det of unit leg directions| = {det1[idx]:.3g} < {PARALLEL_TOL:g})"
        raise SingularConfigurationError(point, None, "parallel", why)
    limit = f"condition number {cond1[idx]:.3g} > {max_condition:g}"
    if cos2[idx, leg - 1] < det1[idx]:
        why = f"near a serial singularity ({limit}, eta / L = {cos2[idx, leg - 1]:.3g})"
        raise SingularConfigurationError(point, leg, "serial", why)
    why = f"near a parallel singularity ({limit}, |det of unit leg directions| = {det1[idx]:.3g})"
    raise SingularConfigurationError(point, None, "parallel", why)
