"""Cutting conditions in a sweep: each design's surface error and chatter stability margin.

A sweep given a program and a cut file (:attr:`~orthoglide_pin.sweep.spec.SweepSpec.cut`,
the cut file's mapping, as :func:`~orthoglide_pin.machining.cutting.cut_conditions`
takes it) cuts the program as the cut file says on every design, along the
plan of its ``cycle_time`` (:mod:`~orthoglide_pin.sweep.program`). Two columns
join the table:

* ``surface_error_max`` [m]: the largest magnitude of the surface error as the
  wall is generated (:func:`~orthoglide_pin.machining.accuracy.accuracy_along_plan`
  with its default sampling, what the part keeps); 0 when nothing cuts;
* ``stability_margin_min`` [-]: the least chatter stability margin over the
  program lines that cut
  (:func:`~orthoglide_pin.machining.plan_stability.stability_along_plan` with
  its default points per line: the limiting axial depth at the spindle speed
  at up to five of each line's cutting samples, along the planned feed there,
  over its line's engaged depth; below 1 the line chatters), with the sweep's
  drive train reflected onto the carriages; NaN when no line cuts.

Both are computed as ``orthoglide accuracy`` and ``orthoglide report --cut``
compute them: the same program, design, plan limits, drive train and cut give
the same figures by all three. The sweep plans under its slider limits only
(``speed``, ``acceleration``; no motor limit), and reflects its drive train
(``drive``), as its record states for every design.

The spindle speed is the cut file's, or the program's ``S`` when the file says
``program``. Both are NaN on a design the program does not reach. The cut file
is part of every design (:func:`design_entry`, its mapping), so it is part of
every design's key, and of the sweep's record (:func:`record_entry`): a
sweep resumed with another cut file is refused, and no part of another is reused.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from orthoglide_pin.exceptions import CutConditionsError, InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams

if TYPE_CHECKING:
    from orthoglide_pin.planning.plan import Plan

__all__ = [
    "ACCURACY_COLUMNS",
    "accuracy_metrics",
    "check_cut",
    "columns",
    "design_entry",
    "record_entry",
]

#: The columns a cut file adds to the table, after the program's.
ACCURACY_COLUMNS: Final = ("surface_error_max", "stability_margin_min")


def check_cut(cut: Any, program: str | None) -> dict[str, Any]:
    """The cut file's mapping, checked once before any design (see the module).

    Args:
        cut: The cut file's mapping, or the path of a cut file.
        program: The sweep's program text (a cut needs one).

    Raises:
        InvalidParameterError: No program, or a mapping that is not JSON.
        CutConditionsError: A bad cut file, or no spindle speed (neither the
            cut file's nor the program's ``S``).
    """
    from orthoglide_pin._io import read_yaml_mapping
    from orthoglide_pin.machining.cutting import cut_conditions
    from orthoglide_pin.machining.plan_samples import program_spindle_speed

    if program is None:
        raise InvalidParameterError("cut", "without a program", "a program to cut (program=)")
    if isinstance(cut, (str, os.PathLike)):
        try:
            cut = read_yaml_mapping(cut, "cut file")
        except CutConditionsError:
            raise
        except InvalidParameterError as exc:
            raise CutConditionsError(exc.name, exc.value, exc.allowed) from None
    if not isinstance(cut, Mapping):
        raise InvalidParameterError("cut", cut, "a cut file's mapping, or its path")
    conditions = cut_conditions(cut)
    if conditions.spindle_speed is None and program_spindle_speed(program) is None:
        raise CutConditionsError(
            "spindle_speed", "program", "a speed in the cut file, or S words in the program"
        )
    try:
        data: dict[str, Any] = json.loads(json.dumps(dict(cut), allow_nan=False))
    except (TypeError, ValueError):
        raise InvalidParameterError("cut", cut, "plain YAML values (numbers, texts)") from None
    return data


def _sha256(cut: Mapping[str, Any]) -> str:
    text = json.dumps(cut, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def design_entry(cut: Mapping[str, Any]) -> dict[str, Any]:
    """The cut as a design carries it: its mapping and SHA-256."""
    return {"sha256": _sha256(cut), "conditions": dict(cut)}


def record_entry(cut: Mapping[str, Any]) -> dict[str, Any]:
    """The cut as the sweep's record names it: SHA-256 and the mapping."""
    return design_entry(cut)


def columns(cut: bool) -> tuple[str, ...]:
    """The cut's columns of the table (none without a cut file)."""
    return ACCURACY_COLUMNS if cut else ()


def unreached() -> dict[str, float]:
    """Both columns on a design the program does not reach."""
    return dict.fromkeys(ACCURACY_COLUMNS, math.nan)


def accuracy_metrics(
    params: OrthoglideParams, plan: Plan, design: Mapping[str, Any]
) -> dict[str, float]:
    """``surface_error_max`` [m] and ``stability_margin_min`` [-] along ``plan`` (the module)."""
    from orthoglide_pin.drives.motor import DriveTrain
    from orthoglide_pin.machining.accuracy import accuracy_along_plan
    from orthoglide_pin.machining.cutting import cut_conditions
    from orthoglide_pin.machining.plan_samples import program_spindle_speed
    from orthoglide_pin.machining.plan_stability import stability_along_plan

    cut = cut_conditions(design["cut"]["conditions"])
    speed = cut.spindle_speed
    if speed is None:
        speed = program_spindle_speed(design["program"]["text"])
    result = accuracy_along_plan(plan, cut, params, spindle_speed=speed)
    stability = stability_along_plan(plan, result, params, drive=DriveTrain(**design["drive"]))
    surface = result.surface_generated
    margin = stability.margin
    return {
        "surface_error_max": float(np.abs(surface).max()) if surface.size else 0.0,
        "stability_margin_min": float(np.min(margin)) if margin.size else math.nan,
    }
