"""An independent check of the full vibration model: a modal frame FEA in OpenSees.

:func:`frame_fea_modes` builds the structure of
:mod:`~orthoglide_pin.elasticity.frame_modes` a second time, in OpenSees
(OpenSeesPy, the optional extra ``pip install 'orthoglide-pin[modal]'``), from
the same nodes (:func:`~orthoglide_pin.elasticity.members.member_nodes`), the
same sections and the same masses, and returns its lowest natural
frequencies. OpenSees assembles its own element stiffness and consistent mass
matrices, its own constraints and its own eigensolver, so the comparison tests
the package's assembly and mass matrices, not the inputs.

The model:

* every member cut into ``segments`` ``elasticBeamColumn`` elements with a
  consistent mass (``-cMass``, translation and torsion);
* each carriage node C: fixed but for its travel along ``e_i`` (with the
  carriage's and the drive's mass, and a ``zeroLength`` actuator spring to the
  frame) and its turn about the leg's revolute axis;
* the platform, spindle and tool: a master node at the tool tip, with
  ``rigidLink('beam')`` to each leg's end revolute and to six point masses
  that reproduce the platform's 6x6 spatial inertia exactly (its mass, centre
  of mass and inertia tensor: ``m/6`` at ``c +- d_k r_k`` along the principal
  axes ``r_k`` of the second-moment tensor ``S = tr(I)/2 - I``, ``d_k^2 = 3
  S_k / m``);
* the revolutes that are not world-fixed (the end revolute D, the four
  parallelogram joints, whose axis ``n`` is skew) as ``zeroLength`` elements
  blocking every relative motion but the turn about the joint's axis, with a
  penalty stiffness :data:`PENALTY` times the members' largest; the bar ends'
  translations follow the small links' ends exactly (``equalDOF``);
* the eigenproblem by OpenSees' ARPACK solver (``-genBandArpack``, shift and
  invert about zero).

Known difference: OpenSees' consistent mass has no rotary inertia of the
sections in bending (the package's has, ``rho I`` per length), which makes its
frequencies up to 0.22 % higher than the full model's on the prototype and
0.1 % on a shorter design. Given the same masses (the package's without that
term) and the same cut, the two agree to 1e-6.

Why OpenSees: its frame elements have consistent masses, rigid links carry a
master node's rotation to offset masses, and its eigensolvers take the full
mass matrix (PyNite's modal analysis could not carry the platform's 6x6
inertia). The wheels hold a compiled interpreter (Linux,
Windows, macOS; Python 3.10-3.13) that does not use numpy. Its licence is not
an open-source one (free for research, education and internal use; a
commercial redistribution needs a licence from its authors), so it stays an
optional extra of its own. Its Linux wheel ships a BLAS that its LAPACK does
not find; :func:`frame_fea_modes` loads it first. OpenSees keeps one model per
process: the calls are serialised by a lock and wipe the model before and
after.
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib
import importlib.util
import itertools
import math
import sys
import threading
from pathlib import Path
from types import ModuleType
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_vector, integer
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.elasticity.mass import (
    MemberMass,
    member_masses,
    platform_inertia,
    reflected_mass,
)
from orthoglide_pin.elasticity.members import Section, bar_section, link_section, member_nodes
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    MissingExtraError,
    SingularConfigurationError,
)
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, jacobian
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = ["PENALTY", "frame_fea_modes", "platform_point_masses"]

#: Stiffness of the revolutes' blocked motions, relative to the members' largest.
PENALTY: Final[float] = 1e4
#: Elements per member by default (the full model's converged cut on the prototype).
SEGMENTS: Final[int] = 6
#: Most elements per member accepted.
MAX_SEGMENTS: Final[int] = 32
#: Most modes asked.
MAX_MODES: Final[int] = 24
#: The libraries of OpenSees' Linux wheel, loaded in this order before it.
_LINUX_LIBS: Final = ("libquadmath.so.0", "libgfortran.so.4", "libblas.so.3")
#: OpenSees' eigensolver (ARPACK, shift and invert, on a banded system).
SOLVER: Final = "-genBandArpack"
#: Fewest eigenpairs asked of ARPACK.
SUBSPACE: Final[int] = 12
_LOCK = threading.Lock()


def _opensees() -> ModuleType:
    """OpenSeesPy's interpreter, or a one-line :class:`MissingExtraError`."""
    if sys.platform.startswith("linux"):
        try:
            spec = importlib.util.find_spec("openseespylinux")
        except (ImportError, ValueError):  # a package set to None in sys.modules
            spec = None
        if spec is not None and spec.origin is not None:
            folder = Path(spec.origin).parent / "lib"
            for name in _LINUX_LIBS:
                with contextlib.suppress(OSError):  # not shipped: the system's, if any
                    ctypes.CDLL(str(folder / name), mode=ctypes.RTLD_GLOBAL)
    try:
        return importlib.import_module("openseespy.opensees")
    except (ImportError, RuntimeError):
        raise MissingExtraError("openseespy", "modal", "the modal frame FEA check") from None


def _cross(r: FloatArray) -> FloatArray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def platform_point_masses(inertia: ArrayLike, point: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Six point masses with the spatial inertia of a rigid body (see the module).

    Args:
        inertia: The body's 6x6 spatial inertia about ``point`` in world axes,
            for ``(v_point, omega)`` (:func:`~orthoglide_pin.elasticity.mass.spatial_inertia`).
        point: The reference point [m], shape (3,).

    Returns:
        Positions [m], shape (6, 3), and masses [kg], shape (6,): their mass,
        first and second moments are the body's.

    Raises:
        InvalidParameterError: Not the spatial inertia of a rigid body (a
            non-positive mass, or principal inertias that break the triangle
            inequality).
    """
    m6 = np.asarray(inertia, dtype=float)
    if m6.shape != (6, 6) or not np.all(np.isfinite(m6)):
        raise InvalidParameterError("inertia", m6.shape, "a finite 6x6 spatial inertia")
    ref = finite_vector("point", point, 3, "[m]")
    mass = float(m6[0, 0])
    if not mass > 0.0:
        raise InvalidParameterError("inertia", mass, "a positive mass")
    skew = m6[3:, :3] / mass
    r = np.array([skew[2, 1], skew[0, 2], skew[1, 0]])
    about_com = m6[3:, 3:] + mass * _cross(r) @ _cross(r)
    second = 0.5 * np.trace(about_com) * np.eye(3) - about_com
    moments, axes = np.linalg.eigh(0.5 * (second + second.T))
    tol = 1e-12 * max(float(np.trace(about_com)), 1e-300)
    if np.any(moments < -tol):
        raise InvalidParameterError(
            "inertia", moments.tolist(), "principal inertias that satisfy the triangle inequality"
        )
    reach = np.sqrt(3.0 * np.clip(moments, 0.0, None) / mass)
    offsets = np.concatenate([axes.T * reach[:, np.newaxis], -(axes.T * reach[:, np.newaxis])])
    return ref + r + offsets, np.full(6, mass / 6.0)


class _Builder:
    """Tags and commands of one OpenSees model."""

    def __init__(self, ops: Any, scale: float) -> None:
        self.ops = ops
        self.nodes = 0
        self.elements = 0
        self.transforms = 0
        ops.uniaxialMaterial("Elastic", 1, PENALTY * scale)

    def node(self, xyz: FloatArray) -> int:
        self.nodes += 1
        self.ops.node(self.nodes, *(float(v) for v in xyz))
        return self.nodes

    def element(self, *args: Any) -> None:
        self.elements += 1
        self.ops.element(args[0], self.elements, *args[1:])

    def beam(
        self,
        a: int,
        b: int,
        pa: FloatArray,
        pb: FloatArray,
        parts: tuple[Section, MemberMass, int, float, float],
    ) -> None:
        """A member from node ``a`` to ``b``, cut into equal elements."""
        section, mass, segments, young, shear = parts
        x = (pb - pa) / np.linalg.norm(pb - pa)
        side = np.eye(3)[int(np.argmin(np.abs(x)))]
        self.transforms += 1
        self.ops.geomTransf("Linear", self.transforms, *np.cross(x, side).tolist())
        area, polar, inertia = section.EA / young, section.GJ / shear, section.EI / young
        props = (area, young, shear, polar, inertia, inertia)
        chain = [a, *(self.node(pa + (pb - pa) * k / segments) for k in range(1, segments)), b]
        for u, v in itertools.pairwise(chain):
            self.element(
                "elasticBeamColumn", u, v, *props, self.transforms, "-mass", mass.mu, "-cMass"
            )

    def hinge(self, a: int, b: int, axis: FloatArray, dirs: tuple[int, ...]) -> None:
        """Block the motions ``dirs`` (1-6, local axes with x = ``axis``) between a and b."""
        side = np.eye(3)[int(np.argmin(np.abs(axis)))]
        y = np.cross(axis, side)
        mats = [1] * len(dirs)
        self.element(
            "zeroLength",
            a,
            b,
            "-mat",
            *mats,
            "-dir",
            *dirs,
            "-orient",
            *axis,
            *(y / np.linalg.norm(y)),
        )


def _build(
    ops: Any,
    point: FloatArray,
    params: OrthoglideParams,
    masses: tuple[MemberMass, MemberMass],
    plat: FloatArray,
    carriage: float,
    segments: int,
) -> None:
    """Define the model of the module in OpenSees' domain (wiped first)."""
    e, g = params.youngs_modulus, params.shear_modulus
    bar = bar_section(params.bar_radius, params.bar_wall, e, g)
    link = link_section(params.link_radius, e, g)
    shortest = min(params.parallelogram_width / 2.0, params.leg_length) / segments
    scale = max(bar.EA, link.EA, bar.EI / shortest**2, link.EI / shortest**2) / shortest
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    b = _Builder(ops, scale)
    ops.uniaxialMaterial("Elastic", 2, params.actuator_stiffness)
    nodes = {k: v[0] for k, v in member_nodes(point[np.newaxis], params).items()}
    tool = b.node(point)
    where, amount = platform_point_masses(plat, point)
    for xyz, m in zip(where, amount, strict=True):
        n = b.node(xyz)
        ops.mass(n, m, m, m, 0.0, 0.0, 0.0)
        ops.rigidLink("beam", tool, n)
    for i in range(3):
        j = (i + 1) % 3
        axis, normal = nodes["axis"][i], nodes["normal"][i]
        c = b.node(nodes["C"][i])
        ops.fix(c, *(0 if dof in (i, 3 + j) else 1 for dof in range(6)))
        ops.mass(c, carriage, carriage, carriage, 0.0, 0.0, 0.0)
        frame = b.node(nodes["C"][i])
        ops.fix(frame, *([1] * 6))
        b.element("zeroLength", frame, c, "-mat", 2, "-dir", i + 1)
        d_plat = b.node(nodes["D"][i])
        ops.rigidLink("beam", tool, d_plat)
        d = b.node(nodes["D"][i])
        b.hinge(d_plat, d, axis, (1, 2, 3, 5, 6))
        ends = {key: b.node(nodes[key][i]) for key in ("A0", "B0", "A1", "B1")}
        for mid, mid_key, keys in ((c, "C", ("A0", "B0")), (d, "D", ("A1", "B1"))):
            for key in keys:
                b.beam(
                    mid,
                    ends[key],
                    nodes[mid_key][i],
                    nodes[key][i],
                    (link, masses[1], segments, e, g),
                )
        for low, up in (("A0", "A1"), ("B0", "B1")):
            tips = []
            for key in (low, up):
                tip = b.node(nodes[key][i])
                ops.equalDOF(ends[key], tip, 1, 2, 3)
                b.hinge(ends[key], tip, normal, (5, 6))
                tips.append(tip)
            b.beam(tips[0], tips[1], nodes[low][i], nodes[up][i], (bar, masses[0], segments, e, g))
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("BandGeneral")


def frame_fea_modes(
    params: OrthoglideParams | None = None,
    point: ArrayLike = (0.0, 0.0, 0.0),
    drive: Drive | DriveTrain | None = None,
    count: int = 6,
    *,
    segments: int = SEGMENTS,
) -> FloatArray:
    """The lowest natural frequencies at a tool point, from OpenSees (see the module).

    Args:
        params: Machine parameters; the prototype when ``None``.
        point: Tool point [m], shape (3,), within the slider limits.
        drive: A drive whose rotary inertia is reflected onto each carriage
            (as :func:`~orthoglide_pin.elasticity.modes.natural_frequencies`); ``None``: none.
        count: Number of frequencies, from 1 to :data:`MAX_MODES`.
        segments: Elements per member, from 1 to :data:`MAX_SEGMENTS`.

    Returns:
        Natural frequencies [Hz], ascending, shape (count,).

    Raises:
        MissingExtraError: OpenSeesPy is not installed (the ``[modal]`` extra).
        InvalidParameterError: A bad point, parameters, drive, count or segments.
        UnreachablePointError, SingularConfigurationError: The point is out of
            reach, beyond the slider limits, singular, or the solver fails.
    """
    p = as_params(params)
    tool = finite_vector("point", point, 3, "[m]")
    m_eq = reflected_mass(drive)
    n_modes = integer("count", count, 1, MAX_MODES)
    cuts = integer("segments", segments, 1, MAX_SEGMENTS)
    check_slider_limits(p, tool)
    inverse_kinematics(tool, p.leg_length)  # reach and serial singularities
    jacobian(tool, p.leg_length)  # parallel singularities
    ops = _opensees()
    table = inertia_table(p)
    masses, plat = member_masses(p, table), platform_inertia(p, table)
    carriage = float(np.mean([b.mass for b in table.kind("carriage")])) + m_eq
    with _LOCK:
        try:
            _build(ops, tool, p, masses, plat, carriage, cuts)
            # ARPACK converges much faster with room beyond the modes wanted
            found = ops.eigen(SOLVER, max(2 * n_modes, SUBSPACE))
            w2 = np.sort(np.asarray(found, dtype=float))[:n_modes]
        except Exception as exc:  # OpenSees reports its failures as bare exceptions
            raise SingularConfigurationError(
                tool, None, "structural", f"OpenSees' eigensolver failed ({exc})"
            ) from None
        finally:
            ops.wipe()
    if w2.shape != (n_modes,) or not np.all(np.isfinite(w2)) or w2[0] <= 0.0:
        raise SingularConfigurationError(
            tool, None, "structural", "OpenSees found a zero or no frequency there"
        )
    out: FloatArray = np.sqrt(w2) / (2.0 * math.pi)
    return out
