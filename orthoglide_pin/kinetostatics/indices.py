"""Kinetostatic performance indices of the Orthoglide (paper, section 3.1).

Vectorised over any ``(..., 3)`` array of tool points [m] (closed form), or
taken from any Jacobian, such as the Pinocchio closed-loop one
(:func:`indices_from_model`):

* velocity transmission factors ``sigma_1 <= sigma_2 <= sigma_3``: the singular
  values of ``J`` (``p_dot = J q_dot``), all 1 at home
  (:func:`transmission_factors`, see :mod:`orthoglide_pin.kinetostatics.transmission`);
* condition number ``sigma_3 / sigma_1 >= 1`` and its inverse in ``(0, 1]``;
* manipulability ``det J`` (positive on the working assembly mode, equal there
  to ``sigma_1 sigma_2 sigma_3``);
* the velocity manipulability ellipsoid ``{J q_dot : |q_dot| <= 1}``: semi-axes
  ``sigma_k`` along the left singular vectors of ``J``; the force ellipsoid
  ``{f : |J^T f| <= 1}`` of the tool forces balanced by unit actuator forces
  (``tau = J^T f``): the same directions, semi-axes ``1 / sigma_k``. Directions
  are the columns of a rotation (orthonormal, ``det = +1``), column ``k``
  along semi-axis ``k``;
* the isotropy conditions of the paper, eqs. (3)-(5), as residuals.

All indices are dimensionless ([m/s] of tool per [m/s] of slider, or [N] per
[N]); the ellipsoid axes are [m/s] per unit slider speed and [N] per unit
actuator force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    finite_vector,
    flag,
    float_array,
    points_array,
    positive_length,
    positive_limit,
)
from orthoglide_pin.exceptions import InvalidParameterError, SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import (
    PARALLEL_TOL,
    etas,
    inverse_jacobian,
    jacobian,
    legs_from_etas,
    radicands,
    unit_leg_determinant,
)
from orthoglide_pin.kinematics.singularity import MAX_CONDITION, check_inverse_jacobian
from orthoglide_pin.kinetostatics.transmission import transmission_factors
from orthoglide_pin.machine.limits import check_slider_values

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = [
    "IsotropyResiduals",
    "KinetostaticIndices",
    "condition_number",
    "force_ellipsoid",
    "indices_from_jacobian",
    "indices_from_model",
    "inverse_condition",
    "isotropy_residuals",
    "kinetostatic_indices",
    "manipulability",
    "transmission_factors",
    "velocity_ellipsoid",
]


def condition_number(points: ArrayLike, leg_length: float, *, check: bool = True) -> FloatArray:
    """Condition number of ``J``: ``sigma_3 / sigma_1 >= 1`` (1 at home), shape ``(...)``.

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        check: As :func:`transmission_factors`.

    Raises:
        UnreachablePointError, SingularConfigurationError: As
            :func:`transmission_factors`.
    """
    s = transmission_factors(points, leg_length, check=check)
    return np.asarray(s[..., 2] / s[..., 0])


def inverse_condition(points: ArrayLike, leg_length: float, *, check: bool = True) -> FloatArray:
    """Inverse condition number ``sigma_1 / sigma_3`` in ``(0, 1]``, shape ``(...)``.

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        check: As :func:`transmission_factors`.
    """
    s = transmission_factors(points, leg_length, check=check)
    return np.asarray(s[..., 0] / s[..., 2])


def manipulability(points: ArrayLike, leg_length: float, *, check: bool = True) -> FloatArray:
    """Manipulability ``det J = eta_1 eta_2 eta_3 / det(u_1, u_2, u_3)``, shape ``(...)``.

    Positive on the working assembly mode, 1 at home, 0 at a serial
    singularity and unbounded towards a parallel one.

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        check: If True, raise for unreachable and parallel-singular points;
            if False, those give NaN and ``inf`` respectively.

    Raises:
        UnreachablePointError: First point out of reach (``check``).
        SingularConfigurationError: First point with
            ``|det(u_1, u_2, u_3)| / L^3 < PARALLEL_TOL`` (``check``).
    """
    p, L = (
        points_array(points, "points"),
        positive_length("leg_length", leg_length),
    )
    check = flag("check", check)
    with np.errstate(all="ignore"):
        eta = etas(p, L, serial=False) if check else np.sqrt(radicands(p, L))
        det = unit_leg_determinant(p, eta, L)
        if check:
            _check_parallel(p, det)
        return np.asarray(np.prod(eta, axis=-1) / (det * L**3))


def _check_parallel(p: FloatArray, det: FloatArray) -> None:
    """Raise for the first point whose ``|det(unit leg directions)|`` is below tolerance."""
    bad = ~(np.abs(det) >= PARALLEL_TOL)
    if bad.any():
        idx = int(np.argmax(bad.reshape(-1)))
        value = float(det.reshape(-1)[idx])
        why = f"coplanar legs (|det of unit leg directions| = {abs(value):.3g} < {PARALLEL_TOL:g})"
        raise SingularConfigurationError(p.reshape(-1, 3)[idx], None, "parallel", why)


def _rotation_columns(vectors: FloatArray) -> FloatArray:
    """Flip column 0 where needed so that every ``(..., 3, 3)`` basis has ``det = +1``."""
    sign = np.sign(np.linalg.det(vectors))
    out: FloatArray = np.array(vectors, dtype=np.float64)
    out[..., :, 0] *= np.where(sign < 0.0, -1.0, 1.0)[..., np.newaxis]
    return out


def velocity_ellipsoid(points: ArrayLike, leg_length: float) -> tuple[FloatArray, FloatArray]:
    """Velocity manipulability ellipsoid ``{J q_dot : |q_dot| <= 1}``.

    Semi-axes are the transmission factors (closed form); directions are the
    eigenvectors of ``J J^T`` (LAPACK ``eigh``), i.e. the left singular vectors
    of ``J``. Where factors coincide (home, the main diagonal) any orthonormal
    basis of their eigenspace is returned.

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].

    Returns:
        ``(axes, directions)``: semi-axes [m/s per m/s], ascending, shape
        ``(..., 3)``, and rotations, shape ``(..., 3, 3)`` whose column ``k``
        is the direction of ``axes[..., k]``.

    Raises:
        UnreachablePointError, SingularConfigurationError: As
            :func:`transmission_factors`.
    """
    axes = transmission_factors(points, leg_length)
    J = jacobian(points, leg_length)
    _, vectors = np.linalg.eigh(J @ np.swapaxes(J, -1, -2))
    return axes, _rotation_columns(vectors)


def force_ellipsoid(points: ArrayLike, leg_length: float) -> tuple[FloatArray, FloatArray]:
    """Force ellipsoid: tool forces ``f`` balanced by unit actuator forces, ``|J^T f| <= 1``.

    The directions of :func:`velocity_ellipsoid`, semi-axes ``1 / sigma_k``
    (so in descending order).

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].

    Returns:
        ``(axes, directions)``: semi-axes [N per N], shape ``(..., 3)``, and
        rotations, shape ``(..., 3, 3)``, column ``k`` along ``axes[..., k]``.
    """
    axes, directions = velocity_ellipsoid(points, leg_length)
    return 1.0 / axes, directions


@dataclass(frozen=True)
class IsotropyResiduals:
    """Residuals of the isotropy conditions of the paper, eqs. (3)-(5).

    With ``k_i = |c_i - b_i| / eta_i = L / eta_i``, all zero exactly where
    ``J^-1 = I`` (the isotropic configuration).

    Attributes:
        eq3: ``(k_1 - k_2, k_2 - k_3, k_3 - k_1)``: equal leg-to-slider angles,
            shape ``(..., 3)``.
        eq4: ``(u_1.u_2, u_2.u_3, u_3.u_1) / L^2``: the cosines between legs
            (orthogonal parallelograms), shape ``(..., 3)``.
        eq5: ``(k_1 - 1, k_2 - 1, k_3 - 1)``: legs along their sliders (factors
            of 1), shape ``(..., 3)``.
    """

    eq3: FloatArray
    eq4: FloatArray
    eq5: FloatArray

    @property
    def max(self) -> FloatArray:
        """Largest absolute residual of the three equations, shape ``(...)``."""
        stacked = np.concatenate([self.eq3, self.eq4, self.eq5], axis=-1)
        return np.asarray(np.max(np.abs(stacked), axis=-1))


def isotropy_residuals(points: ArrayLike, leg_length: float) -> IsotropyResiduals:
    """Residuals of the paper's isotropy conditions (3)-(5) at tool points.

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].

    Raises:
        UnreachablePointError, SingularConfigurationError: A point out of reach
            or serially singular (``k_i`` undefined).
    """
    p, L = (
        points_array(points, "points"),
        positive_length("leg_length", leg_length),
    )
    eta = etas(p, L, serial=True)
    legs = legs_from_etas(p, eta)
    k = L / eta
    nxt = np.roll(np.arange(3), -1)
    cosines = np.einsum("...ij,...ij->...i", legs, legs[..., nxt, :]) / L**2
    return IsotropyResiduals(eq3=k - k[..., nxt], eq4=cosines, eq5=k - 1.0)


@dataclass(frozen=True)
class KinetostaticIndices:
    """The kinetostatic indices of one or many configurations.

    Attributes:
        transmission_factors: ``sigma_1 <= sigma_2 <= sigma_3``, shape ``(..., 3)``.
        condition: ``sigma_3 / sigma_1``, shape ``(...)``.
        inverse_condition: ``sigma_1 / sigma_3``, shape ``(...)``.
        manipulability: ``det J``, shape ``(...)``.
        velocity_axes: Velocity ellipsoid semi-axes (the factors), ``(..., 3)``.
        velocity_directions: Their directions (rotation columns), ``(..., 3, 3)``.
        force_axes: Force ellipsoid semi-axes ``1 / sigma_k``, ``(..., 3)``.
        force_directions: Their directions (the velocity ones), ``(..., 3, 3)``.
    """

    transmission_factors: FloatArray
    condition: FloatArray
    inverse_condition: FloatArray
    manipulability: FloatArray
    velocity_axes: FloatArray
    velocity_directions: FloatArray
    force_axes: FloatArray
    force_directions: FloatArray

    @classmethod
    def from_parts(
        cls, factors: FloatArray, det: FloatArray, directions: FloatArray
    ) -> KinetostaticIndices:
        """Assemble from the ascending factors, ``det J`` and the ellipsoid directions.

        Args:
            factors: Transmission factors, ascending and positive, shape (..., 3).
            det: ``det J``, shape (...).
            directions: Unit directions of the ellipsoid axes as columns, (..., 3, 3).

        Raises:
            InvalidParameterError: Naming the argument of another shape, or
                with non-finite (or non-positive factors) entries.
        """
        factors, det = float_array(factors), float_array(det)
        directions = float_array(directions)
        if factors.ndim == 0 or factors.shape[-1] != 3 or not (factors > 0.0).all():
            raise InvalidParameterError("factors", factors, "positive numbers, shape (..., 3)")
        if not np.isfinite(factors).all():
            raise InvalidParameterError("factors", factors, "finite numbers, shape (..., 3)")
        if det.shape != factors.shape[:-1] or not np.isfinite(det).all():
            raise InvalidParameterError("det", det, f"finite numbers, shape {factors.shape[:-1]}")
        if directions.shape != (*factors.shape, 3) or not np.isfinite(directions).all():
            allowed = f"finite numbers, shape {(*factors.shape, 3)}"
            raise InvalidParameterError("directions", directions, allowed)
        return cls(
            transmission_factors=factors,
            condition=np.asarray(factors[..., 2] / factors[..., 0]),
            inverse_condition=np.asarray(factors[..., 0] / factors[..., 2]),
            manipulability=np.asarray(det),
            velocity_axes=factors,
            velocity_directions=directions,
            force_axes=1.0 / factors,
            force_directions=directions,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready nested lists; each ellipsoid as its list of axes.

        An ellipsoid is ``{"axes": [{"semi_axis": a, "direction": [x, y, z]}, ...]}``,
        three axes in the order of the factors (one such list per point for
        several points): ``axes[k]["direction"]`` is the unit direction of the
        semi-axis ``axes[k]["semi_axis"]``.
        """
        return {
            "transmission_factors": self.transmission_factors.tolist(),
            "condition": self.condition.tolist(),
            "inverse_condition": self.inverse_condition.tolist(),
            "manipulability": self.manipulability.tolist(),
            "velocity_ellipsoid": {
                "axes": _axes_list(self.velocity_axes, self.velocity_directions)
            },
            "force_ellipsoid": {"axes": _axes_list(self.force_axes, self.force_directions)},
        }


def _axes_list(lengths: FloatArray, directions: FloatArray) -> list[Any]:
    """Semi-axes (..., 3) and direction columns (..., 3, 3) as lists of axes (see to_dict)."""
    if lengths.ndim == 1:
        return [
            {"semi_axis": float(lengths[k]), "direction": directions[:, k].tolist()}
            for k in range(lengths.shape[0])
        ]
    return [_axes_list(a, d) for a, d in zip(lengths, directions, strict=True)]


def kinetostatic_indices(
    points: ArrayLike, leg_length: float, *, max_condition: float = MAX_CONDITION
) -> KinetostaticIndices:
    """Every index at tool points, in closed form.

    The points are first judged as the Pinocchio route judges its
    configurations (:func:`indices_from_model`): same thresholds, same errors
    (:func:`orthoglide_pin.kinematics.singularity.check_inverse_jacobian`).

    Args:
        points: Tool points [m], shape ``(3,)`` or ``(..., 3)``.
        leg_length: Leg length ``L`` [m].
        max_condition: Largest condition number of ``J`` accepted.

    Raises:
        UnreachablePointError: A point out of reach.
        SingularConfigurationError: A serial or parallel singularity, or a
            condition number beyond ``max_condition``.
    """
    check_inverse_jacobian(
        inverse_jacobian(points, leg_length), points, max_condition=max_condition
    )
    axes, directions = velocity_ellipsoid(points, leg_length)
    return KinetostaticIndices.from_parts(axes, manipulability(points, leg_length), directions)


def indices_from_jacobian(
    J: ArrayLike, *, max_condition: float = MAX_CONDITION
) -> KinetostaticIndices:
    """Every index from Jacobians ``J`` (``p_dot = J q_dot``), by LAPACK's SVD.

    Args:
        J: Jacobians, shape ``(3, 3)`` or ``(..., 3, 3)``, finite.
        max_condition: Largest condition number accepted (a singular ``J``,
            zero included, has an infinite one).

    Raises:
        InvalidParameterError: ``J`` not finite, of the wrong shape, or
            conditioned beyond ``max_condition``.
    """
    try:
        j = np.asarray(J, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidParameterError("J", J, "an array of shape (..., 3, 3)") from None
    if j.ndim < 2 or j.shape[-2:] != (3, 3) or not np.isfinite(j).all():
        raise InvalidParameterError("J", j.shape, "finite numbers, shape (..., 3, 3)")
    max_condition = positive_limit("max_condition", max_condition)
    u, s, _ = np.linalg.svd(j)
    with np.errstate(divide="ignore", invalid="ignore"):
        condition = np.where(s[..., -1] > 0.0, s[..., 0] / s[..., -1], np.inf)
    if not (condition <= max_condition).all():
        worst = float(np.max(condition))
        raise InvalidParameterError(
            "J",
            f"condition number {worst:.3g}",
            f"a Jacobian of condition number at most {max_condition:g} "
            "(J is singular or near-singular)",
        )
    factors = np.ascontiguousarray(s[..., ::-1])
    return KinetostaticIndices.from_parts(
        factors, np.linalg.det(j), _rotation_columns(u[..., :, ::-1])
    )


def indices_from_model(
    model: ClosedLoopModel | OrthoglideParams | None,
    q: ArrayLike,
    *,
    max_condition: float = MAX_CONDITION,
    check_limits: bool = True,
) -> KinetostaticIndices:
    """Every index from the Pinocchio closed-loop Jacobian of one configuration.

    Args:
        model: The closed-loop model, or the parameters to build it from
            (``None``: the prototype's).
        q: An assembled configuration of all joints [m, rad], shape ``(nv,)``
            (see :meth:`ClosedLoopModel.solve` or
            :meth:`ClosedLoopModel.configuration`).
        max_condition: Largest condition number of ``J`` accepted.
        check_limits: Refuse a configuration whose sliders are beyond the
            machine's slider limits, as ``orthoglide fk`` does (``False``:
            compute there anyway); a singular configuration is said first.

    Raises:
        InvalidParameterError: A bad model or configuration, or a slider
            beyond its limits (``q1``, ``q2``, ``q3``).
        SingularConfigurationError: As :meth:`ClosedLoopModel.jacobian`: the
            closed form's thresholds, read from the projected ``J^-1``.
    """
    from orthoglide_pin.machine.closed_loop import as_model

    cl = as_model(model, "model")
    config = finite_vector("q", q, cl.nv, "[m, rad]")
    check = flag("check_limits", check_limits)
    jac = cl.jacobian(config, max_condition=max_condition)  # singular points first
    if check:
        check_slider_values(cl.params, config[cl.actuated])
    return indices_from_jacobian(jac, max_condition=math.inf)
