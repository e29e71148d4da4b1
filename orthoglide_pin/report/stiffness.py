"""The report's stiffness section: how far the tool yields under a cutting force.

:func:`stiffness_section` evaluates the elastostatic model
(:mod:`orthoglide_pin.elasticity.stiffness`, every source: actuators and
links) over the machine's cube and on the report's plane slices:

* the minimum stiffness over the cube: the smallest eigenvalue of the 3x3
  tool stiffness ``K`` [N/m] (pure force, the platform free to tilt), and
  where it occurs;
* the deflection under the report's cutting force ``F`` [N] (a parameter,
  :data:`~orthoglide_pin.elasticity.maps.DEFAULT_CUTTING_FORCE`
  by default) applied in the softest direction: ``F / k_min`` [m];
* maps of both on the slices, drawn by :func:`stiffness_figure`.

The model's assumptions (moduli, actuator stiffness, which parts and joints
are rigid) go with every output: the JSON (:func:`stiffness_dict`) and the
page (:func:`stiffness_html`).
"""

from __future__ import annotations

import html
import io
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final

import numpy as np

from orthoglide_pin.elasticity.maps import (
    DEFAULT_CUTTING_FORCE,
    StiffnessMap,
    stiffness_map,
)
from orthoglide_pin.kinetostatics.workspace import Grid, cube_grid, slice_grid
from orthoglide_pin.machine.params import OrthoglideParams

__all__ = [
    "DEFAULT_CUTTING_FORCE",
    "StiffnessSection",
    "stiffness_dict",
    "stiffness_figure",
    "stiffness_html",
    "stiffness_section",
]

#: Largest resolutions used (each point costs a structural solve): finer
#: requests of the report are coarsened to these.
MAX_RESOLUTION: Final[int] = 61
MAX_CUBE_RESOLUTION: Final[int] = 21
#: The slices: ``z`` at these fractions of the cube side from its corner.
SLICES: Final = ((0.0, "lower face"), (0.5, "centre"), (1.0, "upper face"))
_MM: Final = 1e3
_UM: Final = 1e6


@dataclass(frozen=True)
class StiffnessSection:
    """The stiffness over the cube and on its slices.

    Attributes:
        cube: The map on the cube grid.
        slices: ``(label, map)`` per slice ``z = const``.
        cutting_force: Magnitude of the cutting force [N].
    """

    cube: StiffnessMap
    slices: tuple[tuple[str, StiffnessMap], ...]
    cutting_force: float


def stiffness_section(
    params: OrthoglideParams,
    corner: np.ndarray[Any, Any],
    side: float,
    cutting_force: float = DEFAULT_CUTTING_FORCE,
    resolution: int = 41,
    cube_resolution: int = 21,
) -> StiffnessSection:
    """Evaluate the stiffness over the cube ``[corner, corner + side]`` and its slices.

    Args:
        params: The machine (sections, moduli, actuator stiffness).
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        cutting_force: Magnitude of the cutting force [N].
        resolution: Points per axis of each slice (at most ``MAX_RESOLUTION``).
        cube_resolution: Points per edge of the cube grid (at most
            ``MAX_CUBE_RESOLUTION``).

    Raises:
        InvalidParameterError: On a bad force or grid.
    """
    resolution = min(resolution, MAX_RESOLUTION)
    cube = stiffness_map(
        cube_grid(corner, side, min(cube_resolution, MAX_CUBE_RESOLUTION)),
        params,
        cutting_force=cutting_force,
    )
    lower = (float(corner[0]), float(corner[1]))
    upper = (lower[0] + side, lower[1] + side)
    slices = []
    for fraction, label in SLICES:
        grid: Grid = slice_grid("z", float(corner[2]) + fraction * side, lower, upper, resolution)
        slices.append((f"z = {label}", stiffness_map(grid, params, cutting_force=cutting_force)))
    return StiffnessSection(cube, tuple(slices), cube.cutting_force)


def stiffness_dict(section: StiffnessSection) -> dict[str, Any]:
    """The section's figures, SI units, JSON-ready (assumptions included)."""
    return {
        **section.cube.summary(),
        "slices": [
            {
                "label": label,
                "z": float(smap.grid.z[0]),
                "min_stiffness": float(smap.min_stiffness.min()),
                "max_deflection": float(smap.deflection.max()),
            }
            for label, smap in section.slices
        ],
        "definition": "K = inv(C[:3, :3]) at the tool tip (platform free to tilt); "
        "min_stiffness: smallest eigenvalue of K; deflection: cutting_force / min_stiffness "
        "(the force in the softest direction)",
    }


def stiffness_figure(section: StiffnessSection, dpi: int = 90) -> bytes:
    """Maps of the minimum stiffness [N/um] and of the deflection [um], as PNG bytes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    rows = len(section.slices)
    fig = Figure(figsize=(8.6, 3.3 * rows + 0.6), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(rows, 2, squeeze=False, sharex=True, sharey=True)
    columns = (
        ("minimum stiffness", "min_stiffness", 1e-6, "minimum stiffness [N/um]", np.argmin),
        (
            f"deflection under {section.cutting_force:g} N",
            "deflection",
            _UM,
            f"deflection under {section.cutting_force:g} N [um]",
            np.argmax,
        ),
    )
    for col, (title, field, scale, label, pick) in enumerate(columns):
        values = [scale * getattr(smap, field)[:, :, 0] for _, smap in section.slices]
        lo, hi = min(float(v.min()) for v in values), max(float(v.max()) for v in values)
        mesh = None
        for row, ((_, smap), field_values) in enumerate(zip(section.slices, values, strict=True)):
            ax = axes[row, col]
            x, y = smap.grid.x * _MM, smap.grid.y * _MM
            mesh = ax.pcolormesh(x, y, field_values.T, shading="gouraud", vmin=lo, vmax=hi)
            i, j = np.unravel_index(pick(field_values), field_values.shape)
            ax.plot(x[i], y[j], "o", ms=9, mfc="none", mec="red", mew=2, clip_on=False)
            ax.set_title(f"{title}, z = {smap.grid.z[0] * _MM:.1f} mm", fontsize=9)
            ax.set_aspect("equal")
        assert mesh is not None
        fig.colorbar(mesh, ax=axes[:, col], label=label, shrink=0.8)
    fig.supxlabel("tool position x [mm]")
    fig.supylabel("tool position y [mm]")
    fig.suptitle("Tool stiffness in its softest direction (circle: the worst of each slice)")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return buf.getvalue()


def stiffness_html(section: StiffnessSection, image: str) -> str:
    """The page's section: the figures, the maps (an ``<img>`` tag) and the assumptions."""
    s = stiffness_dict(section)
    facts: Mapping[str, Any] = s["assumptions"]
    worst = ", ".join(f"{_MM * v:.1f}" for v in s["worst_point"])
    rows = [
        ("minimum stiffness over the cube", f"{s['min_stiffness'] / 1e6:.4g} N/um"),
        ("where", f"({worst}) mm"),
        ("median of the minimum stiffness", f"{s['median_min_stiffness'] / 1e6:.4g} N/um"),
        (
            f"largest deflection under {s['cutting_force']:g} N",
            f"{_UM * s['max_deflection']:.4g} um",
        ),
    ]
    table = "".join(
        f'<tr><td class="text">{html.escape(a)}</td><td>{html.escape(b)}</td></tr>'
        for a, b in rows
    )
    assumptions = [
        f"Young's modulus {facts['youngs_modulus'] / 1e9:.4g} GPa, shear modulus "
        f"{facts['shear_modulus'] / 1e9:.4g} GPa; actuator stiffness "
        f"{facts['actuator_stiffness'] / 1e6:.4g} N/um along each slider.",
        f"Joints: {facts['joints']}; the small links are {facts['small_links']}.",
        "Rigid: " + ", ".join(facts["rigid_parts"]) + ".",
        f"Method: {facts['method']}. {s['definition']}.",
    ]
    notes = "".join(f'<p class="note">{html.escape(a)}</p>' for a in assumptions)
    return f"<table>{table}</table>{image}{notes}"
