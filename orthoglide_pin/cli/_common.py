"""Shared pieces of the command line: parameters, numbers, output and errors.

The argument parser itself is :mod:`orthoglide_pin.cli._parser`.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from orthoglide_pin.exceptions import InvalidParameterError, NonFiniteResultError

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.params import OrthoglideParams

PROG = "orthoglide"
#: Exit status of every reported error (the same as argparse's usage errors).
EXIT_ERROR = 2
_NONE_WORDS = frozenset({"none", "null", "auto"})

Handler = Callable[[argparse.Namespace], int]


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


def numbers(
    name: str, values: Sequence[str], what: str, size: int | None = None
) -> np.ndarray[Any, Any]:
    """The finite numbers of an option, given as words (``-1 0 0``) or one list (``-1,0,0``).

    Args:
        name: The option, for the error message.
        values: Its words.
        what: The numbers expected, with units (e.g. ``"X Y Z or X,Y,Z [m]"``).
        size: How many numbers, or ``None`` for any count.

    Returns:
        The numbers, shape (size,).

    Raises:
        InvalidParameterError: A wrong count (naming the words) or a word that is
            not a finite number (naming it).
    """
    if len(values) == 1 and "," in values[0]:
        values = values[0].split(",")
    if size is not None and len(values) != size:
        raise InvalidParameterError(name, " ".join(values), f"{size} numbers {what}")
    out = []
    for text in values:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise InvalidParameterError(name, text, f"a finite number ({what})")
        out.append(value)
    return np.array(out)


def tool_wrench(values: Sequence[str] | None) -> np.ndarray[Any, Any] | None:
    """``--wrench FX FY FZ [MX MY MZ]``: 3 or 6 finite numbers [N, N.m], or ``None``."""
    if values is None:
        return None
    wrench = numbers("--wrench", values, "FX FY FZ [MX MY MZ] [N, N.m]")
    if wrench.size not in (3, 6):
        raise InvalidParameterError("--wrench", " ".join(values), "3 or 6 numbers [N, N.m]")
    return wrench


def cube_arguments(
    args: argparse.Namespace,
) -> tuple[tuple[float, float, float] | None, float | None]:
    """``(corner, side)`` of ``--corner``/``--workspace`` [m], ``None`` where not given."""
    side = None if args.workspace is None else finite("--workspace", args.workspace)
    corner = None
    if args.corner is not None:
        x, y, z = (finite(f"--corner {n}", v) for n, v in zip("XYZ", args.corner, strict=True))
        corner = (x, y, z)
    return corner, side


def psi_bounds(args: argparse.Namespace) -> tuple[float, float]:
    """``--psi MIN MAX``: the bounds of a criterion on the transmission factors [-].

    Raises:
        InvalidParameterError: A bound that is not a finite number, or not
            ``0 < MIN < 1 < MAX`` (named ``psi_min``, ``psi_max``, as in a file).
    """
    from orthoglide_pin.machine.criterion import check_bounds

    lo, hi = (finite(f"--psi {n}", v) for n, v in zip(("MIN", "MAX"), args.psi, strict=True))
    return check_bounds(lo, hi)


def add_psi_option(p: argparse.ArgumentParser) -> None:
    """``--psi MIN MAX``: another criterion than the machine's ``psi_min``, ``psi_max``."""
    p.add_argument(
        "--psi",
        nargs=2,
        metavar=("MIN", "MAX"),
        help="bounds of the criterion on the transmission factors, MIN < 1 < MAX "
        "(default: the machine's, psi_min and psi_max of --config/--param)",
    )


def with_criterion(args: argparse.Namespace, params: OrthoglideParams) -> OrthoglideParams:
    """``params`` with the criterion of ``--psi``, if given (else its own)."""
    if getattr(args, "psi", None) is None:
        return params
    lo, hi = psi_bounds(args)
    return params.replace(psi_min=lo, psi_max=hi)


def criterion_info(
    args: argparse.Namespace, params: OrthoglideParams, tol: float | None = None
) -> tuple[dict[str, Any], str]:
    """The criterion a command judges by: for ``--json`` and in words.

    Returns:
        ``({"psi_min", "psi_max", "tolerance", "from"}, text)``; ``from`` is
        ``"--psi"`` or ``"machine"`` (the machine's ``psi_min``, ``psi_max``).
    """
    from orthoglide_pin.machine.criterion import CRITERION_TOL, describe

    tol = CRITERION_TOL if tol is None else tol
    given = getattr(args, "psi", None) is not None
    info = {
        "psi_min": params.psi_min,
        "psi_max": params.psi_max,
        "tolerance": tol,
        "from": "--psi" if given else "machine",
    }
    whose = "from --psi" if given else "the machine's psi_min and psi_max"
    return info, f"{describe(params.psi_min, params.psi_max, tol)}, {whose}"


def with_cube(args: argparse.Namespace, params: OrthoglideParams) -> OrthoglideParams:
    """``params`` with the cube of ``--workspace``/``--corner``, if given.

    The cube replaces the machine's prescribed cube, so the slider limits
    derived from it follow; given limits that cannot reach it are refused.
    """
    corner, side = cube_arguments(args)
    changes: dict[str, Any] = {}
    if side is not None:
        changes["workspace_side"] = side
    if corner is not None:
        changes["workspace_corner"] = corner
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


def _plain(value: Any) -> Any:
    """``json.dumps`` hook: numpy scalars and arrays as Python numbers and lists, paths as text."""
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not JSON serializable")


def check_finite(payload: Any, where: str = "") -> None:
    """Refuse a result that holds a NaN or an infinity, naming where it is.

    Args:
        payload: Nested dicts, lists, numbers and arrays.
        where: Name of ``payload`` in the message (built up in the recursion).

    Raises:
        NonFiniteResultError: At the first non-finite number.
    """
    if isinstance(payload, dict):
        for key, value in payload.items():
            check_finite(value, f"{where}.{key}" if where else str(key))
    elif isinstance(payload, (list, tuple)):
        for i, value in enumerate(payload):
            check_finite(value, f"{where}[{i}]")
    elif isinstance(payload, np.ndarray):
        if payload.dtype.kind in "fc" and not np.isfinite(payload).all():
            index = tuple(int(i) for i in np.argwhere(~np.isfinite(payload))[0])
            raise NonFiniteResultError(
                where + "".join(f"[{i}]" for i in index), float(payload[index].real)
            )
    elif isinstance(payload, (float, np.floating)) and not math.isfinite(payload):
        raise NonFiniteResultError(where, float(payload))


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> int:
    """Print the JSON object (``--json``) or the readable text; return 0.

    The result is checked first: a NaN or an infinity anywhere in ``payload``
    is an error (:class:`~orthoglide_pin.exceptions.NonFiniteResultError`, exit
    2) and nothing is printed, so ``--json`` output is always strict JSON
    (no ``NaN`` or ``Infinity``). ``null`` in it means "no value" as
    documented by each command (e.g. ``map``'s ``min`` with no reachable point).
    """
    check_finite(payload)
    print(json.dumps(payload, allow_nan=False, default=_plain) if args.json else text)
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


def error(message: str, command: str | None = None) -> int:
    """Print one line ``orthoglide CMD: error: MESSAGE`` on stderr; return the error status.

    The message is made one line of printable characters (runs of white space
    become one space, other control characters are escaped), at most
    :data:`~orthoglide_pin.exceptions.MAX_MESSAGE_CHARS` long
    (:func:`~orthoglide_pin.exceptions.one_line`), whatever it quotes.

    Args:
        message: What is wrong.
        command: The sub-command (``"plan"``), or ``None`` before one is known.
    """
    from orthoglide_pin.exceptions import one_line

    where = f"{PROG} {command}" if command else PROG
    print(f"{where}: error: {one_line(' '.join(message.split()))}", file=sys.stderr)
    return EXIT_ERROR


def read_program_text(path: str) -> str:
    """The text of a G-code file: a regular text file of at most ``MAX_PROGRAM_BYTES``.

    See :func:`orthoglide_pin.planning.gcode.read_program_file`.
    """
    from orthoglide_pin._io import read_input_text
    from orthoglide_pin.program.modes import MAX_PROGRAM_BYTES

    return read_input_text(path, "program", MAX_PROGRAM_BYTES)


@contextlib.contextmanager
def progress_bar(
    args: argparse.Namespace, description: str, unit: str
) -> Iterator[Callable[[int, int], None]]:
    """A progress callback ``(done, total)`` drawing a tqdm bar on standard error.

    The bar shows on a terminal only: it is quiet under ``--json`` or
    ``--quiet``, or when standard error is not a terminal; it is removed when
    the work ends.
    """
    from tqdm import tqdm

    quiet = bool(getattr(args, "json", False) or getattr(args, "quiet", False))
    shown = not quiet and sys.stderr.isatty()
    bar = tqdm(desc=description, unit=unit, file=sys.stderr, disable=not shown, leave=False)

    def update(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
        bar.update(max(0, done - bar.n))

    try:
        yield update
    finally:
        bar.close()
