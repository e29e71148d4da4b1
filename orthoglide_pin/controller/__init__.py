"""Controller exports: a LinuxCNC 2.9 configuration of a design, with certified limits.

* :mod:`~orthoglide_pin.controller.limits`: the Cartesian speed and
  acceleration limits under which no slider exceeds its own anywhere in the
  cube (interval bounds of ``J^-1`` and of the velocity-product term), and the
  program-to-world axis mapping (:data:`PROGRAM_TO_WORLD`);
* :mod:`~orthoglide_pin.controller.component`: the kinematics component
  (``orthoglide_kins.comp``, closed-form inverse, forward and Jacobian);
* :mod:`~orthoglide_pin.controller.configuration`: the INI, the HAL file of a
  simulated machine and a README.
"""

from orthoglide_pin.controller.component import COMPONENT, component_text
from orthoglide_pin.controller.configuration import FILES, configuration_files
from orthoglide_pin.controller.limits import (
    PROGRAM_TO_WORLD,
    CartesianLimits,
    certify_limits,
    program_to_world,
    world_to_program,
)

__all__ = [
    "COMPONENT",
    "FILES",
    "PROGRAM_TO_WORLD",
    "CartesianLimits",
    "certify_limits",
    "component_text",
    "configuration_files",
    "program_to_world",
    "world_to_program",
]
