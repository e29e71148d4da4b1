"""The elastic members of the Orthoglide: sections and 3D beam elements.

Every deformable member of the elastostatic model
(:mod:`~orthoglide_pin.elasticity.stiffness`) is a straight, prismatic,
linear-elastic Euler-Bernoulli beam (traction, torsion, bending in both
planes; no shear deformation), of a circular section:

* a parallelogram bar: a tube of outer radius ``bar_radius`` and wall
  ``bar_wall`` (a solid bar when the wall equals the radius);
* a small link of a parallelogram: a solid round bar of radius ``link_radius``.

The element stiffness is written directly in world axes for a batch of
elements: with the element's unit axis ``x`` and two unit vectors ``y``,
``z`` completing a right-handed frame, the blocks of the classical 12 x 12
matrix (degrees of freedom ``[t_a, r_a, t_b, r_b]``: translations [m] and
small rotations [rad] of end nodes ``a`` and ``b``) are outer products of
these vectors. Bending about ``z`` uses ``EI_z``, about ``y`` ``EI_y``; an
element whose two ends turn freely about ``z`` (a bar between two revolutes of
axis ``z``) is the same matrix with ``EI_z = 0`` (the static condensation of
both end moments about ``z``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.kinematics.closed_form import leg_vectors
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = [
    "Section",
    "bar_section",
    "beam_stiffness",
    "link_section",
    "member_nodes",
    "tool_transfer",
    "transfer_matrix",
]


@dataclass(frozen=True)
class Section:
    """Stiffness properties of one member's section and material.

    Attributes:
        EA: Axial rigidity [N].
        GJ: Torsional rigidity [N.m^2].
        EI: Bending rigidity, the same about every transverse axis [N.m^2].
    """

    EA: float
    GJ: float
    EI: float


def _tube(outer: float, wall: float, young_modulus: float, shear_modulus: float) -> Section:
    inner = max(outer - wall, 0.0)
    area = math.pi * (outer**2 - inner**2)
    inertia = math.pi * (outer**4 - inner**4) / 4.0
    # Circular sections: the torsion constant is the polar moment, 2 I.
    return Section(young_modulus * area, shear_modulus * 2.0 * inertia, young_modulus * inertia)


def bar_section(
    bar_radius: float, bar_wall: float, young_modulus: float, shear_modulus: float
) -> Section:
    """Section of a parallelogram bar: a round tube.

    Args:
        bar_radius: Outer radius [m].
        bar_wall: Wall thickness [m] (``bar_radius`` for a solid bar).
        young_modulus: Young's modulus [Pa].
        shear_modulus: Shear modulus [Pa].
    """
    return _tube(bar_radius, bar_wall, young_modulus, shear_modulus)


def link_section(link_radius: float, young_modulus: float, shear_modulus: float) -> Section:
    """Section of a small link of a parallelogram: a solid round bar.

    Args:
        link_radius: Radius [m].
        young_modulus: Young's modulus [Pa].
        shear_modulus: Shear modulus [Pa].
    """
    return _tube(link_radius, link_radius, young_modulus, shear_modulus)


def _outer(u: FloatArray, v: FloatArray) -> FloatArray:
    return u[..., :, np.newaxis] * v[..., np.newaxis, :]


def beam_stiffness(
    x: FloatArray,
    y: FloatArray,
    z: FloatArray,
    length: float | FloatArray,
    section: Section,
    *,
    release_z: bool = False,
) -> FloatArray:
    """Stiffness matrices of a batch of beam elements, in world axes.

    Args:
        x: Unit axis of each element, from end ``a`` to end ``b``, shape (..., 3).
        y: Unit transverse vector, shape (..., 3).
        z: ``x`` cross ``y``, shape (..., 3).
        length: Element length [m], a number or shape (...).
        section: Rigidities of the section.
        release_z: True when both ends turn freely about ``z`` (revolutes of
            axis ``z`` at both ends): no bending stiffness about ``z``.

    Returns:
        Element matrices, shape (..., 12, 12) [N/m, N/rad, N.m/rad], for the
        degrees of freedom ``[t_a, r_a, t_b, r_b]`` (world axes).
    """
    L = np.asarray(length, dtype=float)[..., np.newaxis, np.newaxis]
    ei_y = section.EI
    ei_z = 0.0 if release_z else section.EI
    xx, yy, zz = _outer(x, x), _outer(y, y), _outer(z, z)
    k_tt = section.EA / L * xx + 12.0 / L**3 * (ei_z * yy + ei_y * zz)
    k_tr = 6.0 / L**2 * (ei_z * _outer(y, z) - ei_y * _outer(z, y))
    bend = ei_z * zz + ei_y * yy
    k_rr = section.GJ / L * xx + 4.0 / L * bend
    k_rr_ab = -section.GJ / L * xx + 2.0 / L * bend
    k_rt = np.swapaxes(k_tr, -1, -2)
    shape = np.broadcast_shapes(k_tt.shape, k_rr.shape)[:-2]
    out = np.empty((*shape, 12, 12))
    blocks = (
        (k_tt, k_tr, -k_tt, k_tr),
        (k_rt, k_rr, -k_rt, k_rr_ab),
        (-k_tt, -k_tr, k_tt, -k_tr),
        (k_rt, k_rr_ab, -k_rt, k_rr),
    )
    for row, items in enumerate(blocks):
        for col, block in enumerate(items):
            out[..., 3 * row : 3 * row + 3, 3 * col : 3 * col + 3] = block
    return out


def member_nodes(points: ArrayLike, params: OrthoglideParams) -> dict[str, FloatArray]:
    """Where the members of each leg are, for tool points (the elastostatic model's nodes).

    Leg ``i`` (rows ``i`` of each array): ``C`` the carriage's revolute (the base
    small link's midpoint), ``A0``/``B0`` the bars' lower ends, ``A1``/``B1``
    their upper ends, ``D`` the end revolute (the end small link's midpoint),
    all on the geometry of the description (platform offset, tool offset);
    ``axis`` the leg's revolute axis ``e_(i+1)`` and ``normal`` the axis of
    the four revolutes of its parallelogram (normal to its plane).

    Args:
        points: Tool points [m], shape (3,) or (..., 3).
        params: Machine parameters.

    Returns:
        Arrays of shape (..., 3 legs, 3) [m] (unit vectors for the axes).
    """
    p = np.asarray(points, dtype=np.float64)
    legs = leg_vectors(p, params.leg_length)  # u_i = D_i - C_i, (..., 3, 3)
    eye = np.eye(3)
    axis = np.broadcast_to(eye[[1, 2, 0]], legs.shape)
    centre = p - np.asarray(params.tool_offset)
    d = centre[..., np.newaxis, :] - params.platform_offset * eye
    c = d - legs
    half = 0.5 * params.parallelogram_width * axis
    normal = np.cross(legs, axis)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    return {
        "C": c,
        "A0": c + half,
        "B0": c - half,
        "A1": d + half,
        "B1": d - half,
        "D": d,
        "axis": np.array(axis),
        "normal": normal,
    }


def transfer_matrix(r: ArrayLike) -> FloatArray:
    """Rigid transfer ``[[I, -[r]x], [0, I]]``: (translation, rotation) moved by ``r``.

    Args:
        r: Offset [m] from the point where a motion is given to the point where it
            is wanted, shape (..., 3).

    Returns:
        Shape (..., 6, 6): ``(dp_there, w) = X (dp_here, w)``.
    """
    v = np.asarray(r, dtype=np.float64)
    out = np.zeros((*v.shape[:-1], 6, 6))
    out[..., range(6), range(6)] = 1.0
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    out[..., 0, 4], out[..., 0, 5] = z, -y
    out[..., 1, 3], out[..., 1, 5] = -z, x
    out[..., 2, 3], out[..., 2, 4] = y, -x
    return out


def tool_transfer(i: int, params: OrthoglideParams) -> FloatArray:
    """Transfer from the tool tip to leg ``i``'s end revolute ``D``, shape (6, 6).

    ``(dp_D, w) = X (dp_tool, w)``: the platform carries both points rigidly.
    """
    r = -np.asarray(params.tool_offset) - params.platform_offset * np.eye(3)[i]
    return transfer_matrix(r)
