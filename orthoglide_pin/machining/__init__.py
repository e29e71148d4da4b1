"""Machining: what the machine does to the part.

* :mod:`~orthoglide_pin.machining.cutting`: the cutting conditions (tool,
  material coefficients, engagement, spindle speed) and the cut file;
* :mod:`~orthoglide_pin.machining.forces`: Altintas' mechanistic milling
  force over a spindle revolution, its mean and peak;
* :mod:`~orthoglide_pin.machining.surface_error`: the tool's deflection under
  that force from the stiffness model, and the surface error it leaves;
* :mod:`~orthoglide_pin.machining.budget`: the error budget (geometric,
  servo, compliance, thermal) and its combinations;
* :mod:`~orthoglide_pin.machining.frf`: the tool tip's modal model in the
  feed plane (the machine's modes at the point and the tool's) and its
  frequency response;
* :mod:`~orthoglide_pin.machining.stability`: chatter stability where the
  tool is (lobes, a map; the margin along a path,
  :mod:`~orthoglide_pin.machining.stability_path`) by semi-discretization
  (:mod:`~orthoglide_pin.machining.stability_sd`) of the regenerative model
  (:mod:`~orthoglide_pin.machining.regeneration`), with the zero-order
  solution (:mod:`~orthoglide_pin.machining.stability_zoa`) and a time-domain
  simulation (:mod:`~orthoglide_pin.machining.stability_td`) as checks;
* :mod:`~orthoglide_pin.machining.plan_samples` and
  :mod:`~orthoglide_pin.machining.accuracy`: all of it along a planned
  program (:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`);
  they import the planning layer, and load on first use; so does
  :mod:`~orthoglide_pin.machining.plan_stability`, the stability margin of
  every block of a plan (:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan`).

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
from orthoglide_pin.machining.frf import (
    ModalModel,
    frequency_response,
    single_mode,
    tool_tip_model,
    tool_tip_models,
)
from orthoglide_pin.machining.regeneration import MillingProcess
from orthoglide_pin.machining.stability import (
    LOBE_SPEEDS,
    StabilityLobes,
    limit_depth_map,
    milling_process,
    stability_lobes,
    tool_model,
)
from orthoglide_pin.machining.stability_path import (
    StabilityMargin,
    feed_angles,
    program_blocks,
    stability_margin_along,
)
from orthoglide_pin.machining.stability_sd import critical_depths_sd, spectral_radius_sd
from orthoglide_pin.machining.stability_td import (
    ChatterSimulation,
    simulate_chatter,
)
from orthoglide_pin.machining.stability_zoa import (
    critical_depths_zoa,
)
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
    from orthoglide_pin.machining.plan_stability import PlanStability, stability_along_plan

_ACCURACY = "orthoglide_pin.machining.accuracy"
_SAMPLES = "orthoglide_pin.machining.plan_samples"
_PLAN_STABILITY = "orthoglide_pin.machining.plan_stability"
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "AccuracyResult": _ACCURACY,
        "BlockAccuracy": _ACCURACY,
        "accuracy_along_plan": _ACCURACY,
        "CutSamples": _SAMPLES,
        "cut_samples": _SAMPLES,
        "program_spindle_speed": _SAMPLES,
        "PlanStability": _PLAN_STABILITY,
        "stability_along_plan": _PLAN_STABILITY,
    },
    globals(),
)

__all__ = [
    "DEFAULT_MODAL_DAMPING",
    "LOBE_SPEEDS",
    "AccuracyResult",
    "BlockAccuracy",
    "ChatterSimulation",
    "CutConditions",
    "CutSamples",
    "Engagement",
    "ErrorBudget",
    "Material",
    "MillingForces",
    "MillingProcess",
    "ModalModel",
    "PlanStability",
    "StabilityLobes",
    "StabilityMargin",
    "SurfaceError",
    "Tool",
    "ToolMode",
    "accuracy_along_plan",
    "critical_depths_sd",
    "critical_depths_zoa",
    "cut_conditions",
    "cut_samples",
    "error_budget",
    "feed_angles",
    "frequency_response",
    "limit_depth_map",
    "milling_forces",
    "milling_process",
    "program_blocks",
    "program_spindle_speed",
    "read_cut_file",
    "shipped_cut_file",
    "shipped_materials",
    "simulate_chatter",
    "single_mode",
    "spectral_radius_sd",
    "stability_along_plan",
    "stability_lobes",
    "stability_margin_along",
    "tool_model",
    "tool_tip_model",
    "tool_tip_models",
]
