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
* :mod:`~orthoglide_pin.kinetostatics.plotting`: heat maps of a slice;
* :mod:`~orthoglide_pin.kinetostatics.stiffness`: the elastostatic model,
  Cartesian stiffness and tool deflection (members in
  :mod:`~orthoglide_pin.kinetostatics.compliance_members`, compliant joints in
  :mod:`~orthoglide_pin.kinetostatics.compliance_joints`), maps and compliance
  ellipsoids (:mod:`~orthoglide_pin.kinetostatics.stiffness_maps`);
* :mod:`~orthoglide_pin.kinetostatics.frame_fea`: an independent check of
  the elastostatic model, a 3D frame FEA of the same members (PyNite, the
  ``[fea]`` extra).
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
from orthoglide_pin.kinetostatics.frame_fea import frame_compliance
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
from orthoglide_pin.kinetostatics.stiffness import CartesianStiffness, cartesian_stiffness
from orthoglide_pin.kinetostatics.stiffness_maps import (
    StiffnessMap,
    compliance_ellipsoid,
    stiffness_map,
)
from orthoglide_pin.kinetostatics.workspace import (
    Grid,
    WorkspaceMap,
    cube_grid,
    slice_grid,
    transmission_factor_map,
    workspace_map,
)

__all__ = [
    "CartesianStiffness",
    "Certification",
    "FactorRange",
    "Grid",
    "IsotropyResiduals",
    "KinetostaticIndices",
    "StiffnessMap",
    "WorkspaceDesign",
    "WorkspaceMap",
    "cartesian_stiffness",
    "certify",
    "certify_cube",
    "compliance_ellipsoid",
    "condition_number",
    "cube_grid",
    "design_from_workspace",
    "factor_range",
    "force_ellipsoid",
    "frame_compliance",
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
    "stiffness_map",
    "transmission_factor_map",
    "transmission_factors",
    "velocity_ellipsoid",
    "workspace_map",
]
