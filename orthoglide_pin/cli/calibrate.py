"""Calibration commands: ``calibrate`` (identify, or plan the poses) and ``sensitivity``.

* ``calibrate MEASUREMENTS.csv --out DIR``: identify the 18 geometric
  parameters from measured tool positions; writes ``calibration.yaml``,
  ``calibration.html`` and ``residuals.csv`` (:mod:`orthoglide_pin.report.calibration`).
  A data set that cannot determine every parameter is refused (exit 2) unless
  ``--allow-partial``.
* ``calibrate --plan N --out DIR [--noise S]``: N D-optimal poses in the cube:
  ``poses.csv`` (targets and slider values to command) and
  ``expected_std.csv`` (the parameter deviations to expect).
* ``sensitivity X Y Z``: the tool displacement per unit of each geometric error.

``fk`` and ``ik`` take ``--calibration FILE`` to use the identified geometry.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError

#: Default tracker noise of ``--plan`` [m].
DEFAULT_NOISE = 5e-6
#: Slack on the slider limits for measured slider values [m].
LIMIT_TOL = 1e-9
#: Files of a measurement plan.
PLAN_FILES = ("poses.csv", "expected_std.csv")


def _check_limits(q: np.ndarray[Any, Any], lo: float, hi: float) -> None:
    bad = (q < lo - LIMIT_TOL) | (q > hi + LIMIT_TOL)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise InvalidParameterError(
            f"measurements row {r}, q{c + 1}",
            float(q[r, c]),
            f"a slider value within the limits [{lo:.6g}, {hi:.6g}] m of the design",
        )


def _cmd_calibrate(args: argparse.Namespace) -> int:
    from orthoglide_pin._paths import output_directory

    params = common.build_params(args)
    if (args.measurements is None) == (args.plan is None):
        raise InvalidParameterError(
            "calibrate", args.measurements, "either MEASUREMENTS.csv or --plan N, not both"
        )
    if args.plan is not None:
        return _plan(args, params)
    if args.noise is not None:
        raise InvalidParameterError("--noise", args.noise, "only with --plan N")
    from orthoglide_pin.calibration.identification import identify
    from orthoglide_pin.calibration.measurements import check_measured_design, read_measurements
    from orthoglide_pin.calibration.model import GeometricModel
    from orthoglide_pin.calibration.result import Calibration
    from orthoglide_pin.report.calibration import (
        calibration_payload,
        outliers_text,
        write_calibration_outputs,
    )

    output_directory(args.out, force=args.force)  # before the work
    data = read_measurements(args.measurements)
    check_measured_design(data, params)  # poses of another design: refused
    _check_limits(data.q, params.slider_lower, params.slider_upper)
    nominal = GeometricModel.nominal(params.leg_length)
    result = identify(data.q, data.points, nominal, allow_partial=args.allow_partial)
    calibration = Calibration.from_identification(result, data, params)
    path = write_calibration_outputs(args.out, calibration, result, data, force=args.force)
    payload = {"path": str(Path(path).resolve()), **calibration_payload(calibration)}
    um = 1e6
    lines = [
        f"{path}",
        f"  outliers left out of the fit: {outliers_text(result.outliers, len(data))}",
        f"  RMS tool error: drawing {um * calibration.rms_before:.2f} um, "
        f"calibrated {um * calibration.rms_after:.2f} um",
        f"  noise estimate {um * calibration.noise_estimate:.2f} um per axis",
    ]
    if result.unidentifiable:
        lines.append(f"  {len(result.unidentifiable)} combination(s) held at the drawing's values")
    return common.emit(args, payload, "\n".join(lines))


def _plan(args: argparse.Namespace, params: Any) -> int:
    from orthoglide_pin._io import atomic_write_text
    from orthoglide_pin._outdir import claim_directory
    from orthoglide_pin._validation import number_in
    from orthoglide_pin.calibration.experiment import MAX_NOISE, MIN_NOISE, plan_poses
    from orthoglide_pin.calibration.model import PARAMETER_NAMES, PARAMETER_UNITS
    from orthoglide_pin.machine.digest import design_comment

    if args.allow_partial:
        raise InvalidParameterError("--allow-partial", True, "only with MEASUREMENTS.csv")
    noise = DEFAULT_NOISE if args.noise is None else common.finite("--noise", args.noise)
    noise = number_in("--noise", noise, MIN_NOISE, MAX_NOISE, "[m]")
    count = _count(args.plan)
    with common.progress_bar(args, "choosing poses", "poses") as progress:
        plan = plan_poses(params, count, noise=noise, progress=progress)
    target = claim_directory(args.out, PLAN_FILES, force=args.force)
    poses = (
        design_comment(params)
        + "x,y,z,q1,q2,q3\n"
        + "".join(
            ",".join(repr(float(v)) for v in (*p, *q)) + "\n"
            for p, q in zip(plan.points, plan.q, strict=True)
        )
    )
    std = "parameter,expected_std,unit\n" + "".join(
        f"{n},{float(s)!r},{u}\n"
        for n, s, u in zip(PARAMETER_NAMES, plan.expected_std, PARAMETER_UNITS, strict=True)
    )
    atomic_write_text(target / PLAN_FILES[0], poses)
    atomic_write_text(target / PLAN_FILES[1], std)
    payload = {
        "path": str(target.resolve()),
        "poses": plan.points.tolist(),
        "q": plan.q.tolist(),
        "noise": plan.noise,
        "expected_std": dict(zip(PARAMETER_NAMES, plan.expected_std.tolist(), strict=True)),
        "log_det": plan.log_det,
    }
    worst = int(np.argmax(plan.expected_std))
    text = (
        f"{target}\n  {count} poses (D-optimal); for a tracker noise of {1e6 * noise:g} um, "
        f"the largest expected deviation is {PARAMETER_NAMES[worst]} "
        f"{plan.expected_std[worst]:.3g} {PARAMETER_UNITS[worst]}"
    )
    return common.emit(args, payload, text)


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InvalidParameterError("--plan", text, "a whole number of poses") from None
    return value


def _cmd_sensitivity(args: argparse.Namespace) -> int:
    from orthoglide_pin.calibration.model import PARAMETER_NAMES
    from orthoglide_pin.calibration.sensitivities import GROUP_UNITS, GROUPS, sensitivity
    from orthoglide_pin.cli.kinematics import checked_ik

    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    checked_ik(point, params)  # reachable, within the slider limits
    jac = sensitivity(params, point)
    columns = np.linalg.norm(jac, axis=0)
    groups = {g: float(np.sqrt(np.sum(columns[[PARAMETER_NAMES.index(n) for n in names]] ** 2)))
              for g, names in GROUPS.items()}  # fmt: skip
    payload = {
        "point": point.tolist(),
        "parameters": {n: float(c) for n, c in zip(PARAMETER_NAMES, columns, strict=True)},
        "displacements": {n: jac[:, k].tolist() for k, n in enumerate(PARAMETER_NAMES)},
        "groups": groups,
    }
    lines = [f"tool displacement per unit error at p = {common.fmt(point)} m:"]
    lines += [f"  {g:18s} {v:.4g} {GROUP_UNITS[g]}" for g, v in groups.items()]
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the calibration commands to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "calibrate",
        _cmd_calibrate,
        "identify the built machine's geometry from measured tool positions, "
        "or plan the poses to measure",
    )
    p.add_argument(
        "measurements",
        nargs="?",
        metavar="MEASUREMENTS.csv",
        help="CSV with the columns q1,q2,q3,x,y,z [m]: slider values and measured tool "
        "positions in the world frame",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--force",
        action="store_true",
        help="also write into a non-empty directory that orthoglide did not write",
    )
    p.add_argument(
        "--allow-partial",
        action="store_true",
        help="hold the combinations the poses cannot determine at the drawing's values "
        "(refused otherwise)",
    )
    p.add_argument("--plan", metavar="N", help="propose N poses (D-optimal) instead")
    p.add_argument(
        "--noise",
        metavar="S",
        help=f"with --plan: tracker noise per axis [m], 1e-9 to 0.01 (default {DEFAULT_NOISE:g})",
    )
    p = common.add_command(
        sub,
        parent,
        "sensitivity",
        _cmd_sensitivity,
        "tool displacement per unit of each geometric error at a point",
    )
    common.add_point(p)
