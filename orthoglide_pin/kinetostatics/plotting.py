"""Heat maps of a workspace slice, and figures that show themselves in a notebook.

:func:`plot_slice` draws one index of a plane
:class:`~orthoglide_pin.kinetostatics.workspace.WorkspaceMap`
over its reachable points, with the outline of a cube (its section by the
plane, or its dashed projection when the plane misses it), marked points
(projected on the plane: the isotropic point, Q1, Q2) and the singular curves
in the plane: the serial cylinder of each leg (distance 0) and the parallel
surface (``det(u_1, u_2, u_3) = 0``). It draws into a new figure or into given
axes, on a colour scale of its own or a given one (``vmin``, ``vmax``: two
designs side by side on one scale), returns the figure and, given a path,
writes it as PNG, atomically.

:func:`new_figure` makes the package's figures: matplotlib on its Agg canvas
(no display needed, pyplot's global state left alone), shown as an image by
Jupyter (``_repr_png_``) whether or not pyplot was imported. matplotlib is
imported on first use. Axis and colour-bar labels are words with their units
(:data:`INDEX_LABELS`).
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_bytes
from orthoglide_pin._validation import (
    choice,
    finite_vector,
    instance_of,
    integer,
    mapping,
    path_argument,
    positive_number,
    text,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.workspace import AXES, INDEX_NAMES, WorkspaceMap

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

FloatArray = NDArray[np.float64]

#: Units of the indices ("" for a pure number).
UNITS: Final = {
    "psi_min": "",
    "psi_mid": "",
    "psi_max": "",
    "condition": "",
    "inverse_condition": "",
    "manipulability": "",
    "serial_distance": "m",
    "parallel_distance": "m",
}
#: Colour-bar labels of the indices: words and units.
INDEX_LABELS: Final = {
    "psi_min": "smallest velocity transmission factor [-]",
    "psi_mid": "middle velocity transmission factor [-]",
    "psi_max": "largest velocity transmission factor [-]",
    "condition": "condition number of the Jacobian [-]",
    "inverse_condition": "inverse condition number of the Jacobian [-]",
    "manipulability": "manipulability, det J [-]",
    "serial_distance": "distance to a serial singularity [m]",
    "parallel_distance": "distance to the parallel singularity [m]",
}
#: Indices drawn on a logarithmic colour scale when they span more than a decade.
LOG_INDICES: Final = frozenset({"condition", "psi_max", "manipulability"})
_SERIAL_COLOURS: Final = ("tab:red", "tab:green", "tab:blue")
#: Highest resolution of a PNG [dots per inch] (a 7 x 6 inch figure is then
#: 8400 x 7200 pixels, 240 MB of RGBA).
MAX_DPI: Final[int] = 1200


@cache
def _figure_class() -> type[Figure]:
    """The figure class of :func:`new_figure` (made once, on first use of matplotlib)."""
    from matplotlib.figure import Figure

    class NotebookFigure(Figure):
        """A figure that Jupyter displays as a PNG image."""

        def _repr_png_(self) -> bytes:
            buf = io.BytesIO()
            self.savefig(buf, format="png", bbox_inches="tight")
            return buf.getvalue()

    return NotebookFigure


def new_figure(width: float, height: float, **kwargs: Any) -> Figure:
    """A figure of ``width`` x ``height`` inches on an Agg canvas, shown as PNG by Jupyter.

    Args:
        width: Width [in].
        height: Height [in].
        **kwargs: Passed to ``matplotlib.figure.Figure`` (``layout``...).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = _figure_class()(figsize=(width, height), **kwargs)
    FigureCanvasAgg(fig)
    return fig


def save_png(fig: Figure, path: str | Path, dpi: int) -> Path:
    """Write ``fig`` to ``path`` as PNG at ``dpi``, atomically; return the path.

    Raises:
        InvalidParameterError: ``path`` is not a path, or ``dpi`` not an
            integer in ``[1, MAX_DPI]``.
    """
    out, dpi = Path(path_argument("path", path)), integer("dpi", dpi, 1, MAX_DPI)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    atomic_write_bytes(out, buf.getvalue())
    return out


def _plane(wmap: WorkspaceMap) -> tuple[int, int, int]:
    """``(fixed, a, b)`` axis indices of a plane map; raise for a 3-D map."""
    fixed = wmap.grid.fixed_axis
    if fixed is None:
        raise InvalidParameterError(
            "grid.shape", wmap.grid.shape, "a plane slice (exactly one axis of one point)"
        )
    a, b = (i for i in range(3) if i != fixed)
    return fixed, a, b


def _norm(
    values: np.ma.MaskedArray[Any, Any], index: str, vmin: float | None, vmax: float | None
) -> Any:
    """The colour scale: ``[vmin, vmax]`` where given, else the values' range."""
    from matplotlib.colors import LogNorm, Normalize

    data = values.compressed()
    lo = vmin if vmin is not None else float(data.min()) if data.size else 0.0
    hi = vmax if vmax is not None else float(data.max()) if data.size else 1.0
    if index in LOG_INDICES and lo > 0.0 and hi > 10.0 * lo:
        return LogNorm(lo, hi)
    return Normalize(lo, hi if hi > lo else lo + 1.0)


def _cube(cube: Any) -> tuple[FloatArray, float]:
    """``(corner [m], side [m])`` of the cube to outline, checked."""
    if not isinstance(cube, (tuple, list)) or len(cube) != 2:
        raise InvalidParameterError("cube", cube, "(corner, side) [m], or None")
    return finite_vector("cube", cube[0], 3, "[m]"), positive_number("cube", cube[1])


def _markers(markers: Any) -> dict[str, FloatArray]:
    """Named points to mark [m], checked."""
    named = mapping("markers", markers, "a mapping of names to points [m], or None")
    return {str(k): finite_vector(f"markers[{k!r}]", p, 3, "[m]") for k, p in named.items()}


def _limit(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
        raise InvalidParameterError(name, value, "a finite number or None")
    if not np.isfinite(value):
        raise InvalidParameterError(name, value, "a finite number or None")
    return float(value)


def plot_slice(
    wmap: WorkspaceMap,
    index: str,
    path: str | Path | None = None,
    *,
    ax: Axes | None = None,
    vmin: float | None = None,
    vmax: float | None = None,
    cube: tuple[ArrayLike, float] | None = None,
    markers: Mapping[str, ArrayLike] | None = None,
    title: str | None = None,
    dpi: int = 120,
) -> Figure:
    """Draw ``index`` of a plane map as a heat map; return the figure.

    Two designs on one colour scale: give both calls the same ``vmin`` and
    ``vmax``, and an axes each of one figure.

    Args:
        wmap: A map on a plane slice
            (see :func:`~orthoglide_pin.kinetostatics.workspace.slice_grid`).
        index: One of :data:`~orthoglide_pin.kinetostatics.workspace.INDEX_NAMES`.
        path: Also write the whole figure there as PNG (atomically), if given.
        ax: Axes to draw into (with its colour bar beside it); by default a
            new 7 x 6 inch figure (:func:`new_figure`).
        vmin: Index value at the colormap's start (default: the smallest shown).
        vmax: Index value at its end (default: the largest shown). A
            logarithmic index spanning more than a decade gets a log scale.
        cube: ``(corner, side)`` of a cube to outline [m].
        markers: Named points to mark [m], e.g. ``{"Q1": ..., "Q2": ...}``.
        title: Axes title (default: index and plane).
        dpi: Resolution of the PNG [dots per inch].

    Returns:
        The figure drawn into (that of ``ax`` when given).

    Raises:
        InvalidParameterError: A 3-D map, an unknown index, a non-finite
            ``vmin``/``vmax`` or ``vmin >= vmax``; nothing is written.
    """
    from matplotlib.axes import Axes
    from matplotlib.figure import SubFigure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    instance_of("wmap", wmap, WorkspaceMap, "a WorkspaceMap (workspace_map)")
    choice("index", index, INDEX_NAMES)
    if path is not None:
        path_argument("path", path)
    integer("dpi", dpi, 1, MAX_DPI)
    if ax is not None:
        instance_of("ax", ax, Axes, "matplotlib Axes or None")
    if title is not None:
        text("title", title, "a title (str) or None")
    outline = None if cube is None else _cube(cube)
    marks = {} if markers is None else _markers(markers)
    fixed, a, b = _plane(wmap)
    values = np.squeeze(wmap.index(index), axis=fixed)
    lo, hi = _limit("vmin", vmin), _limit("vmax", vmax)
    if lo is not None and hi is not None and not lo < hi:
        raise InvalidParameterError("vmin, vmax", (lo, hi), "vmin < vmax")
    reach = np.squeeze(wmap.reachable, axis=fixed)
    shown = np.ma.masked_where(~reach | ~np.isfinite(values), values)
    coords = (wmap.grid.x, wmap.grid.y, wmap.grid.z)
    ca, cb, level = coords[a], coords[b], float(coords[fixed][0])

    if ax is None:
        ax = new_figure(7.0, 6.0).add_subplot()
    owner = ax.figure  # a figure, or a subfigure of one
    mesh = ax.pcolormesh(ca, cb, shown.T, shading="nearest", cmap="viridis")
    mesh.set_norm(_norm(shown, index, lo, hi))
    owner.colorbar(mesh, ax=ax, label=INDEX_LABELS.get(index, index))
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

    if outline is not None:
        corner, side = outline
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
    for name, p in marks.items():
        ax.plot(p[a], p[b], marker="o", color="white", markeredgecolor="black")
        ax.annotate(
            f"{name} ({AXES[fixed]}={p[fixed]:.3f})",
            (p[a], p[b]),
            textcoords="offset points",
            xytext=(6, 6),
            color="white",
            fontsize=8,
        )

    ax.set_xlabel(f"tool position {AXES[a]} [m]")
    ax.set_ylabel(f"tool position {AXES[b]} [m]")
    ax.set_aspect("equal")
    ax.set_facecolor("0.85")  # unreachable points
    words = INDEX_LABELS.get(index, index).rsplit(" [", 1)[0]
    ax.set_title(title or f"{words} on the plane {AXES[fixed]} = {level:.4g} m")
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, facecolor="0.6")
    fig = owner.figure if isinstance(owner, SubFigure) else owner
    if path is not None:
        save_png(fig, path, dpi)
    return fig
