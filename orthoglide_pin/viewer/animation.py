"""A trajectory played in the browser: per-frame placements of every moving visual.

The tool path of a trajectory (times ``t`` [s], shape (N,), tool points ``p``
[m], shape (N, 3)) is resampled at a frame rate, each frame's configuration of
the 18 joints is computed in closed form with every loop closed
(:meth:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel.configuration`), and each
visual that moves gets a meshcat animation clip: position and quaternion
keyframes (three.js interpolates between them). An ellipsoid can follow the
tool: its clip adds a scale track (the semi-axes) and a colour track (the
condition number).

Keyframe times are in frames (meshcat's clips divide them by their ``fps``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.viewer.scene import meshcat

FloatArray = NDArray[np.float64]

#: Default frame rate of an animation [1/s].
DEFAULT_FPS: Final[float] = 60.0
#: Most frames in one animation: a longer trajectory gets a lower frame rate.
MAX_FRAMES: Final[int] = 1500
#: Repetitions of a looping clip (it plays until the page is closed).
LOOP_REPETITIONS: Final[int] = 1_000_000


@dataclass(frozen=True)
class Frames:
    """A trajectory resampled at a uniform frame rate.

    Attributes:
        times: Frame times from the start [s], shape (F,).
        points: Tool points [m], shape (F, 3).
        fps: Frame rate [1/s].
    """

    times: FloatArray
    points: FloatArray
    fps: float

    @property
    def keys(self) -> FloatArray:
        """Keyframe times in frames (``times * fps``), shape (F,)."""
        return self.times * self.fps


def samples(trajectory: Any) -> tuple[FloatArray, FloatArray]:
    """Times [s], shape (N,), and tool points [m], shape (N, 3), of a trajectory.

    Args:
        trajectory: An object with attributes ``t`` and ``p`` (such as
            :class:`orthoglide_pin.motion.trajectory.Trajectory`), or a pair ``(t, p)``.

    Raises:
        InvalidParameterError: If the times are not finite and strictly
            increasing, or the points do not match them.
    """
    if hasattr(trajectory, "t") and hasattr(trajectory, "p"):
        t_raw, p_raw = trajectory.t, trajectory.p
    elif isinstance(trajectory, tuple) and len(trajectory) == 2:
        t_raw, p_raw = trajectory
    else:
        raise InvalidParameterError(
            "trajectory",
            type(trajectory).__name__,
            "an object with t (N,) and p (N, 3), or (t, p)",
        )
    t, p = np.asarray(t_raw, dtype=float), np.asarray(p_raw, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.isfinite(t).all() or np.any(np.diff(t) <= 0):
        raise InvalidParameterError(
            "trajectory times", f"array of shape {t.shape}", "N >= 2 finite, increasing times [s]"
        )
    if p.shape != (t.size, 3) or not np.isfinite(p).all():
        raise InvalidParameterError(
            "trajectory points",
            f"array of shape {p.shape}",
            f"finite points of shape ({t.size}, 3)",
        )
    return t, p


def resample(
    t: ArrayLike,
    p: ArrayLike,
    fps: float = DEFAULT_FPS,
    max_frames: int = MAX_FRAMES,
    *,
    time_scale: float = 1.0,
) -> Frames:
    """Resample a tool path at ``fps`` (linear interpolation), at most ``max_frames`` frames.

    The first and last frames are the first and last samples; a path too long
    for ``max_frames`` at ``fps`` gets a lower frame rate.

    Args:
        t: Times [s], shape (N,), increasing.
        p: Tool points [m], shape (N, 3).
        fps: Frame rate [1/s] of the animation.
        max_frames: Most frames.
        time_scale: Animation time over trajectory time (2: half speed).

    Returns:
        The frames; their ``times`` are animation times from 0 [s].
    """
    fps = positive_number("fps", fps, "a positive frame rate [1/s]")
    time_scale = positive_number("time_scale", time_scale, "a positive number")
    t_arr, p_arr = samples((t, p))
    duration = float(t_arr[-1] - t_arr[0]) * time_scale
    count = max(2, min(int(max_frames), math.ceil(duration * fps - 1e-9) + 1))
    times = np.linspace(0.0, duration, count)
    source = t_arr[0] + times / time_scale
    points = np.stack([np.interp(source, t_arr, p_arr[:, k]) for k in range(3)], -1)
    return Frames(times, points, (count - 1) / duration)


def quaternions(rotations: ArrayLike) -> FloatArray:
    """Unit quaternions ``(x, y, z, w)`` (three.js order) of rotations, shape (..., 4).

    Shepperd's method: the largest of ``w, x, y, z`` is taken from the diagonal
    and the others from the off-diagonal terms, accurate for every rotation.
    """
    r = np.asarray(rotations, dtype=float)
    m = r.reshape(-1, 3, 3)
    m00, m11, m22 = m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]
    d10, d02, d21 = m[:, 1, 0] - m[:, 0, 1], m[:, 0, 2] - m[:, 2, 0], m[:, 2, 1] - m[:, 1, 2]
    s01, s02, s12 = m[:, 0, 1] + m[:, 1, 0], m[:, 0, 2] + m[:, 2, 0], m[:, 1, 2] + m[:, 2, 1]
    cases = np.stack([m00 + m11 + m22, m00, m11, m22], -1)
    big = np.argmax(cases, -1)
    q = np.empty((m.shape[0], 4))  # (w, x, y, z)
    with np.errstate(invalid="ignore", divide="ignore"):
        sw = 2.0 * np.sqrt(np.maximum(1.0 + m00 + m11 + m22, 0.0))
        sx = 2.0 * np.sqrt(np.maximum(1.0 + m00 - m11 - m22, 0.0))
        sy = 2.0 * np.sqrt(np.maximum(1.0 - m00 + m11 - m22, 0.0))
        sz = 2.0 * np.sqrt(np.maximum(1.0 - m00 - m11 + m22, 0.0))
        options = [
            np.stack([sw / 4, d21 / sw, d02 / sw, d10 / sw], -1),
            np.stack([d21 / sx, sx / 4, s01 / sx, s02 / sx], -1),
            np.stack([d02 / sy, s01 / sy, sy / 4, s12 / sy], -1),
            np.stack([d10 / sz, s02 / sz, s12 / sz, sz / 4], -1),
        ]
    for k, option in enumerate(options):
        q[big == k] = option[big == k]
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    out: FloatArray = q[:, [1, 2, 3, 0]].reshape(*r.shape[:-2], 4)
    return out


def _continuous(q: FloatArray) -> FloatArray:
    """Flip signs along the first axis (frames) so consecutive quaternions agree."""
    out: FloatArray = q.copy()
    for k in range(1, out.shape[0]):
        flip = np.sum(out[k] * out[k - 1], axis=-1) < 0.0
        out[k][flip] *= -1.0
    return out


def _meshcat_path(path: str) -> Any:
    return meshcat("path").Path(tuple(p for p in path.split("/") if p))


class AnimationBuilder:
    """Collects per-path clips into one ``meshcat.animation.Animation``.

    Args:
        frames: The frames every clip uses.
    """

    def __init__(self, frames: Frames) -> None:
        self.frames = frames
        self._anim = meshcat("animation")
        self.animation = self._anim.Animation(default_framerate=frames.fps)

    def _clip(self, path: str) -> Any:
        key = _meshcat_path(path)
        if key not in self.animation.clips:
            self.animation.clips[key] = self._anim.AnimationClip(fps=self.frames.fps)
        return self.animation.clips[key]

    def _track(self, path: str, name: str, jstype: str, values: FloatArray) -> None:
        keys = [float(k) for k in self.frames.keys]
        rows = [[float(v) for v in row] for row in values]
        self._clip(path).tracks[name] = self._anim.AnimationTrack(name, jstype, keys, rows)

    def transforms(self, path: str, matrices: ArrayLike, *, scale: bool = False) -> None:
        """Position and quaternion tracks (and scale when ``scale``) of ``path``.

        Args:
            path: meshcat path of the node to move.
            matrices: Its 4 x 4 transform at every frame, shape (F, 4, 4) [m].
            scale: Also animate the scale: ``matrices`` are then
                ``[R diag(s) | c]`` with ``R`` a rotation and ``s > 0``.
        """
        m = np.asarray(matrices, dtype=float)
        lin = m[:, :3, :3]
        s = np.linalg.norm(lin, axis=1) if scale else np.ones((m.shape[0], 3))
        self._track(path, "position", "vector3", m[:, :3, 3])
        self._track(
            path, "quaternion", "quaternion", _continuous(quaternions(lin / s[:, None, :]))
        )
        if scale:
            self._track(path, "scale", "vector3", s)

    def colors(self, mesh_path: str, rgb: ArrayLike) -> None:
        """Colour track of the material of the mesh at ``mesh_path`` (``.../<object>``)."""
        self._track(mesh_path, "material.color", "color", np.asarray(rgb, dtype=float))

    def paths(self) -> list[str]:
        """The animated paths."""
        return [p.lower() for p in self.animation.clips]
