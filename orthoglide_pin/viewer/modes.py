"""A natural mode played in the browser: the machine oscillating about a tool point.

:func:`mode_motion` takes one mode of :func:`~orthoglide_pin.elasticity.modes.natural_frequencies`
at a point ``p0`` (the tool's unit direction ``d`` and the platform's rotation
per metre of tool motion ``w`` [rad/m]) and makes the frames of one period of
the oscillation ``x(t) = s sin(2 pi t / T) (d, w)``:

* the platform, spindle and tool move as one rigid body: the tool tip to
  ``p0 + s sin(.) d``, turned by the rotation vector ``s sin(.) w`` about it;
* each leg follows its own joint on the displaced platform: leg ``i`` takes the
  closed-form configuration of the loops
  (:meth:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel.configuration`)
  of the tool point that puts its platform joint ``r_i`` where the turned
  platform has it, ``p + (R - I) r_i``. Its carriage, bars and small links move
  with it; the legs stay rigid and keep their orientation, so the members' own
  bending (the full model's member modes) and the actuators' compression are
  not drawn.

**Amplitude.** The modes are linear: their size is arbitrary. The drawing
scales the mode so that the largest displacement of the platform's joints and
of the tool tip is ``amplitude`` [m] (default :data:`DEFAULT_AMPLITUDE` of the
cube's side): ``s = amplitude / max(1, |w| reach)``, ``reach`` the distance from
the tool tip to the farthest platform joint. **Time.** One period is played in
:data:`DEFAULT_PERIOD` seconds, over and over: the real oscillation (about
100 Hz and more) is far too fast to see.

A mode in which the tool tip does not move (a rotation about it) has no
direction in the mode shape: it is refused, as are a point outside the
machine's cube or the slider limits and a mode number outside the model's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import choice, finite_vector, positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.viewer.animation import Frames

if TYPE_CHECKING:
    from orthoglide_pin.drives.motor import Drive, DriveTrain
    from orthoglide_pin.elasticity.modes import NaturalModes
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.viewer.machine import MachineDrawing

FloatArray = NDArray[np.float64]

__all__ = ["DEFAULT_AMPLITUDE", "DEFAULT_PERIOD", "ModeMotion", "mode_motion"]

#: Default drawn amplitude, a share of the cube's side [-] (10 mm on the prototype).
DEFAULT_AMPLITUDE: Final[float] = 0.05
#: Largest drawn amplitude, a share of the cube's side [-].
MAX_AMPLITUDE: Final[float] = 0.25
#: Animation time of one period [s].
DEFAULT_PERIOD: Final[float] = 2.0
#: Frames per period.
FRAMES_PER_PERIOD: Final[int] = 60
#: A point this far outside the cube is still inside [m].
CUBE_TOL: Final[float] = 1e-9
#: Links of the platform's rigid body (the others belong to a leg).
PLATFORM_LINKS: Final = ("platform", "spindle", "tool")


@dataclass(frozen=True)
class ModeMotion:
    """One period of a mode, frame by frame.

    Attributes:
        mode: The mode's number, from 1 (the lowest).
        modes: The modes computed at the point (``mode`` of them).
        scale: Tool displacement of the drawing at the top of the swing [m].
        frames: Times [s] (one period), tool tip positions [m], shape (F, 3), frame rate.
        rotations: The platform's orientation at each frame, shape (F, 3, 3).
        configurations: Joint values of each leg's own closure [m, rad], shape (F, 18).
        attachments: The platform joints of the legs from the tool tip at rest [m], (3, 3).
    """

    mode: int
    modes: NaturalModes
    scale: float
    frames: Frames
    rotations: FloatArray
    configurations: FloatArray
    attachments: FloatArray

    @property
    def point(self) -> FloatArray:
        """The tool point at rest [m], shape (3,)."""
        return np.asarray(self.modes.points, dtype=float).reshape(3)

    @property
    def frequency(self) -> float:
        """The mode's natural frequency [Hz]."""
        return float(self.modes.frequencies.reshape(-1)[self.mode - 1])

    @property
    def direction(self) -> FloatArray:
        """The tool tip's unit direction in the mode, shape (3,)."""
        return np.asarray(self.modes.direction.reshape(-1, 3)[self.mode - 1], dtype=float)

    @property
    def rotation(self) -> FloatArray:
        """The platform's rotation per metre of tool motion [rad/m], shape (3,)."""
        return np.asarray(self.modes.rotation.reshape(-1, 3)[self.mode - 1], dtype=float)

    def placements(self, drawing: MachineDrawing) -> dict[str, FloatArray]:
        """Per moving visual, its 4 x 4 placement at every frame [m], shape (F, 4, 4)."""
        mats = drawing.placements(self.configurations)
        rest = drawing.placements(self.configurations[0])
        p0 = self.point
        rigid = np.zeros((len(self.rotations), 4, 4))
        rigid[:, :3, :3] = self.rotations
        rigid[:, :3, 3] = self.frames.points - self.rotations @ p0
        rigid[:, 3, 3] = 1.0
        out = {}
        for i, visual in enumerate(drawing.visuals):
            m = rigid @ rest[i] if visual.link in PLATFORM_LINKS else mats[:, i]
            if not np.allclose(m, m[0], rtol=0.0, atol=1e-12):
                out[visual.name] = m
        return out


def _rotations(vectors: FloatArray) -> FloatArray:
    """Rotation matrices of rotation vectors [rad], shape (F, 3) -> (F, 3, 3)."""
    from scipy.spatial.transform import Rotation

    return np.asarray(Rotation.from_rotvec(vectors).as_matrix(), dtype=float)


def _mode_number(mode: Any, model: str) -> int:
    from orthoglide_pin.elasticity.modes import FULL_MODES, PLATFORM_MODES

    high = PLATFORM_MODES if model == "platform" else FULL_MODES
    ok = isinstance(mode, (int, np.integer)) and not isinstance(mode, bool)
    if not ok or not 1 <= int(mode) <= high:
        raise InvalidParameterError(
            "mode", mode, f"an integer from 1 to {high} (the {model} model's modes)"
        )
    return int(mode)


def _attachments(model: ClosedLoopModel, point: FloatArray) -> FloatArray:
    """Each leg's platform joint from the tool tip [m], (3, 3) (Pinocchio's placements)."""
    import pinocchio as pin

    pin.forwardKinematics(model.model, model.data, model.configuration(point))
    rows = []
    for i in (1, 2, 3):
        joint = model.model.getJointId(f"leg{i}_end_revolute")
        rows.append(np.array(model.data.oMi[joint].translation) - point)
    return np.array(rows)


def _leg_columns(model: ClosedLoopModel) -> list[NDArray[np.intp]]:
    """The joint (velocity) indices of each leg, from the joints' names."""
    names = list(model.model.names)
    joints = model.model.joints
    return [
        np.array(
            [joints[j].idx_v for j, n in enumerate(names) if n.startswith(f"leg{i}_")],
            dtype=np.intp,
        )
        for i in (1, 2, 3)
    ]


def mode_motion(
    model: ClosedLoopModel,
    point: ArrayLike,
    mode: int,
    *,
    drive: Drive | DriveTrain | None = None,
    vibration_model: str = "platform",
    amplitude: float | None = None,
    period: float = DEFAULT_PERIOD,
) -> ModeMotion:
    """The frames of one period of a natural mode at a tool point (see the module).

    Args:
        model: The machine's closed-loop model.
        point: The tool point [m], shape (3,), inside the machine's cube.
        mode: The mode's number, 1 for the lowest, up to 6 (platform model) or
            the full model's :data:`~orthoglide_pin.elasticity.modes.FULL_MODES`.
        drive: A drive whose rotary inertia is reflected onto each carriage, or ``None``.
        vibration_model: ``"platform"`` or ``"full"``
            (:func:`~orthoglide_pin.elasticity.modes.natural_frequencies`).
        amplitude: Largest displacement drawn of the platform's joints and the tool
            tip [m], up to :data:`MAX_AMPLITUDE` of the cube's side; by default
            :data:`DEFAULT_AMPLITUDE` of it.
        period: Animation time of one period [s].

    Returns:
        The motion, frame by frame.

    Raises:
        InvalidParameterError: A bad point (or one outside the cube), mode,
            model, amplitude, period or drive; a mode with no tool motion.
        UnreachablePointError, SingularConfigurationError: A point beyond the
            slider limits, or (near) singular.
    """
    from orthoglide_pin.elasticity.modes import natural_frequencies
    from orthoglide_pin.machine.closed_loop import as_model

    model = as_model(model, "model")
    vibration_model = choice("vibration_model", vibration_model, ("platform", "full"))
    number = _mode_number(mode, vibration_model)
    p0 = finite_vector("point", point, 3, "[m]")
    cube = model.params.workspace
    if np.any(p0 < cube.q1 - CUBE_TOL) or np.any(p0 > cube.q2 + CUBE_TOL):
        mm = ", ".join(f"{1e3 * v:.3f}" for v in p0)
        raise InvalidParameterError("point", f"({mm}) mm", f"a point in the {cube.describe()}")
    side = float(cube.side)
    size = DEFAULT_AMPLITUDE * side if amplitude is None else amplitude
    size = positive_number("amplitude", size, "a positive length [m]")
    if size > MAX_AMPLITUDE * side:
        raise InvalidParameterError(
            "amplitude",
            size,
            f"at most {MAX_AMPLITUDE * side:.6g} m ({MAX_AMPLITUDE:g} of the cube's side)",
        )
    period = positive_number("period", period, "a positive time [s]")
    modes = natural_frequencies(model.params, p0, drive, count=number, model=vibration_model)
    d = modes.direction.reshape(-1, 3)[number - 1]
    w = modes.rotation.reshape(-1, 3)[number - 1]
    if not np.any(d):
        raise InvalidParameterError(
            "mode",
            number,
            "a mode in which the tool tip moves (this one turns the platform about it, "
            "which its shape does not give)",
        )
    r = _attachments(model, p0)
    reach = float(np.linalg.norm(r, axis=1).max())
    scale = size / max(1.0, float(np.linalg.norm(w)) * reach)
    times = np.linspace(0.0, period, FRAMES_PER_PERIOD + 1)
    swing = scale * np.sin(2.0 * math.pi * times / period)
    tips = p0 + swing[:, None] * d
    rotations = _rotations(swing[:, None] * w)
    q = np.zeros((times.size, model.nv))
    for i, cols in enumerate(_leg_columns(model)):
        reached = tips + np.einsum("fij,j->fi", rotations, r[i]) - r[i]
        q[:, cols] = model.configuration(reached)[:, cols]
    frames = Frames(times, tips, FRAMES_PER_PERIOD / period)
    return ModeMotion(number, modes, scale, frames, rotations, q, r)
