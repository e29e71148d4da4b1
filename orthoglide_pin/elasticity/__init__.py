"""Elasticity: the machine's stiffness, the tool's deflection, and the frame FEA check.

* :mod:`~orthoglide_pin.elasticity.stiffness`: the elastostatic model,
  Cartesian stiffness and tool deflection (members in
  :mod:`~orthoglide_pin.elasticity.members`, compliant joints in
  :mod:`~orthoglide_pin.elasticity.joints`);
* :mod:`~orthoglide_pin.elasticity.maps`: stiffness maps over a grid and
  compliance ellipsoids;
* :mod:`~orthoglide_pin.elasticity.frame_fea`: an independent check of the
  elastostatic model, a 3D frame FEA of the same members (PyNite, the
  ``[fea]`` extra).

The layer sits above :mod:`~orthoglide_pin.kinetostatics` (its maps use the
workspace grids) and above :mod:`~orthoglide_pin.dynamics` and
:mod:`~orthoglide_pin.drives`, because the machine's vibration needs the
bodies' inertias and the drives' reflected inertia as well as its stiffness.
It stays below the outputs (report, sweep, viewer, command line).
"""

from __future__ import annotations

from orthoglide_pin.elasticity.frame_fea import frame_compliance
from orthoglide_pin.elasticity.maps import StiffnessMap, compliance_ellipsoid, stiffness_map
from orthoglide_pin.elasticity.stiffness import CartesianStiffness, cartesian_stiffness

__all__ = [
    "CartesianStiffness",
    "StiffnessMap",
    "cartesian_stiffness",
    "compliance_ellipsoid",
    "frame_compliance",
    "stiffness_map",
]
