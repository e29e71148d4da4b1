"""Cutting conditions: the tool, the material's cutting coefficients, the engagement.

A cut file (``cut.yaml``, see the formats reference) gives, in SI units except
the spindle speed in rpm:

* ``tool``: ``diameter`` [m], ``teeth``, ``helix_angle`` [rad] and optional
  ``modes`` of the tool and spindle (``frequency`` [Hz], ``damping`` [-],
  ``stiffness`` [N/m], ``direction`` ``x`` or ``y`` of the program's axes);
* ``material``: the name of a shipped material (:func:`shipped_materials`,
  each with its source) or a mapping of its six coefficients;
* ``engagement``: one mapping for the whole program, or a list of them each
  for a range of program ``lines``: ``axial_depth`` [m], ``radial_width``
  [m], ``milling`` (``up`` or ``down``);
* ``spindle_speed`` [rpm], or ``program`` (the program's ``S``);
* ``modal_damping`` [-] of the machine's modes (default
  :data:`DEFAULT_MODAL_DAMPING`).

The cutting coefficients are those of Altintas' linear edge-force model
(Manufacturing Automation, 2nd ed., 2012, ch. 2): on an edge element of
axial length ``dz`` cutting a chip of thickness ``h``, ``dF_t = (K_tc h +
K_te) dz`` (tangential), ``dF_r = (K_rc h + K_re) dz`` (radial),
``dF_a = (K_ac h + K_ae) dz`` (axial). The API's values are SI (``kt``
[N/m^2], ``kte`` [N/m]); the files are SI too (a value in N/mm^2 or N/mm is
refused with the value meant). Immersion angles are Altintas': measured from
the normal to the feed (+y of the feed frame), clockwise, with the cutter
turning clockwise and feeding along +x.
"""

from __future__ import annotations

import importlib.resources
import itertools
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np

from orthoglide_pin._io import parse_yaml_mapping, read_yaml_mapping
from orthoglide_pin.exceptions import CutConditionsError, InvalidParameterError
from orthoglide_pin.machining._checks import RPM_PER_RAD_S, _choice, _fields, number

__all__ = [
    "DEFAULT_MODAL_DAMPING",
    "EXAMPLE_CUT_FILES",
    "MILLING",
    "MODE_DIRECTIONS",
    "RPM_PER_RAD_S",
    "CutConditions",
    "Engagement",
    "Material",
    "Tool",
    "ToolMode",
    "cut_conditions",
    "number",
    "read_cut_file",
    "shipped_cut_file",
    "shipped_materials",
]

#: Default modal damping ratio of the machine's modes [-]: 2 %, a common value
#: for machine-tool structures with bolted and guided joints (1 to 5 %).
DEFAULT_MODAL_DAMPING: Final = 0.02
#: The shipped cut files: name -> file in ``orthoglide_pin/machining/examples/``.
EXAMPLE_CUT_FILES: Final = {"aluminium_finish": "aluminium_finish.yaml"}
#: The milling directions.
MILLING: Final = ("up", "down")
#: The feed-plane directions of a tool mode (the program's X and Y).
MODE_DIRECTIONS: Final = ("x", "y")


@dataclass(frozen=True)
class ToolMode:
    """A mode of the tool and spindle, in one of the program's feed-plane axes.

    Attributes:
        frequency: Natural frequency [Hz].
        damping: Damping ratio [-].
        stiffness: Modal stiffness at the tool tip [N/m].
        direction: ``"x"`` or ``"y"``: the program's X or Y axis.
    """

    frequency: float
    damping: float
    stiffness: float
    direction: str = "x"

    def __post_init__(self) -> None:
        for name in ("frequency", "damping", "stiffness"):
            object.__setattr__(self, name, number(name, getattr(self, name)))
        _choice("direction", self.direction, MODE_DIRECTIONS)


@dataclass(frozen=True)
class Tool:
    """An end mill.

    Attributes:
        diameter: Diameter [m].
        teeth: Number of teeth (flutes), 1 to 20.
        helix_angle: Helix angle [rad], 0 to 70 degrees.
        modes: The tool's and spindle's own modes (may be empty).
    """

    diameter: float
    teeth: int
    helix_angle: float = 0.0
    modes: tuple[ToolMode, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "diameter", number("diameter", self.diameter))
        teeth = self.teeth
        if isinstance(teeth, bool) or not isinstance(teeth, int) or not 1 <= teeth <= 20:
            raise CutConditionsError("teeth", teeth, "an integer in [1, 20]")
        object.__setattr__(self, "helix_angle", number("helix_angle", self.helix_angle))
        modes = self.modes
        if not isinstance(modes, (tuple, list)) or not all(isinstance(m, ToolMode) for m in modes):
            raise CutConditionsError("modes", modes, "a tuple of ToolMode")
        object.__setattr__(self, "modes", tuple(modes))


@dataclass(frozen=True)
class Material:
    """A material's cutting coefficients (Altintas' linear edge-force model).

    Attributes:
        name: Its name.
        kt: Tangential shearing coefficient K_tc [N/m^2].
        kr: Radial shearing coefficient K_rc [N/m^2].
        ka: Axial shearing coefficient K_ac [N/m^2].
        kte: Tangential edge coefficient K_te [N/m].
        kre: Radial edge coefficient K_re [N/m].
        kae: Axial edge coefficient K_ae [N/m].
        source: Where the values come from.
    """

    name: str
    kt: float
    kr: float
    ka: float = 0.0
    kte: float = 0.0
    kre: float = 0.0
    kae: float = 0.0
    source: str = "given"

    def __post_init__(self) -> None:
        for key in ("name", "source"):
            value = getattr(self, key)
            if not isinstance(value, str) or not value.strip() or len(value) > 400:
                raise CutConditionsError(key, value, "a text of 1 to 400 characters")
        for key in ("kt", "kr", "ka", "kte", "kre", "kae"):
            object.__setattr__(self, key, number(key, getattr(self, key)))


@dataclass(frozen=True)
class Engagement:
    """How the tool engages the part, for the whole program or a range of its lines.

    Attributes:
        axial_depth: Axial depth of cut a_p [m].
        radial_width: Radial width of cut a_e [m] (at most the tool's diameter).
        milling: ``"up"`` (conventional) or ``"down"`` (climb).
        lines: ``(first, last)`` program lines (1-based, inclusive), or ``None``
            for every line that no other engagement names.
    """

    axial_depth: float
    radial_width: float
    milling: str = "down"
    lines: tuple[int, int] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "axial_depth", number("axial_depth", self.axial_depth))
        object.__setattr__(self, "radial_width", number("radial_width", self.radial_width))
        _choice("milling", self.milling, MILLING)
        if self.lines is not None:
            lines = self.lines
            ok = isinstance(lines, (tuple, list)) and len(lines) == 2
            ok = ok and all(isinstance(x, int) and not isinstance(x, bool) for x in lines)
            if not ok or not 1 <= lines[0] <= lines[1]:
                raise CutConditionsError("lines", lines, "[first, last] with 1 <= first <= last")
            object.__setattr__(self, "lines", (int(lines[0]), int(lines[1])))

    def immersion(self, diameter: float) -> tuple[float, float]:
        """Entry and exit angles ``(phi_start, phi_exit)`` [rad] (Altintas' convention).

        Up milling: ``(0, arccos(1 - 2 a_e / D))``; down milling:
        ``(arccos(2 a_e / D - 1), pi)``. A width of the full diameter is slotting,
        ``(0, pi)`` for both.

        Raises:
            CutConditionsError: ``radial_width`` exceeds ``diameter``.
        """
        diameter = number("diameter", diameter)
        if self.radial_width > diameter * (1.0 + 1e-12):
            raise CutConditionsError(
                "radial_width", self.radial_width, f"at most the tool's diameter {diameter:g} m"
            )
        ratio = min(self.radial_width / diameter, 1.0)
        if self.milling == "up":
            return 0.0, math.acos(1.0 - 2.0 * ratio)
        return math.acos(2.0 * ratio - 1.0), math.pi


@dataclass(frozen=True)
class CutConditions:
    """Everything a cut needs: tool, material, engagements, spindle speed, damping.

    Attributes:
        tool: The end mill.
        material: The material's cutting coefficients.
        engagements: At most one without ``lines`` (the default), others for
            ranges of lines that do not overlap.
        spindle_speed: Spindle speed [rad/s], or ``None`` for the program's ``S``.
        modal_damping: Damping ratio of the machine's modes [-].
    """

    tool: Tool
    material: Material
    engagements: tuple[Engagement, ...]
    spindle_speed: float | None = None
    modal_damping: float = DEFAULT_MODAL_DAMPING

    def __post_init__(self) -> None:
        if not isinstance(self.tool, Tool):
            raise CutConditionsError("tool", self.tool, "a Tool")
        if not isinstance(self.material, Material):
            raise CutConditionsError("material", self.material, "a Material")
        found = self.engagements
        if not isinstance(found, (tuple, list)) or not found:
            raise CutConditionsError("engagements", found, "at least one Engagement")
        if not all(isinstance(e, Engagement) for e in found):
            raise CutConditionsError("engagements", found, "Engagement values")
        object.__setattr__(self, "engagements", tuple(found))
        for e in self.engagements:
            e.immersion(self.tool.diameter)  # width within the diameter
        if sum(e.lines is None for e in self.engagements) > 1:
            raise CutConditionsError("engagement", found, "at most one without lines")
        ranges = sorted(e.lines for e in self.engagements if e.lines is not None)
        for (_, last), (first, end) in itertools.pairwise(ranges):
            if first <= last:
                raise CutConditionsError("lines", [first, end], "ranges that do not overlap")
        if self.spindle_speed is not None:
            speed = number("spindle_speed", self.spindle_speed, "spindle_speed_rad")
            object.__setattr__(self, "spindle_speed", speed)
        object.__setattr__(self, "modal_damping", number("modal_damping", self.modal_damping))

    def engagement_at(self, line: int) -> Engagement | None:
        """The engagement of program line ``line``: its range's, else the default, or ``None``."""
        if isinstance(line, bool) or not isinstance(line, (int, np.integer)):
            raise CutConditionsError("line", line, "a program line number (int)")
        default = None
        for e in self.engagements:
            if e.lines is None:
                default = e
            elif e.lines[0] <= line <= e.lines[1]:
                return e
        return default


def shipped_materials() -> dict[str, Material]:
    """The shipped materials by name (``materials.yaml`` of the package, with sources)."""
    text = (importlib.resources.files("orthoglide_pin.machining") / "materials.yaml").read_text(
        encoding="utf-8"
    )
    data = parse_yaml_mapping(text, "materials")
    return {name: Material(name=name, **values) for name, values in data.items()}


def shipped_cut_file(name: str = "aluminium_finish") -> Path:
    """The shipped example cut file ``name`` (a path on disk for an ordinary install).

    Raises:
        CutConditionsError: ``name`` is not one of :data:`EXAMPLE_CUT_FILES`.
    """
    _choice("name", name, tuple(EXAMPLE_CUT_FILES))
    folder = importlib.resources.files("orthoglide_pin.machining") / "examples"
    return Path(str(folder / EXAMPLE_CUT_FILES[name]))


def _material(value: Any) -> Material:
    if isinstance(value, str):
        materials = shipped_materials()
        _choice("material", value, tuple(materials))
        return materials[value]
    data = _fields(Material, value, "material")
    data.setdefault("name", "given")
    for key in ("kt", "kr"):
        if key not in data:
            raise CutConditionsError(f"material.{key}", None, "a coefficient (it is missing)")
    return Material(**data)


def _engagements(value: Any) -> tuple[Engagement, ...]:
    items = [value] if isinstance(value, Mapping) else value
    if not isinstance(items, list) or not items:
        raise CutConditionsError("engagement", value, "a mapping, or a list of mappings")
    out = []
    for item in items:
        data = _fields(Engagement, item, "engagement")
        for key in ("axial_depth", "radial_width"):
            if key not in data:
                raise CutConditionsError(f"engagement.{key}", None, "a length [m] (it is missing)")
        if isinstance(data.get("lines"), list):
            data["lines"] = tuple(data["lines"])
        out.append(Engagement(**data))
    return tuple(out)


def _tool(value: Any) -> Tool:
    data = _fields(Tool, value, "tool")
    for key in ("diameter", "teeth"):
        if key not in data:
            raise CutConditionsError(f"tool.{key}", None, "a value (it is missing)")
    modes = data.get("modes", [])
    if not isinstance(modes, list):
        raise CutConditionsError("tool.modes", modes, "a list of mappings")
    data["modes"] = tuple(ToolMode(**_fields(ToolMode, m, "tool.modes")) for m in modes)
    return Tool(**data)


def cut_conditions(data: Mapping[str, Any]) -> CutConditions:
    """The cut conditions of a cut file's mapping (see the module for its keys).

    Raises:
        CutConditionsError: A missing, unknown or bad value, named in one line.
    """
    keys = ("tool", "material", "engagement", "spindle_speed", "modal_damping")
    if not isinstance(data, Mapping):
        raise CutConditionsError("cut file", data, "a mapping of names to values")
    for key in data:
        if key not in keys:
            raise CutConditionsError("cut file key", key, "one of " + ", ".join(keys))
    for key in keys[:3]:
        if key not in data:
            raise CutConditionsError(key, None, f"a {key} section (it is missing)")
    speed = data.get("spindle_speed", "program")
    if isinstance(speed, str) and speed != "program":
        raise CutConditionsError("spindle_speed", speed, "a speed [rpm], or program (its S)")
    spindle = None if speed == "program" else number("spindle_speed", speed) / RPM_PER_RAD_S
    return CutConditions(
        tool=_tool(data["tool"]),
        material=_material(data["material"]),
        engagements=_engagements(data["engagement"]),
        spindle_speed=spindle,
        modal_damping=data.get("modal_damping", DEFAULT_MODAL_DAMPING),
    )


def read_cut_file(path: str | os.PathLike[str]) -> CutConditions:
    """Read a cut file (``cut.yaml``) safely: size cap, text check, YAML errors located.

    Raises:
        CutConditionsError: Not a readable small text file, bad YAML (line and
            column named), or a missing, unknown or bad value (named, with
            what is allowed), in one line.
    """
    try:
        data = read_yaml_mapping(path, "cut file")
    except CutConditionsError:
        raise
    except InvalidParameterError as exc:
        raise CutConditionsError(exc.name, exc.value, exc.allowed) from None
    return cut_conditions(data)
