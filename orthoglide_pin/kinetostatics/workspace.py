"""Workspace maps: kinetostatic indices, reachability and singular distances on grids.

A :class:`Grid` is regular along x, y and z (the whole cube, or a plane slice
with one axis of a single value). Maps are computed block by block on reused
scratch, so memory beyond the results stays flat whatever the grid:

* :func:`transmission_factor_map`: the transmission factors only, the fast path
  (closed form, see :mod:`orthoglide_pin.kinetostatics.transmission`);
* :func:`workspace_map`: per point, reachability, every index and the distances
  to the serial and parallel singular surfaces (:class:`WorkspaceMap`).

Reachability: every leg within reach and away from its serial singularity
(``eta_i >= REACH_MARGIN L``), away from the parallel singularity
(``|det(u_1, u_2, u_3)| / L^3 >= REACH_MARGIN``), and the slider values within
the parameters' slider limits (``LIMIT_TOL`` of slack).

Distances [m]: to the serial singular surface of leg ``i``, the cylinder
``p_j^2 + p_k^2 = L^2`` around slider axis ``i``, exactly ``L - sqrt(p_j^2 + p_k^2)``
(negative out of reach); to the parallel singular surface ``det = 0`` (no closed
form), the first-order estimate ``|det| / |grad det|`` with the gradient in
closed form. It is exact for a plane and, near a simple root of ``det`` away from
serial singularities, off by a term of second order in the distance. It is only
an estimate elsewhere: about half the distance near a double root (the three
legs parallel, as at ``(t, t, t)`` with ``t = L / sqrt(3)``, where ``det`` touches
0 without changing sign), and too small near a serial singularity, where
``eta_i -> 0`` makes ``grad det`` unbounded.
"""

from __future__ import annotations

import io
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._paths import given_path
from orthoglide_pin._validation import (
    choice,
    finite_number,
    finite_vector,
    float_array,
    instance_of,
    integer,
    path_argument,
    points_array,
    positive_length,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import legs_from_etas, unit_leg_determinant
from orthoglide_pin.kinetostatics.transmission import BLOCK, factors_into, scratch
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Reachability margin: ``eta_i / L`` and ``|det(u_1, u_2, u_3)| / L^3`` at least this.
REACH_MARGIN: Final[float] = 1e-2
#: Slack on the slider limits [m] (rounding at the limits' own points).
LIMIT_TOL: Final[float] = 1e-12
#: Names accepted by :meth:`WorkspaceMap.index`, in CSV column order.
INDEX_NAMES: Final = (
    "psi_min",
    "psi_mid",
    "psi_max",
    "condition",
    "inverse_condition",
    "manipulability",
    "serial_distance",
    "parallel_distance",
)
AXES: Final = ("x", "y", "z")
#: Largest grid accepted [points]: checked before any array is allocated
#: (a map of 50 M points holds 1.2 GB of factors).
MAX_GRID_POINTS: Final[int] = 50_000_000
_MAX_POINTS: Final[int] = MAX_GRID_POINTS


def _check_size(n: int, dims: int) -> None:
    """Refuse ``n`` points per axis on ``dims`` axes beyond :data:`MAX_GRID_POINTS`."""
    if n**dims > MAX_GRID_POINTS:
        edge = int(MAX_GRID_POINTS ** (1.0 / dims) + 1e-9)
        raise InvalidParameterError(
            "n", n, f"at most {edge} points per axis ({MAX_GRID_POINTS} points in all)"
        )


@dataclass(frozen=True)
class Grid:
    """A regular grid of tool points, flattened in C order (x slowest, z fastest).

    Attributes:
        x: Coordinates along x [m], shape ``(nx,)``, likewise ``y`` and ``z``.
    """

    x: FloatArray
    y: FloatArray
    z: FloatArray

    def __post_init__(self) -> None:
        for name in AXES:
            values = getattr(self, name)
            arr = float_array(values)
            if arr.ndim != 1 or arr.size < 1 or not np.isfinite(arr).all():
                raise InvalidParameterError(name, values, "a non-empty 1-D array of finite [m]")
            object.__setattr__(self, name, arr)
        if self.size > _MAX_POINTS:
            raise InvalidParameterError("grid size", self.size, f"at most {_MAX_POINTS} points")

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(nx, ny, nz)``."""
        return (self.x.size, self.y.size, self.z.size)

    @property
    def size(self) -> int:
        """Number of points."""
        return self.x.size * self.y.size * self.z.size

    @property
    def fixed_axis(self) -> int | None:
        """Index of the single-valued axis of a plane slice, else ``None``."""
        single = [i for i, n in enumerate(self.shape) if n == 1]
        return single[0] if len(single) == 1 else None

    def points(self) -> FloatArray:
        """Every point [m], shape ``(nx, ny, nz, 3)`` (materialised: small grids)."""
        return np.stack(np.meshgrid(self.x, self.y, self.z, indexing="ij"), axis=-1)

    def point(self, index: int) -> FloatArray:
        """The point of flat (C-order) index ``index`` [m], shape (3,)."""
        i, j, k = np.unravel_index(integer("index", index, 0, self.size - 1), self.shape)
        return np.array([self.x[i], self.y[j], self.z[k]])

    def blocks(self, block: int = BLOCK) -> Iterator[tuple[int, int]]:
        """Flat index ranges ``[start, stop)``: whole z-rows, or pieces of one z-row.

        Args:
            block: Most points per range (a positive integer).
        """
        block = integer("block", block)
        nz, rows = self.z.size, self.x.size * self.y.size
        if nz <= block:
            step = (block // nz) * nz
            return ((s, min(s + step, rows * nz)) for s in range(0, rows * nz, step))
        return (
            (r * nz + s, r * nz + min(s + block, nz))
            for r in range(rows)
            for s in range(0, nz, block)
        )

    def fill(self, start: int, stop: int, rows: FloatArray) -> None:
        """Write the points ``[start, stop)`` of :meth:`blocks` as rows ``x, y, z`` of ``rows``.

        Args:
            start: First flat index, in ``[0, size)``.
            stop: One past the last, in ``(start, size]``; a range of :meth:`blocks`.
            rows: A writeable float64 array of at least 3 rows and
                ``stop - start`` columns.
        """
        start = integer("start", start, 0, self.size - 1)
        stop = integer("stop", stop, start + 1, self.size)
        ok = isinstance(rows, np.ndarray) and rows.dtype == np.float64 and rows.ndim == 2
        if not (
            ok and rows.shape[0] >= 3 and rows.shape[1] >= stop - start and rows.flags.writeable
        ):
            got = getattr(rows, "shape", type(rows).__name__)
            raise InvalidParameterError(
                "rows", got, f"a writeable float64 array (>= 3, >= {stop - start})"
            )
        ny, nz = self.y.size, self.z.size
        r0, r1 = start // nz, (stop - 1) // nz + 1
        if start % nz == 0 and (stop - start) % nz == 0:
            r = np.arange(r0, r1)
            view = rows[0:3, : stop - start].reshape(3, r1 - r0, nz)
            assert np.may_share_memory(view, rows)  # a view: splitting a contiguous axis
            view[0] = self.x[r // ny][:, np.newaxis]
            view[1] = self.y[r % ny][:, np.newaxis]
            view[2] = self.z[np.newaxis, :]
        else:  # a piece of one z-row (blocks longer than a row are cut row by row)
            rows[0, : stop - start] = self.x[r0 // ny]
            rows[1, : stop - start] = self.y[r0 % ny]
            rows[2, : stop - start] = self.z[start - r0 * nz : stop - r0 * nz]


def cube_grid(corner: ArrayLike, side: float, n: int) -> Grid:
    """``n^3`` points spanning the cube ``[corner, corner + side]`` (corners included).

    Args:
        corner: Lowest corner [m], shape ``(3,)``.
        side: Side [m].
        n: Points per edge (>= 2, ``n^3 <= MAX_GRID_POINTS``: 368).

    Raises:
        InvalidParameterError: A bad corner or side, or ``n`` out of range
            (checked before anything is allocated).
    """
    c, h = (
        points_array(corner, "corner"),
        positive_length("side", side),
    )
    if c.shape != (3,):
        raise InvalidParameterError("corner.shape", c.shape, "an array of shape (3,)")
    n = integer("n", n, 2)
    _check_size(n, 3)
    return Grid(*(np.linspace(ci, ci + h, n) for ci in c))


def slice_grid(
    axis: str, value: float, lower: Sequence[float], upper: Sequence[float], n: int
) -> Grid:
    """A plane slice ``axis = value``, ``n x n`` points over ``[lower, upper]``.

    Args:
        axis: ``"x"``, ``"y"`` or ``"z"``: the fixed coordinate.
        value: Its value [m].
        lower: Lower bounds [m] of the two other coordinates, in x, y, z order.
        upper: Upper bounds [m], likewise.
        n: Points along each in-plane axis (>= 2, ``n^2 <= MAX_GRID_POINTS``: 7071).

    Raises:
        InvalidParameterError: A bad axis, bounds or ``n`` (checked before
            anything is allocated).
    """
    choice("axis", axis, AXES)
    value = finite_number("value", value, "[m]")
    n = integer("n", n, 2)
    _check_size(n, 2)
    lo, hi = (finite_vector(name, b, 2, "[m]") for name, b in (("lower", lower), ("upper", upper)))
    if not np.all(hi > lo):
        raise InvalidParameterError("upper", tuple(hi), f"greater than lower {tuple(lo)}")
    fixed = AXES.index(axis)
    in_plane = iter(np.linspace(a, b, n) for a, b in zip(lo, hi, strict=True))
    coords = [np.array([value]) if i == fixed else next(in_plane) for i in range(3)]
    return Grid(*coords)


def transmission_factor_map(grid: Grid, leg_length: float, *, block: int = BLOCK) -> FloatArray:
    """Transmission factors on a grid, block-wise (NaN out of reach).

    Args:
        grid: The grid.
        leg_length: Leg length ``L`` [m].
        block: Points per block.

    Returns:
        Ascending factors, shape ``(nx, ny, nz, 3)``.
    """
    instance_of("grid", grid, Grid, "a Grid (cube_grid or slice_grid)")
    L = positive_length("leg_length", leg_length)
    block = integer("block", block)
    out = np.empty((*grid.shape, 3))
    flat = out.reshape(-1, 3)
    buf = scratch(grid.size, block)
    for start, stop in grid.blocks(buf.shape[1]):
        grid.fill(start, stop, buf)
        factors_into(buf, stop - start, L, flat[start:stop], check=False)
    return out


@dataclass(frozen=True)
class WorkspaceMap:
    """Indices, reachability and singular distances on a grid.

    Arrays have the grid's shape ``(nx, ny, nz)`` (plus a last axis of 3 where
    stated); values are NaN where undefined (a leg out of reach).

    Attributes:
        grid: The grid.
        leg_length: Leg length ``L`` [m].
        slider_limits: ``(lower, upper)`` slider limits used for reachability [m].
        reachable: Reachable points (see the module), bool.
        transmission_factors: Ascending factors, ``(..., 3)``.
        condition: ``sigma_3 / sigma_1``.
        inverse_condition: ``sigma_1 / sigma_3``.
        manipulability: ``det J``.
        serial_distances: Signed distance to the serial cylinder of each leg
            [m], ``(..., 3)`` (negative out of reach).
        serial_distance: The smallest of them [m].
        serial_leg: The leg it belongs to (1, 2 or 3), int8.
        parallel_det: ``det(u_1, u_2, u_3) / L^3``, signed (1 at home).
        parallel_distance: First-order distance to ``det = 0`` [m].
    """

    grid: Grid
    leg_length: float
    slider_limits: tuple[float, float]
    reachable: NDArray[np.bool_]
    transmission_factors: FloatArray
    condition: FloatArray
    inverse_condition: FloatArray
    manipulability: FloatArray
    serial_distances: FloatArray
    serial_distance: FloatArray
    serial_leg: NDArray[np.int8]
    parallel_det: FloatArray
    parallel_distance: FloatArray

    def index(self, name: str) -> FloatArray:
        """The index ``name`` (one of ``INDEX_NAMES``), grid-shaped."""
        columns = ("psi_min", "psi_mid", "psi_max")
        if not isinstance(name, str) or name not in (*columns, *INDEX_NAMES):
            allowed = "one of " + ", ".join((*columns, *INDEX_NAMES))
            raise InvalidParameterError("index name", name, allowed)
        if name in columns:
            return self.transmission_factors[..., columns.index(name)]
        return np.asarray(getattr(self, name))

    def to_csv(self) -> str:
        """CSV text: ``x, y, z`` [m], ``reachable`` (0/1), then every index, one row per point."""
        pts = self.grid.points().reshape(-1, 3)
        cols = [pts, self.reachable.reshape(-1, 1).astype(float)]
        cols += [self.index(n).reshape(-1, 1) for n in INDEX_NAMES]
        cols.append(self.serial_leg.reshape(-1, 1).astype(float))
        header = ",".join([*AXES, "reachable", *INDEX_NAMES, "serial_leg"])
        buf = io.StringIO()
        fmt = ["%.10g"] * 3 + ["%d"] + ["%.10g"] * len(INDEX_NAMES) + ["%d"]
        np.savetxt(buf, np.hstack(cols), delimiter=",", header=header, comments="", fmt=fmt)
        return buf.getvalue()

    def save_csv(self, path: str | Path) -> Path:
        """Write :meth:`to_csv` to ``path`` atomically; returns the path."""
        target = given_path(path_argument("path", path))
        atomic_write_text(target, self.to_csv())
        return target


def parallel_det_and_gradient(points: FloatArray, L: float) -> tuple[FloatArray, FloatArray]:
    """``det(u_1, u_2, u_3) / L^3`` and its gradient [1/m], for ``(m, 3)`` points.

    With ``C_i = u_(i+1) x u_(i+2)`` the cofactor rows of the leg matrix,
    ``d det / d p_m = (sum_(i != m) C_im - C_ii p_m / eta_i) / L^3``: only
    ``eta_i`` moves in row ``i`` besides ``p``. NaN out of reach.
    """
    with np.errstate(all="ignore"):
        sq = points * points
        eta = np.sqrt(L * L - (sq.sum(axis=1, keepdims=True) - sq))
        legs = legs_from_etas(points, eta)
        cof = np.cross(legs[:, [1, 2, 0]], legs[:, [2, 0, 1]])
        diag = np.einsum("nii->ni", cof)
        s = (diag / eta).sum(axis=1, keepdims=True)
        grad = cof.sum(axis=1) - diag - points * (s - diag / eta)
        return unit_leg_determinant(points, eta, L), grad / L**3


def _map_block(p: FloatArray, L: float, limits: tuple[float, float]) -> dict[str, FloatArray]:
    """Every field of :class:`WorkspaceMap` but the factors, for ``(m, 3)`` points."""
    sq = p * p
    rho2 = sq.sum(axis=1, keepdims=True) - sq
    with np.errstate(all="ignore"):
        serial = L - np.sqrt(rho2)
        eta = np.sqrt(L * L - rho2)
        det, grad = parallel_det_and_gradient(p, L)
        q = p + L - eta
        within = np.all((q >= limits[0] - LIMIT_TOL) & (q <= limits[1] + LIMIT_TOL), axis=1)
        reach = np.all(eta >= REACH_MARGIN * L, axis=1) & (np.abs(det) >= REACH_MARGIN) & within
        return {
            "reachable": reach,
            "manipulability": np.prod(eta, axis=1) / (det * L**3),
            "serial_distances": serial,
            "serial_distance": serial.min(axis=1),
            "serial_leg": (np.argmin(serial, axis=1) + 1).astype(np.int8),
            "parallel_det": det,
            "parallel_distance": np.abs(det) / np.linalg.norm(grad, axis=1),
        }


def workspace_map(grid: Grid, params: OrthoglideParams, *, block: int = BLOCK) -> WorkspaceMap:
    """Reachability, indices and singular distances at every point of ``grid``.

    Args:
        grid: The grid.
        params: The machine (leg length and slider limits).
        block: Points per block.
    """
    instance_of("grid", grid, Grid, "a Grid (cube_grid or slice_grid)")
    params = as_params(params)
    L, limits = params.leg_length, (params.slider_lower, params.slider_upper)
    block = integer("block", block)
    shape, n = grid.shape, grid.size
    factors = np.empty((n, 3))
    fields: dict[str, NDArray[np.generic]] = {}
    buf = scratch(n, block)
    for start, stop in grid.blocks(buf.shape[1]):
        grid.fill(start, stop, buf)
        points = buf[0:3, : stop - start].T.copy()
        factors_into(buf, stop - start, L, factors[start:stop], check=False)
        for name, values in _map_block(points, L, limits).items():
            if name not in fields:
                fields[name] = np.empty((n, *values.shape[1:]), dtype=values.dtype)
            fields[name][start:stop] = values
    with np.errstate(all="ignore"):
        condition = factors[:, 2] / factors[:, 0]
    shaped = {k: v.reshape(*shape, *v.shape[1:]) for k, v in fields.items()}
    return WorkspaceMap(
        grid=grid,
        leg_length=L,
        slider_limits=limits,
        transmission_factors=factors.reshape(*shape, 3),
        condition=condition.reshape(shape),
        inverse_condition=(1.0 / condition).reshape(shape),
        **shaped,  # type: ignore[arg-type]
    )


__all__ = [
    "INDEX_NAMES",
    "LIMIT_TOL",
    "REACH_MARGIN",
    "Grid",
    "WorkspaceMap",
    "cube_grid",
    "parallel_det_and_gradient",
    "slice_grid",
    "transmission_factor_map",
    "workspace_map",
]
