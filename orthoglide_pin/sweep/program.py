"""A part program in a sweep: each design's cycle time and the limit that binds most.

A sweep given a program (:attr:`~orthoglide_pin.sweep.spec.SweepSpec.program`,
its G-code text) plans it on every design
(:func:`~orthoglide_pin.planning.plan.plan_program`) with the sweep's settings
as the **slider** limits, as ``orthoglide report --program`` does: ``speed``
bounds every slider's speed [m/s], ``acceleration`` every slider's
acceleration [m/s^2], and the program's feeds cap the tool's path speed. The
sweep keeps only a drive train, no motor data, so no motor limit applies (and
the plan needs no torque). Two
columns join the table:

* ``cycle_time`` [s]: the program's duration on the design, dwells included;
* ``binding_limit``: the limit that binds for the largest share of the cycle
  time (``slider_speed``, ``slider_acceleration`` or ``feed``; ``"none"`` when
  none binds, e.g. a program of dwells).

On a design whose cube or slider range the program leaves (in redesign mode
the cube follows the leg), ``cycle_time`` is NaN and ``binding_limit`` is
:data:`UNREACHABLE`; the design's other metrics stand. The program is part of every
design (:func:`design_entry`: its text and SHA-256), so it is part of every
design's key, and of the sweep's record (:func:`record_entry`: its hash, size
and blocks): a sweep resumed with another program is refused, and no part of
another program is reused. With a cut file as well, the program is cut on
every design (:mod:`~orthoglide_pin.sweep.accuracy`: ``surface_error_max``,
``stability_margin_min``).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping
from typing import Any, Final

from orthoglide_pin.exceptions import InvalidParameterError, ProgramError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.sweep import accuracy as _accuracy

#: The columns a program adds to the table, after the metrics.
PROGRAM_COLUMNS: Final = ("cycle_time", "binding_limit")
#: Of them, the text columns.
PROGRAM_TEXT_COLUMNS: Final = frozenset({"binding_limit"})
#: ``binding_limit`` of a design whose cube or slider range the program leaves.
UNREACHABLE: Final = "unreachable"
#: Largest program text [characters] carried in a sweep.
MAX_PROGRAM_CHARS: Final[int] = 8_000_000


def check_program(text: Any) -> str:
    """The program text, read once to refuse a bad program before any design.

    Raises:
        InvalidParameterError: Not a text, or longer than :data:`MAX_PROGRAM_CHARS`.
        ProgramError: The first bad line of the program.
    """
    from orthoglide_pin.planning.gcode import read_program

    if not isinstance(text, str) or len(text) > MAX_PROGRAM_CHARS:
        raise InvalidParameterError(
            "program",
            type(text).__name__,
            f"G-code text of at most {MAX_PROGRAM_CHARS} characters",
        )
    read_program(text)
    return text


def _sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def design_entry(text: str) -> dict[str, str]:
    """The program as a design carries it: its text and SHA-256."""
    return {"sha256": _sha256(text), "text": text}


def record_entry(text: str) -> dict[str, Any]:
    """The program as the sweep's record names it: SHA-256, size and blocks."""
    from orthoglide_pin.planning.gcode import read_program

    return {
        "sha256": _sha256(text),
        "bytes": len(text.encode("utf-8")),
        "blocks": len(read_program(text).blocks),
    }


def columns(program: bool) -> tuple[str, ...]:
    """The program's columns of the table (none without a program)."""
    return PROGRAM_COLUMNS if program else ()


def program_metrics(params: OrthoglideParams, design: Mapping[str, Any]) -> dict[str, Any]:
    """``cycle_time`` [s] and ``binding_limit`` of the design's program (see the module).

    With a cut file (``design["cut"]``), also ``surface_error_max`` [m] and
    ``stability_margin_min`` [-] along the same plan (:mod:`~orthoglide_pin.sweep.accuracy`).
    """
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import plan_program
    from orthoglide_pin.program.axes import design_axes

    entry = design["program"]
    limits = PlanLimits(
        slider_speed=float(design["speed"]),
        slider_acceleration=float(design["acceleration"]),
    )
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    cut = design.get("cut") is not None
    try:
        program = read_program(entry["text"], axes=design_axes(params))
        plan = plan_program(program, dyn, limits)
    except ProgramError:  # out of this design's reach
        return {
            "cycle_time": math.nan,
            "binding_limit": UNREACHABLE,
            **(_accuracy.unreached() if cut else {}),
        }
    shares = {k: v for k, v in plan.binding.items() if v > 0.0}
    return {
        "cycle_time": float(plan.cycle_time),
        "binding_limit": max(shares, key=shares.__getitem__) if shares else "none",
        **(_accuracy.accuracy_metrics(params, plan, design) if cut else {}),
    }
