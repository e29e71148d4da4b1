"""Heat maps of a workspace slice (matplotlib, Agg canvas: no display needed).

:func:`plot_slice` draws one index of a plane
:class:`~orthoglide_pin.kinetostatics.workspace.WorkspaceMap`
over its reachable points, with the outline of a cube (its section by the
plane, or its dashed projection when the plane misses it), marked points
(projected on the plane: the isotropic point, Q1, Q2) and the singular curves
in the plane: the serial cylinder of each leg (distance 0) and the parallel
surface (``det(u_1, u_2, u_3) = 0``). matplotlib is imported on first use and
drawn on its Agg canvas directly, leaving pyplot's global state alone. The
image is written atomically.
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_bytes
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.workspace import AXES, WorkspaceMap

FloatArray = NDArray[np.float64]

#: Units of the indices, for the colour bar.
UNITS: Final = {
    "serial_distance": "m",
    "parallel_distance": "m",
}
#: Indices drawn on a logarithmic colour scale when they span more than a decade.
LOG_INDICES: Final = frozenset({"condition", "psi_max", "manipulability"})
_SERIAL_COLOURS: Final = ("tab:red", "tab:green", "tab:blue")


def _plane(wmap: WorkspaceMap) -> tuple[int, int, int]:
    """``(fixed, a, b)`` axis indices of a plane map; raise for a 3-D map."""
    fixed = wmap.grid.fixed_axis
    if fixed is None:
        raise InvalidParameterError(
            "grid.shape", wmap.grid.shape, "a plane slice (exactly one axis of one point)"
        )
    a, b = (i for i in range(3) if i != fixed)
    return fixed, a, b


def _norm(values: np.ma.MaskedArray[Any, Any], index: str) -> Any:
    from matplotlib.colors import LogNorm, Normalize

    data = values.compressed()
    if data.size == 0:
        return Normalize(0.0, 1.0)
    lo, hi = float(data.min()), float(data.max())
    if index in LOG_INDICES and lo > 0.0 and hi > 10.0 * lo:
        return LogNorm(lo, hi)
    return Normalize(lo, hi if hi > lo else lo + 1.0)


def plot_slice(
    wmap: WorkspaceMap,
    index: str,
    path: str | Path,
    *,
    cube: tuple[ArrayLike, float] | None = None,
    markers: Mapping[str, ArrayLike] | None = None,
    title: str | None = None,
    dpi: int = 120,
) -> Path:
    """Draw ``index`` of a plane map as a heat map and write it as PNG.

    Args:
        wmap: A map on a plane slice
            (see :func:`~orthoglide_pin.kinetostatics.workspace.slice_grid`).
        index: One of :data:`~orthoglide_pin.kinetostatics.workspace.INDEX_NAMES`.
        path: Output PNG file (written atomically).
        cube: ``(corner, side)`` of a cube to outline [m].
        markers: Named points to mark [m], e.g. ``{"Q1": ..., "Q2": ...}``.
        title: Figure title (default: index and plane).
        dpi: Resolution [dots per inch].

    Returns:
        The path written.

    Raises:
        InvalidParameterError: A 3-D map or an unknown index.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    fixed, a, b = _plane(wmap)
    values = np.squeeze(wmap.index(index), axis=fixed)
    reach = np.squeeze(wmap.reachable, axis=fixed)
    shown = np.ma.masked_where(~reach | ~np.isfinite(values), values)
    coords = (wmap.grid.x, wmap.grid.y, wmap.grid.z)
    ca, cb, level = coords[a], coords[b], float(coords[fixed][0])

    fig = Figure(figsize=(7.0, 6.0))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    mesh = ax.pcolormesh(ca, cb, shown.T, shading="nearest", cmap="viridis")
    mesh.set_norm(_norm(shown, index))
    unit = UNITS.get(index)
    fig.colorbar(mesh, ax=ax, label=f"{index} [{unit}]" if unit else index)
    handles: list[Any] = []

    serial = np.squeeze(wmap.serial_distances, axis=fixed)
    for leg in range(3):
        field = serial[..., leg]
        if np.nanmin(field) < 0.0 < np.nanmax(field):
            ax.contour(ca, cb, field.T, levels=[0.0], colors=_SERIAL_COLOURS[leg])
            handles.append(
                Line2D([], [], color=_SERIAL_COLOURS[leg], label=f"serial, leg {leg + 1}")
            )
    det = np.ma.masked_invalid(np.squeeze(wmap.parallel_det, axis=fixed))
    if det.count() and det.min() < 0.0 < det.max():
        ax.contour(ca, cb, det.T, levels=[0.0], colors="black", linestyles="dashed")
        handles.append(Line2D([], [], color="black", linestyle="dashed", label="parallel"))

    if cube is not None:
        corner, side = np.asarray(cube[0], dtype=float), float(cube[1])
        cuts = corner[fixed] <= level <= corner[fixed] + side
        ax.add_patch(
            Rectangle(
                (corner[a], corner[b]),
                side,
                side,
                fill=False,
                edgecolor="white",
                linewidth=1.5,
                linestyle="solid" if cuts else "dotted",
            )
        )
        label = "cube" if cuts else "cube (projection)"
        handles.append(Line2D([], [], color="white", linestyle="solid", label=label))
    for name, point in (markers or {}).items():
        p = np.asarray(point, dtype=float)
        ax.plot(p[a], p[b], marker="o", color="white", markeredgecolor="black")
        ax.annotate(
            f"{name} ({AXES[fixed]}={p[fixed]:.3f})",
            (p[a], p[b]),
            textcoords="offset points",
            xytext=(6, 6),
            color="white",
            fontsize=8,
        )

    ax.set_xlabel(f"{AXES[a]} [m]")
    ax.set_ylabel(f"{AXES[b]} [m]")
    ax.set_aspect("equal")
    ax.set_facecolor("0.85")  # unreachable points
    ax.set_title(title or f"{index} on the plane {AXES[fixed]} = {level:.4g} m")
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, facecolor="0.6")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    out = Path(path)
    atomic_write_bytes(out, buf.getvalue())
    return out
