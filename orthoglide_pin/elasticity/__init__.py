"""Elasticity: the machine's stiffness, the tool's deflection, and the frame FEA check.

* :mod:`~orthoglide_pin.elasticity.stiffness`: the elastostatic model,
  Cartesian stiffness and tool deflection (members in
  :mod:`~orthoglide_pin.elasticity.members`, compliant joints in
  :mod:`~orthoglide_pin.elasticity.joints`);
* :mod:`~orthoglide_pin.elasticity.maps`: stiffness maps over a grid and
  compliance ellipsoids;
* :mod:`~orthoglide_pin.elasticity.frame_fea`: an independent check of the
  elastostatic model, a 3D frame FEA of the same members (PyNite, the
  ``[fea]`` extra);
* :mod:`~orthoglide_pin.elasticity.frame_modal_fea`: an independent check
  of the full vibration model, a modal frame FEA of the same structure
  (OpenSeesPy, the ``[modal]`` extra);
* :mod:`~orthoglide_pin.elasticity.modes`: natural frequencies and mode
  shapes, the full model (:mod:`~orthoglide_pin.elasticity.frame_modes`, the
  members with their beam masses, :mod:`~orthoglide_pin.elasticity.mass`)
  and the fast platform model (:mod:`~orthoglide_pin.elasticity.platform_model`,
  the platform and the carriages on springs); they import Pinocchio and load on
  first use.

The layer sits above :mod:`~orthoglide_pin.kinetostatics` (its maps use the
workspace grids) and above :mod:`~orthoglide_pin.dynamics` and
:mod:`~orthoglide_pin.drives`, because the machine's vibration needs the
bodies' inertias and the drives' reflected inertia as well as its stiffness.
It stays below the outputs (report, sweep, viewer, command line).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.elasticity.frame_fea import frame_compliance
from orthoglide_pin.elasticity.maps import StiffnessMap, compliance_ellipsoid, stiffness_map
from orthoglide_pin.elasticity.stiffness import CartesianStiffness, cartesian_stiffness

if TYPE_CHECKING:
    from orthoglide_pin.elasticity.frame_modal_fea import frame_fea_modes
    from orthoglide_pin.elasticity.modes import NaturalModes, natural_frequencies

_MODES = "orthoglide_pin.elasticity.modes"
_MODAL_FEA = "orthoglide_pin.elasticity.frame_modal_fea"
__getattr__, __dir__ = lazy_exports(
    __name__,
    {"NaturalModes": _MODES, "natural_frequencies": _MODES, "frame_fea_modes": _MODAL_FEA},
    globals(),
)

__all__ = [
    "CartesianStiffness",
    "NaturalModes",
    "StiffnessMap",
    "cartesian_stiffness",
    "compliance_ellipsoid",
    "frame_compliance",
    "frame_fea_modes",
    "natural_frequencies",
    "stiffness_map",
]
