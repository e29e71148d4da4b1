"""Calibration: the built machine's geometry, identified from measurements.

* :mod:`~orthoglide_pin.calibration.model`: the 18-parameter geometric error
  model (carriage points, rail directions, leg lengths) and its closed-form
  direct and inverse kinematics and Jacobians;
* :mod:`~orthoglide_pin.calibration.identification`: identification from measured
  tool positions (SVD identifiability, robust start, Levenberg-Marquardt,
  noise and parameter deviations);
* :mod:`~orthoglide_pin.calibration.measurements`: measurement files, read and
  checked;
* :mod:`~orthoglide_pin.calibration.result`: a calibration as a file, and the
  compensated kinematics it gives;
* :mod:`~orthoglide_pin.calibration.experiment`: measurement planning
  (D-optimal poses);
* :mod:`~orthoglide_pin.calibration.sensitivities`: the tool's sensitivity to
  each geometric error over the cube.

The layer sits above ``machine`` and ``kinematics``; its names load on first
use (the identification imports SciPy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports

if TYPE_CHECKING:
    from orthoglide_pin.calibration.experiment import MeasurementPlan, plan_poses
    from orthoglide_pin.calibration.identification import Identification, identify
    from orthoglide_pin.calibration.measurements import (
        Measurements,
        parse_measurements,
        read_measurements,
    )
    from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel
    from orthoglide_pin.calibration.result import (
        Calibration,
        load_calibration,
        write_calibration,
    )
    from orthoglide_pin.calibration.sensitivities import sensitivity, sensitivity_indices

_NAMES = {
    "MeasurementPlan": "experiment",
    "plan_poses": "experiment",
    "Identification": "identification",
    "identify": "identification",
    "Measurements": "measurements",
    "parse_measurements": "measurements",
    "read_measurements": "measurements",
    "PARAMETER_NAMES": "model",
    "GeometricModel": "model",
    "Calibration": "result",
    "load_calibration": "result",
    "write_calibration": "result",
    "sensitivity": "sensitivities",
    "sensitivity_indices": "sensitivities",
}
__getattr__, __dir__ = lazy_exports(
    __name__, {name: f"{__name__}.{module}" for name, module in _NAMES.items()}, globals()
)

__all__ = [
    "PARAMETER_NAMES",
    "Calibration",
    "GeometricModel",
    "Identification",
    "MeasurementPlan",
    "Measurements",
    "identify",
    "load_calibration",
    "parse_measurements",
    "plan_poses",
    "read_measurements",
    "sensitivity",
    "sensitivity_indices",
    "write_calibration",
]
