"""Overlays drawn over the machine: workspace cube, reference points, ellipsoids, paths.

* the prescribed workspace cube as a wireframe (12 edges);
* markers: small spheres at the isotropic point, Q1 and Q2;
* manipulability ellipsoids: a unit sphere placed by ``[R diag(s a) | c]``
  where ``a`` are the semi-axes, ``R`` the directions (a rotation, ``det R =
  +1``: meshcat splits a transform into position, rotation and scale, so a
  reflection or a shear would be lost) and ``s`` a drawing scale [m per unit];
  coloured by their condition number through a colormap, with a legend;
* a tool path as a polyline.

The ellipsoids come from :mod:`orthoglide_pin.kinetostatics.indices` (closed form): velocity
ellipsoids have the transmission factors as semi-axes, force ellipsoids their
inverses; both are dimensionless, hence the drawing scale. Compliance
ellipsoids (:func:`~orthoglide_pin.elasticity.maps.compliance_ellipsoid`,
the elastostatic model with actuators and links) have the tool displacement per
unit force as semi-axes, counted in [um/N] for the drawing scale; their
"condition number" is the ratio of their largest to smallest semi-axis.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_number, finite_rows, text
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.viewer.machine import rgb_int
from orthoglide_pin.viewer.scene import meshcat

FloatArray = NDArray[np.float64]

#: Ellipsoid kinds and their indices functions.
ELLIPSOID_KINDS: Final = ("velocity", "force", "compliance")
#: Unit of the compliance ellipsoids' semi-axes for drawing [m/N per um/N].
COMPLIANCE_UNIT: Final[float] = 1e-6
#: Most ellipsoids drawn at once (each is one meshcat object): a 20^3 grid.
MAX_ELLIPSOIDS: Final[int] = 8000
#: Most grid points per edge of :meth:`Viewer.grid_points` (``20^3 = MAX_ELLIPSOIDS``).
MAX_GRID_EDGE: Final[int] = 20
#: Default drawing scale of an ellipsoid [m per unit semi-axis].
ELLIPSOID_SCALE: Final[float] = 0.015
#: Default colormap of the condition number (cyan at 1, magenta at the top):
#: its colours differ from the machine's materials.
COLORMAP: Final[str] = "cool"
#: Colour of the cube edges, the tool path and the markers (RGB in [0, 1]).
CUBE_RGB: Final = (0.2, 0.2, 0.2)
PATH_RGB: Final = (0.05, 0.05, 0.05)
MARKER_RGB: Final = {
    "isotropic point": (1.0, 0.84, 0.0),
    "Q1": (0.55, 0.0, 0.0),
    "Q2": (0.0, 0.0, 0.5),
}
#: Radius of a marker sphere [m].
MARKER_RADIUS: Final[float] = 0.008


def css(rgb: ArrayLike) -> str:
    """An RGB colour in [0, 1] as a CSS ``#rrggbb`` string."""
    return f"#{rgb_int(rgb):06x}"


def cube_wireframe(corner: ArrayLike, side: float, rgb: ArrayLike = CUBE_RGB) -> dict[str, Any]:
    """The 12 edges of the cube ``[corner, corner + side]`` as a lowered meshcat object.

    Args:
        corner: Lowest corner [m], shape (3,).
        side: Side [m], positive.
        rgb: Colour in [0, 1].
    """
    c = finite_rows("corner", corner, 3, "[m]")[0]
    if not (np.isfinite(side) and side > 0):
        raise InvalidParameterError("side", side, "a positive length [m]")
    corners = np.array(list(itertools.product((0.0, 1.0), repeat=3)))
    edges = [
        (i, j)
        for i, j in itertools.combinations(range(8), 2)
        if np.abs(corners[i] - corners[j]).sum() == 1
    ]
    vertices = np.array([c + side * corners[k] for edge in edges for k in edge])
    g = meshcat("geometry")
    lines = g.LineSegments(
        g.PointsGeometry(vertices.T.astype(np.float32)),
        g.LineBasicMaterial(color=rgb_int(rgb), linewidth=2.0),
    )
    out: dict[str, Any] = lines.lower()
    return out


def polyline(
    points: ArrayLike, rgb: ArrayLike = PATH_RGB, colors: ArrayLike | None = None
) -> dict[str, Any]:
    """A polyline through ``points`` [m], shape (N, 3), as a lowered meshcat object.

    ``colors``: an RGB colour in [0, 1] per point, shape (N, 3), blended along the
    line (instead of the one colour ``rgb``).
    """
    p = finite_rows("path points", points, 3, "[m]")
    g = meshcat("geometry")
    c = None if colors is None else finite_rows("path colours", colors, 3).T.astype(np.float32)
    line = g.Line(
        g.PointsGeometry(p.T.astype(np.float32), color=c),
        g.LineBasicMaterial(color=rgb_int(rgb), linewidth=2.0, vertexColors=c is not None),
    )
    out: dict[str, Any] = line.lower()
    return out


def sphere(radius: float, rgb: ArrayLike, opacity: float = 1.0) -> dict[str, Any]:
    """A sphere of ``radius`` [m] centred on its node, as a lowered meshcat object."""
    g = meshcat("geometry")
    material = g.MeshLambertMaterial(color=rgb_int(rgb), opacity=float(opacity))
    out: dict[str, Any] = g.Mesh(g.Sphere(float(radius)), material).lower()
    return out


def translation(point: ArrayLike) -> FloatArray:
    """The 4 x 4 homogeneous translation to ``point`` [m]."""
    m = np.eye(4)
    m[:3, 3] = np.asarray(point, dtype=float)
    return m


def ellipsoid_matrix(
    centre: ArrayLike, axes: ArrayLike, directions: ArrayLike, scale: float
) -> FloatArray:
    """``[R diag(scale axes) | centre]``: the unit sphere onto an ellipsoid, shape (..., 4, 4).

    A ``directions`` basis with ``det = -1`` is turned into a rotation by
    flipping its first column (the same ellipsoid).

    Args:
        centre: Centres [m], shape (..., 3).
        axes: Semi-axes (dimensionless), shape (..., 3).
        directions: Orthonormal columns along the semi-axes, shape (..., 3, 3).
        scale: Drawing scale [m per unit].
    """
    c = np.asarray(centre, dtype=float)
    a = np.asarray(axes, dtype=float)
    r = np.array(directions, dtype=float)
    flip = np.linalg.det(r) < 0.0
    r[..., :, 0] = np.where(flip[..., np.newaxis], -r[..., :, 0], r[..., :, 0])
    m = np.zeros((*c.shape[:-1], 4, 4))
    m[..., :3, :3] = r * (scale * a)[..., np.newaxis, :]
    m[..., :3, 3] = c
    m[..., 3, 3] = 1.0
    return m


@dataclass(frozen=True)
class Ellipsoids:
    """Manipulability ellipsoids at tool points.

    Attributes:
        kind: ``"velocity"``, ``"force"`` or ``"compliance"``.
        points: Centres [m], shape (N, 3).
        axes: Semi-axes (dimensionless; [um/N] for compliance), shape (N, 3).
        directions: Rotations whose column ``k`` is along ``axes[:, k]``, shape (N, 3, 3).
        condition: Condition number of ``J`` (of ``C[:3, :3]`` for compliance)
            (>= 1), shape (N,).
    """

    kind: str
    points: FloatArray
    axes: FloatArray
    directions: FloatArray
    condition: FloatArray


def check_kind(kind: str, name: str = "ellipsoid kind") -> str:
    """``kind`` if it is an ellipsoid kind, else :class:`InvalidParameterError` naming ``name``."""
    if not isinstance(kind, str) or kind not in ELLIPSOID_KINDS:
        raise InvalidParameterError(name, kind, " or ".join(ELLIPSOID_KINDS))
    return kind


def ellipsoids(
    points: ArrayLike,
    leg_length: float,
    kind: str = "velocity",
    params: OrthoglideParams | None = None,
) -> Ellipsoids:
    """Velocity, force or compliance ellipsoids at tool points.

    Args:
        points: Tool points [m], shape (3,) or (N, 3).
        leg_length: Leg length [m] (velocity and force ellipsoids).
        kind: One of :data:`ELLIPSOID_KINDS`.
        params: The machine, for compliance ellipsoids (default: the prototype
            with this leg length).

    Raises:
        InvalidParameterError: On bad points (more than ``MAX_ELLIPSOIDS``
            included) or an unknown kind.
        UnreachablePointError, SingularConfigurationError: As the indices.
    """
    from orthoglide_pin.kinetostatics import indices

    p = finite_rows("ellipsoid points", points, 3, "[m]")
    if p.shape[0] > MAX_ELLIPSOIDS:
        raise InvalidParameterError(
            "ellipsoid points", f"{p.shape[0]} points", f"at most {MAX_ELLIPSOIDS} points"
        )
    if check_kind(kind) == "compliance":
        from orthoglide_pin.elasticity.maps import compliance_ellipsoid
        from orthoglide_pin.machine.params import prototype

        machine = prototype().replace(leg_length=leg_length) if params is None else params
        compliance, rotations = compliance_ellipsoid(p, machine)
        axes = compliance / COMPLIANCE_UNIT
        return Ellipsoids(kind, p, axes, rotations, axes[:, 2] / axes[:, 0])
    fn = indices.velocity_ellipsoid if kind == "velocity" else indices.force_ellipsoid
    axes, directions = fn(p, leg_length)
    condition = indices.condition_number(p, leg_length)
    return Ellipsoids(kind, p, axes, directions, np.asarray(condition, dtype=float))


def color_range(
    condition: ArrayLike, vmin: float | None = None, vmax: float | None = None
) -> tuple[float, float]:
    """The colour range of condition numbers: 1 (isotropic) to their largest value.

    A range of zero width (every value 1) widens to ``[1, 2]``.
    """
    lo = 1.0 if vmin is None else finite_number("vmin", vmin)
    hi = float(np.max(condition)) if vmax is None else finite_number("vmax", vmax)
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise InvalidParameterError("color range", (lo, hi), "finite numbers")
    if hi <= lo + 1e-9:
        hi = lo + 1.0
    return lo, hi


@dataclass(frozen=True)
class ColorScale:
    """The colour scale of the condition number, shared by the legend and every ellipsoid.

    Attributes:
        vmin: Condition number at the colormap's start (>= 1 usually).
        vmax: Condition number at its end.
        colormap: matplotlib colormap name.
        fixed: The range was given by the user: values beyond it are clamped
            to the colormap's ends (the legend says so); otherwise the viewer
            makes it cover every ellipsoid drawn.
    """

    vmin: float
    vmax: float
    colormap: str = COLORMAP
    fixed: bool = False

    @classmethod
    def covering(
        cls,
        condition: ArrayLike,
        colormap: str = COLORMAP,
        vmin: float | None = None,
        vmax: float | None = None,
    ) -> ColorScale:
        """The scale from 1 (or ``vmin``) to the largest ``condition`` (or ``vmax``)."""
        lo, hi = color_range(condition, vmin, vmax)
        return cls(lo, hi, colormap, vmin is not None or vmax is not None)

    def rgb(self, condition: ArrayLike) -> FloatArray:
        """Colours of ``condition`` on this scale (clamped to its ends), shape (..., 3)."""
        return colors(condition, self.vmin, self.vmax, self.colormap)


def colors(values: ArrayLike, vmin: float, vmax: float, colormap: str = COLORMAP) -> FloatArray:
    """RGB colours in [0, 1] of ``values`` through a matplotlib colormap, shape (..., 3)."""
    import matplotlib

    try:
        cmap = matplotlib.colormaps[text("colormap", colormap, "a matplotlib colormap name")]
    except KeyError:
        raise InvalidParameterError("colormap", colormap, "a matplotlib colormap name") from None
    t = np.clip((np.asarray(values, dtype=float) - vmin) / (vmax - vmin), 0.0, 1.0)
    return np.asarray(cmap(t)[..., :3], dtype=float)


def legend(
    items: dict[str, Any] | None = None,
    bar: tuple[str, ColorScale] | None = None,
    values: ArrayLike | None = None,
) -> dict[str, Any]:
    """Legend description for the page: an optional colour bar, then swatches.

    Args:
        items: Labels and their RGB colours in [0, 1] (swatches).
        bar: ``(title, scale)`` of a colour bar, or ``None``.
        values: The values drawn on the bar's scale: an end they pass is
            labelled ``<=`` or ``>=`` (clamped colours).
    """
    out: dict[str, Any] = {
        "items": [{"label": k, "color": css(v)} for k, v in (items or {}).items()]
    }
    if bar is not None:
        title, scale = bar
        lo, hi = scale.vmin, scale.vmax
        v = np.asarray([] if values is None else values, dtype=float)
        below = bool(v.size and v.min() < lo - 1e-12 * abs(lo))
        above = bool(v.size and v.max() > hi + 1e-12 * abs(hi))
        stops = colors(np.linspace(lo, hi, 11), lo, hi, scale.colormap)
        out.update(
            title=title,
            min=lo,
            max=hi,
            colormap=scale.colormap,
            min_label=("<= " if below else "") + f"{lo:.3g}",
            max_label=(">= " if above else "") + f"{hi:.3g}",
            stops=[css(c) for c in stops],
        )
    return out
