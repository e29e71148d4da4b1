"""The ``certify`` command: the transmission bounds proven over a whole cube."""

from __future__ import annotations

import argparse
from typing import Any

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError


def _mm(values: Any) -> str:
    return common.fmt(values, 1e3, ".3f") + " mm"


def _cmd_certify(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinetostatics.certify import certify

    params = common.build_params(args)
    corner, side = common.cube_arguments(args)
    lo, hi = common.psi_bounds(args)
    tol = common.finite("--tol", args.tol)
    if args.max_boxes < 1:
        raise InvalidParameterError("--max-boxes", args.max_boxes, "a positive integer")
    result = certify(params, corner, side, lo, hi, tol=tol, max_boxes=args.max_boxes)
    full = result.to_dict()
    payload = {
        "certified": result.certified,
        "factor_bounds": full["factor_bounds"],
        "counterexample": full["counterexample"],
        "boxes": result.boxes,
        "seconds": result.seconds,
        **{k: v for k, v in full.items() if k not in ("certified", "boxes", "seconds")},
    }
    f_lo, f_hi = result.factor_bounds
    lines = [
        f"Cube of side {1e3 * result.side:.2f} mm from {_mm(result.corner)}, "
        f"leg {1e3 * result.leg_length:.2f} mm, bounds [{lo:g}, {hi:g}]",
        f"  {result.status.upper()}: {result.reason}",
        f"  certified enclosure of the factors  [{f_lo:.6f}, {f_hi:.6f}]"
        + ("" if result.tight else f" (not within {result.tolerance:g} of the attained ones)"),
        f"  attained at points                  [{result.attained[0]:.6f}, "
        f"{result.attained[1]:.6f}]",
        f"  certified margin                    {result.margin:+.3g}",
        f"  {result.boxes} boxes, depth {result.depth}, {result.seconds:.2f} s",
    ]
    if result.counterexample is not None:
        lines.append(f"  counterexample {_mm(result.counterexample)}")
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``certify`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "certify",
        _cmd_certify,
        "prove (interval arithmetic, branch and bound) that every point of a cube has its "
        "transmission factors within bounds, or give a counterexample",
    )
    common.add_cube_options(p)
    p.add_argument(
        "--psi",
        nargs=2,
        default=["0.5", "2"],
        metavar=("MIN", "MAX"),
        help="bounds on the transmission factors",
    )
    p.add_argument(
        "--tol", default="1e-4", metavar="TOL", help="tolerance of the certified enclosure"
    )
    p.add_argument("--max-boxes", type=int, default=400_000, metavar="N", help="budget of boxes")
