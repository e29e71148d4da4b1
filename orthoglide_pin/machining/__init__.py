"""Machining: what the machine does to the part.

* :mod:`~orthoglide_pin.machining.cutting`: the cutting conditions (tool,
  material coefficients, engagement, spindle speed) and the cut file;

The layer sits above :mod:`~orthoglide_pin.planning` and
:mod:`~orthoglide_pin.elasticity` (it takes a planned program and the
machine's stiffness and modes) and below the outputs (report, sweep, viewer,
command line). It never imports the simulation.
"""

from __future__ import annotations

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

__all__ = [
    "DEFAULT_MODAL_DAMPING",
    "CutConditions",
    "Engagement",
    "Material",
    "Tool",
    "ToolMode",
    "cut_conditions",
    "read_cut_file",
    "shipped_cut_file",
    "shipped_materials",
]
