"""Closed-form motion of every joint of the cut tree: positions, velocities, accelerations.

Each leg ``i`` has three independent joint functions of the tool point
``P = (p_1, p_2, p_3)`` (design notes, section 2, and
:meth:`orthoglide_pin.machine.closed_loop.ClosedLoopModel.configuration`). With
``(x, y, z) = (p_i, p_(i+1), p_(i+2))`` the coordinates in the leg frame,
``eta = sqrt(L^2 - y^2 - z^2)`` and ``c = sqrt(L^2 - y^2)``:

* the slider ``q = x + L - eta`` [m];
* the leg's turn about ``y_l``, ``theta = atan2(-z, eta)`` [rad];
* the parallelogram's opening, ``phi = asin(y / L)`` [rad].

The six joints of a leg follow with fixed signs (:data:`LEG_JOINTS`): slider
``q``, base revolute ``theta``, bar a base ``phi``, bar a tip ``-phi``, end
revolute ``-theta``, bar b base ``phi``. Their time derivatives are exact:

* ``eta' = -(y y' + z z') / eta``,
  ``eta'' = -(y'^2 + z'^2 + y y'' + z z'' + eta'^2) / eta``;
* ``q' = x' - eta'``, ``q'' = x'' - eta''``;
* ``phi' = y' / c``, ``phi'' = (y'' + y phi'^2) / c``;
* ``theta' = (z eta' - eta z') / c^2``,
  ``theta'' = (z eta'' - eta z'') / c^2 + 2 y y' theta' / c^2``.

The gradients ``d(q, theta, phi)/dP`` (rows of ``Q' = dq/dP``) are the first
derivatives with ``P' = e_m``. Along a path ``P(s)`` the same formulas give the
derivatives in ``s`` with ``P' = dP/ds`` and ``P'' = d2P/ds2``
(:func:`path_motion`, laid out leg by leg for batch evaluation). Every function
is vectorised over ``N`` points and never loops in Python over points.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    MAX_ACCELERATION,
    MAX_LENGTH,
    MAX_SPEED,
    bounded_rows,
    points_array,
    positive_length,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import (
    direct_kinematics,
    etas,
    ik_and_jacobian,
    inverse_kinematics,
)

FloatArray = NDArray[np.float64]

#: World axes of the leg-frame coordinates ``(x, y, z)`` of leg ``i`` (row ``i``).
LEG_AXES: Final = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1]], dtype=np.intp)
#: The six joints of a leg: (name suffix, joint function, sign), functions being
#: 0 = slider ``q``, 1 = ``theta``, 2 = ``phi``.
LEG_JOINTS: Final = (
    ("slider", 0, 1.0),
    ("base_revolute", 1, 1.0),
    ("bar_a_base", 2, 1.0),
    ("bar_a_tip", 2, -1.0),
    ("end_revolute", 1, -1.0),
    ("bar_b_base", 2, 1.0),
)


#: Largest tangent entry ``dP/ds`` accepted [-] (unit vectors for the arc length).
MAX_TANGENT: Final[float] = 1e3
#: Largest curvature entry ``d2P/ds2`` accepted [1/m]: radii down to 1 nm (``MIN_LENGTH``).
MAX_CURVATURE: Final[float] = 1e9


@dataclass(frozen=True)
class LegMotion:
    """Joint functions of the three legs and their derivatives, at ``N`` points.

    Arrays have shape ``(N, 3, 3)``: point, leg, function (``q`` [m],
    ``theta`` [rad], ``phi`` [rad]).

    Attributes:
        values: The joint functions [m, rad].
        rates: Their time derivatives [m/s, rad/s].
        accelerations: Their second time derivatives [m/s^2, rad/s^2].
        gradients: ``d(function)/dP`` in world axes, shape ``(N, 3, 3, 3)``
            (point, leg, function, world axis) [1, rad/m].
    """

    values: FloatArray
    rates: FloatArray
    accelerations: FloatArray
    gradients: FloatArray


def _split(p: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Leg-frame coordinates ``(x, y, z)`` of ``p`` (N, 3), each ``(N, 3 legs)``."""
    return p[:, LEG_AXES[:, 0]], p[:, LEG_AXES[:, 1]], p[:, LEG_AXES[:, 2]]


def leg_motion(
    points: ArrayLike, velocities: ArrayLike, accelerations: ArrayLike, leg_length: float
) -> LegMotion:
    """Joint functions of every leg and their first two time derivatives.

    Args:
        points: Tool points ``P`` [m], shape ``(N, 3)``.
        velocities: Tool velocities ``P'`` [m/s], shape ``(N, 3)``.
        accelerations: Tool accelerations ``P''`` [m/s^2], shape ``(N, 3)``.
        leg_length: Leg length ``L`` [m].

    Returns:
        The motion of the joint functions (see :class:`LegMotion`).

    Raises:
        InvalidParameterError: Non-finite input or mismatched shapes.
        UnreachablePointError, SingularConfigurationError: As
            :func:`orthoglide_pin.kinematics.closed_form.inverse_kinematics`.
    """
    L = positive_length("leg_length", leg_length)
    p = _points(points, "points")
    pd = _points(velocities, "velocities", MAX_SPEED)
    pdd = _points(accelerations, "accelerations", MAX_ACCELERATION)
    if not p.shape == pd.shape == pdd.shape:
        shapes = (p.shape, pd.shape, pdd.shape)
        raise InvalidParameterError("shapes", shapes, "three arrays of the same shape (N, 3)")
    inverse_kinematics(p, L)  # raises for unreachable or serially singular points
    x, y, z = _split(p)
    xd, yd, zd = _split(pd)
    xdd, ydd, zdd = _split(pdd)
    c2 = L * L - y * y
    eta = np.sqrt(c2 - z * z)
    c = np.sqrt(c2)
    ed = -(y * yd + z * zd) / eta
    edd = -(yd * yd + zd * zd + y * ydd + z * zdd + ed * ed) / eta
    phd = yd / c
    thd = (z * ed - eta * zd) / c2
    values = np.stack([x + L - eta, np.arctan2(-z, eta), np.arcsin(y / L)], axis=-1)
    rates = np.stack([xd - ed, thd, phd], axis=-1)
    accel = np.stack(
        [
            xdd - edd,
            (z * edd - eta * zdd + 2.0 * y * yd * thd) / c2,
            (ydd + y * phd * phd) / c,
        ],
        axis=-1,
    )
    # Gradients in leg coordinates (x, y, z), then scattered to world axes.
    local = np.zeros((*x.shape, 3, 3))
    local[..., 0, 0] = 1.0
    local[..., 0, 1] = y / eta
    local[..., 0, 2] = z / eta
    local[..., 1, 1] = -y * z / (eta * c2)
    local[..., 1, 2] = -1.0 / eta
    local[..., 2, 1] = 1.0 / c
    grads = np.empty_like(local)
    for leg in range(3):
        grads[:, leg][..., LEG_AXES[leg]] = local[:, leg]
    return LegMotion(values, rates, accel, grads)


@dataclass(frozen=True)
class PathMotion:
    """Joint functions of the three legs along a path ``P(s)``, leg by leg.

    Arrays are laid out leg first and point last, so that each leg's terms are
    contiguous rows of ``N`` numbers; functions are ``(q, theta, phi)``.

    Attributes:
        slider: Slider values ``q`` [m], shape (3, N).
        cos_theta: ``cos theta = eta / c``, shape (3, N); likewise ``sin_theta``
            (``-z / c``), ``cos_phi`` (``c / L``) and ``sin_phi`` (``y / L``).
        first: ``d(q, theta, phi)/ds`` [1, rad/m], shape (3 legs, 3, N).
        second: ``d2(q, theta, phi)/ds2`` [1/m, rad/m^2], shape (3 legs, 3, N).
        theta_gradient: ``d theta/dP`` along the leg's ``(y, z)`` axes [rad/m],
            shape (3 legs, 2, N) (none along ``x``).
        phi_gradient: ``d phi/dP`` along the leg's ``y`` axis [rad/m], shape
            (3, N) (the only one).
    """

    slider: FloatArray
    cos_theta: FloatArray
    sin_theta: FloatArray
    cos_phi: FloatArray
    sin_phi: FloatArray
    first: FloatArray
    second: FloatArray
    theta_gradient: FloatArray
    phi_gradient: FloatArray


def path_motion(
    points: ArrayLike, tangents: ArrayLike, curvatures: ArrayLike, leg_length: float
) -> PathMotion:
    """Joint functions along a path and their first two derivatives in ``s``.

    The formulas of the module with ``P' = dP/ds`` and ``P'' = d2P/ds2``: the
    same numbers as :func:`leg_motion` (which reads them as time derivatives),
    in the layout of :class:`PathMotion`.

    Args:
        points: Path points ``P(s)`` [m], shape (N, 3) or (3,).
        tangents: ``dP/ds`` [-], same shape, entries within ``+-MAX_TANGENT``.
        curvatures: ``d2P/ds2`` [1/m], same shape, within ``+-MAX_CURVATURE``.
        leg_length: Leg length ``L`` [m].

    Returns:
        The joint functions and their derivatives, leg by leg.

    Raises:
        InvalidParameterError: Non-finite or out-of-range input, mismatched shapes.
        UnreachablePointError, SingularConfigurationError: As
            :func:`orthoglide_pin.kinematics.closed_form.inverse_kinematics`.
    """
    L = positive_length("leg_length", leg_length)
    p = bounded_rows("points", points, 3, MAX_LENGTH, "[m]")
    pd = bounded_rows("tangents", tangents, 3, MAX_TANGENT, "[-]")
    pdd = bounded_rows("curvatures", curvatures, 3, MAX_CURVATURE, "[1/m]")
    if not p.shape == pd.shape == pdd.shape:
        shapes = (p.shape, pd.shape, pdd.shape)
        raise InvalidParameterError("shapes", shapes, "three arrays of the same shape (N, 3)")
    eta = etas(p, L, serial=True).T  # raises for unreachable or serially singular points
    x, y, z = (p.T[LEG_AXES[:, a]] for a in range(3))  # leg coordinates, rows (3, N)
    xd, yd, zd = (pd.T[LEG_AXES[:, a]] for a in range(3))
    xdd, ydd, zdd = (pdd.T[LEG_AXES[:, a]] for a in range(3))
    c2 = L * L - y * y
    c = np.sqrt(c2)
    ed = -(y * yd + z * zd) / eta
    edd = -(yd * yd + zd * zd + y * ydd + z * zdd + ed * ed) / eta
    phd = yd / c
    thd = (z * ed - eta * zd) / c2
    n = p.shape[0]
    first, second, grad = np.empty((3, 3, n)), np.empty((3, 3, n)), np.empty((3, 2, n))
    first[:, 0], first[:, 1], first[:, 2] = xd - ed, thd, phd
    second[:, 0] = xdd - edd
    second[:, 1] = (z * edd - eta * zdd + 2.0 * y * yd * thd) / c2
    second[:, 2] = (ydd + y * phd * phd) / c
    grad[:, 0], grad[:, 1] = -y * z / (eta * c2), -1.0 / eta
    return PathMotion(
        slider=x + L - eta,
        cos_theta=eta / c,
        sin_theta=-z / c,
        cos_phi=c / L,
        sin_phi=y / L,
        first=first,
        second=second,
        theta_gradient=grad,
        phi_gradient=1.0 / c,
    )


def _points(values: ArrayLike, name: str, limit: float = MAX_LENGTH) -> FloatArray:
    """A finite float array of shape ``(N, 3)``, entries within ``+-limit``."""
    arr = points_array(values, name, limit=limit)
    if arr.ndim != 2:
        raise InvalidParameterError(f"{name}.shape", arr.shape, "an array of shape (N, 3)")
    return arr


def scatter(functions: FloatArray, leg_indices: NDArray[np.intp]) -> FloatArray:
    """Spread joint functions ``(N, 3, 3)`` onto the joints of the cut tree.

    Args:
        functions: Per point, leg and function (``q``, ``theta``, ``phi``).
        leg_indices: Velocity index of each joint of :data:`LEG_JOINTS`, per leg,
            shape ``(3, 6)``.

    Returns:
        Joint values, shape ``(N, 3 * 6)`` in the tree's velocity order.
    """
    out = np.empty((functions.shape[0], leg_indices.size))
    for slot, (_, fn, sign) in enumerate(LEG_JOINTS):
        out[:, leg_indices[:, slot]] = sign * functions[:, :, fn]
    return out


def gather(torques: FloatArray, leg_indices: NDArray[np.intp]) -> FloatArray:
    """Transpose of :func:`scatter`: joint torques ``(N, 18)`` to per-function ``(N, 3, 3)``."""
    out = np.zeros((torques.shape[0], 3, 3))
    for slot, (_, fn, sign) in enumerate(LEG_JOINTS):
        out[:, :, fn] += sign * torques[:, leg_indices[:, slot]]
    return out


def tool_motion_from_sliders(
    q: ArrayLike, q_dot: ArrayLike, q_ddot: ArrayLike, leg_length: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tool motion of a slider motion (working assembly mode).

    ``P = FK(q)``, ``P' = J q'`` and, from ``J^-1 P' = q'``,
    ``P'' = J (q'' - (d J^-1/dt) P')`` with ``(J^-1)_ii = 1`` and
    ``(J^-1)_ij = p_j / eta_i``, so ``d(J^-1)_ij/dt = p_j' / eta_i - p_j eta_i' / eta_i^2``.

    Args:
        q: Slider values [m], shape ``(N, 3)``.
        q_dot: Slider velocities [m/s], shape ``(N, 3)``.
        q_ddot: Slider accelerations [m/s^2], shape ``(N, 3)``.
        leg_length: Leg length ``L`` [m].

    Returns:
        ``(p, p_dot, p_ddot)`` [m, m/s, m/s^2], each ``(N, 3)``.

    Raises:
        InvalidParameterError: Non-finite input or mismatched shapes.
        NoAssemblyError: Slider values without assembly.
        SingularConfigurationError: A parallel singularity on the way.
    """
    L = positive_length("leg_length", leg_length)
    qa = _points(q, "q")
    qd, qdd = _points(q_dot, "q_dot", MAX_SPEED), _points(q_ddot, "q_ddot", MAX_ACCELERATION)
    if not qa.shape == qd.shape == qdd.shape:
        shapes = (qa.shape, qd.shape, qdd.shape)
        raise InvalidParameterError("shapes", shapes, "three arrays of the same shape (N, 3)")
    p = direct_kinematics(qa, L)
    _, J = ik_and_jacobian(p, L)
    pd = np.einsum("nij,nj->ni", J, qd)
    _, y, z = _split(p)
    _, yd, zd = _split(pd)
    eta = np.sqrt(L * L - y * y - z * z)
    ed = -(y * yd + z * zd) / eta
    # (dJ^-1/dt P')_i = sum_{j != i} (p_j' / eta_i - p_j eta_i' / eta_i^2) p_j'
    corr = (yd * yd + zd * zd) / eta - (y * yd + z * zd) * ed / (eta * eta)
    pdd = np.einsum("nij,nj->ni", J, qdd - corr)
    return p, pd, pdd
