"""The full vibration model: the stiffness model's members with their masses.

The structure is that of :mod:`~orthoglide_pin.elasticity.stiffness` (nodes
from :func:`~orthoglide_pin.elasticity.members.member_nodes`), now with every
member cut into ``segments`` Euler-Bernoulli elements carrying their
consistent mass (:func:`~orthoglide_pin.elasticity.mass.beam_mass`):

* the platform, spindle and tool: one rigid body (6 degrees of freedom: the
  tool tip's translation and the platform's rotation), with its spatial
  inertia from the description (:func:`~orthoglide_pin.elasticity.mass.platform_inertia`);
* each carriage: guided along its rail ``e_i`` (one degree of freedom ``s_i``)
  against the actuator spring ``actuator_stiffness``, with its mass and, given
  a drive, the drive's reflected inertia ``m_eq`` on the carriage side of the
  spring (:func:`~orthoglide_pin.elasticity.mass.reflected_mass`);
* the small links: beams held at their midpoint by the leg's revolutes (on the
  carriage: ``s_i`` and a turn ``phi_C``; on the platform: its motion and a
  turn ``phi_D``);
* the bars: tubes between the small links' ends; all four joints of each
  parallelogram are revolutes of axis ``n`` (a turn of its own at each bar
  end), so each bar bends in its plane as a pinned-pinned beam.

The generalised eigenproblem ``K phi = omega^2 M phi`` goes to
:func:`scipy.linalg.eigh`. :func:`frame_modes` cuts each member into 2, 3, 4,
6, 8, 12, 16 elements until two successive cuts give the requested
frequencies within :data:`CONVERGENCE` (relative); the six lowest of the
prototype converge at 6 elements per member (639 degrees of freedom).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.elasticity.mass import MemberMass, beam_mass
from orthoglide_pin.elasticity.members import Section, bar_section, beam_stiffness, link_section
from orthoglide_pin.elasticity.members import member_nodes as _member_nodes
from orthoglide_pin.exceptions import SingularConfigurationError
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

#: Relative change of the requested frequencies below which the subdivision stops.
CONVERGENCE: Final[float] = 5e-4
#: The subdivisions tried, in elements per member.
SEGMENTS: Final = (2, 3, 4, 6, 8, 12, 16)
#: Parts whose kinetic energies the shapes report.
PARTS: Final = ("platform", "carriages", "members")


@dataclass(frozen=True)
class FrameMatrices:
    """Stiffness and mass matrices of the full model at one point.

    Attributes:
        K: Stiffness, shape (N, N) [N/m, N, N.m/rad].
        M: Mass, shape (N, N); ``M = sum(parts.values())``.
        parts: The mass matrix split by part (see :data:`PARTS`).
        platform: Indices of the tool tip's translation and the platform's
            rotation, shape (6,).
        sliders: Indices of the carriages' travel ``s_i``, shape (3,).
        nodes: Indices of the member nodes that move freely (translation then
            rotation), shape (m, 6).
        segments: Elements per member.
    """

    K: FloatArray
    M: FloatArray
    parts: dict[str, FloatArray]
    platform: IntArray
    sliders: IntArray
    nodes: IntArray
    segments: int


class _Assembly:
    """Dense matrices filled element by element through small DOF maps."""

    def __init__(self, size: int) -> None:
        self.K = np.zeros((size, size))
        self.parts = {name: np.zeros((size, size)) for name in PARTS}
        self.next = 0
        self.free: list[IntArray] = []

    def new(self, count: int) -> IntArray:
        out = np.arange(self.next, self.next + count, dtype=np.intp)
        self.next += count
        return out

    def add(self, idx: IntArray, t: FloatArray, k: FloatArray | None, m: FloatArray) -> None:
        sel = np.ix_(idx, idx)
        if k is not None:
            self.K[sel] += t.T @ k @ t
        self.parts["members"][sel] += t.T @ m @ t


_Node = tuple[IntArray, FloatArray]  # global indices, map (6, len) to the node's motion


def _free(asm: _Assembly) -> _Node:
    idx = asm.new(6)
    asm.free.append(idx)
    return idx, np.eye(6)


def _frame(x: FloatArray) -> tuple[FloatArray, FloatArray]:
    k = int(np.argmin(np.abs(x)))
    y = np.cross(x, np.eye(3)[k])
    y /= np.linalg.norm(y)
    return y, np.cross(x, y)


def _element(a: _Node, b: _Node) -> tuple[IntArray, FloatArray]:
    idx = np.unique(np.concatenate([a[0], b[0]]))
    t = np.zeros((12, idx.size))
    t[:6, np.searchsorted(idx, a[0])] = a[1]
    t[6:, np.searchsorted(idx, b[0])] = b[1]
    return idx, t


def _member(
    asm: _Assembly,
    start: _Node,
    end: _Node,
    pa: FloatArray,
    pb: FloatArray,
    segments: int,
    section: Section,
    mass: MemberMass,
) -> None:
    """Cut the member ``pa -> pb`` into equal elements between ``start`` and ``end``."""
    x = (pb - pa) / np.linalg.norm(pb - pa)
    y, z = _frame(x)
    length = float(np.linalg.norm(pb - pa)) / segments
    k = beam_stiffness(x, y, z, length, section)
    m = beam_mass(x, y, z, length, mass)
    nodes = [start, *(_free(asm) for _ in range(segments - 1)), end]
    for a, b in itertools.pairwise(nodes):
        idx, t = _element(a, b)
        asm.add(idx, t, k, m)


def _hinge(asm: _Assembly, node: _Node, axis: FloatArray) -> _Node:
    """The node's motion plus a turn of its own about ``axis`` (a revolute)."""
    turn = asm.new(1)
    t = np.zeros((6, node[1].shape[1] + 1))
    t[:, :-1] = node[1]
    t[3:, -1] = axis
    return np.concatenate([node[0], turn]), t


def frame_matrices(
    point: FloatArray,
    params: OrthoglideParams,
    masses: tuple[MemberMass, MemberMass],
    platform: FloatArray,
    carriage: float,
    *,
    segments: int = 4,
    rigidity: float = 1.0,
) -> FrameMatrices:
    """Assemble ``K`` and ``M`` of the full model at a tool point.

    Args:
        point: Tool point [m], shape (3,).
        params: Machine parameters (sections, moduli, actuator stiffness).
        masses: The bars' and small links' mass per length
            (:func:`~orthoglide_pin.elasticity.mass.member_masses`).
        platform: The platform's spatial inertia about the tool tip, (6, 6).
        carriage: Mass moving with each carriage [kg] (with the drive's ``m_eq``).
        segments: Elements per member (>= 1).
        rigidity: Factor on every member's rigidities (a large value makes the
            members rigid, for the checks).
    """
    bar_mass, link_mass = masses
    e, g = params.youngs_modulus * rigidity, params.shear_modulus * rigidity
    bar = bar_section(params.bar_radius, params.bar_wall, e, g)
    link = link_section(params.link_radius, e, g)
    per_leg = 3 + 6 * (4 * segments + 2 * (segments - 1)) + 4
    asm = _Assembly(6 + 3 * per_leg)
    plat = asm.new(6)
    nodes = _member_nodes(point[np.newaxis], params)
    tool = np.asarray(point, dtype=float)
    sliders = []
    for i in range(3):
        axis, normal = nodes["axis"][0, i], nodes["normal"][0, i]
        s, phi_c, phi_d = asm.new(1), asm.new(1), asm.new(1)
        sliders.append(int(s[0]))
        t_c = np.zeros((6, 2))
        t_c[:3, 0], t_c[3:, 1] = np.eye(3)[i], axis
        c_node: _Node = (np.concatenate([s, phi_c]), t_c)
        r = nodes["D"][0, i] - tool
        t_d = np.zeros((6, 7))
        t_d[:3, :3], t_d[3:, 3:6], t_d[3:, 6] = np.eye(3), np.eye(3), axis
        t_d[:3, 3:6] = -np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
        d_node: _Node = (np.concatenate([plat, phi_d]), t_d)
        ends = {key: _free(asm) for key in ("A0", "B0", "A1", "B1")}
        for mid, mid_key, keys in ((c_node, "C", ("A0", "B0")), (d_node, "D", ("A1", "B1"))):
            for key in keys:
                pa, pb = nodes[mid_key][0, i], nodes[key][0, i]
                _member(asm, mid, ends[key], pa, pb, segments, link, link_mass)
        for low, up in (("A0", "A1"), ("B0", "B1")):
            lower, upper = _hinge(asm, ends[low], normal), _hinge(asm, ends[up], normal)
            pa, pb = nodes[low][0, i], nodes[up][0, i]
            _member(asm, lower, upper, pa, pb, segments, bar, bar_mass)
        asm.K[s[0], s[0]] += params.actuator_stiffness
        asm.parts["carriages"][s[0], s[0]] += carriage
    asm.parts["platform"][np.ix_(plat, plat)] += platform
    mass = sum(asm.parts.values())
    return FrameMatrices(
        asm.K,
        np.asarray(mass),
        asm.parts,
        plat,
        np.array(sliders, dtype=np.intp),
        np.array(asm.free, dtype=np.intp),
        segments,
    )


def solve_modes(mats: FrameMatrices, count: int) -> tuple[FloatArray, FloatArray]:
    """The ``count`` lowest ``omega^2`` [rad^2/s^2] and mass-normalised modes (N, count).

    Raises:
        SingularConfigurationError: The structure is a mechanism (a zero mode).
    """
    from scipy.linalg import LinAlgError, eigh

    try:
        w2, phi = eigh(mats.K, mats.M, subset_by_index=[0, count - 1])
    except LinAlgError:
        raise SingularConfigurationError(
            None, None, "structural", "the mass or stiffness matrix is singular"
        ) from None
    scale = max(float(np.max(np.abs(np.diag(mats.K)) / np.diag(mats.M))), 1.0)
    if w2[0] <= 1e-9 * scale:
        raise SingularConfigurationError(
            None, None, "structural", "the structure is a mechanism there (a zero frequency)"
        )
    return np.asarray(w2), np.asarray(phi)


def frame_modes(
    point: FloatArray,
    params: OrthoglideParams,
    masses: tuple[MemberMass, MemberMass],
    platform: FloatArray,
    carriage: float,
    count: int,
    *,
    rigidity: float = 1.0,
) -> tuple[FloatArray, FloatArray, FrameMatrices]:
    """Lowest modes of the full model, the members cut until they converge.

    Returns:
        ``omega^2`` (count,), the modes (N, count) and the matrices of the
        finest subdivision used.
    """
    last = None
    for segments in SEGMENTS:
        mats = frame_matrices(
            point, params, masses, platform, carriage, segments=segments, rigidity=rigidity
        )
        w2, phi = solve_modes(mats, count)
        if last is not None and np.all(np.abs(np.sqrt(w2 / last) - 1.0) < CONVERGENCE):
            break
        last = w2
    return w2, phi, mats


def model_size(segments: int) -> int:
    """Degrees of freedom of the full model with ``segments`` elements per member."""
    return 6 + 3 * (3 + 6 * (4 * segments + 2 * (segments - 1)) + 4)


__all__ = [
    "CONVERGENCE",
    "PARTS",
    "SEGMENTS",
    "FrameMatrices",
    "frame_matrices",
    "frame_modes",
    "model_size",
    "solve_modes",
]
