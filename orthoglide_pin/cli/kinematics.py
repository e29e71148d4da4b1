"""Kinematics commands: ``urdf``, ``ik``, ``fk`` and ``jacobian``.

``urdf -o NAME.urdf`` writes the URDF and, beside it, ``NAME.loops.yaml``: the
loop closures and actuated joints of the cut tree. ``urdf --package-dir DIR``
writes a self-contained description folder: the URDF, its loop data and the
CAD meshes, with mesh names relative to the folder
(:mod:`orthoglide_pin.machine.export`).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    UnreachablePointError,
)

if TYPE_CHECKING:
    from orthoglide_pin.machine.params import OrthoglideParams


def _cmd_urdf(args: argparse.Namespace) -> int:
    from orthoglide_pin.machine import description

    params = common.build_params(args)
    if args.force and args.package_dir is None:
        raise InvalidParameterError("--force", True, "only with --package-dir DIR")
    if args.package_dir is not None:
        if args.output is not None:
            raise InvalidParameterError(
                "--package-dir", args.package_dir, "not combined with -o/--output"
            )
        from orthoglide_pin.machine.export import write_package

        urdf = write_package(args.package_dir, params, force=args.force).resolve()
        folder = urdf.parent
        files = sorted(p.name for p in folder.iterdir() if not p.name.startswith("."))
        payload = {"path": str(folder), "urdf": str(urdf), "files": files}
        return common.emit(args, payload, f"{folder}\n" + "\n".join(f"  {f}" for f in files))
    if args.output is None:
        text = description.render_urdf(params)
        return common.emit(args, {"urdf": text}, text.rstrip("\n"))
    path = description.write_urdf(args.output, params).resolve()
    loops = description.loops_path(path)
    return common.emit(args, {"path": str(path), "loops": str(loops)}, f"{path}\n{loops}")


def checked_ik(point: np.ndarray[Any, Any], params: OrthoglideParams) -> np.ndarray[Any, Any]:
    """Slider values of a tool point, refused beyond the slider limits."""
    from orthoglide_pin.kinematics.closed_form import inverse_kinematics
    from orthoglide_pin.machine.limits import check_slider_limits

    check_slider_limits(params, point, hint=None)  # reach, then the slider limits
    return inverse_kinematics(point, params.leg_length)


def _check_limits(point: Any, q: np.ndarray[Any, Any], params: OrthoglideParams) -> None:
    """Slider values of a calibrated machine at ``point``, against the limits."""
    from orthoglide_pin.machine.limits import LIMIT_TOL

    lo, hi = params.slider_lower, params.slider_upper
    for i, qi in enumerate(q):
        if not lo - LIMIT_TOL <= qi <= hi + LIMIT_TOL:
            raise UnreachablePointError(
                point, i + 1, f"slider value {qi:.6g} m outside the limits [{lo:.6g}, {hi:.6g}] m"
            )


def _cmd_ik(args: argparse.Namespace) -> int:
    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    if args.calibration is not None:
        from orthoglide_pin.calibration.result import load_calibration

        calibration = load_calibration(args.calibration)
        calibration.check_design(params, args.calibration)  # made for this design
        q = calibration.inverse_kinematics(point)
        _check_limits(point, q, params)
        payload = {"q": q.tolist(), "calibration": args.calibration}
        return common.emit(args, payload, f"q = {common.fmt(q)} m (calibrated)")
    q = checked_ik(point, params)
    return common.emit(args, {"q": q.tolist()}, f"q = {common.fmt(q)} m")


def _cmd_fk(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinematics.closed_form import direct_kinematics
    from orthoglide_pin.machine.limits import check_slider_values

    params = common.build_params(args)
    q = common.triple(args, ("q1", "q2", "q3"))
    check_slider_values(params, q, hint=None)
    if args.calibration is not None:
        if args.all_branches:
            raise InvalidParameterError("--all-branches", True, "not with --calibration")
        from orthoglide_pin.calibration.result import load_calibration

        calibration = load_calibration(args.calibration)
        calibration.check_design(params, args.calibration)  # made for this design
        p = calibration.direct_kinematics(q)
        payload = {"p": p.tolist(), "calibration": args.calibration}
        return common.emit(args, payload, f"p = {common.fmt(p)} m (calibrated)")
    if args.all_branches:
        both = direct_kinematics(q, params.leg_length, branch="all")
        text = f"working: p = {common.fmt(both[0])} m\nother:   p = {common.fmt(both[1])} m"
        return common.emit(args, {"branches": both.tolist()}, text)
    p = direct_kinematics(q, params.leg_length)
    return common.emit(args, {"p": p.tolist()}, f"p = {common.fmt(p)} m")


def _cmd_jacobian(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinematics import closed_form as kinematics
    from orthoglide_pin.kinematics.slider_limits import BOUNDARY_TOL
    from orthoglide_pin.machine.limits import check_slider_limits

    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    J: np.ndarray[Any, Any]
    J_inv: np.ndarray[Any, Any]
    if args.method == "closed-form":
        from orthoglide_pin.kinematics.singularity import check_inverse_jacobian

        J_inv = kinematics.inverse_jacobian(point, params.leg_length)
        check_inverse_jacobian(J_inv, point)  # the thresholds of the Pinocchio route
        check_slider_limits(params, point, hint=None, tol=BOUNDARY_TOL)  # after singularities
        J = kinematics.jacobian(point, params.leg_length)
    else:
        q = kinematics.inverse_kinematics(point, params.leg_length)
        model = common.closed_loop_model(params)
        assembly = model.solve(q)
        J = model.jacobian(assembly.q)  # refuses singular and near-singular points
        J_inv = model.inverse_jacobian(assembly.q)
        check_slider_limits(params, point, hint=None, tol=BOUNDARY_TOL)  # after singularities
    payload = {"method": args.method, "J": J.tolist(), "J_inv": J_inv.tolist()}
    text = (
        f"J (p_dot = J q_dot), {args.method}, at p = {common.fmt(point)} m:\n"
        f"{common.fmt_matrix(J)}\nJ^-1:\n{common.fmt_matrix(J_inv)}"
    )
    return common.emit(args, payload, text)


def _add_calibration(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument(
        "--calibration",
        metavar="FILE.yaml",
        help=f"a calibration.yaml of orthoglide calibrate, made for this design: {what}",
    )


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the kinematics commands to the ``orthoglide`` parser."""
    p = common.add_command(
        sub, parent, "urdf", _cmd_urdf, "render the URDF (stdout, or a file with -o)"
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help="write the URDF to FILE atomically, and its loop closures and actuated "
        "joints beside it (FILE with the suffix .loops.yaml)",
    )
    p.add_argument(
        "--package-dir",
        metavar="DIR",
        help="write a self-contained description folder DIR: orthoglide.urdf, "
        "orthoglide.loops.yaml and the CAD meshes (names relative to DIR); a non-empty "
        "DIR not written by orthoglide is refused (unless --force)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="with --package-dir: write into a non-empty DIR that orthoglide did not "
        "write, keeping its other files",
    )
    p = common.add_command(
        sub, parent, "ik", _cmd_ik, "slider values [m] of a tool point [m] (working branch)"
    )
    common.add_point(p)
    _add_calibration(p, "the slider values that put the calibrated machine's tool at the point")
    p = common.add_command(sub, parent, "fk", _cmd_fk, "tool point [m] of slider values [m]")
    for name in ("q1", "q2", "q3"):
        p.add_argument(name, metavar=name.upper(), help=f"slider value {name} [m]")
    p.add_argument("--all-branches", action="store_true", help="both assembly modes")
    _add_calibration(p, "where the calibrated machine's tool is (working assembly)")
    p = common.add_command(
        sub,
        parent,
        "jacobian",
        _cmd_jacobian,
        "Jacobian J (p_dot = J q_dot) and J^-1 at a tool point",
    )
    common.add_point(p)
    p.add_argument("--method", choices=("closed-form", "pinocchio"), default="closed-form")
