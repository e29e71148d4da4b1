"""Elastostatic model of the Orthoglide: Cartesian stiffness and tool deflection.

Method: matrix structural analysis of the real members, with every loop kept.
Each leg is a 3D frame of Euler-Bernoulli beams
(:mod:`~orthoglide_pin.elasticity.members`) between rigid
bodies, assembled in world axes, and statically condensed onto the platform;
the three legs then act in parallel on the platform. Because a beam element
has exactly six rigid-body modes, this is the virtual joint method (VJM) of
Pashkevich, Chablat and Wenger (Mechanism and Machine Theory, 2009) with one
exact 6D virtual spring per member: the over-constrained loops (each planar
parallelogram, and the three legs that each block two platform rotations) are
solved as they are, by summing stiffnesses, and no constraint row is dropped.
Per leg, the two lower bar ends are condensed first (each couples its bar's
upper end and the carriage's two free motions), then the two upper ends, then
the slider travel and the two revolute turns: only 6x6 and 3x3 solves, batched
over the points.

The structure, as built (nodes from
:func:`~orthoglide_pin.elasticity.members.member_nodes`, at the
joints of the description in the closed-loop model's configuration):

* rigid: the frame and rails, the carriages (guided along ``e_i`` without
  play), the platform, the spindle and the tool;
* actuators: the carriage of leg ``i`` moves along ``e_i`` against one axial
  spring ``actuator_stiffness`` [N/m] (screw, nut and thrust bearings in
  series); rigid when ``"actuators"`` is not a source;
* the small links: solid round beams of length ``parallelogram_width`` along
  the leg's revolute axis ``e_(i+1)``, each held at its midpoint by the leg's
  revolute (on the carriage, on the platform), which turns freely about that
  axis and is rigid otherwise;
* the bars: tubes of length ``leg_length`` joining the ends of the two small
  links; **all four joints of each parallelogram are revolutes** (ideal:
  rigid, frictionless, without clearance) of axis ``n``, normal to the
  parallelogram's plane, so a bar carries traction, torsion and out-of-plane
  bending, and no in-plane bending. (The kinematic model closes each
  parallelogram with a 3D point, a spherical fourth joint, only to avoid a
  redundant row; a spherical joint would make the machine softer.)
* the joints' bearings are springs with the ``"joints"`` source
  (``joint_stiffness`` radial and axial, ``joint_tilt_stiffness``; free about
  each joint's axis; :mod:`~orthoglide_pin.elasticity.joints`,
  a dense and slower assembly), else ideal;
* when ``"links"`` is not a source the links are rigid bodies, exactly:
  the compliance is then the actuators' seen through the Jacobian,
  ``C = J6 diag(1/k_a) J6^T`` with ``J6 = [J; 0]`` (the rigid legs block every
  platform rotation), which has no stiffness matrix (``K6`` is ``None``).

Outputs at the tool tip, in world axes, for small displacements:

* ``C``: the 6x6 compliance, ``(dp, dtheta) = C (f, m)`` with ``dp`` [m],
  ``dtheta`` [rad], ``f`` [N], ``m`` [N.m] about the tool tip;
* ``K6 = inv(C)``: the 6x6 stiffness (when every source is elastic);
* ``K = inv(C[:3, :3])`` [N/m]: the stiffness against a pure tool force with
  the platform free to tilt (not the translational block of ``K6``);
* the deflection ``C w`` under a tool wrench ``w``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_vector, flag, integer, points_array
from orthoglide_pin.elasticity.joints import joint_model_stiffness
from orthoglide_pin.elasticity.members import (
    Section,
    bar_section,
    beam_stiffness,
    link_section,
    member_nodes,
    tool_transfer,
)
from orthoglide_pin.exceptions import InvalidParameterError, SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import inverse_jacobian, jacobian
from orthoglide_pin.kinematics.singularity import MAX_CONDITION, check_inverse_jacobian
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = [
    "DEFAULT_SOURCES",
    "SOURCES",
    "CartesianStiffness",
    "cartesian_stiffness",
    "parse_sources",
    "stiffness_assumptions",
]

#: Compliance sources the model knows.
SOURCES: Final = ("actuators", "links", "joints")
#: Sources used unless told otherwise: the drives and the members (the joints'
#: bearings are an option: their stiffness is rarely known).
DEFAULT_SOURCES: Final = ("actuators", "links")
#: Points per block of the vectorised computation.
BLOCK: Final[int] = 1024

# Degrees of freedom of one leg, reduced to what the joints let move: the bar
# ends A0, B0 (carriage side) and A1, B1 (platform side), 6 each; the slider
# travel s, the base revolute's turn, the end revolute's turn; then the
# platform's motion at the end revolute's point D (translation, rotation).
_A0, _B0, _A1, _B1 = (slice(6 * k, 6 * k + 6) for k in range(4))
_S, _PHI_C, _PHI_D = 24, 25, 26
_MASTERS: Final = 27


def parse_sources(sources: str | Iterable[str]) -> tuple[str, ...]:
    """Validate compliance sources, as a list or a comma-separated string.

    Returns:
        The sources in canonical order, without repeats.

    Raises:
        InvalidParameterError: On an unknown or missing source.
    """
    allowed = "a non-empty subset of " + ", ".join(SOURCES)
    if not isinstance(sources, (str, Iterable)) or isinstance(sources, Mapping):
        raise InvalidParameterError("sources", sources, allowed)
    items = sources.split(",") if isinstance(sources, str) else list(sources)
    names = {str(s).strip() for s in items if str(s).strip()}
    if not names or not names <= set(SOURCES):
        raise InvalidParameterError("sources", ",".join(sorted(names)) or sources, allowed)
    return tuple(s for s in SOURCES if s in names)


def stiffness_assumptions(
    params: OrthoglideParams, sources: Iterable[str] = DEFAULT_SOURCES
) -> dict[str, Any]:
    """The assumptions of the elastostatic model, to state with every result.

    Returns:
        A JSON-ready mapping (SI units, strings for the qualitative ones).
    """
    src = parse_sources(sources)
    links, joints = "links" in src, "joints" in src
    return {
        "method": "matrix structural analysis of Euler-Bernoulli beams, statically "
        "condensed, over-constrained loops kept (VJM with exact 6D member springs)",
        "sources": list(src),
        "reference_point": "tool tip, world axes; wrench (force [N], moment [N.m])",
        "youngs_modulus": params.youngs_modulus if links else None,
        "shear_modulus": params.shear_modulus if links else None,
        "actuator_stiffness": params.actuator_stiffness if "actuators" in src else None,
        "actuators": "axial spring along each slider" if "actuators" in src else "rigid",
        "links": "bars (tubes) and small links (solid) as beams" if links else "rigid",
        "joint_stiffness": params.joint_stiffness if joints else None,
        "joint_tilt_stiffness": params.joint_tilt_stiffness if joints else None,
        "joints": (
            "revolutes with compliant bearings (radial and axial, and tilt; free about their axes)"
            if joints
            else "ideal revolutes (rigid, frictionless, no clearance)"
        )
        + "; all four joints of each parallelogram are revolutes",
        "small_links": "held at their midpoint by the leg's revolute",
        "rigid_parts": ["frame and rails", "carriages", "platform", "spindle and tool"],
    }


@dataclass(frozen=True)
class CartesianStiffness:
    """Cartesian stiffness of the tool tip at a batch of points.

    Attributes:
        points: Tool points [m], shape (..., 3).
        compliance: ``C``, shape (..., 6, 6): ``(dp [m], dtheta [rad])`` per
            ``(f [N], m [N.m])``.
        K: ``inv(C[:3, :3])`` [N/m], shape (..., 3, 3).
        K6: ``inv(C)``, shape (..., 6, 6), or ``None`` when it is infinite
            (rigid links: the platform cannot tilt).
        sources: The compliance sources.
        assumptions: See :func:`stiffness_assumptions`.
    """

    points: FloatArray
    compliance: FloatArray
    K: FloatArray
    K6: FloatArray | None
    sources: tuple[str, ...]
    assumptions: dict[str, Any]

    def deflection(self, wrench: ArrayLike) -> FloatArray:
        """Tool displacement [m] and rotation [rad] under a tool wrench.

        Args:
            wrench: Force [N] and moment about the tool tip [N.m], shape (6,).

        Returns:
            ``C w``, shape (..., 6).
        """
        w = finite_vector("wrench", wrench, 6, "[N, N.m]")
        out: FloatArray = self.compliance @ w
        return out

    def min_stiffness(self) -> FloatArray:
        """Smallest eigenvalue of ``K`` [N/m], shape (...): the softest direction."""
        largest = np.linalg.eigvalsh(self.compliance[..., :3, :3])[..., -1]
        return np.asarray(1.0 / largest, dtype=np.float64)


def _frame(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A right-handed frame ``(x, y, z)`` for a world axis ``x`` (+-e_k)."""
    k = int(np.argmax(np.abs(x)))
    y = np.zeros(3)
    y[(k + 1) % 3] = 1.0
    return x, y, np.cross(x, y)


class _Leg:
    """Constant data of one leg: the small links' stiffness, transfer to the tool."""

    def __init__(self, i: int, params: OrthoglideParams, link: Section) -> None:
        j = (i + 1) % 3
        self.axis = np.eye(3)[j]  # the leg's revolute axes, e_(i+1)
        half = params.parallelogram_width / 2.0
        # Full DOFs of a small-link half: its midpoint (C or D) and its end.
        # The carriage lets C move along e_i (s) and turn about the axis
        # (phi_C) only; D moves with the platform and turns about the axis.
        c_map = {i: _S, 3 + j: _PHI_C}
        d_map = {k: _MASTERS + k for k in range(6)}
        k = np.zeros((33, 33))
        for mid, end, sign in (
            (c_map, 0, 1.0),
            (c_map, 6, -1.0),
            (d_map, 12, 1.0),
            (d_map, 18, -1.0),
        ):
            ke = beam_stiffness(*_frame(sign * self.axis), half, link)
            t = np.zeros((12, 33))
            for full, red in mid.items():
                t[full, red] = 1.0
            if mid is d_map:
                t[3 + j, _PHI_D] = 1.0  # the rotation at D is the platform's plus phi_D
            t[6:, end : end + 6] = np.eye(6)
            k += t.T @ ke @ t
        # Constant blocks of the small links: each bar end with itself, a lower
        # end with (s, phi_C), an upper end with (phi_D, platform), and the
        # last nine DOFs (s, phi_C, phi_D, platform) with themselves.
        self.ends = [k[e, e] for e in (_A0, _B0, _A1, _B1)]
        self.lower_s = [k[e, _S:_PHI_D] for e in (_A0, _B0)]
        self.upper_t = [k[e, _PHI_D:] for e in (_A1, _B1)]
        self.tail_blocks = k[_S:, _S:]
        self.transfer = tool_transfer(i, params)

    def tail(self, u: FloatArray, normal: FloatArray, bar: Section) -> FloatArray:
        """The leg condensed onto ``(s, phi_C, phi_D, platform at D)``, shape (n, 9, 9).

        The members only (no actuator spring): the bar ends are condensed out.

        Args:
            u: The bars' vectors, lower to upper end [m], shape (n, 3).
            normal: Unit axes of the parallelogram's revolutes, shape (n, 3).
            bar: The bars' section.
        """
        n = u.shape[0]
        length = np.linalg.norm(u, axis=1)
        x = u / length[:, np.newaxis]
        bars = beam_stiffness(x, np.cross(normal, x), normal, length, bar, release_z=True)
        k_aa, k_ab, k_bb = bars[:, :6, :6], bars[:, :6, 6:], bars[:, 6:, 6:]
        k_ba = np.swapaxes(k_ab, 1, 2)
        tail = np.empty((n, 9, 9))
        tail[:] = self.tail_blocks
        for side in (0, 1):  # bar a (A0-A1), then bar b (B0-B1)
            lower_s, upper_t = self.lower_s[side], self.upper_t[side]
            # The lower end couples the upper end (the bar) and (s, phi_C).
            both = np.concatenate([k_ab, np.broadcast_to(lower_s, (n, 6, 2))], axis=2)
            both = np.linalg.solve(self.ends[side] + k_aa, both)
            x_up, x_s = both[:, :, :6], both[:, :, 6:]
            tail[:, :2, :2] -= lower_s.T @ x_s
            # The upper end then couples (s, phi_C) and (phi_D, platform).
            pivot = self.ends[2 + side] + k_bb - k_ba @ x_up
            rhs = np.concatenate([-(k_ba @ x_s), np.broadcast_to(upper_t, (n, 6, 7))], axis=2)
            tail -= np.swapaxes(rhs, 1, 2) @ np.linalg.solve(pivot, rhs)
        return tail

    def stiffness(
        self, u: FloatArray, normal: FloatArray, bar: Section, k_a: float | None
    ) -> FloatArray:
        """The leg's stiffness at the tool tip, shape (n, 6, 6).

        Args:
            u: The bars' vectors, lower to upper end [m], shape (n, 3).
            normal: Unit axes of the parallelogram's revolutes, shape (n, 3).
            bar: The bars' section.
            k_a: Actuator stiffness [N/m], ``None`` for a rigid actuator.
        """
        tail = self.tail(u, normal, bar)
        if k_a is None:  # a rigid actuator: s = 0 exactly
            slaves = slice(1, 3)
        else:
            tail[:, 0, 0] += k_a
            slaves = slice(0, 3)
        k_sm = tail[:, slaves, 3:]
        condensed = np.linalg.solve(tail[:, slaves, slaves], k_sm)
        k_d = tail[:, 3:, 3:] - np.swapaxes(k_sm, 1, 2) @ condensed
        out: FloatArray = self.transfer.T @ k_d @ self.transfer
        return out


def _positive_definite(k: FloatArray) -> bool:
    try:
        np.linalg.cholesky(k)
    except np.linalg.LinAlgError:
        return False
    return True


def _structural_stiffness(
    p: FloatArray,
    params: OrthoglideParams,
    k_a: float | None,
    block: int,
) -> FloatArray:
    """``K6`` (n, 6, 6) of the frame model at the points ``p`` (n, 3)."""
    bar = bar_section(
        params.bar_radius, params.bar_wall, params.youngs_modulus, params.shear_modulus
    )
    link = link_section(params.link_radius, params.youngs_modulus, params.shear_modulus)
    legs = [_Leg(i, params, link) for i in range(3)]
    out = np.empty((p.shape[0], 6, 6))
    for start in range(0, p.shape[0], block):
        chunk = p[start : start + block]
        nodes = member_nodes(chunk, params)
        u, normal = nodes["A1"] - nodes["A0"], nodes["normal"]
        try:
            out[start : start + block] = sum(
                leg.stiffness(u[:, i], normal[:, i], bar, k_a) for i, leg in enumerate(legs)
            )
        except np.linalg.LinAlgError:
            _raise_singular(chunk, params, k_a, legs, bar)
    return out


def _raise_singular(
    chunk: FloatArray, params: OrthoglideParams, k_a: float | None, legs: list[_Leg], bar: Section
) -> None:
    for point in chunk:
        nodes = member_nodes(point[np.newaxis], params)
        u, normal = nodes["A1"] - nodes["A0"], nodes["normal"]
        try:
            for i, leg in enumerate(legs):
                leg.stiffness(u[:, i], normal[:, i], bar, k_a)
        except np.linalg.LinAlgError:
            raise SingularConfigurationError(
                point, None, "structural", "the structure is a mechanism there"
            ) from None
    raise SingularConfigurationError(chunk[0], None, "structural", "singular stiffness")


def cartesian_stiffness(
    points: ArrayLike,
    params: OrthoglideParams | None = None,
    sources: str | Iterable[str] = DEFAULT_SOURCES,
    *,
    check_limits: bool = True,
    max_condition: float = MAX_CONDITION,
    block: int = BLOCK,
) -> CartesianStiffness:
    """Compliance and stiffness of the tool tip (see the module for the model).

    The points are first judged as the indices
    (:func:`~orthoglide_pin.kinetostatics.indices.kinetostatic_indices`) and
    ``orthoglide jacobian`` judge them: reach, serial and parallel
    singularities, and the condition number of ``J``
    (:func:`~orthoglide_pin.kinematics.singularity.check_inverse_jacobian`).
    Beyond that limit the rigid-link stiffness ``inv(J diag(1/k_a) J^T)``
    has lost its digits (it may even show a negative eigenvalue), so no
    stiffness is given there.

    Args:
        points: Tool points [m], shape (3,) or (..., 3).
        params: Machine parameters (sections, moduli, actuator stiffness);
            the prototype when ``None``.
        sources: Compliance sources, a subset of :data:`SOURCES`.
        check_limits: Refuse points whose slider values leave the machine's
            slider limits, as ``orthoglide ik`` does.
        max_condition: Largest condition number of ``J`` accepted.
        block: Points per block of the computation.

    Returns:
        The compliance, ``K``, ``K6`` (``None`` with rigid links) and the
        assumptions, for every point.

    Raises:
        InvalidParameterError: On bad points, sources or options.
        UnreachablePointError, SingularConfigurationError: At the first point
            out of reach (or beyond the slider limits), or singular (serial,
            parallel or structural, or conditioned beyond ``max_condition``).
    """
    params = as_params(params)
    src = parse_sources(sources)
    p = points_array(points, "points")
    block = integer("block", block)
    shape = p.shape[:-1]
    flat = np.ascontiguousarray(p.reshape(-1, 3))
    if flag("check_limits", check_limits):
        check_slider_limits(params, flat)
    # reach, serial and parallel singularities, conditioning: the indices' thresholds
    j_inv = inverse_jacobian(flat, params.leg_length)
    check_inverse_jacobian(j_inv, flat, max_condition=max_condition)
    jac = jacobian(flat, params.leg_length)
    k_a = params.actuator_stiffness if "actuators" in src else None
    k6: FloatArray | None = None
    if "joints" in src:
        k6 = joint_model_stiffness(flat, params, src, k_a, block)
    elif "links" in src:
        k6 = _structural_stiffness(flat, params, k_a, block)
    if k6 is not None:
        try:
            np.linalg.cholesky(k6)  # positive definite, or a mechanism somewhere
            c: FloatArray = np.asarray(np.linalg.inv(k6), dtype=np.float64)
        except np.linalg.LinAlgError:
            bad = next(i for i, k in enumerate(k6) if not _positive_definite(k))
            raise SingularConfigurationError(
                flat[bad], None, "structural", "the platform is free to move there"
            ) from None
    else:
        c = np.zeros((flat.shape[0], 6, 6))
        c[:, :3, :3] = (jac / params.actuator_stiffness) @ np.swapaxes(jac, 1, 2)
    k = np.asarray(np.linalg.inv(c[:, :3, :3]), dtype=np.float64)
    return CartesianStiffness(
        points=p,
        compliance=c.reshape(*shape, 6, 6),
        K=k.reshape(*shape, 3, 3),
        K6=None if k6 is None else k6.reshape(*shape, 6, 6),
        sources=src,
        assumptions=stiffness_assumptions(params, src),
    )
