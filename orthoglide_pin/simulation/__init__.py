"""The machine in a physics engine (MuJoCo, ``pip install 'orthoglide-pin[sim]'``).

* :mod:`~orthoglide_pin.simulation.mjcf`: the machine as MJCF, with its loop
  closures as equality constraints, its drives and its force limits;
* :mod:`~orthoglide_pin.simulation.slider_drive`: the drive as the slider sees
  it (armature, friction, screw efficiency, the torque available, the
  feedforward torque);
* :mod:`~orthoglide_pin.simulation.engine`: the MJCF compiled and written, and
  our closed-loop states in MuJoCo's joint order;
* :mod:`~orthoglide_pin.simulation.servo`: the position loop of each slider
  (controllers, gains, encoder);
* :mod:`~orthoglide_pin.simulation.run`: a planned program run in MuJoCo under
  servo control (:func:`simulate`);
* :mod:`~orthoglide_pin.simulation.stepping`: the servo loop around MuJoCo's
  steps, compiled with numba when it is installed
  (:mod:`~orthoglide_pin.simulation.stepping_compiled`, the same values);
* :mod:`~orthoglide_pin.simulation.contour`: the contour error, the tool's
  distance to the programmed path;
* :mod:`~orthoglide_pin.simulation.outputs`: the columns of ``simulation.csv``
  and the summary of ``orthoglide simulate``.

The modules import Pinocchio (through the dynamics layer): their names are
loaded on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports

if TYPE_CHECKING:
    from orthoglide_pin.simulation.contour import ContourError, contour_error
    from orthoglide_pin.simulation.engine import write_mjcf
    from orthoglide_pin.simulation.mjcf import mjcf_text
    from orthoglide_pin.simulation.run import SimulationRun, simulate
    from orthoglide_pin.simulation.servo import ServoSettings
    from orthoglide_pin.simulation.slider_drive import slider_force_limit, slider_ratio

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "ContourError": "orthoglide_pin.simulation.contour",
        "contour_error": "orthoglide_pin.simulation.contour",
        "write_mjcf": "orthoglide_pin.simulation.engine",
        "mjcf_text": "orthoglide_pin.simulation.mjcf",
        "SimulationRun": "orthoglide_pin.simulation.run",
        "simulate": "orthoglide_pin.simulation.run",
        "ServoSettings": "orthoglide_pin.simulation.servo",
        "slider_force_limit": "orthoglide_pin.simulation.slider_drive",
        "slider_ratio": "orthoglide_pin.simulation.slider_drive",
    },
    globals(),
)

__all__ = [
    "ContourError",
    "ServoSettings",
    "SimulationRun",
    "contour_error",
    "mjcf_text",
    "simulate",
    "slider_force_limit",
    "slider_ratio",
    "write_mjcf",
]
