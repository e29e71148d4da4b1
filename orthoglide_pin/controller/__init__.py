"""Controller exports: a LinuxCNC 2.9 configuration of a design, with certified limits.

* :mod:`~orthoglide_pin.controller.limits`: the Cartesian speed and
  acceleration limits under which no slider exceeds its own anywhere in the
  cube (interval bounds of ``J^-1`` and of the velocity-product term);
* :mod:`~orthoglide_pin.controller.component`: the kinematics component
  (``orthoglide_kins.comp``, closed-form inverse, forward and Jacobian), in
  the design's program axes (:func:`~orthoglide_pin.program.axes.design_axes`,
  the axes ``orthoglide plan`` reads programs with; so are the INI's soft limits);
* :mod:`~orthoglide_pin.controller.configuration`: the INI, the HAL file of a
  simulated machine and a README;
* :mod:`~orthoglide_pin.controller.stream`: the optimal route, the time-optimal
  plan as a joint stream that HAL's ``streamer`` plays at the servo rate;
* :mod:`~orthoglide_pin.controller.player`: ``orthoglide_play.py``, which plays
  a stream on a running LinuxCNC session of the configuration.
"""

from orthoglide_pin.controller.component import COMPONENT, component_text
from orthoglide_pin.controller.configuration import FILES, configuration_files
from orthoglide_pin.controller.limits import CartesianLimits, certify_limits
from orthoglide_pin.controller.player import PLAYER, player_text
from orthoglide_pin.controller.stream import (
    STREAM_FILES,
    stream_columns,
    stream_files,
    stream_hal_text,
    stream_text,
)

__all__ = [
    "COMPONENT",
    "FILES",
    "PLAYER",
    "STREAM_FILES",
    "CartesianLimits",
    "certify_limits",
    "component_text",
    "configuration_files",
    "player_text",
    "stream_columns",
    "stream_files",
    "stream_hal_text",
    "stream_text",
]
