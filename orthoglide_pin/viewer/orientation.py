"""Which way is up: the machine's mounting on screen, the camera and the axis triad.

The machine frame of this package has ``e3`` pointing **down** on the
prototype: the vertical slider sits above the platform and the tool points
along ``+e3`` towards the table, so gravity is ``(0, 0, +9.81)`` m/s^2
(:data:`orthoglide_pin.dynamics.inverse.DEFAULT_GRAVITY`). meshcat draws its
world with ``+Z`` up on screen. The viewer's root node therefore carries a
rotation ``R_up`` that maps the machine's *up* direction onto meshcat's
``+Z``; everything below the root stays in the machine frame [m].

``up`` names the machine axis that points up on screen, the opposite of
gravity for that mounting:

========  =====================================================  =================
``up``    mounting                                               rotation ``R_up``
========  =====================================================  =================
``-z``    the prototype (default): z slider above the platform    ``Rx(pi)``
``+z``    upside down: z slider below the platform                identity
``-x``    on its side, x slider above the platform                ``Ry(pi/2)``
``+x``    on its side, x slider below the platform                ``Ry(-pi/2)``
``-y``    on its side, y slider above the platform                ``Rx(-pi/2)``
``+y``    on its side, y slider below the platform                ``Rx(pi/2)``
========  =====================================================  =================

Each ``R_up`` is a proper rotation (``det = +1``), so the triad stays
right-handed on screen. The camera looks at the machine from the side of the
tool (away from the sliders), from above (:func:`view_direction`).

The **axis triad** is the machine frame at its origin (the tool tip at home):
three arrows, x red, y green, z blue, listed in the legend with the one that
points up or down on screen.
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.viewer.machine import rgb_int
from orthoglide_pin.viewer.scene import meshcat

FloatArray = NDArray[np.float64]

#: Machine axes that may point up on screen (see the module's table).
UP_DIRECTIONS: Final = ("-z", "+z", "-x", "+x", "-y", "+y")
#: The prototype's mounting: ``e3`` points down, so ``-z`` is up.
DEFAULT_UP: Final[str] = "-z"
#: ``R_up``: machine frame to meshcat's frame (``+Z`` up on screen), by ``up``.
_ROTATIONS: Final = {
    "+z": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "-z": ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
    "+x": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)),
    "-x": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0)),
    "+y": ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "-y": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
}
#: The side the camera looks from, machine frame, before its horizontal projection:
#: the tool's side (+x, +y, +z), slightly off the diagonal to show depth.
FRONT: Final = (1.0, 0.8, 1.0)
#: Camera height over its horizontal distance (tangent of the view's elevation).
ELEVATION: Final[float] = 0.6
#: Colours of the x, y and z arrows (RGB in [0, 1]).
AXIS_RGB: Final = {"x": (0.85, 0.1, 0.1), "y": (0.1, 0.65, 0.1), "z": (0.1, 0.3, 0.9)}
#: Arrow shaft radius over the arrow's length; head length and radius likewise.
SHAFT_RADIUS: Final[float] = 0.025
HEAD_LENGTH: Final[float] = 0.2
HEAD_RADIUS: Final[float] = 0.06
#: Rotations that turn meshcat's cylinder axis (local y) onto x, y and z.
_CYLINDER_ONTO: Final = {
    "x": ((0.0, 1.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "y": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "z": ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
}


def check_up(up: str) -> str:
    """``up`` in its canonical form (``"z"`` and ``"+Z"`` read as ``"+z"``).

    Raises:
        InvalidParameterError: If ``up`` is not a signed machine axis.
    """
    text = str(up).strip().lower()
    text = text if text[:1] in ("+", "-") else "+" + text
    if text not in UP_DIRECTIONS:
        raise InvalidParameterError("up", up, "one of " + ", ".join(UP_DIRECTIONS))
    return text


def up_rotation(up: str = DEFAULT_UP) -> FloatArray:
    """``R_up``: the rotation from the machine frame to meshcat's (``+Z`` up), (3, 3)."""
    return np.array(_ROTATIONS[check_up(up)], dtype=float)


def up_vector(up: str = DEFAULT_UP) -> FloatArray:
    """The machine-frame unit vector that points up on screen, shape (3,)."""
    u = check_up(up)
    out = np.zeros(3)
    out["xyz".index(u[1])] = 1.0 if u[0] == "+" else -1.0
    return out


def view_direction(up: str = DEFAULT_UP) -> FloatArray:
    """Unit vector from the scene's centre to the camera, machine frame, shape (3,).

    The horizontal part of :data:`FRONT` (the tool's side), raised by
    :data:`ELEVATION` towards ``up``.
    """
    u = up_vector(up)
    front = np.asarray(FRONT, dtype=float)
    horizontal = front - (front @ u) * u
    d = horizontal + ELEVATION * float(np.linalg.norm(horizontal)) * u
    out: FloatArray = d / np.linalg.norm(d)
    return out


def root_transform(up: str, centre: NDArray[np.float64]) -> FloatArray:
    """The root node's 4 x 4 transform: ``R_up`` about ``centre`` [m], which lands at 0."""
    r = up_rotation(up)
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = -r @ np.asarray(centre, dtype=float)
    return m


def legend_items(up: str = DEFAULT_UP) -> dict[str, tuple[float, float, float]]:
    """Legend swatches of the triad: ``"x axis"``..., the vertical one marked up or down."""
    u = check_up(up)
    out = {}
    for axis, rgb in AXIS_RGB.items():
        where = "" if axis != u[1] else (" (up)" if u[0] == "+" else " (down)")
        out[f"{axis} axis{where}"] = rgb
    return out


def triad(length: float) -> dict[str, tuple[dict[str, Any], FloatArray]]:
    """The machine frame's arrows at its origin: ``{name: (lowered mesh, 4 x 4 transform)}``.

    Each axis has a shaft (cylinder) and a head (cone), named ``"x_shaft"``,
    ``"x_head"``...; their transforms are in the machine frame [m].

    Args:
        length: Arrow length [m], positive.
    """
    if not (np.isfinite(length) and length > 0):
        raise InvalidParameterError("triad length", length, "a positive length [m]")
    g = meshcat("geometry")
    shaft_length = (1.0 - HEAD_LENGTH) * length
    out: dict[str, tuple[dict[str, Any], FloatArray]] = {}
    for axis, rgb in AXIS_RGB.items():
        material = g.MeshLambertMaterial(color=rgb_int(rgb))
        rotation = np.array(_CYLINDER_ONTO[axis], dtype=float)
        e = rotation[:, 1]
        parts = (
            ("shaft", g.Cylinder(shaft_length, SHAFT_RADIUS * length), 0.5 * shaft_length),
            (
                "head",
                g.Cylinder(HEAD_LENGTH * length, radiusTop=0.0, radiusBottom=HEAD_RADIUS * length),
                shaft_length + 0.5 * HEAD_LENGTH * length,
            ),
        )
        for part, geometry, along in parts:
            m = np.eye(4)
            m[:3, :3] = rotation
            m[:3, 3] = along * e
            out[f"{axis}_{part}"] = (g.Mesh(geometry, material).lower(), m)
    return out
