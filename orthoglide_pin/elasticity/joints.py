"""Compliant joints: the revolutes' bearings as springs, and a leg assembled with them.

With the ``joints`` compliance source of
:mod:`~orthoglide_pin.elasticity.stiffness`, each of the six revolutes of a
leg (the carriage's, the four of the parallelogram, the platform's) is a
zero-length spring between the two bodies it joins, at its own point: their
relative translation there is resisted by ``joint_stiffness`` [N/m] in every
direction (radial and axial), their relative rotation by
``joint_tilt_stiffness`` [N.m/rad] about the two axes normal to the joint's
axis, and it is free about that axis (:func:`joint_spring`).

:func:`leg_stiffness_with_joints` assembles one leg as a frame of such springs
and of the members, then condenses it onto the platform:

* with elastic links, each member is a beam between its own end nodes
  (:func:`~orthoglide_pin.elasticity.members.beam_stiffness`,
  the bars without end releases: the springs turn freely about their axes);
* with rigid links, each member is a rigid body (6 DOFs at a reference point)
  and a spring sees it through the rigid transfer to the joint's point.

The assembly is dense (up to 67 DOFs per leg) and solved per point in
batches: slower than the joint-free model, which condenses small blocks.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.elasticity.members import (
    Section,
    bar_section,
    beam_stiffness,
    link_section,
    member_nodes,
    tool_transfer,
    transfer_matrix,
)
from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = ["joint_model_stiffness", "joint_spring", "leg_stiffness_with_joints"]

_EYE6: Final = np.eye(6)


def joint_spring(axis: FloatArray, stiffness: float, tilt_stiffness: float) -> FloatArray:
    """Stiffness of a revolute's bearings on the relative motion of its two bodies.

    Args:
        axis: Unit axis of the joint, shape (..., 3).
        stiffness: Translational stiffness, radial and axial [N/m].
        tilt_stiffness: Rotational stiffness about the axes normal to ``axis``
            [N.m/rad]; none about ``axis``.

    Returns:
        ``S``, shape (..., 6, 6): energy ``d^T S d / 2`` for the relative
        translation and rotation ``d`` of one body against the other.
    """
    a = np.asarray(axis, dtype=np.float64)
    out = np.zeros((*a.shape[:-1], 6, 6))
    out[..., :3, :3] = stiffness * np.eye(3)
    out[..., 3:, 3:] = tilt_stiffness * (np.eye(3) - a[..., :, np.newaxis] * a[..., np.newaxis, :])
    return out


class _Frame:
    """A leg's stiffness matrix over blocks of DOFs, for a batch of points."""

    def __init__(self, n: int, size: int) -> None:
        self.k = np.zeros((n, size, size))

    def spring(
        self,
        spring: FloatArray,
        first: tuple[slice, FloatArray] | None,
        second: tuple[slice, FloatArray],
    ) -> None:
        """A spring on ``X2 z2 - X1 z1`` (``first`` ``None``: a fixed body)."""
        ends = [(second[0], second[1], 1.0)]
        if first is not None:
            ends.append((first[0], first[1], -1.0))
        for rows, x_r, s_r in ends:
            left = s_r * np.swapaxes(x_r, -1, -2) @ spring
            for cols, x_c, s_c in ends:
                self.k[:, rows, cols] += s_c * (left @ x_c)

    def beam(self, element: FloatArray, a: slice, b: slice) -> None:
        """A beam element (..., 12, 12) between plain nodes ``a`` and ``b``."""
        for rows, er in ((a, slice(0, 6)), (b, slice(6, 12))):
            for cols, ec in ((a, slice(0, 6)), (b, slice(6, 12))):
                self.k[:, rows, cols] += element[..., er, ec]


def leg_stiffness_with_joints(
    i: int,
    nodes: dict[str, FloatArray],
    params: OrthoglideParams,
    *,
    links: tuple[Section, Section] | None,
    actuator: float | None,
) -> FloatArray:
    """Stiffness of leg ``i`` with compliant joints, on the platform's motion at ``D``.

    Args:
        i: Leg index, 0 to 2.
        nodes: Leg ``i``'s rows of
            :func:`~orthoglide_pin.elasticity.members.member_nodes`
            (each shape (n, 3)).
        params: Machine parameters (joint stiffnesses, link width).
        links: Sections of the bars and of the small links (elastic links),
            or ``None`` (rigid links).
        actuator: Actuator stiffness [N/m], or ``None`` (rigid actuator).

    Returns:
        Shape (n, 6, 6): the force and moment on the platform against its
        translation at ``D`` and its rotation.

    Raises:
        numpy.linalg.LinAlgError: If the leg is a mechanism with the platform held.
    """
    n = nodes["C"].shape[0]
    axis = nodes["axis"]
    normal = nodes["normal"]
    k_t, k_r = params.joint_stiffness, params.joint_tilt_stiffness
    revolute, hinge = joint_spring(axis, k_t, k_r), joint_spring(normal, k_t, k_r)
    eye = np.broadcast_to(_EYE6, (n, 6, 6))
    bodies = 10 if links is not None else 4
    s = 6 * bodies
    size = s + (1 if actuator is not None else 0) + 6
    frame = _Frame(n, size)
    block = [slice(6 * k, 6 * k + 6) for k in range(bodies)]
    masters = slice(size - 6, size)
    carriage: tuple[slice, FloatArray] | None = None
    if actuator is not None:
        frame.k[:, s, s] += actuator
        slide = np.zeros((n, 6, 1))
        slide[:, i, 0] = 1.0  # the carriage moves along e_i only
        carriage = (slice(s, s + 1), slide)
    if links is not None:
        bar, link = links
        # Nodes: C, A0, B0 (base link), A0', B0', A1', B1' (bar ends), A1, B1, D (end link).
        c, a0, b0, a0b, b0b, a1b, b1b, a1, b1, d = block
        half = 0.5 * params.parallelogram_width
        e = np.eye(3)[(i + 1) % 3]
        for mid, end, sign in ((c, a0, 1.0), (c, b0, -1.0), (d, a1, 1.0), (d, b1, -1.0)):
            y = np.eye(3)[(i + 2) % 3]
            frame.beam(beam_stiffness(sign * e, y, np.cross(sign * e, y), half, link), mid, end)
        u = nodes["A1"] - nodes["A0"]
        length = np.linalg.norm(u, axis=-1)
        x = u / length[:, np.newaxis]
        element = beam_stiffness(x, np.cross(normal, x), normal, length, bar)
        frame.beam(element, a0b, a1b)
        frame.beam(element, b0b, b1b)
        for first, second in ((a0, a0b), (b0, b0b), (a1b, a1), (b1b, b1)):
            frame.spring(hinge, (first, eye), (second, eye))
        frame.spring(revolute, carriage, (c, eye))
        frame.spring(revolute, (d, eye), (masters, eye))
    else:
        # Rigid bodies: base link (at C), bar a (at A0), bar b (at B0), end link (at D).
        base, bar_a, bar_b, end = block

        def at(body: slice, ref: str, point: str) -> tuple[slice, FloatArray]:
            return body, transfer_matrix(nodes[point] - nodes[ref])

        frame.spring(revolute, carriage, (base, eye))
        frame.spring(hinge, at(base, "C", "A0"), (bar_a, eye))
        frame.spring(hinge, at(base, "C", "B0"), (bar_b, eye))
        frame.spring(hinge, at(bar_a, "A0", "A1"), at(end, "D", "A1"))
        frame.spring(hinge, at(bar_b, "B0", "B1"), at(end, "D", "B1"))
        frame.spring(revolute, (end, eye), (masters, eye))
    k = frame.k
    slaves = slice(0, size - 6)
    k_sm = k[:, slaves, masters]
    out: FloatArray = k[:, masters, masters] - np.swapaxes(k_sm, 1, 2) @ np.linalg.solve(
        k[:, slaves, slaves], k_sm
    )
    return out


def joint_model_stiffness(
    points: FloatArray,
    params: OrthoglideParams,
    sources: tuple[str, ...],
    actuator: float | None,
    block: int,
) -> FloatArray:
    """``K6`` at the tool tip with compliant joints, shape (n, 6, 6).

    Args:
        points: Tool points [m], shape (n, 3), checked by the caller.
        params: Machine parameters.
        sources: Compliance sources (``"links"`` in them: elastic links).
        actuator: Actuator stiffness [N/m], or ``None`` (rigid actuators).
        block: Points per batch.

    Raises:
        SingularConfigurationError: If a leg is a mechanism with the platform held.
    """
    young, shear = params.youngs_modulus, params.shear_modulus
    sections = (
        (
            bar_section(params.bar_radius, params.bar_wall, young, shear),
            link_section(params.link_radius, young, shear),
        )
        if "links" in sources
        else None
    )
    out = np.zeros((points.shape[0], 6, 6))
    for start in range(0, points.shape[0], block):
        chunk = points[start : start + block]
        nodes = member_nodes(chunk, params)
        for i in range(3):
            leg = {key: value[:, i] for key, value in nodes.items()}
            x = tool_transfer(i, params)
            try:
                k_d = leg_stiffness_with_joints(i, leg, params, links=sections, actuator=actuator)
            except np.linalg.LinAlgError:
                raise SingularConfigurationError(
                    chunk[0], i + 1, "structural", "a leg is a mechanism near this point"
                ) from None
            out[start : start + block] += x.T @ k_d @ x
    return out
