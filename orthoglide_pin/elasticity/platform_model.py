"""The platform vibration model: the platform, the carriages and the bars' first bending.

Degrees of freedom: the tool tip's translation and the platform's rotation
(six), each carriage's travel ``s_i`` along its rail (three), and, for each
leg, the amplitude of its two bars' first bending mode in the parallelogram's
plane, both bars bending together (three): the component modes of a
Craig-Bampton reduction. (The bars bending in opposition couple with the
platform's rotation only, which the legs hold stiffly; leaving them out keeps
the eigenproblem at 12 x 12 and moves the three lowest modes by at most 0.01 %
over the cube.) The stiffness is that of
:mod:`~orthoglide_pin.elasticity.stiffness`: each leg's members statically
condensed onto its carriage travel and the platform (the bar ends and the two
revolute turns of the leg are condensed out), in parallel, plus the actuator
spring ``actuator_stiffness`` between each carriage and the frame; and each
bar's bending, pinned-pinned between its revolutes (``sin(pi x / L)``, of
modal stiffness ``EI (pi / L)^4 L / 2``). The masses, constant for a point and
independent of every stiffness:

* the platform, spindle and tool: their spatial inertia about the tool tip
  (:func:`~orthoglide_pin.elasticity.mass.platform_inertia`);
* each carriage, with the drive's reflected inertia ``m_eq``, on ``s_i``;
* the small link on the carriage moves with the carriage (its ends lie on the
  revolute's axis, so the revolute's turn does not move them); the small link
  on the platform moves with the platform, a rigid rod about ``D``;
* each bar: a velocity linear along it between its lower end (moving with the
  carriage) and its upper end (moving with the platform), ``T = m/6 (v0^2 +
  v0.v1 + v1^2)`` (the consistent mass of a two-node rod), plus its bending:
  modal mass ``m/2``, coupled to the ends' velocities across the bar by
  ``m/pi``, per bar.

The masses being fixed, the frequencies obey Rayleigh's bounds: scaling every
stiffness by ``k`` scales every frequency by ``sqrt(k)``; stiffening any part
(the actuators) raises no frequency, and by at most ``sqrt(k)``; adding mass
lowers none. The model leaves out the bars bending in opposition, out of their
plane and beyond the first mode, and the small links' bending, which the full model
(:mod:`~orthoglide_pin.elasticity.frame_modes`) has.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.elasticity.mass import MemberMass
from orthoglide_pin.elasticity.members import (
    Section,
    bar_section,
    link_section,
    member_nodes,
    transfer_matrix,
)
from orthoglide_pin.elasticity.stiffness import BLOCK, _Leg, _raise_singular
from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = ["SIZE", "platform_matrices", "platform_modes"]

#: Degrees of freedom: the platform's six motions at the tool tip, the three
#: carriages, and the first in-plane bending mode of each leg's bars (together).
SIZE: Final[int] = 12
_PLATFORM = slice(0, 6)
_BARS: Final = (("A0", "A1"), ("B0", "B1"))


def _rod(mass: float, length: float, member: MemberMass, axis: FloatArray) -> FloatArray:
    """6x6 inertia about the centre of a uniform rod of unit ``axis`` (n, 3), shape (n, 6, 6)."""
    n = axis.shape[0]
    out = np.zeros((n, 6, 6))
    out[:, :3, :3] = mass * np.eye(3)
    along = axis[:, :, np.newaxis] * axis[:, np.newaxis, :]
    transverse = mass * length**2 / 12.0 + member.bending * length
    out[:, 3:, 3:] = transverse * (np.eye(3) - along) + member.polar * length * along
    return out


def _stiffness(
    p: FloatArray, params: OrthoglideParams, legs: list[_Leg], bar: Section
) -> FloatArray:
    """``K`` (n, 12, 12): the legs condensed onto the platform and carriages; actuators; bars."""
    nodes = member_nodes(p, params)
    u, normal = nodes["A1"] - nodes["A0"], nodes["normal"]
    out = np.zeros((p.shape[0], SIZE, SIZE))
    keep, turns = [0, *range(3, 9)], slice(1, 3)
    for i, leg in enumerate(legs):
        tail = leg.tail(u[:, i], normal[:, i], bar)  # (s, phi_C, phi_D, platform at D)
        k_km = tail[:, turns][:, :, keep]
        k7 = tail[:, keep][:, :, keep] - np.swapaxes(k_km, 1, 2) @ np.linalg.solve(
            tail[:, turns, turns], k_km
        )
        x = leg.transfer  # the platform's motion at D from its motion at the tool
        s = 6 + i
        out[:, _PLATFORM, _PLATFORM] += x.T @ k7[:, 1:, 1:] @ x
        coupling = k7[:, 0, 1:] @ x
        out[:, s, _PLATFORM] = coupling
        out[:, _PLATFORM, s] = coupling
        out[:, s, s] = k7[:, 0, 0] + params.actuator_stiffness
        length = np.linalg.norm(u[:, i], axis=1)
        # pinned-pinned, two bars: 2 EI (pi / L)^4 L / 2 for sin(pi x / L)
        out[:, 9 + i, 9 + i] = bar.EI * np.pi**4 / length**3
    return out


def _masses(
    p: FloatArray,
    params: OrthoglideParams,
    masses: tuple[MemberMass, MemberMass],
    platform: FloatArray,
    carriage: float,
) -> list[FloatArray]:
    """The mass matrices (n, 12, 12) of the platform, the carriages and the members.

    The platform only translates: every point it carries keeps its offset from
    the tool tip, so its share of the links' and bars' mass is one matrix.
    """
    n = p.shape[0]
    bar, link = masses
    m_bar, m_link = bar.mu * params.leg_length, link.mu * params.parallelogram_width
    nodes = member_nodes(p, params)
    plat = np.zeros((n, SIZE, SIZE))
    plat[:, _PLATFORM, _PLATFORM] = platform
    carriages = np.zeros((n, SIZE, SIZE))
    members = np.zeros((n, SIZE, SIZE))
    held = np.zeros((6, 6))  # the platform's links and the bars' upper ends
    for i in range(3):
        s = 6 + i
        carriages[:, s, s] = carriage
        members[:, s, s] = m_link + 2.0 * m_bar / 3.0
        x_link = transfer_matrix(nodes["D"][0, i] - p[0])  # platform link, about D
        rod = _rod(m_link, params.parallelogram_width, link, nodes["axis"][:1, i])[0]
        held += x_link.T @ rod @ x_link
        for low, end in _BARS:
            g = transfer_matrix(nodes[end][0, i] - p[0])[:3, :]  # the upper end's velocity
            held += m_bar / 3.0 * g.T @ g
            members[:, s, _PLATFORM] += m_bar / 6.0 * g[i, :]
            members[:, _PLATFORM, s] += m_bar / 6.0 * g[i, :]
            # the bar's bending sin(pi x / L) across it, in its plane: modal mass
            # m/2, and m/pi times the ends' velocities across the bar
            across = np.cross(nodes["normal"][:, i], nodes[end][:, i] - nodes[low][:, i])
            across *= m_bar / math.pi / np.linalg.norm(across, axis=1, keepdims=True)
            b = 9 + i
            members[:, b, b] += m_bar / 2.0
            members[:, b, s] += across[:, i]
            members[:, s, b] += across[:, i]
            members[:, b, _PLATFORM] += across @ g
            members[:, _PLATFORM, b] += across @ g
    members[:, _PLATFORM, _PLATFORM] += held
    return [plat, carriages, members]


def platform_matrices(
    p: FloatArray,
    params: OrthoglideParams,
    masses: tuple[MemberMass, MemberMass],
    platform: FloatArray,
    carriage: float,
    *,
    block: int = BLOCK,
) -> tuple[FloatArray, list[FloatArray]]:
    """Stiffness and mass matrices of the platform model at tool points.

    Args:
        p: Tool points [m], shape (n, 3).
        params: Machine parameters (sections, moduli, actuator stiffness).
        masses: The bars' and small links' mass per length
            (:func:`~orthoglide_pin.elasticity.mass.member_masses`).
        platform: The platform's spatial inertia about the tool tip, (6, 6).
        carriage: Mass moving with each carriage [kg] (with the drive's ``m_eq``).
        block: Points per block of the computation.

    Returns:
        ``K`` (n, 12, 12) [N/m, N, N.m/rad] and the mass matrices of the
        platform, the carriages and the members (n, 12, 12) [kg, kg.m,
        kg.m^2], for ``(tool translation, platform rotation, s_1, s_2, s_3,
        the bending of leg 1, 2, 3's bars)`` (the deflection of the middle of
        both bars of the leg [m]).

    Raises:
        SingularConfigurationError: The structure is a mechanism at a point.
    """
    bar = bar_section(
        params.bar_radius, params.bar_wall, params.youngs_modulus, params.shear_modulus
    )
    link = link_section(params.link_radius, params.youngs_modulus, params.shear_modulus)
    legs = [_Leg(i, params, link) for i in range(3)]
    k = np.empty((p.shape[0], SIZE, SIZE))
    for start in range(0, p.shape[0], block):
        chunk = p[start : start + block]
        try:
            k[start : start + block] = _stiffness(chunk, params, legs, bar)
        except np.linalg.LinAlgError:
            _raise_singular(chunk, params, params.actuator_stiffness, legs, bar)
    return k, _masses(p, params, masses, platform, carriage)


def platform_modes(
    k: FloatArray, parts: list[FloatArray], p: FloatArray, count: int
) -> tuple[FloatArray, FloatArray]:
    """The lowest ``omega^2`` [rad^2/s^2] (n, count) and mass-normalised modes (n, 12, count).

    Raises:
        SingularConfigurationError: A zero (or negative) frequency at a point.
    """
    mass = parts[0] + parts[1] + parts[2]
    low = np.linalg.cholesky(mass)
    li = np.linalg.inv(low)
    w2, y = np.linalg.eigh(li @ k @ np.swapaxes(li, 1, 2))
    if np.any(w2[:, 0] <= 0.0):
        bad = int(np.argmax(w2[:, 0] <= 0.0))
        raise SingularConfigurationError(p[bad], None, "structural", "a zero frequency there")
    phi = np.swapaxes(li, 1, 2) @ y[:, :, :count]
    return np.asarray(w2[:, :count]), np.asarray(phi)
