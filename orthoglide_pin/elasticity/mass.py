"""The machine's masses for its vibration: beam mass matrices, the platform, the drives.

* :func:`beam_mass`: the consistent mass matrix of a uniform 3D beam element
  (Przemieniecki, *Theory of Matrix Structural Analysis*, 1968: cubic Hermite
  bending, linear traction and torsion, with the rotary inertia of the
  section), in world axes for a batch of elements, the same degrees of freedom
  as :func:`~orthoglide_pin.elasticity.members.beam_stiffness`. A rigid motion
  of the element gives exactly the kinetic energy of a uniform rod of that
  mass, length and section;
* :func:`member_masses`: the mass per length and section inertias of the bars
  and small links, from the description's masses (uniform members);
* :func:`platform_inertia`: the platform, spindle and tool as one rigid body,
  their 6x6 spatial inertia about the tool tip in world axes, from the
  description's inertials placed by Pinocchio;
* :func:`reflected_mass`: a drive's rotary inertia seen at its carriage,
  ``m_eq = J_motor_side (2 pi n / l)^2`` with ``J_motor_side = J_rotor +
  J_screw / n^2`` (``(J_rotor + J_screw) (2 pi / l)^2`` for a direct drive).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.dynamics.inertia import InertiaTable
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = [
    "MemberMass",
    "beam_mass",
    "member_masses",
    "platform_inertia",
    "reflected_mass",
    "spatial_inertia",
]


@dataclass(frozen=True)
class MemberMass:
    """Mass properties of a uniform member, per length.

    Attributes:
        mu: Mass per length [kg/m].
        polar: Mass moment of the section about the member's axis per length
            (``rho J``) [kg.m].
        bending: Mass moment of the section about a transverse axis per length
            (``rho I``, half of ``polar`` for a circular section) [kg.m].
    """

    mu: float
    polar: float
    bending: float


def _local_mass(length: float, m: MemberMass) -> FloatArray:
    """The 12x12 consistent mass matrix in the element's axes ``(x, y, z)``."""
    L = float(length)
    out = np.zeros((12, 12))
    mass = m.mu * L
    axial = mass / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    out[np.ix_([0, 6], [0, 6])] += axial
    out[np.ix_([3, 9], [3, 9])] += m.polar * L / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    trans = (
        mass
        / 420.0
        * np.array(
            [
                [156.0, 22.0 * L, 54.0, -13.0 * L],
                [22.0 * L, 4.0 * L**2, 13.0 * L, -3.0 * L**2],
                [54.0, 13.0 * L, 156.0, -22.0 * L],
                [-13.0 * L, -3.0 * L**2, -22.0 * L, 4.0 * L**2],
            ]
        )
    )
    rotary = (
        m.bending
        / (30.0 * L)
        * np.array(
            [
                [36.0, 3.0 * L, -36.0, 3.0 * L],
                [3.0 * L, 4.0 * L**2, -3.0 * L, -(L**2)],
                [-36.0, -3.0 * L, 36.0, -3.0 * L],
                [3.0 * L, -(L**2), -3.0 * L, 4.0 * L**2],
            ]
        )
    )
    bend = trans + rotary
    flip = np.diag([1.0, -1.0, 1.0, -1.0])  # the x-z plane: theta_y = -dw/dx
    out[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] += bend
    out[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] += flip @ bend @ flip
    return out


def beam_mass(
    x: FloatArray, y: FloatArray, z: FloatArray, length: float, member: MemberMass
) -> FloatArray:
    """Consistent mass matrices of a batch of equal beam elements, in world axes.

    Args:
        x: Unit axis of each element, from end ``a`` to end ``b``, shape (..., 3).
        y: Unit transverse vector, shape (..., 3).
        z: ``x`` cross ``y``, shape (..., 3).
        length: Element length [m].
        member: Mass per length and section inertias.

    Returns:
        Shape (..., 12, 12) [kg, kg.m, kg.m^2] for ``[t_a, r_a, t_b, r_b]``.
    """
    local = _local_mass(length, member)
    rot = np.stack([x, y, z], axis=-2)  # rows: the element's axes in world components
    t = np.zeros((*rot.shape[:-2], 12, 12))
    for k in range(4):
        t[..., 3 * k : 3 * k + 3, 3 * k : 3 * k + 3] = rot
    out: FloatArray = np.swapaxes(t, -1, -2) @ local @ t
    return out


def _kind_mass(table: InertiaTable, kind: str, what: str) -> float:
    masses = [b.mass for b in table.kind(kind)]
    if not masses:
        raise InvalidParameterError(what, None, f"a description with {kind} bodies")
    return float(np.mean(masses))


def member_masses(params: OrthoglideParams, table: InertiaTable) -> tuple[MemberMass, MemberMass]:
    """The bars' and the small links' mass per length, uniform along each member.

    Returns:
        ``(bar, link)``: the bar (a tube of ``bar_radius``, ``bar_wall``, length
        ``leg_length``) and the small link (solid, ``link_radius``, length
        ``parallelogram_width``), with the description's masses.
    """
    outer, inner = params.bar_radius, max(params.bar_radius - params.bar_wall, 0.0)
    mu_bar = _kind_mass(table, "bar", "bar_mass") / params.leg_length
    r2_bar = outer**2 + inner**2
    bar = MemberMass(mu_bar, mu_bar * r2_bar / 2.0, mu_bar * r2_bar / 4.0)
    mu_link = _kind_mass(table, "small_link", "link_mass") / params.parallelogram_width
    r2_link = params.link_radius**2
    link = MemberMass(mu_link, mu_link * r2_link / 2.0, mu_link * r2_link / 4.0)
    return bar, link


def _cross(r: FloatArray) -> FloatArray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def spatial_inertia(
    mass: float, com: FloatArray, inertia: FloatArray, point: FloatArray
) -> FloatArray:
    """6x6 mass matrix of a rigid body for the motion ``(v_point, omega)``, world axes.

    Args:
        mass: Mass [kg].
        com: Centre of mass [m], shape (3,).
        inertia: Inertia about the centre of mass [kg.m^2], shape (3, 3).
        point: The reference point [m], shape (3,).

    Returns:
        ``M`` with kinetic energy ``0.5 (v, w)^T M (v, w)``, shape (6, 6).
    """
    rx = _cross(np.asarray(com, dtype=float) - np.asarray(point, dtype=float))
    out = np.zeros((6, 6))
    out[:3, :3] = mass * np.eye(3)
    out[:3, 3:] = -mass * rx
    out[3:, :3] = mass * rx
    out[3:, 3:] = inertia - mass * rx @ rx
    return out


def platform_inertia(
    params: OrthoglideParams, table: InertiaTable, model: Any = None
) -> FloatArray:
    """Spatial inertia of the platform, spindle and tool about the tool tip, world axes.

    The platform only translates, so the matrix is the same at every point; it
    is computed at the cube's centre with Pinocchio's frame placements of the
    description's links (every body of kind ``platform`` or ``spindle``).

    Args:
        params: Machine parameters.
        table: The bodies' inertias (:func:`~orthoglide_pin.dynamics.inertia.inertia_table`).
        model: The machine's :class:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel`
            (built from ``params`` when ``None``).

    Returns:
        Shape (6, 6) for ``(v_tool [m/s], omega [rad/s])``.
    """
    import pinocchio as pin

    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    if model is None:
        model = ClosedLoopModel(params)
    centre = np.asarray(params.workspace.center, dtype=float)
    q = model.configuration(centre)
    pin.framesForwardKinematics(model.model, model.data, q)
    tool = np.array(model.data.oMf[model.tool_frame].translation)
    out = np.zeros((6, 6))
    for body in table.bodies:
        if body.kind not in ("platform", "spindle"):
            continue
        placement = model.data.oMf[model.model.getFrameId(body.link)]
        rot = np.array(placement.rotation)
        com = rot @ body.com + np.array(placement.translation)
        out += spatial_inertia(body.mass, com, rot @ body.inertia @ rot.T, tool)
    return out


def reflected_mass(drive: Drive | DriveTrain | None) -> float:
    """A drive's rotary inertia seen at its carriage [kg]; 0 without a drive.

    ``m_eq = (J_rotor + J_screw / n^2) (2 pi n / l)^2``: the rotor turns at
    ``2 pi n q' / l`` and the screw at ``2 pi q' / l`` for a carriage speed
    ``q'`` (lead ``l`` [m/rev], ``n`` motor turns per screw turn).

    Raises:
        InvalidParameterError: Not a drive, or a non-finite inertia.
    """
    if drive is None:
        return 0.0
    train = drive.train if isinstance(drive, Drive) else drive
    if not isinstance(train, DriveTrain):
        raise InvalidParameterError("drive", drive, "a Drive, a DriveTrain or None")
    ratio = 2.0 * math.pi * train.gear_ratio / train.lead
    value = train.reflected_inertia * ratio**2
    if not math.isfinite(value) or value < 0.0:
        raise InvalidParameterError(
            "drive inertia", value, "a finite, non-negative rotor and screw inertia"
        )
    return float(value)
