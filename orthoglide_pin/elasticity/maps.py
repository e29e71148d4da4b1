"""Stiffness over the workspace: maps, the worst point, compliance ellipsoids.

Built on :func:`~orthoglide_pin.elasticity.stiffness.cartesian_stiffness`
(vectorised over points). Two scalar fields summarise the 3x3 stiffness
``K = inv(C[:3, :3])`` at each tool point [N/m]:

* the **minimum stiffness** ``k_min``: the smallest eigenvalue of ``K``, the
  stiffness in the softest direction;
* the **deflection under a cutting force** of magnitude ``F`` [N] applied in
  that softest direction, the worst direction: ``F / k_min`` [m]. (The tool
  rotation that comes with it is in the 6x6 compliance.)

The **compliance ellipsoid** at a point is the set of tool displacements
``C[:3, :3] f`` under unit forces ``|f| <= 1``: semi-axes are the eigenvalues
of ``C[:3, :3]`` [m/N], along its eigenvectors.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import instance_of, positive_number
from orthoglide_pin.elasticity.stiffness import (
    DEFAULT_SOURCES,
    cartesian_stiffness,
    parse_sources,
    stiffness_assumptions,
)
from orthoglide_pin.kinematics.singularity import MAX_CONDITION
from orthoglide_pin.kinetostatics.workspace import Grid
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

__all__ = [
    "DEFAULT_CUTTING_FORCE",
    "StiffnessMap",
    "compliance_ellipsoid",
    "stiffness_map",
]

#: Magnitude of the cutting force of the maps and the report [N]: a light
#: milling or drilling force of an aluminium machining, applied at the tool
#: tip in the worst direction.
DEFAULT_CUTTING_FORCE: Final[float] = 100.0


@dataclass(frozen=True)
class StiffnessMap:
    """Stiffness indices on a grid of tool points.

    Attributes:
        grid: The grid (shape ``(nx, ny, nz)``).
        min_stiffness: Smallest eigenvalue of ``K`` [N/m], grid shape.
        max_stiffness: Largest eigenvalue of ``K`` [N/m], grid shape.
        deflection: ``cutting_force / min_stiffness`` [m], grid shape.
        cutting_force: Magnitude of the cutting force [N].
        sources: Compliance sources.
        assumptions: See
            :func:`~orthoglide_pin.elasticity.stiffness.stiffness_assumptions`.
    """

    grid: Grid
    min_stiffness: FloatArray
    max_stiffness: FloatArray
    deflection: FloatArray
    cutting_force: float
    sources: tuple[str, ...]
    assumptions: dict[str, Any]

    def worst(self) -> tuple[FloatArray, float]:
        """The point of lowest stiffness [m], shape (3,), and that stiffness [N/m]."""
        idx = int(np.argmin(self.min_stiffness))
        return self.grid.point(idx), float(self.min_stiffness.reshape(-1)[idx])

    def summary(self) -> dict[str, Any]:
        """JSON-ready figures over the grid (SI units), with the assumptions."""
        point, k_min = self.worst()
        return {
            "min_stiffness": k_min,
            "worst_point": [float(v) for v in point],
            "median_min_stiffness": float(np.median(self.min_stiffness)),
            "max_stiffness": float(self.max_stiffness.max()),
            "cutting_force": self.cutting_force,
            "max_deflection": float(self.deflection.max()),
            "grid_points": int(self.grid.size),
            "assumptions": self.assumptions,
        }


def stiffness_map(
    grid: Grid,
    params: OrthoglideParams | None = None,
    sources: str | Iterable[str] = DEFAULT_SOURCES,
    *,
    cutting_force: float = DEFAULT_CUTTING_FORCE,
    check_limits: bool = True,
    max_condition: float = MAX_CONDITION,
) -> StiffnessMap:
    """Minimum stiffness and worst-direction deflection at every grid point.

    Args:
        grid: Tool points (see :func:`~orthoglide_pin.kinetostatics.workspace.cube_grid`).
        params: Machine parameters; the prototype when ``None``.
        sources: Compliance sources.
        cutting_force: Magnitude of the cutting force [N].
        check_limits: Refuse points beyond the slider limits.
        max_condition: Largest condition number of ``J`` accepted.

    Raises:
        InvalidParameterError: On a bad grid, sources, force or options.
        UnreachablePointError, SingularConfigurationError: At the first bad point.
    """
    instance_of("grid", grid, Grid, "a Grid (cube_grid or slice_grid)")
    params = as_params(params)
    force = positive_number("cutting_force", cutting_force, "a positive force [N]")
    src = parse_sources(sources)
    points = grid.points().reshape(-1, 3)
    result = cartesian_stiffness(
        points, params, src, check_limits=check_limits, max_condition=max_condition
    )
    eig: FloatArray = np.asarray(np.linalg.eigvalsh(result.K), dtype=np.float64)
    k_min: FloatArray = eig[:, 0].reshape(grid.shape)
    return StiffnessMap(
        grid=grid,
        min_stiffness=k_min,
        max_stiffness=eig[:, -1].reshape(grid.shape),
        deflection=np.asarray(force / k_min, dtype=np.float64),
        cutting_force=force,
        sources=src,
        assumptions=stiffness_assumptions(params, src),
    )


def compliance_ellipsoid(
    points: ArrayLike,
    params: OrthoglideParams | None = None,
    sources: str | Iterable[str] = DEFAULT_SOURCES,
    *,
    check_limits: bool = True,
    max_condition: float = MAX_CONDITION,
) -> tuple[FloatArray, FloatArray]:
    """Compliance ellipsoid ``{C[:3, :3] f : |f| <= 1}`` of the tool tip.

    Args:
        points: Tool points [m], shape (3,) or (..., 3).
        params: Machine parameters; the prototype when ``None``.
        sources: Compliance sources.
        check_limits: Refuse points beyond the slider limits.
        max_condition: Largest condition number of ``J`` accepted.

    Returns:
        ``(axes, directions)``: semi-axes [m/N], ascending, shape (..., 3), and
        rotations (``det = +1``), shape (..., 3, 3), column ``k`` along
        ``axes[..., k]``.
    """
    result = cartesian_stiffness(
        points, params, sources, check_limits=check_limits, max_condition=max_condition
    )
    axes, vectors = np.linalg.eigh(result.compliance[..., :3, :3])
    sign = np.where(np.linalg.det(vectors) < 0.0, -1.0, 1.0)
    vectors[..., :, 0] *= sign[..., np.newaxis]
    return np.asarray(axes, dtype=np.float64), np.asarray(vectors, dtype=np.float64)
