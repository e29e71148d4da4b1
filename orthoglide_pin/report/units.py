"""The units of everything a person reads: pages, terminal summaries, the viewer.

The API, the JSON and the CSV files are in SI units (m, s, kg, N, N.m, rad);
what is shown to a person follows one convention, the same on every page, in
every terminal summary and in the viewer's legends (:data:`DISPLAY`):

* lengths in mm (small errors, residuals and deviations in µm);
* the feed, the tool's path speed, in mm/min, as a program's ``F`` words;
* every other speed (slider, tool) in mm/s;
* motor speeds in rpm;
* accelerations in m/s^2, jerks in m/s^3, forces in N, torques in N.m, times in s.

:func:`shown` converts an SI value to its display unit, :func:`quantity`
formats it with the unit and :func:`label` names an axis or a column.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Final, overload

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.drives.motor import RPM_PER_RAD_S
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]

#: Each kind of quantity: its display unit and the factor from its SI value.
DISPLAY: Final = MappingProxyType(
    {
        "length": ("mm", 1e3),
        "error": ("µm", 1e6),
        "feed": ("mm/min", 6e4),
        "speed": ("mm/s", 1e3),
        "motor_speed": ("rpm", RPM_PER_RAD_S),
        "acceleration": ("m/s^2", 1.0),
        "jerk": ("m/s^3", 1.0),
        "force": ("N", 1.0),
        "torque": ("N.m", 1.0),
        "time": ("s", 1.0),
    }
)
#: The display kind of each limit of a plan (:data:`~orthoglide_pin.planning.verify.LIMIT_NAMES`).
LIMIT_KINDS: Final = MappingProxyType(
    {
        "slider_speed": "speed",
        "slider_acceleration": "acceleration",
        "slider_jerk": "jerk",
        "motor_torque": "torque",
        "motor_speed": "motor_speed",
        "feed": "feed",
    }
)


def _entry(kind: str) -> tuple[str, float]:
    try:
        return DISPLAY[kind]
    except KeyError:
        raise InvalidParameterError("kind", kind, "one of " + ", ".join(DISPLAY)) from None


def unit(kind: str) -> str:
    """The display unit of ``kind`` (a key of :data:`DISPLAY`), e.g. ``"mm/min"``."""
    return _entry(kind)[0]


@overload
def shown(kind: str, value: float) -> float: ...
@overload
def shown(kind: str, value: FloatArray) -> FloatArray: ...
def shown(kind: str, value: float | FloatArray) -> float | FloatArray:
    """``value`` [SI] in the display unit of ``kind``: ``shown("feed", 0.05)`` is 3000.0."""
    factor = _entry(kind)[1]
    if isinstance(value, np.ndarray):
        return value * factor  # a masked array stays masked
    return float(value) * factor


def quantity(kind: str, value: float, spec: str = ".4g") -> str:
    """``value`` [SI] as text in its unit: ``quantity("speed", 1.2)`` is ``"1200 mm/s"``."""
    return f"{shown(kind, float(value)):{spec}} {unit(kind)}"


def label(name: str, kind: str) -> str:
    """An axis or column label: ``label("slider speed", "speed")`` is ``"slider speed [mm/s]"``."""
    return f"{name} [{unit(kind)}]"
