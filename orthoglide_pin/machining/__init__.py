"""Machining: what the machine does to the part.

* :mod:`~orthoglide_pin.machining.cutting`: the cutting conditions (tool,
  material coefficients, engagement, spindle speed) and the cut file;
* :mod:`~orthoglide_pin.machining.forces`: Altintas' mechanistic milling
  force over a spindle revolution, its mean and peak;
* :mod:`~orthoglide_pin.machining.surface_error`: the tool's deflection under
  that force from the stiffness model, and the surface error it leaves;
* :mod:`~orthoglide_pin.machining.budget`: the error budget (geometric,
  servo, compliance, thermal) and its combinations;
* :mod:`~orthoglide_pin.machining.plan_samples` and
  :mod:`~orthoglide_pin.machining.accuracy`: all of it along a planned
  program (:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`);
  they import the planning layer, and load on first use.

The layer sits above :mod:`~orthoglide_pin.planning` and
:mod:`~orthoglide_pin.elasticity` (it takes a planned program and the
machine's stiffness and modes) and below the outputs (report, sweep, viewer,
command line). It never imports the simulation: a simulated contour error is
given to it as an array.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.machining.budget import ErrorBudget, error_budget
from orthoglide_pin.machining.cutting import (
    DEFAULT_MODAL_DAMPING,
    CutConditions,
    Engagement,
    Material,
    Tool,
    ToolMode,
    cut_conditions,
    read_cut_file,
    shipped_cut_file,
    shipped_materials,
)
from orthoglide_pin.machining.forces import MillingForces, milling_forces
from orthoglide_pin.machining.surface_error import SurfaceError

if TYPE_CHECKING:
    from orthoglide_pin.machining.accuracy import (
        AccuracyResult,
        BlockAccuracy,
        accuracy_along_plan,
    )
    from orthoglide_pin.machining.plan_samples import (
        CutSamples,
        cut_samples,
        program_spindle_speed,
    )

_ACCURACY = "orthoglide_pin.machining.accuracy"
_SAMPLES = "orthoglide_pin.machining.plan_samples"
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "AccuracyResult": _ACCURACY,
        "BlockAccuracy": _ACCURACY,
        "accuracy_along_plan": _ACCURACY,
        "CutSamples": _SAMPLES,
        "cut_samples": _SAMPLES,
        "program_spindle_speed": _SAMPLES,
    },
    globals(),
)

__all__ = [
    "DEFAULT_MODAL_DAMPING",
    "AccuracyResult",
    "BlockAccuracy",
    "CutConditions",
    "CutSamples",
    "Engagement",
    "ErrorBudget",
    "Material",
    "MillingForces",
    "SurfaceError",
    "Tool",
    "ToolMode",
    "accuracy_along_plan",
    "cut_conditions",
    "cut_samples",
    "error_budget",
    "milling_forces",
    "program_spindle_speed",
    "read_cut_file",
    "shipped_cut_file",
    "shipped_materials",
]
