"""Chatter stability where the tool is: lobes at a point, a map, the margin along a path.

The machine's modes move with the tool (the prototype's lowest falls from
213 Hz at home to 108 Hz at Q2), so its stability lobes do too. At each point
the tool tip's modal model in the feed plane
(:func:`~orthoglide_pin.machining.frf.tool_tip_models`: the machine's modes
with the cut file's modal damping, plus the tool's own modes) is turned so
that x runs along the feed, and the regenerative milling model of
:mod:`~orthoglide_pin.machining.stability_sd` gives the limiting axial depth:

* :func:`stability_lobes`: the limit against spindle speed at one point, by
  semi-discretization, with the zero-order solution for comparison;
* :func:`limit_depth_map`: the limit at one spindle speed over many points;
* :func:`~orthoglide_pin.machining.stability_path.stability_margin_along`:
  for each block of a program, the limit at its spindle speed divided by its
  engaged axial depth (> 1: stable; 0.5: the cut is twice as deep as it may be).

Modes whose resonant flexibility is below :data:`RELEVANT` of the largest are
left out (they neither move the lobes nor the limit by more than that share).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    capped_points,
    finite_number,
    finite_vector,
    flag,
    instance_of,
)
from orthoglide_pin.drives.motor import Drive, DriveTrain
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining.cutting import RPM_PER_RAD_S, CutConditions, Engagement, Tool
from orthoglide_pin.machining.frf import ModalModel, single_mode, tool_tip_models
from orthoglide_pin.machining.regeneration import MillingProcess, paired, speeds_array
from orthoglide_pin.machining.stability_sd import STEPS, critical_depths_sd
from orthoglide_pin.machining.stability_zoa import critical_depths_zoa
from orthoglide_pin.program.axes import ProgramAxes

FloatArray = NDArray[np.float64]

__all__ = [
    "LOBE_SPEEDS",
    "StabilityLobes",
    "limit_depth_map",
    "milling_process",
    "stability_lobes",
    "tool_model",
]

#: Spindle speeds of the lobes when none are given: 200 from 2,000 to 24,000 rpm.
LOBE_SPEEDS: Final = np.linspace(2000.0, 24000.0, 200) / RPM_PER_RAD_S
#: Least resonant flexibility of a mode kept, as a share of the largest [-].
RELEVANT: Final[float] = 0.01
#: Depths searched for the limit [m]: below, a cut is called unstable at once;
#: above, stable at any depth (``inf``).
DEPTH_RANGE: Final = (1e-5, 0.05)
#: Points per batch of the margin along a path (memory: about 1 MB each).
CHUNK: Final[int] = 100
#: Most points of a map or a path.
MAX_POINTS: Final[int] = 100_000


def tool_model(tool: Tool) -> ModalModel | None:
    """The tool's and spindle's own modes as a modal model (``None`` if it has none)."""
    instance_of("tool", tool, Tool, "a Tool")
    out = None
    for mode in tool.modes:
        one = single_mode(mode.frequency, mode.damping, mode.stiffness, mode.direction)
        out = one if out is None else out.with_modes(one)
    return out


def milling_process(conditions: CutConditions, engagement: Engagement) -> MillingProcess:
    """Teeth, shearing coefficients and immersion of a cut (no edge forces: no chip, no effect)."""
    start, end = engagement.immersion(conditions.tool.diameter)
    m = conditions.material
    return MillingProcess(conditions.tool.teeth, m.kt, m.kr, start, end)


@dataclass(frozen=True)
class StabilityLobes:
    """The limiting axial depth against spindle speed at one point.

    Attributes:
        point: Tool point in the world frame [m], shape (3,).
        speeds: Spindle speeds [rad/s], shape (s,).
        depths: Limiting axial depth by semi-discretization [m], shape (s,).
        zero_order: The same by the zero-order solution [m], shape (s,), or ``None``.
        model: The tip's modes in the feed frame (x along the feed).
        feed_angle: The feed's direction from program +X towards +Y [rad].
        engagement: The engagement (immersion, up or down milling) of the lobes.
    """

    point: FloatArray
    speeds: FloatArray
    depths: FloatArray
    zero_order: FloatArray | None
    model: ModalModel
    feed_angle: float
    engagement: Engagement

    @property
    def minimum(self) -> float:
        """The lowest limiting depth over the speeds [m] (the unconditional limit)."""
        return float(np.min(self.depths))

    def limit_at(self, speed: float) -> float:
        """The limiting depth at a spindle speed [rad/s], between the computed speeds [m]."""
        omega = finite_number("speed", speed, "[rad/s]")
        return float(np.interp(omega, self.speeds, self.depths))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: speeds in rpm, depths in mm (``null`` above the range)."""

        def mm(values: FloatArray) -> list[float | None]:
            return [None if not math.isfinite(v) else float(v) * 1e3 for v in values]

        return {
            "point": self.point.tolist(),
            "feed_angle": self.feed_angle,
            "milling": self.engagement.milling,
            "radial_width_mm": self.engagement.radial_width * 1e3,
            "axial_depth_mm": self.engagement.axial_depth * 1e3,
            "speeds_rpm": (self.speeds * RPM_PER_RAD_S).tolist(),
            "limit_depth_mm": mm(self.depths),
            "zero_order_depth_mm": None if self.zero_order is None else mm(self.zero_order),
            "minimum_depth_mm": self.minimum * 1e3,
            "modes": self.model.to_dict()["modes"],
            "method": "semi-discretization (first order), zero-order for comparison",
        }


def _models(
    params: OrthoglideParams | None,
    points: FloatArray,
    conditions: CutConditions,
    angles: FloatArray,
    options: dict[str, Any],
) -> list[ModalModel]:
    models = tool_tip_models(
        params, points, damping=conditions.modal_damping, tool=tool_model(conditions.tool),
        **options,
    )  # fmt: skip
    return [
        m.significant(RELEVANT, resonant=True).rotated(float(a))
        for m, a in zip(models, angles, strict=True)
    ]


def _check(conditions: CutConditions) -> CutConditions:
    return instance_of("conditions", conditions, CutConditions, "CutConditions (read_cut_file)")


def _engagement(conditions: CutConditions, engagement: Engagement | None) -> Engagement:
    if engagement is not None:
        return instance_of("engagement", engagement, Engagement, "an Engagement or None")
    default = [e for e in conditions.engagements if e.lines is None] or list(
        conditions.engagements
    )
    return default[0]


def stability_lobes(
    conditions: CutConditions,
    point: ArrayLike = (0.0, 0.0, 0.0),
    *,
    params: OrthoglideParams | None = None,
    speeds: ArrayLike | None = None,
    feed_angle: float = 0.0,
    engagement: Engagement | None = None,
    drive: Drive | DriveTrain | None = None,
    model: str = "platform",
    axes: ProgramAxes | None = None,
    zero_order: bool = True,
    steps: int = STEPS,
) -> StabilityLobes:
    """The stability lobes at a point (see the module).

    Args:
        conditions: The cut (tool, material, engagements, modal damping).
        point: Tool point in the world frame [m], shape (3,).
        params: Machine parameters; the prototype when ``None``.
        speeds: Spindle speeds [rad/s]; :data:`LOBE_SPEEDS` when ``None``.
        feed_angle: The feed's direction from program +X towards +Y [rad].
        engagement: The engagement; the conditions' default (the one without
            lines, else the first) when ``None``.
        drive: A drive whose rotary inertia is reflected onto the carriages.
        model: The machine's vibration model, ``"platform"`` or ``"full"``.
        axes: The program's axes on the machine (the design's when ``None``).
        zero_order: Also return the zero-order lobes (they are computed anyway:
            the semi-discretization starts from them).
        steps: Fewest semi-discretization intervals over the cut.

    Raises:
        InvalidParameterError, CutConditionsError: Bad arguments (named).
        UnreachablePointError, SingularConfigurationError: A point out of reach.
    """
    _check(conditions)
    eng = _engagement(conditions, engagement)
    p = finite_vector("point", point, 3, "[m] (one point x, y, z)")
    omega = LOBE_SPEEDS if speeds is None else speeds_array("speeds", speeds)
    angle = finite_number("feed_angle", feed_angle, "[rad]")
    zero_order = flag("zero_order", zero_order)
    options = {"drive": drive, "model": model, "axes": axes}
    tip = _models(params, p[np.newaxis], conditions, np.array([angle]), options)[0]
    process = milling_process(conditions, eng)
    zoa = critical_depths_zoa(tip, process, omega)  # cheap, and a good first guess
    depths = critical_depths_sd(tip, process, omega, DEPTH_RANGE, steps, guess=zoa)
    return StabilityLobes(p, omega, depths, zoa if zero_order else None, tip, angle, eng)


def _speeds(
    conditions: CutConditions, speed: ArrayLike | None, count: int, name: str = "speeds"
) -> FloatArray:
    if speed is None:
        if conditions.spindle_speed is None:
            raise InvalidParameterError(
                "spindle_speed", None, "a speed [rad/s], here or in the cut file"
            )
        speed = conditions.spindle_speed
    return paired(name, speed, count)


def limit_depth_map(
    conditions: CutConditions,
    points: ArrayLike,
    *,
    speed: float | None = None,
    feed_angle: float = 0.0,
    engagement: Engagement | None = None,
    params: OrthoglideParams | None = None,
    **options: Any,
) -> FloatArray:
    """The limiting axial depth [m] at one spindle speed at each point, shape (n,).

    Args:
        conditions: The cut.
        points: Tool points in the world frame [m], shape (n, 3).
        speed: Spindle speed [rad/s]; the conditions' when ``None``.
        feed_angle: The feed's direction from program +X towards +Y [rad].
        engagement: The engagement (the conditions' default when ``None``).
        params: Machine parameters; the prototype when ``None``.
        **options: ``drive``, ``model``, ``axes`` (see :func:`stability_lobes`).
    """
    _check(conditions)
    eng = _engagement(conditions, engagement)
    p = capped_points(points, "points", MAX_POINTS).reshape(-1, 3)
    omega = _speeds(conditions, speed, p.shape[0], "speed")
    angles = np.full(p.shape[0], finite_number("feed_angle", feed_angle, "[rad]"))
    return _limits(conditions, p, omega, angles, milling_process(conditions, eng), params, options)


def _limits(
    conditions: CutConditions,
    points: FloatArray,
    omega: FloatArray,
    angles: FloatArray,
    process: MillingProcess,
    params: OrthoglideParams | None,
    options: dict[str, Any],
) -> FloatArray:
    out = np.empty(points.shape[0])
    for start in range(0, points.shape[0], CHUNK):
        sl = slice(start, start + CHUNK)
        models = _models(params, points[sl], conditions, angles[sl], options)
        out[sl] = critical_depths_sd(models, process, omega[sl], DEPTH_RANGE)
    return out
