"""Shared pieces of the command line: parser, parameters, output and errors."""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from orthoglide_pin.exceptions import InvalidParameterError

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.params import OrthoglideParams

PROG = "orthoglide"
#: Exit status of every reported error (the same as argparse's usage errors).
EXIT_ERROR = 2
_NONE_WORDS = frozenset({"none", "null", "auto"})
# Negative numbers (with exponents, inf and nan) are positionals, never options.
_NEGATIVE_NUMBER = re.compile(
    r"^-(\d+\.?\d*([eE][-+]?\d+)?|\.\d+([eE][-+]?\d+)?|inf(inity)?|nan)$", re.IGNORECASE
)

Handler = Callable[[argparse.Namespace], int]


class Parser(argparse.ArgumentParser):
    """Argument parser that reads ``-1e-3`` or ``-.5`` as numbers, not options."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER


# ------------------------------------------------------------------ helpers
def unit(name: str) -> str:
    """SI unit of a parameter (from the table of plausible ranges)."""
    from orthoglide_pin.machine.ranges import PLAUSIBLE_RANGES

    entry = PLAUSIBLE_RANGES.get(name)
    if entry is not None:
        return entry[2]
    return "kg" if name.endswith("_mass") else "m"


def finite(name: str, text: str) -> float:
    """Parse a positional number [m]; reject non-numeric and non-finite text."""
    try:
        value = float(text)
    except ValueError:
        raise InvalidParameterError(name, text, "a finite number [m]") from None
    if not math.isfinite(value):
        raise InvalidParameterError(name, text, "a finite number [m]")
    return value


def triple(args: argparse.Namespace, names: Sequence[str]) -> np.ndarray[Any, Any]:
    """The three positional numbers ``names`` of ``args`` as an array [m]."""
    return np.array([finite(n, getattr(args, n)) for n in names])


def _parse_param(text: str, optional: frozenset[str]) -> tuple[str, Any]:
    """Split one ``--param NAME=VALUE`` (values are validated by the parameters)."""
    name, sep, value = text.partition("=")
    name, value = name.strip(), value.strip()
    if not sep or not name:
        raise InvalidParameterError(
            "--param", text, "NAME=VALUE, e.g. leg_length=0.3 or tool_offset=0,0,0.2"
        )
    if name in optional and value.lower() in _NONE_WORDS:
        return name, None
    return name, value


def build_params(args: argparse.Namespace) -> OrthoglideParams:
    """Parameters of a command: ``--config`` (or the prototype), then ``--param``.

    ``--param slider_lower=none`` (or ``auto``) derives a slider limit from the
    cube, like an omitted or ``null`` limit in the file.
    """
    from orthoglide_pin.machine.params import (
        LIMIT_FIELDS,
        OPTIONAL_FIELDS,
        OrthoglideParams,
        prototype,
    )

    optional = frozenset(OPTIONAL_FIELDS) | frozenset(LIMIT_FIELDS)
    changes = dict(_parse_param(t, optional) for t in args.param)
    base = OrthoglideParams.load(args.config) if args.config else prototype()
    return base.replace(**changes) if changes else base


def add_cube_options(p: argparse.ArgumentParser) -> None:
    """``--workspace LW`` and ``--corner X Y Z``: another prescribed cube [m]."""
    p.add_argument(
        "--workspace",
        metavar="LW",
        help="side of the prescribed cube [m] (default: the machine's, workspace_side)",
    )
    p.add_argument(
        "--corner",
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="lowest corner Q1 of the cube [m] (default: the machine's, workspace_corner)",
    )


def with_cube(args: argparse.Namespace, params: OrthoglideParams) -> OrthoglideParams:
    """``params`` with the cube of ``--workspace``/``--corner``, if given.

    The cube replaces the machine's prescribed cube, so the slider limits
    derived from it follow; given limits that cannot reach it are refused.
    """
    changes: dict[str, Any] = {}
    if args.workspace is not None:
        changes["workspace_side"] = finite("--workspace", args.workspace)
    if args.corner is not None:
        changes["workspace_corner"] = tuple(finite("--corner", c) for c in args.corner)
    return params.replace(**changes) if changes else params


#: Values this small, relative to the largest printed with them, print as 0.
NOISE_RTOL = 1e-12


def denoise(values: Any) -> np.ndarray[Any, Any]:
    """Values with rounding noise (``2.1e-17`` next to ``0.2``, or alone) set to 0."""
    arr = np.asarray(values, dtype=float)
    finite_abs = np.abs(arr[np.isfinite(arr)])
    top = max(1.0, float(finite_abs.max())) if finite_abs.size else 1.0
    return np.where(np.abs(arr) < NOISE_RTOL * top, 0.0, arr)


def fmt(values: Any, scale: float = 1.0, spec: str = ".10g") -> str:
    """Format numbers as ``(a, b, c)``, multiplied by ``scale``; noise prints as 0."""
    shown = denoise(scale * np.ravel(np.asarray(values, dtype=float)))
    return "(" + ", ".join(f"{float(v):{spec}}" for v in shown) + ")"


def fmt_matrix(m: np.ndarray[Any, Any]) -> str:
    """Rows of a small matrix, one indented line each."""
    snapped = np.where(np.abs(m) < 5e-10, 0.0, m)  # no "-0.000000000" from rounding noise
    return "\n".join("  [" + " ".join(f"{v:13.9f}" for v in row) + "]" for row in snapped)


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> int:
    """Print the JSON object (``--json``) or the readable text; return 0."""
    print(json.dumps(payload) if args.json else text)
    return 0


def closed_loop_model(params: OrthoglideParams) -> ClosedLoopModel:
    """The closed-loop Pinocchio model (imports Pinocchio on first use)."""
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    return ClosedLoopModel(params)


def add_command(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
    common: argparse.ArgumentParser,
    name: str,
    handler: Handler,
    help_text: str,
) -> argparse.ArgumentParser:
    """Add sub-command ``name`` with the common options, run by ``handler``."""
    p = sub.add_parser(name, parents=[common], help=help_text, description=help_text)
    p.set_defaults(handler=handler)
    return p


def add_point(p: argparse.ArgumentParser) -> None:
    """Positional tool point ``X Y Z`` [m]."""
    for name in ("x", "y", "z"):
        p.add_argument(name, metavar=name.upper(), help=f"tool point {name} [m]")


def error(message: str) -> int:
    """Print one error line on stderr and return the error exit status."""
    print(f"{PROG}: error: {' '.join(message.split())}", file=sys.stderr)
    return EXIT_ERROR
