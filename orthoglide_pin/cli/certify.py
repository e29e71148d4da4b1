"""The ``certify`` command: a machine's criterion proven over a whole cube."""

from __future__ import annotations

import argparse
from typing import Any

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError

#: Exit status of each outcome: certified, violated (a counterexample), and
#: neither proven nor refuted (undecided, or a box that may meet a singular surface).
EXIT_STATUS = {"certified": 0, "violated": 1, "undecided": 3, "singular": 3}
#: The exit statuses in words, for ``--help``.
EPILOG = (
    "Exit status: 0 when certified (every factor of the cube proven within the criterion, "
    "to the tolerance), 1 when violated (a counterexample), 3 when undecided (neither "
    "proven nor refuted: a bound reached within the resolution, a box that may meet a "
    "singular surface, or the box budget spent, which a larger --max-boxes may "
    "extend), 2 on an error."
)


def _mm(values: Any) -> str:
    return common.fmt(values, 1e3, ".3f") + " mm"


def _cmd_certify(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinetostatics.certify import BOX_BUDGET_CAP, certify
    from orthoglide_pin.kinetostatics.design import prototype_note

    params = common.with_criterion(args, common.build_params(args))
    corner, side = common.cube_arguments(args)
    tol = common.finite("--tol", args.tol)
    if not 1 <= args.max_boxes <= BOX_BUDGET_CAP:
        raise InvalidParameterError(
            "--max-boxes", args.max_boxes, f"an integer in [1, {BOX_BUDGET_CAP}]"
        )
    result = certify(params, corner, side, tol=tol, max_boxes=args.max_boxes)
    info, criterion = common.criterion_info(args, params, result.tolerance)
    own_cube = corner is None and side is None
    note = prototype_note(params) if own_cube else None
    full = result.to_dict()
    payload = {
        "certified": result.certified,
        "factor_bounds": full["factor_bounds"],
        "counterexample": full["counterexample"],
        "boxes": result.boxes,
        "seconds": result.seconds,
        **{k: v for k, v in full.items() if k not in ("certified", "boxes", "seconds")},
        "criterion": info,
        "exit_status": EXIT_STATUS[result.status],
        "note": note,
    }
    f_lo, f_hi = result.factor_bounds
    lines = [
        f"Cube of side {1e3 * result.side:.2f} mm from {_mm(result.corner)}, "
        f"leg {1e3 * result.leg_length:.2f} mm",
        f"  criterion {criterion}",
        f"  {result.status.upper()}: {result.reason}",
        f"  certified enclosure of the factors  [{f_lo:.6f}, {f_hi:.6f}]"
        + ("" if result.tight else f" (not within {result.tolerance:g} of the attained ones)"),
        f"  attained at points                  [{result.attained[0]:.6f}, "
        f"{result.attained[1]:.6f}]",
        f"  certified margin                    {result.margin:+.3g} (to the criterion "
        f"widened by {result.tolerance:g}; >= 0 when certified)",
        f"  {result.boxes} boxes, depth {result.depth}, {result.seconds:.2f} s",
    ]
    if result.counterexample is not None:
        lines.append(f"  counterexample {_mm(result.counterexample)}")
    if note is not None:
        lo, hi = result.attained
        lines.append(f"  note: {note}: they lie in [{lo:.4f}, {hi:.4f}] over this cube")
    code = common.emit(args, payload, "\n".join(lines))
    return code if code else EXIT_STATUS[result.status]


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``certify`` command to the ``orthoglide`` parser."""
    from orthoglide_pin.machine.criterion import CRITERION_TOL

    p = common.add_command(
        sub,
        parent,
        "certify",
        _cmd_certify,
        "prove (interval arithmetic, branch and bound) that every point of a cube meets "
        "the machine's criterion on its transmission factors, or give a counterexample",
    )
    common.add_cube_options(p)
    common.add_psi_option(p)
    p.add_argument(
        "--tol",
        default=f"{CRITERION_TOL:g}",
        metavar="TOL",
        help="tolerance: the criterion's bounds are proven widened by it (the rule "
        "design uses), and the enclosure is refined to within it",
    )
    p.add_argument("--max-boxes", type=int, default=400_000, metavar="N", help="budget of boxes")
    p.epilog = EPILOG
