"""Natural frequencies and mode shapes of the machine at tool points.

Two models, both linear about the machine at rest at the point:

* ``"full"`` (:mod:`~orthoglide_pin.elasticity.frame_modes`): the stiffness
  model's members with their consistent beam masses, subdivided until the
  frequencies converge, the platform, spindle and tool as one rigid body, each
  carriage on its rail against its actuator spring. It has the bars' own
  bending modes (near 500 Hz on the prototype) and is solved point by point;
* ``"platform"`` (:mod:`~orthoglide_pin.elasticity.platform_model`): the
  platform (six motions), the three carriages on their rails and each leg's
  bars bending together in their plane; each leg's members statically condensed
  onto its carriage and the platform, the actuator springs between the
  carriages and the frame, and the bars and small links as rods moving with
  their ends. Its masses do not depend on any stiffness, so its frequencies
  obey Rayleigh's bounds (stiffening a part raises none by more than the
  square root of the factor). Vectorised over points (its cost:
  ``benchmarks/bench_modes.py``). Against the full model, over the cubes of
  the prototype, a 340.75 mm leg and a 0.15 m design, with and without a
  drive: the three lowest frequencies within 2.5 % (see the guide for the
  measured figures), also where the bars' bending comes first (legs of 0.7 m
  and more).

**Drives.** Given a drive, its rotary inertia (rotor, gear, screw) is
reflected onto its carriage, ``m_eq = (J_rotor + J_screw / n^2) (2 pi n /
l)^2``, and sits **on the carriage side of the actuator spring**: the screw,
nut and bearings are the spring, and the rotor turns with the carriage. This
holds for a stiff screw and a soft (or open) servo loop. A stiff position loop
holds the motor still instead: the reflected inertia then drops out, and a
flexible screw puts part of it on the motor side, between the spring and the
frame, which raises the modes where the carriages move. Without a drive the
carriages move alone (the output says so).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import capped_points, choice, instance_of
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.elasticity import frame_modes as fm
from orthoglide_pin.elasticity import platform_model as pm
from orthoglide_pin.elasticity.mass import member_masses, platform_inertia, reflected_mass
from orthoglide_pin.elasticity.stiffness import BLOCK
from orthoglide_pin.exceptions import InvalidParameterError, SingularConfigurationError
from orthoglide_pin.kinematics.closed_form import (
    ik_and_jacobian,
    inverse_jacobian,
    inverse_kinematics,
)
from orthoglide_pin.kinematics.singularity import check_inverse_jacobian
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams, prototype

FloatArray = NDArray[np.float64]

__all__ = ["MODELS", "NaturalModes", "natural_frequencies", "tool_mass"]

#: The two vibration models.
MODELS: Final = ("platform", "full")
#: Most points of one call: about 7 kB and 0.14 ms each (platform model), 1 GB in all.
MAX_POINTS: Final[int] = 100_000
#: Modes of the platform model (the rigid platform's six motions).
PLATFORM_MODES: Final[int] = 6
#: Most modes asked of the full model (its coarsest subdivision's size).
FULL_MODES: Final[int] = fm.model_size(fm.SEGMENTS[0])
#: Tool motion below which a mode is called a pure rotation (relative to the
#: largest motion of the platform's points within 1 m of the tool) [-].
_PURE_ROTATION: Final[float] = 1e-9


@dataclass(frozen=True)
class NaturalModes:
    """Natural frequencies and mode shapes at a batch of points.

    Attributes:
        points: Tool points [m], shape (..., 3).
        frequencies: Natural frequencies [Hz], ascending, shape (..., count).
        direction: The tool tip's direction of motion in each mode (unit), shape
            (..., count, 3); zero for a rotation about the tool tip.
        rotation: The platform's rotation per metre of tool motion [rad/m],
            shape (..., count, 3).
        energy: Kinetic-energy shares of the platform (with spindle and tool),
            the carriages (with the drives) and the members, shape (..., count, 3).
        model: ``"platform"`` or ``"full"``.
        drive_mass: Reflected drive mass on each carriage [kg] (0: no drive).
        segments: Elements per member of the full model (per point), or ``None``.
        tool_motion: The tool tip's translation per unit modal coordinate, the
            modes normalised to the mass matrix (``phi^T M phi = 1``)
            [kg^-1/2], shape (..., count, 3): modal masses and receptances at
            the tool (:mod:`~orthoglide_pin.machining.frf`); ``None`` if not kept.
    """

    points: FloatArray
    frequencies: FloatArray
    direction: FloatArray
    rotation: FloatArray
    energy: FloatArray
    model: str
    drive_mass: float
    segments: NDArray[np.intp] | None
    tool_motion: FloatArray | None = None

    @property
    def lowest(self) -> FloatArray:
        """The lowest frequency [Hz] at each point, shape (...)."""
        return np.asarray(self.frequencies[..., 0])

    def assumptions(self) -> list[str]:
        """What the frequencies assume, one sentence per line."""
        lines = [
            "Linear vibration about the machine at rest at each point, no damping.",
            "Stiffness: actuators and members, ideal revolutes (the stiffness model).",
        ]
        if self.model == "full":
            lines.append(
                "Full model: consistent beam masses, members subdivided until two successive "
                f"subdivisions agree within {fm.CONVERGENCE:g} (relative)."
            )
        else:
            lines.append(
                "Platform model: the platform's 6x6 stiffness against its inertia plus the legs "
                "and drives reduced to the tool's translation; no member vibration."
            )
        if self.drive_mass > 0.0:
            lines.append(
                f"Drive: {self.drive_mass:.4g} kg reflected onto each carriage, on the carriage "
                "side of the actuator spring (a stiff servo loop would remove it)."
            )
        else:
            lines.append("No drive: the carriages move alone (no reflected rotor inertia).")
        return lines

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form of the first (or only) point's modes."""
        freq = self.frequencies.reshape(-1, self.frequencies.shape[-1])
        count = freq.shape[1]
        direction = self.direction.reshape(-1, count, 3)
        rotation = self.rotation.reshape(-1, count, 3)
        energy = self.energy.reshape(-1, count, 3)
        return {
            "point": self.points.reshape(-1, 3)[0].tolist(),
            "model": self.model,
            "frequencies": freq[0].tolist(),
            "shapes": [
                {
                    "frequency": float(freq[0, k]),
                    "tool_direction": direction[0, k].tolist(),
                    "platform_rotation": rotation[0, k].tolist(),
                    "energy": dict(zip(fm.PARTS, energy[0, k].tolist(), strict=True)),
                }
                for k in range(count)
            ],
            "drive_mass": self.drive_mass,
            "segments": None if self.segments is None else int(self.segments.reshape(-1)[0]),
            "assumptions": self.assumptions(),
        }


def _count(count: Any, model: str) -> int:
    high = PLATFORM_MODES if model == "platform" else FULL_MODES
    ok = isinstance(count, (int, np.integer)) and not isinstance(count, bool)
    if not ok or not 1 <= int(count) <= high:
        raise InvalidParameterError(
            "count", count, f"an integer from 1 to {high} (the {model} model's modes)"
        )
    return int(count)


def tool_mass(params: OrthoglideParams, points: FloatArray, model: Any = None) -> FloatArray:
    """Mass matrix of the rigid machine reduced to the tool's translation [kg], (n, 3, 3).

    ``T = 0.5 v^T M_x v`` for a tool velocity ``v``: Pinocchio's joint-space
    mass matrix (``crba``) of the cut tree brought to the tool through the
    gradients ``R = df/dP`` of each leg's joint functions, ``M_x = R^T P M P^T R``
    (every body, without the drives; as in
    :mod:`~orthoglide_pin.dynamics.motion_forms`).

    Args:
        params: Machine parameters.
        points: Tool points [m], shape (n, 3).
        model: The machine's :class:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel`
            (built from ``params`` when ``None``).
    """
    import pinocchio as pin

    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.kinematics.joint_motion import LEG_JOINTS, leg_motion, scatter
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    dyn = ClosedLoopDynamics(ClosedLoopModel(params) if model is None else model)
    idx = dyn.leg_indices
    zero = np.zeros_like(points)
    motion = leg_motion(points, zero, zero, params.leg_length)
    q = scatter(motion.values, idx)
    n, nv = q.shape
    proj = np.zeros((9, nv))  # joint velocities from joint-function rates, leg by leg
    for slot, (_, fn, sign) in enumerate(LEG_JOINTS):
        proj[3 * np.arange(3) + fn, idx[:, slot]] += sign
    engine = dyn.engine((0.0, 0.0, 0.0))
    mass = np.empty((n, nv, nv))
    crba, pin_model, pin_data = pin.crba, engine.model, engine.data
    for k in range(n):
        mass[k] = crba(pin_model, pin_data, q[k])
    upper = np.triu(np.ones((nv, nv), dtype=bool))
    mass = np.where(upper, mass, np.swapaxes(mass, 1, 2))  # crba fills the upper triangle
    r = motion.gradients.reshape(n, 9, 3)
    m_f = proj @ mass @ proj.T
    out = np.swapaxes(r, 1, 2) @ m_f @ r
    return np.asarray(0.5 * (out + np.swapaxes(out, 1, 2)), dtype=np.float64)


def _shapes(phi: FloatArray, parts: list[FloatArray]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tool direction, rotation [rad/m] and energy shares of modes ``phi`` (n, 6+, k)."""
    t, w = phi[:, :3, :], phi[:, 3:6, :]
    size = np.linalg.norm(t, axis=1)  # (n, k)
    floor = _PURE_ROTATION * np.maximum(size, np.linalg.norm(w, axis=1))
    moving = size > floor
    big = np.argmax(np.abs(t), axis=1)[:, np.newaxis, :]
    sign = np.where(np.take_along_axis(t, big, axis=1) < 0.0, -1.0, 1.0)
    safe = np.where(moving, size, 1.0)[:, np.newaxis, :]
    direction = np.where(moving[:, np.newaxis, :], sign * t / safe, 0.0)
    rotation = np.where(moving[:, np.newaxis, :], sign * w / safe, 0.0)
    energies = np.stack([np.sum(phi * (m @ phi), axis=1) for m in parts], axis=-1)
    total = np.sum(energies, axis=-1, keepdims=True)
    return (
        np.swapaxes(direction, 1, 2),
        np.swapaxes(rotation, 1, 2),
        energies / np.where(total > 0.0, total, 1.0),
    )


def natural_frequencies(
    params: OrthoglideParams | None = None,
    points: ArrayLike = (0.0, 0.0, 0.0),
    drive: Drive | DriveTrain | None = None,
    count: int = 6,
    model: str = "platform",
) -> NaturalModes:
    """Natural frequencies and mode shapes at tool points (see the module).

    Args:
        params: Machine parameters; the prototype when ``None``.
        points: Tool points [m], shape (3,) or (..., 3), within the slider limits;
            at most :data:`MAX_POINTS` of them.
        drive: A drive (``--motor`` file, :func:`~orthoglide_pin.drives.motor.load_drive`)
            whose rotary inertia is reflected onto each carriage; ``None``: none.
        count: Number of modes, from 1 to 6 (platform model) or to
            :data:`FULL_MODES` (full model).
        model: ``"platform"`` (vectorised) or ``"full"`` (point by point).

    Returns:
        The lowest ``count`` frequencies [Hz] and their shapes at each point.

    Raises:
        InvalidParameterError: Bad points (or more than :data:`MAX_POINTS`), drive,
            count or model.
        UnreachablePointError, SingularConfigurationError: A point out of reach
            or beyond the slider limits, or (near) singular.
    """
    params = prototype() if params is None else params
    instance_of("params", params, OrthoglideParams, "OrthoglideParams or None")
    model = choice("model", model, MODELS)
    n_modes = _count(count, model)
    m_eq = reflected_mass(drive)
    p = capped_points(points, "points", MAX_POINTS)
    shape = p.shape[:-1]
    flat = np.ascontiguousarray(p.reshape(-1, 3))
    check_slider_limits(params, flat)
    inverse_kinematics(flat, params.leg_length)
    ik_and_jacobian(flat, params.leg_length)  # parallel singularities
    table = inertia_table(params)
    segments = None
    masses, plat = member_masses(params, table), platform_inertia(params, table)
    m_c = float(np.mean([b.mass for b in table.kind("carriage")])) + m_eq
    if model == "platform":
        # judged as the stiffness model judges them (the condition number of J)
        check_inverse_jacobian(inverse_jacobian(flat, params.leg_length), flat)
        blocks = []
        for start in range(0, flat.shape[0], BLOCK):  # blocks that stay in the cache
            chunk = flat[start : start + BLOCK]
            k_b, parts = pm.platform_matrices(chunk, params, masses, plat, m_c)
            w2_b, phi = pm.platform_modes(k_b, parts, chunk, n_modes)
            blocks.append((w2_b, *_shapes(phi, parts), np.swapaxes(phi[:, :3, :], 1, 2)))
        w2, direction, rotation, energy, motion = (
            np.concatenate(col) for col in zip(*blocks, strict=True)
        )
    else:
        rows = []
        for point in flat:
            try:
                w2_k, phi, mats = fm.frame_modes(point, params, masses, plat, m_c, n_modes)
            except SingularConfigurationError:
                raise SingularConfigurationError(
                    point, None, "structural", "the structure is a mechanism there"
                ) from None
            # the platform's six motions come first in the full model's DOFs
            parts = [mats.parts[name][np.newaxis] for name in fm.PARTS]
            rows.append((w2_k, *_shapes(phi[np.newaxis], parts), mats.segments, phi[:3].T))
        w2 = np.stack([r[0] for r in rows])
        direction, rotation, energy = (np.concatenate([r[i] for r in rows]) for i in (1, 2, 3))
        motion = np.stack([r[5] for r in rows])
        segments = np.array([r[4] for r in rows], dtype=np.intp).reshape(shape)
    freq = np.sqrt(w2) / (2.0 * math.pi)
    return NaturalModes(
        points=p,
        frequencies=freq.reshape(*shape, n_modes),
        direction=direction.reshape(*shape, n_modes, 3),
        rotation=rotation.reshape(*shape, n_modes, 3),
        energy=energy.reshape(*shape, n_modes, 3),
        model=model,
        drive_mass=m_eq,
        segments=segments,
        tool_motion=motion.reshape(*shape, n_modes, 3),
    )
