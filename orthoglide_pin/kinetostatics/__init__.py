"""Kinetostatics: how well the machine transmits speed and force, and designs from a cube.

* :mod:`~orthoglide_pin.kinetostatics.transmission`: the transmission factors
  (singular values of ``J``) in closed form, block-wise;
* :mod:`~orthoglide_pin.kinetostatics.indices`: condition, manipulability,
  velocity and force ellipsoids, isotropy residuals (closed form or Pinocchio);
* :mod:`~orthoglide_pin.kinetostatics.workspace`: grids and workspace maps;
* :mod:`~orthoglide_pin.kinetostatics.design`: the machine of a prescribed
  cube and transmission bounds (paper section 3.4), verified on a grid;
* :mod:`~orthoglide_pin.kinetostatics.factor_range`: the factors over a
  machine's cube on a grid, and whether its criterion holds there;
* :mod:`~orthoglide_pin.kinetostatics.certify`: the criterion proven over the
  whole cube (interval arithmetic and branch and bound, on
  :mod:`~orthoglide_pin.kinetostatics.interval_jacobian`; its verdict in
  :mod:`~orthoglide_pin.kinetostatics.certification`), and the largest
  certified cube (:mod:`~orthoglide_pin.kinetostatics.largest_cube`);
* :mod:`~orthoglide_pin.kinetostatics.plotting`: heat maps of a slice.

The machine's stiffness lives one layer up, in :mod:`orthoglide_pin.elasticity`.
"""

from __future__ import annotations

from orthoglide_pin.kinetostatics.certify import Certification, certify, certify_cube
from orthoglide_pin.kinetostatics.design import (
    WorkspaceDesign,
    design_from_workspace,
    prototype_cube,
    prototype_note,
)
from orthoglide_pin.kinetostatics.factor_range import FactorRange, factor_range
from orthoglide_pin.kinetostatics.indices import (
    IsotropyResiduals,
    KinetostaticIndices,
    condition_number,
    force_ellipsoid,
    indices_from_jacobian,
    indices_from_model,
    inverse_condition,
    isotropy_residuals,
    kinetostatic_indices,
    manipulability,
    transmission_factors,
    velocity_ellipsoid,
)
from orthoglide_pin.kinetostatics.largest_cube import largest_certified_side
from orthoglide_pin.kinetostatics.plotting import plot_slice
from orthoglide_pin.kinetostatics.workspace import (
    Grid,
    WorkspaceMap,
    cube_grid,
    slice_grid,
    transmission_factor_map,
    workspace_map,
)

__all__ = [
    "Certification",
    "FactorRange",
    "Grid",
    "IsotropyResiduals",
    "KinetostaticIndices",
    "WorkspaceDesign",
    "WorkspaceMap",
    "certify",
    "certify_cube",
    "condition_number",
    "cube_grid",
    "design_from_workspace",
    "factor_range",
    "force_ellipsoid",
    "indices_from_jacobian",
    "indices_from_model",
    "inverse_condition",
    "isotropy_residuals",
    "kinetostatic_indices",
    "largest_certified_side",
    "manipulability",
    "plot_slice",
    "prototype_cube",
    "prototype_note",
    "slice_grid",
    "transmission_factor_map",
    "transmission_factors",
    "velocity_ellipsoid",
    "workspace_map",
]
