"""The tool tip's vibration in the feed plane: a modal model and its frequency response.

Chatter lives in the plane of the cut: the tool tip's motion along the
program's X and Y (the feed plane of a ``G17`` program). Its model is a set of
independent modes, each with a modal mass ``m_k`` [kg], a natural frequency
``f_k`` [Hz], a damping ratio ``zeta_k`` [-] and a shape ``u_k`` (2,): the tool
tip moves by ``r = U q`` for modal coordinates ``q`` and a force ``F`` [N] at
the tip drives ``m_k q_k'' + c_k q_k' + k_k q_k = u_k . F``. The tip's
receptance (frequency response) is then

    G(omega) = sum_k u_k u_k^T / (k_k - m_k omega^2 + i c_k omega)   [m/N],

with ``k_k = m_k (2 pi f_k)^2`` and ``c_k = 2 zeta_k sqrt(k_k m_k)``.

The machine's part (:func:`tool_tip_model`) comes from its natural modes at
the point (:func:`~orthoglide_pin.elasticity.modes.natural_frequencies`): each
mode is normalised to the mass matrix, ``phi^T M phi = 1``, so its tool
translation ``t_k`` [kg^-1/2] is the tip's motion per unit modal coordinate of a
1 kg modal mass. Brought to the program's axes (the design's
:class:`~orthoglide_pin.program.axes.ProgramAxes`), its X and Y components give
``u_k`` scaled to unit length and ``m_k = 1 / |u_k|^2``, the mass that the
mode shows to a force in the plane. The structure's damping is not modelled:
every machine mode gets one modal damping ratio (the cut file's, by default
:data:`~orthoglide_pin.machining.cutting.DEFAULT_MODAL_DAMPING`). The tool's
and spindle's own modes (the cut file's measured modes: frequency, damping,
stiffness along X or Y) are added in series: their receptances add to the machine's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    finite_number,
    finite_vector,
    flag,
    float_array,
    instance_of,
    number_in,
    positive_number,
)
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import DEFAULT_MODAL_DAMPING
from orthoglide_pin.program.axes import ProgramAxes, design_axes

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

__all__ = [
    "ModalModel",
    "frequency_response",
    "single_mode",
    "tool_tip_model",
    "tool_tip_models",
]

#: Modes whose in-plane flexibility ``|u|^2 / k`` is below this share of the
#: largest are dropped (they move the tool out of the plane) [-].
NEGLIGIBLE_MODE: Final[float] = 1e-6
#: Axis names of the two in-plane directions.
AXES: Final = ("x", "y")


def _vector(
    name: str, value: ArrayLike, low: float, high: float, unit: str, size: int = 0
) -> FloatArray:
    bad = isinstance(value, (str, dict))
    arr = np.empty(0) if bad else np.atleast_1d(float_array(value))
    if size and arr.size == 1 and arr.ndim == 1:
        arr = np.full(size, arr[0])
    if (
        arr.ndim != 1
        or arr.size == 0
        or (size and arr.size != size)
        or not np.all(np.isfinite(arr))
    ):
        what = f"{size} finite numbers" if size else "a non-empty vector of finite numbers"
        raise InvalidParameterError(name, value, f"{what} {unit}")
    if np.any(arr <= low) or np.any(arr >= high):
        raise InvalidParameterError(name, value, f"values in ({low:g}, {high:g}) {unit}")
    return arr


@dataclass(frozen=True)
class ModalModel:
    """Modes of the tool tip in the feed plane (see the module).

    Attributes:
        frequencies: Natural frequencies [Hz], shape (n,).
        damping: Damping ratios [-], shape (n,), each in (0, 1).
        masses: Modal masses [kg], shape (n,).
        shapes: The tip's motion per modal coordinate along X and Y [-], shape (2, n).
        sources: What each mode is (``"machine"`` or ``"tool x"``, ``"tool y"``).
    """

    frequencies: FloatArray
    damping: FloatArray
    masses: FloatArray
    shapes: FloatArray
    sources: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        f = _vector("frequencies", self.frequencies, 0.0, math.inf, "[Hz]")
        n = f.size
        z = _vector("damping", self.damping, 0.0, 1.0, "[-]", n)
        m = _vector("masses", self.masses, 0.0, math.inf, "[kg]", n)
        u = float_array(self.shapes)
        if u.shape != (2, n) or not np.all(np.isfinite(u)):
            raise InvalidParameterError(
                "shapes", self.shapes, f"finite numbers of shape (2, {n}) (X and Y per mode)"
            )
        given = self.sources
        ok = isinstance(given, (tuple, list)) and all(isinstance(x, str) for x in given)
        src = tuple(given) if ok and given else ("machine",) * n
        if not ok or len(src) != n:
            raise InvalidParameterError("sources", self.sources, f"{n} labels, one per mode")
        for name, value in (("frequencies", f), ("damping", z), ("masses", m), ("shapes", u)):
            object.__setattr__(self, name, np.array(value, dtype=np.float64))
        object.__setattr__(self, "sources", src)

    @property
    def count(self) -> int:
        """Number of modes."""
        return int(self.frequencies.size)

    @property
    def omega(self) -> FloatArray:
        """Natural angular frequencies [rad/s], shape (n,)."""
        return np.asarray(2.0 * math.pi * self.frequencies)

    @property
    def stiffnesses(self) -> FloatArray:
        """Modal stiffnesses ``k = m omega^2`` [N/m], shape (n,)."""
        return np.asarray(self.masses * self.omega**2)

    @property
    def viscous(self) -> FloatArray:
        """Modal viscous damping ``c = 2 zeta m omega`` [N.s/m], shape (n,)."""
        return np.asarray(2.0 * self.damping * self.masses * self.omega)

    def static_compliance(self) -> FloatArray:
        """The tip's static compliance in the plane ``sum u u^T / k`` [m/N], (2, 2)."""
        return np.asarray((self.shapes / self.stiffnesses) @ self.shapes.T)

    def rotated(self, angle: float) -> ModalModel:
        """The model in axes turned by ``angle`` [rad] about Z: x along the feed.

        Args:
            angle: The feed's direction in the X-Y plane, from +X towards +Y [rad].
        """
        turn = finite_number("angle", angle, "[rad]")
        c, s = math.cos(turn), math.sin(turn)
        rot = np.array([[c, s], [-s, c]])  # feed-frame coordinates of a program vector
        return ModalModel(
            self.frequencies, self.damping, self.masses, rot @ self.shapes, self.sources
        )

    def with_modes(self, other: ModalModel) -> ModalModel:
        """This model and ``other``'s modes together (receptances in series add)."""
        instance_of("other", other, ModalModel, "a ModalModel")
        return ModalModel(
            np.concatenate([self.frequencies, other.frequencies]),
            np.concatenate([self.damping, other.damping]),
            np.concatenate([self.masses, other.masses]),
            np.concatenate([self.shapes, other.shapes], axis=1),
            self.sources + other.sources,
        )

    def significant(self, share: float = NEGLIGIBLE_MODE, resonant: bool = False) -> ModalModel:
        """The modes whose in-plane flexibility is at least ``share`` of the largest.

        Args:
            share: The least share kept [-].
            resonant: Compare the flexibilities at resonance, ``|u|^2 / (2 zeta k)``
                (the peaks of the receptance), instead of the static ones.
        """
        share = number_in("share", share, 0.0, 1.0, "[-]")
        resonant = flag("resonant", resonant)
        flex = np.sum(self.shapes**2, axis=0) / self.stiffnesses
        if resonant:
            flex = flex / (2.0 * self.damping)
        keep = flex >= share * float(np.max(flex))
        if not np.any(keep):  # pragma: no cover - the largest always passes
            keep[np.argmax(flex)] = True
        return ModalModel(
            self.frequencies[keep],
            self.damping[keep],
            self.masses[keep],
            self.shapes[:, keep],
            tuple(s for s, k in zip(self.sources, keep, strict=True) if k),
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: one entry per mode, stiffness in [N/m]."""
        return {
            "modes": [
                {
                    "frequency": float(self.frequencies[k]),
                    "damping": float(self.damping[k]),
                    "mass": float(self.masses[k]),
                    "stiffness": float(self.stiffnesses[k]),
                    "shape": self.shapes[:, k].tolist(),
                    "source": self.sources[k],
                }
                for k in range(self.count)
            ]
        }


def single_mode(
    frequency: float, damping: float, stiffness: float, direction: str = "x", source: str = ""
) -> ModalModel:
    """One mode along X or Y from its frequency [Hz], damping [-] and stiffness [N/m]."""
    axis = AXES.index(direction) if isinstance(direction, str) and direction in AXES else -1
    if axis < 0:
        raise InvalidParameterError("direction", direction, "'x' or 'y'")
    if not isinstance(source, str):
        raise InvalidParameterError("source", source, "a label (str)")
    k = positive_number("stiffness", stiffness, "a positive finite number [N/m]")
    f = positive_number("frequency", frequency, "a positive finite number [Hz]")
    zeta = number_in("damping", damping, 0.0, 1.0, "[-]")
    shape = np.zeros((2, 1))
    shape[axis, 0] = 1.0
    return ModalModel(
        np.array([f]),
        np.array([zeta]),
        np.array([k / (2.0 * math.pi * f) ** 2]),
        shape,
        (source or f"tool {direction}",),
    )


def frequency_response(model: ModalModel, frequencies: ArrayLike) -> ComplexArray:
    """The tip's receptance ``G`` [m/N] at frequencies [Hz], shape (..., 2, 2).

    ``G[..., i, j]`` is the displacement along axis i (X, Y) per unit force along j.
    """
    instance_of("model", model, ModalModel, "a ModalModel")
    f = float_array(frequencies) if not isinstance(frequencies, (str, dict)) else np.empty(0)
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f < 0.0):
        raise InvalidParameterError("frequencies", frequencies, "finite frequencies >= 0 [Hz]")
    w = 2.0 * math.pi * f[..., np.newaxis]
    den = model.stiffnesses - model.masses * w**2 + 1j * model.viscous * w  # (..., n)
    u = model.shapes
    return np.asarray(np.einsum("in,...n,jn->...ij", u, 1.0 / den, u), dtype=np.complex128)


def tool_tip_models(
    params: OrthoglideParams | None = None,
    points: ArrayLike = (0.0, 0.0, 0.0),
    *,
    damping: float = DEFAULT_MODAL_DAMPING,
    tool: ModalModel | None = None,
    drive: Drive | DriveTrain | None = None,
    count: int = 6,
    model: str = "platform",
    axes: ProgramAxes | None = None,
) -> list[ModalModel]:
    """The tool tip's modes in the feed plane at each of a batch of points.

    Args:
        params: Machine parameters; the prototype when ``None``.
        points: Tool points in the world frame [m], shape (3,) or (n, 3).
        damping: Modal damping ratio of every machine mode [-], in (0, 1).
        tool: The tool's and spindle's own modes (:func:`single_mode`), added in series.
        drive: A drive whose rotary inertia is reflected onto the carriages.
        count: Machine modes kept (see
            :func:`~orthoglide_pin.elasticity.modes.natural_frequencies`).
        model: ``"platform"`` (vectorised) or ``"full"`` (point by point).
        axes: The program's axes on the machine (the design's when ``None``):
            the feed plane is the program's X-Y plane.

    Returns:
        One :class:`ModalModel` per point, X and Y of the program; modes that
        do not move the tool in the plane (flexibility below
        :data:`NEGLIGIBLE_MODE` of the largest) are left out.

    Raises:
        InvalidParameterError: Bad damping, tool, axes (and see ``natural_frequencies``).
        UnreachablePointError, SingularConfigurationError: As ``natural_frequencies``.
    """
    from orthoglide_pin.elasticity.modes import natural_frequencies

    zeta = number_in("damping", damping, 0.0, 1.0, "[-]")
    if zeta <= 0.0 or zeta >= 1.0:
        raise InvalidParameterError("damping", damping, "a ratio in (0, 1) [-]")
    if tool is not None:
        instance_of("tool", tool, ModalModel, "a ModalModel (single_mode) or None")
    frame = design_axes(params) if axes is None else axes
    instance_of("axes", frame, ProgramAxes, "ProgramAxes or None")
    modes = natural_frequencies(params, points, drive, count=count, model=model)
    assert modes.tool_motion is not None  # natural_frequencies keeps it
    freq = modes.frequencies.reshape(-1, modes.frequencies.shape[-1])
    # program X and Y components of the world tool translation of each mode
    motion = modes.tool_motion.reshape(freq.shape[0], -1, 3) @ frame.matrix[:, :2]  # (p, n, 2)
    out = []
    for f, t in zip(freq, motion, strict=True):
        size2 = np.maximum(np.sum(t**2, axis=1), 1e-300)
        shapes = (t / np.sqrt(size2)[:, np.newaxis]).T
        machine = ModalModel(f, np.full(f.size, zeta), 1.0 / size2, shapes).significant()
        out.append(machine if tool is None else machine.with_modes(tool))
    return out


def tool_tip_model(
    params: OrthoglideParams | None = None,
    point: ArrayLike = (0.0, 0.0, 0.0),
    **options: Any,
) -> ModalModel:
    """The tool tip's modes in the feed plane at one point (:func:`tool_tip_models`).

    Args:
        params: Machine parameters; the prototype when ``None``.
        point: Tool point in the world frame [m], shape (3,).
        **options: ``damping``, ``tool``, ``drive``, ``count``, ``model``, ``axes``.
    """
    p = finite_vector("point", point, 3, "[m] (one point x, y, z)")
    return tool_tip_models(params, p, **options)[0]
