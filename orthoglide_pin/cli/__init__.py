"""Command-line interface ``orthoglide`` (also ``python -m orthoglide_pin``).

Sub-commands, all in SI units (metres, kilograms):

* ``urdf [-o FILE]``: the URDF of the machine (stdout, or written atomically
  with its loop data beside it, ``FILE`` with the suffix ``.loops.yaml``);
* ``ik X Y Z``: slider values of a tool point (working branch, within limits);
* ``fk Q1 Q2 Q3 [--all-branches]``: tool point(s) of slider values;
* ``jacobian X Y Z [--method closed-form|pinocchio]``: ``J`` and ``J^-1``;
* ``summary [-o FILE.urdf] [--psi MIN MAX]``: parameters, masses, constraint
  rank, mobility and home Jacobian, the factors over the cube against the
  machine's criterion, and the URDF written next to it;
* ``design --workspace LW --psi MIN MAX [--write-config FILE.yaml]``: the machine
  of a prescribed cube, verified on a grid and certified over the whole cube;
  the file carries the cube and the bounds (the machine's criterion);
* ``certify [--workspace LW] [--corner X Y Z] [--psi MIN MAX]``: prove that
  every point of a cube meets the machine's criterion on its transmission
  factors (interval arithmetic), or give a counterexample; exit status 0 when
  certified, 1 when violated, 3 when undecided;
* ``indices X Y Z [--method closed-form|pinocchio]``: transmission factors,
  condition, manipulability and ellipsoids;
* ``map [--slice z=0.0] [--index NAME] --out FILE.png [--csv FILE]``: heat map
  of an index on a plane slice;
* ``stiffness X Y Z [--sources actuators,links,joints] [--wrench FX FY FZ MX MY MZ]``:
  Cartesian stiffness (``K``, ``K6``) of the tool tip and its deflection under a
  wrench, with the elastostatic model's assumptions;
* ``modes X Y Z [--motor FILE.yaml] [--count N] [--model full|platform]``:
  natural frequencies and mode shapes at a point;
* ``lobes X Y Z --cut CUT.yaml [--motor FILE.yaml] [--out DIR]``: chatter
  stability lobes at a point (the limiting axial depth against spindle speed);
  ``lobes --map --cut CUT.yaml [--grid N] [--speed RPM]``: the limiting depth at
  one speed over the design's cube;
* ``view [--ellipsoids grid|POINTS] [--trajectory NAME] [--static FILE.html]``:
  the machine in a browser, served on 127.0.0.1 until Ctrl-C, or one
  self-contained HTML file;
* ``sweep --leg-length START:STOP:N [--param NAME=START:STOP:N ...] --out DIR``:
  a grid of designs on local processes or a Dask cluster, as a tidy table
  (CSV and Parquet) and a plot; a rerun carries on where it stopped;
* ``dynamics --point X Y Z [--velocity ...] [--acceleration ...] [--wrench ...]``:
  slider forces, motor torques and speeds of one tool state;
* ``report [--motor FILE.yaml] [--safety-factor K] [--out DIR]``: the
  torque-requirement report (HTML, JSON, CSV), written atomically; exit status
  1 when its verdict is FAIL (the report is written), 0 on PASS or without
  motor data;
* ``plan PROGRAM.nc [--motor FILE.yaml] [--max-slider-speed V]
  [--max-slider-acceleration A] --out DIR``: the time-optimal feed of a part
  program and its cycle time, verified (``plan --example NAME`` prints one);
* ``accuracy PROGRAM.nc --cut CUT.yaml --out DIR``: what the program does to
  the part: cutting forces, surface error, the chatter stability margin of
  every line that cuts and the error budget (``accuracy.json``,
  ``accuracy.csv``, ``accuracy.html``);
* ``mjcf -o FILE.xml [--motor FILE.yaml] [--gravity GX GY GZ]``: the machine
  as MJCF for MuJoCo, its loops as equality constraints, its drives and force
  limits (``pip install 'orthoglide-pin[sim]'``);
* ``drive --example`` / ``drive --check FILE.yaml``: print the shipped example
  drive file (``orthoglide drive --example > drive.yaml``), or read one;
* ``calibrate MEASUREMENTS.csv --out DIR [--allow-partial]``: identify the
  built machine's geometry from measured tool positions (``calibration.yaml``,
  its page and the residuals); ``calibrate --plan N --out DIR [--noise S]``:
  the N poses to measure (D-optimal); ``fk`` and ``ik`` take
  ``--calibration FILE`` to compensate;
* ``sensitivity X Y Z``: the tool displacement per unit of each geometric error.

Every command takes ``--param NAME=VALUE`` (repeatable), ``--config FILE.yaml``
and ``--json`` (exactly one JSON object on stdout, strict JSON: never ``NaN`` or
``Infinity``). ``orthoglide --version`` prints the version; each command's
``--help`` shows every default.

How a command ends:

* any error of the package or of the arguments: one line
  ``orthoglide CMD: error: <message>`` on stderr (``orthoglide: error:`` when
  no command could be read), status 2 (the usage is
  shown by ``--help`` only; no warning of numpy or another library is shown);
* a result that would be NaN or infinite: an error, status 2;
* Ctrl-C: one line ``orthoglide: interrupted``, status 130; SIGTERM:
  ``orthoglide: terminated``, status 143; temporary files are removed;
* a closed pipe (``| head``): quietly, status 141.
Each command family lives in its own module with a ``register`` function;
Pinocchio is imported only by the commands that use it.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli import (
    _parser,
    accuracy,
    calibrate,
    certify,
    design,
    drive,
    dynamics,
    kinematics,
    linuxcnc,
    lobes,
    modes,
    plan,
    program,
    simulation,
    stiffness,
    summary,
    sweep,
    view,
)
from orthoglide_pin.cli import _runtime as runtime
from orthoglide_pin.exceptions import OrthoglideError, path_repr

#: Command families, in the order of ``orthoglide --help``.
_FAMILIES = (
    kinematics, summary, design, certify, stiffness, modes, lobes, view, sweep, dynamics, drive,
    program, plan, accuracy, simulation, calibrate, linuxcnc,
)  # fmt: skip


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``orthoglide`` and its sub-commands."""
    parent = _parser.Parser(add_help=False)
    parent.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override one parameter in SI units (repeatable), e.g. leg_length=0.3, "
        "tool_offset=0,0,0.2, bar_mass=auto",
    )
    parent.add_argument("--config", metavar="FILE.yaml", help="parameters file (YAML)")
    parent.add_argument("--json", action="store_true", help="print one JSON object")

    parser = _parser.Parser(
        prog=common.PROG, description="Reference model of the Orthoglide (SI units)."
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for family in _FAMILIES:
        family.register(sub, parent)
    return parser


def _version() -> str:
    """The installed version of orthoglide-pin."""
    import importlib.metadata

    try:
        return importlib.metadata.version("orthoglide-pin")
    except importlib.metadata.PackageNotFoundError:  # pragma: no cover - source tree only
        return "unknown"


def _run(parser: argparse.ArgumentParser, argv: Sequence[str] | None) -> int:
    """Parse ``argv`` and run its command; every error becomes one line."""
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and usage errors (2)
        sys.stdout.flush()  # a closed pipe shows here, not at exit
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    handler: common.Handler = args.handler
    command = str(getattr(args, "command", "") or "") or None
    try:
        code = handler(args)
        sys.stdout.flush()  # a closed pipe shows here, not at exit
        return code
    except BrokenPipeError:
        raise
    except OrthoglideError as exc:
        return common.error(str(exc), command)
    except OSError as exc:  # an output file that cannot be written
        where = f" {path_repr(os.fsdecode(exc.filename))}" if exc.filename else ""
        return common.error(f"cannot write{where}: {exc.strerror or exc}", command)


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``orthoglide`` with ``argv`` (default: ``sys.argv[1:]``).

    Args:
        argv: Command-line arguments, without the program name.

    Returns:
        The exit status: 0 on success, 2 on any usage or input error, 130
        after Ctrl-C, 143 after SIGTERM, 141 when stdout was closed.
    """
    parser = build_parser()
    try:
        with runtime.signals_as_exceptions(), runtime.quiet_libraries():
            return _run(parser, argv)
    except KeyboardInterrupt:
        runtime.say("interrupted", new_line=True)
        return runtime.EXIT_INTERRUPTED
    except runtime.Terminated:
        runtime.say("terminated", new_line=True)
        return runtime.EXIT_TERMINATED
    except BrokenPipeError:
        runtime.silence_stdout()
        return runtime.EXIT_BROKEN_PIPE
