"""The checks of the cutting conditions: plausible ranges, named in one line (private)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, Final

from orthoglide_pin.exceptions import CutConditionsError

#: Revolutions per minute in one rad/s.
RPM_PER_RAD_S: Final = 60.0 / (2.0 * math.pi)
#: Plausible ranges: name -> (low, high, unit, factors a unit slip multiplies by).
RANGES: Final[dict[str, tuple[float, float, str, tuple[float, ...]]]] = {
    "diameter": (2e-4, 0.2, "m", (1e-3,)),
    "helix_angle": (0.0, math.radians(70.0), "rad", (math.pi / 180.0,)),
    "frequency": (1.0, 1e5, "Hz", ()),
    "damping": (1e-5, 0.99, "-", (1e-2,)),
    "stiffness": (1e3, 1e12, "N/m", (1e6,)),
    "kt": (1e7, 2e10, "N/m^2", (1e6,)),
    "kr": (0.0, 2e10, "N/m^2", (1e6,)),
    "ka": (0.0, 2e10, "N/m^2", (1e6,)),
    "kte": (0.0, 1e6, "N/m", (1e3,)),
    "kre": (0.0, 1e6, "N/m", (1e3,)),
    "kae": (0.0, 1e6, "N/m", (1e3,)),
    "axial_depth": (1e-6, 0.1, "m", (1e-3,)),
    "radial_width": (1e-6, 0.2, "m", (1e-3,)),
    "spindle_speed": (1.0, 200_000.0, "rpm", ()),
    "spindle_speed_rad": (1.0 / RPM_PER_RAD_S, 200_000.0 / RPM_PER_RAD_S, "rad/s", ()),
    "modal_damping": (1e-5, 0.99, "-", (1e-2,)),
}
_WORDS: Final[dict[Any, str]] = {
    1e-3: "mm",
    1e6: "N/mm^2",
    1e3: "N/mm",
    1e-2: "percent",
    ("N/m", 1e6): "N/um",
    ("rad", math.pi / 180.0): "degrees",
}


def number(name: str, value: Any, key: str | None = None) -> float:
    """``value`` as a float in the plausible range of ``key`` (default: ``name``'s last part).

    Raises:
        CutConditionsError: Out of range; a unit slip gets the value meant.
    """
    low, high, unit, slips = RANGES[key or name.rsplit(".", 1)[-1]]
    try:
        out = math.nan if isinstance(value, (bool, str)) else float(value)
    except (TypeError, ValueError, OverflowError):
        out = math.nan
    if math.isfinite(out) and low <= out <= high:
        return out
    allowed = f"a number in [{low:g}, {high:g}] {unit}"
    for factor in slips if math.isfinite(out) else ():
        meant = out * factor
        if meant != 0.0 and low <= meant <= high:
            word = _WORDS.get((unit, factor)) or _WORDS[factor]
            allowed = f"{unit} (in {word}?): did you mean {meant:.6g}? ({allowed})"
            break
    raise CutConditionsError(name, value, allowed)


def _choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if not isinstance(value, str) or value not in choices:
        raise CutConditionsError(name, value, "one of " + ", ".join(map(repr, choices)))
    return value


def _fields(cls: type, data: Any, section: str) -> dict[str, Any]:
    """The mapping ``data`` for the dataclass ``cls``: every key one of its fields."""
    if not isinstance(data, Mapping):
        raise CutConditionsError(section, data, "a mapping of names to values")
    names = [f.name for f in dataclasses.fields(cls)]
    for key in data:
        if key not in names:
            raise CutConditionsError(f"{section} key", key, "one of " + ", ".join(names))
    return dict(data)
