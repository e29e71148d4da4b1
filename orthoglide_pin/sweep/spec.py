"""Parameter sweeps: the grid of designs, its parsing and the tidy table of results.

A sweep evaluates a product grid of designs. Its first axis is usually the leg
length (``leg_length=0.25:0.45:21``); any scalar machine parameter
(:class:`~orthoglide_pin.machine.params.OrthoglideParams`, except the slider limits,
which every design derives from its cube) and the settings of :data:`SETTINGS`
may vary too, alone or together (the product of every axis, the first axis
slowest). Each design is evaluated by
:func:`~orthoglide_pin.sweep.metrics.evaluate_design`, run by
:func:`~orthoglide_pin.sweep.runner.run_sweep`.

Modes (what varies, what stays):

* ``"fixed-cube"``: the cube (``cube_corner``, ``cube_side``; by default the
  base machine's prescribed cube, ``base.workspace``: for the prototype the
  0.2 m cube with its lower corner at ``-0.31 / sqrt(18)`` on each axis) stays
  where it is while the leg length varies. Each design's machine has that cube
  as its prescribed workspace and its slider limits derived from it (the range
  of the slider values over the cube), so the stroke just covers it and the
  worst case of a row is the one ``orthoglide report`` gives for the same
  machine; the metrics include the transmission-factor bounds *reached* in the
  cube.
* ``"redesign"``: each design is the paper's design for the bounds
  ``psi_min``, ``psi_max`` (section 3.4): its cube has Q1 and Q2 as opposite
  corners, so the cube side and the leg length fix each other,
  ``Lw = L (f2 - f1)``. With a ``leg_length`` axis the cube follows the leg
  (``Lw`` derived); without one, the leg follows ``cube_side`` (``L`` derived).
  Sweeping both is refused. ``cube_corner`` does not apply (the corner is Q1).

Each design is a plain JSON-ready dictionary; its key is a stable hash of
everything that defines it (the mode, every machine parameter, the settings,
the grids and :data:`SCHEMA`), so a changed setting never reuses an old result.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from orthoglide_pin._validation import (
    MAX_ACCELERATION,
    MAX_SPEED,
    bounded_number,
    choice,
    finite_number,
    finite_vector,
    instance_of,
    integer,
)
from orthoglide_pin._validation import text as check_text
from orthoglide_pin.drives.motor import DriveTrain
from orthoglide_pin.elasticity.stiffness import stiffness_assumptions
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.cube import Cube
from orthoglide_pin.machine.params import (
    LIMIT_FIELDS,
    WORKSPACE_FIELDS,
    OrthoglideParams,
    field_names,
    prototype,
)
from orthoglide_pin.motion.cycle import CYCLE_A_MAX, CYCLE_V_MAX
from orthoglide_pin.sweep import accuracy as _accuracy
from orthoglide_pin.sweep import program as _program

if TYPE_CHECKING:
    pass

#: Version of the design and metric definitions (part of every key).
SCHEMA: Final[int] = 2
#: The two modes (see the module).
MODES: Final = ("fixed-cube", "redesign")
#: Sweep settings that may also be axes: bounds on the transmission factors,
#: cube side [m], tool speed [m/s] and acceleration [m/s^2] of the requirement.
SETTINGS: Final = ("psi_min", "psi_max", "cube_side", "speed", "acceleration")
#: Machine parameters that cannot be axes: vectors, the derived slider limits, the
#: cube and its criterion (the settings ``cube_side``, ``cube_corner``,
#: ``psi_min`` and ``psi_max`` set them).
FIXED_FIELDS: Final = frozenset({"tool_offset", "carriage_size", *LIMIT_FIELDS, *WORKSPACE_FIELDS})
#: Tool speed [m/s] and acceleration [m/s^2] of the requirement (paper, section 4).
DEFAULT_SPEED: Final[float] = CYCLE_V_MAX
DEFAULT_ACCELERATION: Final[float] = CYCLE_A_MAX
#: Ranges of the requirement's speed and acceleration (:mod:`orthoglide_pin._validation`).
_MOTION_LIMITS: Final = {
    "speed": (MAX_SPEED, "[m/s]"),
    "acceleration": (MAX_ACCELERATION, "[m/s^2]"),
}
#: Points per edge of the transmission-factor grid of each design's cube.
DEFAULT_GRID: Final[int] = 50
#: Points per edge of the (coarser) grid of the worst-case force and torque.
DEFAULT_REQUIREMENT_GRID: Final[int] = 5
#: Significant digits kept of the values of ``START:STOP:N``.
GRID_DIGITS: Final[int] = 12
#: Largest number of designs in one sweep, even when forced (the run refuses
#: more than :data:`orthoglide_pin.sweep.runner.MAX_DESIGNS` unless forced).
HARD_MAX_DESIGNS: Final[int] = 1_000_000
#: Largest ``grid`` (160^3 = 4.1 M points per design, ~0.1 GB per array).
MAX_GRID: Final[int] = 160
#: Largest ``requirement_grid`` (41^3 = 68,921 points per design, ~0.5 M
#: inverse-dynamics evaluations).
MAX_REQUIREMENT_GRID: Final[int] = 41

#: Columns of the table that describe each design, after ``key, status, error, mode``.
PARAMETER_COLUMNS: Final = (
    "leg_length",
    "cube_side",
    "cube_corner_x",
    "cube_corner_y",
    "cube_corner_z",
    "psi_min",
    "psi_max",
    "speed",
    "acceleration",
)
#: Metric columns (units in the README and in
#: :mod:`~orthoglide_pin.sweep.metrics`), in table order.
METRIC_COLUMNS: Final = (
    "slider_lower",
    "slider_upper",
    "stroke",
    "ratio",
    "design_cube_side",
    "psi_min_reached",
    "psi_max_reached",
    "bounds_hold",
    "in_bounds_fraction",
    "condition_min",
    "condition_max",
    "condition_mean",
    "condition_std",
    "moving_mass",
    "max_slider_force",
    "max_motor_torque",
    "footprint_x",
    "footprint_y",
    "footprint_z",
    "footprint_area",
    "footprint_volume",
    "min_stiffness",
    "centre_stiffness",
    "max_deflection",
    "lowest_frequency",
)
HEAD_COLUMNS: Final = ("key", "status", "error", "mode")


def sweepable_names() -> tuple[str, ...]:
    """Names that may be axes: ``leg_length``, scalar machine parameters, then settings."""
    params = tuple(n for n in field_names() if n not in FIXED_FIELDS)
    return (*params, *SETTINGS)


def _number(name: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise InvalidParameterError(name, text, "a finite number")
    return value


def parse_values(text: str, name: str = "values") -> tuple[float, ...]:
    """Values of one axis: ``START:STOP:N``, a list ``A,B,C`` or one value ``A``.

    ``START:STOP:N`` gives ``N`` evenly spaced values, both ends included,
    rounded to :data:`GRID_DIGITS` significant digits.

    Raises:
        InvalidParameterError: On text that is none of these, a non-finite
            value, ``N < 1`` or repeated values.
    """
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise InvalidParameterError(name, text, "START:STOP:N, a list A,B,C or a value")
        start, stop = _number(name, parts[0]), _number(name, parts[1])
        try:
            n = int(parts[2])
        except ValueError:
            n = 0
        if n < 1 or (n == 1 and start != stop) or n > HARD_MAX_DESIGNS:
            raise InvalidParameterError(
                name, text, f"START:STOP:N with an integer N in [2, {HARD_MAX_DESIGNS}]"
            )
        # 12 significant digits: 0.3, not 0.30000000000000004 (the keys stay readable)
        values = tuple(float(f"{v:.{GRID_DIGITS}g}") for v in np.linspace(start, stop, n))
    else:
        items = [t for t in text.split(",") if t.strip()]
        if not items:
            raise InvalidParameterError(name, text, "START:STOP:N, a list A,B,C or a value")
        values = tuple(_number(name, t.strip()) for t in items)
    if len(set(values)) != len(values):
        raise InvalidParameterError(name, text, "values that are all different")
    return values


@dataclass(frozen=True)
class SweepAxis:
    """One swept quantity.

    Attributes:
        name: A name of :func:`sweepable_names`.
        values: Its values, in SI units (``leg_length`` [m], ...).
    """

    name: str
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        allowed = sweepable_names()
        if not isinstance(self.name, str) or self.name not in allowed:
            raise InvalidParameterError("sweep axis", self.name, "one of " + ", ".join(allowed))
        try:
            values = tuple(float(v) for v in self.values)
        except (TypeError, ValueError):
            raise InvalidParameterError(self.name, self.values, "finite numbers") from None
        if not values or not all(math.isfinite(v) for v in values):
            raise InvalidParameterError(self.name, self.values, "one or more finite numbers")
        if len(set(values)) != len(values):
            raise InvalidParameterError(self.name, self.values, "values that are all different")
        object.__setattr__(self, "values", values)

    @classmethod
    def parse(cls, text: str) -> SweepAxis:
        """An axis from ``NAME=START:STOP:N``, ``NAME=A,B,C`` or ``NAME=A``."""
        name, sep, values = check_text("text", text, "an axis NAME=VALUES").partition("=")
        if not sep or not name.strip():
            raise InvalidParameterError("axis", text, "NAME=START:STOP:N or NAME=A,B,C")
        return cls(name.strip(), parse_values(values, name.strip()))


@dataclass(frozen=True)
class SweepSpec:
    """A grid of designs and the settings of their evaluation.

    Attributes:
        axes: The swept quantities; the designs are their product, the first
            axis slowest. No axis: one design.
        mode: ``"fixed-cube"`` or ``"redesign"`` (see the module).
        base: Machine parameters of every design, before the axes apply.
        cube_side: Side ``Lw`` of the cube [m] (redesign: when no
            ``leg_length`` axis); ``None``: the base's ``workspace_side``.
        cube_corner: Lowest corner of the fixed cube [m], shape (3,);
            ``None``: the base's ``workspace_corner``.
        psi_min: Lower bound of the criterion on the transmission factors;
            ``None``: the base machine's (``base.psi_min``).
        psi_max: Upper bound; ``None``: the base machine's (``base.psi_max``).
        speed: Tool speed of the requirement [m/s].
        acceleration: Tool acceleration of the requirement [m/s^2].
        grid: Points per edge of each cube's transmission-factor grid, in
            ``[2, MAX_GRID]``.
        requirement_grid: Points per edge of the worst-case force and torque
            grid, in ``[2, MAX_REQUIREMENT_GRID]``.
        drive: Ball screw and motor drive train of the torque requirement.
        program: A part program (G-code text) planned on every design, or ``None``
            (:mod:`~orthoglide_pin.sweep.program`: ``cycle_time``, ``binding_limit``).
        cut: A cut file (its mapping, or its path) to cut the program with on
            every design, or ``None`` (:mod:`~orthoglide_pin.sweep.accuracy`:
            ``surface_error_max``, ``stability_margin_min``); needs ``program``.
    """

    axes: tuple[SweepAxis, ...] = ()
    mode: str = "fixed-cube"
    base: OrthoglideParams = dataclasses.field(default_factory=prototype)
    cube_side: float | None = None
    cube_corner: tuple[float, float, float] | None = None
    psi_min: float | None = None
    psi_max: float | None = None
    speed: float = DEFAULT_SPEED
    acceleration: float = DEFAULT_ACCELERATION
    grid: int = DEFAULT_GRID
    requirement_grid: int = DEFAULT_REQUIREMENT_GRID
    drive: DriveTrain = dataclasses.field(default_factory=DriveTrain)
    program: str | None = None
    cut: Any = None

    def __post_init__(self) -> None:
        given: Any = self.axes  # axes, or texts NAME=VALUES, or one text
        raw, kinds = (given,) if isinstance(given, str) else given, (str, SweepAxis)
        if not isinstance(raw, (tuple, list)) or not all(isinstance(a, kinds) for a in raw):
            raise InvalidParameterError("axes", self.axes, "SweepAxis or NAME=VALUES texts")
        axes = tuple(SweepAxis.parse(a) if isinstance(a, str) else a for a in raw)
        names = [a.name for a in axes]
        for name in names:
            if names.count(name) > 1:
                raise InvalidParameterError("sweep axis", name, "each axis given once")
        choice("mode", self.mode, MODES)
        object.__setattr__(self, "base", as_params(self.base, "base"))
        instance_of("drive", self.drive, DriveTrain, "a DriveTrain")
        if self.mode == "redesign" and {"leg_length", "cube_side"} <= set(names):
            raise InvalidParameterError(
                "sweep axis",
                "cube_side",
                "leg_length or cube_side in redesign mode, not both (each fixes the other)",
            )
        designs = math.prod(len(a.values) for a in axes)
        if designs > HARD_MAX_DESIGNS:
            raise InvalidParameterError(
                "number of designs", designs, f"at most {HARD_MAX_DESIGNS} designs in one sweep"
            )
        object.__setattr__(self, "axes", axes)
        for name in ("cube_side", "psi_min", "psi_max"):  # the base machine's by default
            if getattr(self, name) is None:
                base_name = "workspace_side" if name == "cube_side" else name
                object.__setattr__(self, name, getattr(self.base, base_name))
        for name in SETTINGS:
            value = finite_number(name, getattr(self, name))
            if name in _MOTION_LIMITS:  # before any worker squares it
                high, unit = _MOTION_LIMITS[name]
                value = bounded_number(name, value, high, unit, allow_zero=True)
            object.__setattr__(self, name, float(value))
        if self.cube_corner is not None:
            corner = finite_vector("cube_corner", self.cube_corner, 3, "[m]")
            object.__setattr__(self, "cube_corner", tuple(float(c) for c in corner))
        integer("grid", self.grid, 2, MAX_GRID)
        integer("requirement_grid", self.requirement_grid, 2, MAX_REQUIREMENT_GRID)
        if self.program is not None:
            object.__setattr__(self, "program", _program.check_program(self.program))
        if self.cut is not None:
            object.__setattr__(self, "cut", _accuracy.check_cut(self.cut, self.program))

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the axes, in order."""
        return tuple(a.name for a in self.axes)

    def __len__(self) -> int:
        return math.prod(len(a.values) for a in self.axes)

    def corner(self) -> tuple[float, float, float]:
        """Lowest corner of the fixed cube [m] (the base machine's by default)."""
        return self.cube_corner or self.base.workspace_corner

    def cube(self) -> Cube:
        """The fixed cube of fixed-cube mode: :meth:`corner` and ``cube_side`` [m]."""
        side = self.base.workspace_side if self.cube_side is None else self.cube_side
        return Cube(self.corner(), side)

    def designs(self) -> list[dict[str, Any]]:
        """Every design, in grid order (plain dictionaries, JSON-ready).

        Keys: ``mode``; ``values``, the axes' values; ``params``, every machine
        parameter but the leg length, the slider limits and the cube, axes applied
        (validated when evaluated); ``leg_length`` [m], ``None`` when derived
        from ``cube_side``; the settings of :data:`SETTINGS`, axes applied
        (``cube_side`` left out when derived from the leg); ``cube_corner`` [m],
        ``None`` in redesign mode; ``grid``, ``requirement_grid`` and ``drive``.
        """
        base = self.base.to_dict()
        for name in ("leg_length", *LIMIT_FIELDS, *WORKSPACE_FIELDS):
            base.pop(name)
        from_side = self.mode == "redesign" and "leg_length" not in self.names
        corner = list(self.corner()) if self.mode == "fixed-cube" else None
        out = []
        for combo in itertools.product(*(a.values for a in self.axes)):
            values = dict(zip(self.names, combo, strict=True))
            design: dict[str, Any] = {
                "mode": self.mode,
                "values": values,
                "params": {**base, **{k: v for k, v in values.items() if k in base}},
                "leg_length": None
                if from_side
                else values.get("leg_length", self.base.leg_length),
                **{n: values.get(n, getattr(self, n)) for n in SETTINGS},
                "cube_corner": corner,
                "grid": self.grid,
                "requirement_grid": self.requirement_grid,
                "drive": dataclasses.asdict(self.drive),
            }
            if self.mode == "redesign" and not from_side:
                del design["cube_side"]
            if self.program is not None:  # absent without one: earlier keys stay valid
                design["program"] = _program.design_entry(self.program)
            if self.cut is not None:  # likewise
                design["cut"] = _accuracy.design_entry(self.cut)
            out.append(design)
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description of the sweep (written next to its results)."""
        return {
            "schema": SCHEMA,
            "mode": self.mode,
            "axes": {a.name: list(a.values) for a in self.axes},
            "base": self.base.to_dict(),
            "cube_side": self.cube_side,
            "cube_corner": list(self.corner()) if self.mode == "fixed-cube" else None,
            **{n: getattr(self, n) for n in SETTINGS if n != "cube_side"},
            "grid": self.grid,
            "requirement_grid": self.requirement_grid,
            "drive": dataclasses.asdict(self.drive),
            # The stiffness metrics' model, for the base machine (an axis over a
            # modulus or the actuator stiffness changes it per design).
            "stiffness_assumptions": stiffness_assumptions(self.base),
            **({} if self.program is None else {"program": _program.record_entry(self.program)}),
            **({} if self.cut is None else {"cut": _accuracy.record_entry(self.cut)}),
        }


def design_key(design: Mapping[str, Any]) -> str:
    """Stable key of a design: 16 hex digits of the SHA-256 of its canonical JSON."""
    text = json.dumps({"schema": SCHEMA, **design}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


__all__ = [
    "HARD_MAX_DESIGNS",
    "HEAD_COLUMNS",
    "MAX_GRID",
    "MAX_REQUIREMENT_GRID",
    "METRIC_COLUMNS",
    "MODES",
    "PARAMETER_COLUMNS",
    "SETTINGS",
    "SweepAxis",
    "SweepSpec",
    "design_key",
    "parse_values",
    "sweepable_names",
]
