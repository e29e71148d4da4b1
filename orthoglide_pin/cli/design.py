"""Design and performance commands: ``design``, ``indices`` and ``map``."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinetostatics.certify import Certification
from orthoglide_pin.kinetostatics.workspace import AXES, INDEX_NAMES
from orthoglide_pin.machine.criterion import CRITERION_TOL

#: Default resolution of ``orthoglide map`` (points along each in-plane axis).
DEFAULT_RESOLUTION = 201
#: Largest resolution accepted by ``orthoglide map``.
MAX_RESOLUTION = 4001
#: Default half-width of the mapped square, relative to the leg length.
DEFAULT_EXTENT = 1.1


def _mm(values: Any) -> str:
    return common.fmt(values, 1e3, ".2f") + " mm"


def _cmd_design(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinetostatics.design import design_from_workspace

    side = common.finite("--workspace", args.workspace)
    lo, hi = common.psi_bounds(args)
    design = design_from_workspace(side, lo, hi, grid_points=args.grid)
    # Q1 and Q2 are points (q1, q2, q3 read like slider values elsewhere)
    payload = {k.replace("q1", "Q1").replace("q2", "Q2"): v for k, v in design.to_dict().items()}
    config = None
    if args.write_config:
        config = design.to_params(common.build_params(args)).save(args.write_config).resolve()
    payload["config"] = None if config is None else str(config)
    d = design
    cert = None if args.no_certify else d.certify()
    payload.update(_certified(cert))
    payload["criterion"] = {"psi_min": lo, "psi_max": hi, "tolerance": CRITERION_TOL}
    verdict = "hold" if d.bounds_hold else "DO NOT HOLD"
    lines = [
        f"Design for a {1e3 * d.cube_side:.1f} mm cube, factors in [{d.psi_min:g}, {d.psi_max:g}]",
        f"  leg_length     {1e3 * d.leg_length:.2f} mm",
        f"  stroke         {1e3 * d.stroke:.2f} mm",
        f"  slider_limits  {_mm(d.slider_limits)}",
        f"  Q1             {_mm(d.q1)}   factors {common.fmt(d.factors_q1, spec='.4f')}",
        f"  Q2             {_mm(d.q2)}   factors {common.fmt(d.factors_q2, spec='.4f')}",
        f"  cube_corner    {_mm(d.cube_corner)}",
        f"  ratio          {d.ratio:.3f} (cube side / stroke)",
        f"  psi_min_found  {d.psi_min_found:.6f} at {_mm(d.psi_min_at)}",
        f"  psi_max_found  {d.psi_max_found:.6f} at {_mm(d.psi_max_at)}",
        f"  the bounds {verdict} on a {d.grid_points}^3 grid of the cube "
        f"(to {CRITERION_TOL:g}, the tolerance of the criterion)",
    ]
    if cert is not None:
        lo_c, hi_c = cert.factor_bounds
        margin = payload["certified_margin"]
        lines.append(
            f"  certified      {'yes' if cert.certified else 'NO (' + cert.status + ')'}: "
            f"every factor of the whole cube lies in [{lo_c:.6f}, {hi_c:.6f}] (proven against "
            f"the bounds widened by {cert.tolerance:g}, since Q1 and Q2 reach them exactly; "
            "orthoglide certify applies the same rule), "
            f"margin {'none' if margin is None else f'{margin:+.2g}'}, "
            f"{cert.boxes} boxes, {cert.seconds:.2f} s"
        )
        if cert.counterexample is not None:
            lines.append(f"  counterexample {_mm(cert.counterexample)}")
    if config is not None:
        lines.append(f"  config written to {config} (with the criterion psi_min, psi_max)")
    return common.emit(args, payload, "\n".join(lines))


def _certified(cert: Certification | None) -> dict[str, Any]:
    """``certified``, ``certified_margin`` (to the widened bounds) and ``certification``."""
    if cert is None:
        return {"certified": None, "certified_margin": None, "certification": None}
    margin = cert.margin
    return {
        "certified": cert.certified,
        "certified_margin": margin if np.isfinite(margin) else None,
        "certification": cert.to_dict(),
    }


def _cmd_indices(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinematics import closed_form as kinematics
    from orthoglide_pin.kinetostatics import indices
    from orthoglide_pin.machine.limits import check_slider_limits

    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    if args.method == "closed-form":
        result = indices.kinetostatic_indices(point, params.leg_length)
    else:
        q = kinematics.inverse_kinematics(point, params.leg_length)
        model = common.closed_loop_model(params)
        result = indices.indices_from_model(model, model.solve(q).q, check_limits=False)
    check_slider_limits(params, point, hint=None)  # then the slider limits, as ik does
    iso = indices.isotropy_residuals(point, params.leg_length)
    payload = {"method": args.method, "point": point.tolist(), **result.to_dict()}
    payload["isotropy_residuals"] = {
        "eq3": iso.eq3.tolist(),
        "eq4": iso.eq4.tolist(),
        "eq5": iso.eq5.tolist(),
    }

    def block(name: str, axes: np.ndarray[Any, Any], dirs: np.ndarray[Any, Any]) -> str:
        rows = [f"{name}:"]
        rows += [
            f"  semi-axis {axes[k]:.6f} along {common.fmt(dirs[:, k], spec='+.6f')}"
            for k in range(3)
        ]
        return "\n".join(rows)

    text = "\n".join(
        [
            f"Kinetostatic indices ({args.method}) at p = {common.fmt(point)} m",
            f"transmission_factors: {common.fmt(result.transmission_factors, spec='.9f')}",
            f"condition: {float(result.condition):.9f}  "
            f"(inverse {float(result.inverse_condition):.9f})",
            f"manipulability (det J): {float(result.manipulability):.9f}",
            block("velocity_ellipsoid", result.velocity_axes, result.velocity_directions),
            block("force_ellipsoid", result.force_axes, result.force_directions),
            f"isotropy residuals: eq3 {common.fmt(iso.eq3, spec='.3g')}, "
            f"eq4 {common.fmt(iso.eq4, spec='.3g')}, eq5 {common.fmt(iso.eq5, spec='.3g')}",
        ]
    )
    return common.emit(args, payload, text)


def _parse_slice(text: str) -> tuple[str, float]:
    axis, sep, value = text.partition("=")
    axis = axis.strip().lower()
    if not sep or axis not in AXES:
        raise InvalidParameterError("--slice", text, "AXIS=VALUE with AXIS one of x, y, z")
    return axis, common.finite("--slice value", value.strip())


def _cmd_map(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinetostatics.plotting import plot_slice
    from orthoglide_pin.kinetostatics.workspace import slice_grid, workspace_map

    params = common.with_cube(args, common.build_params(args))
    axis, value = _parse_slice(args.slice)
    n = args.resolution
    if not 2 <= n <= MAX_RESOLUTION:
        raise InvalidParameterError("--resolution", n, f"an integer in [2, {MAX_RESOLUTION}]")
    if args.extent is None:
        hi = DEFAULT_EXTENT * params.leg_length
        lo = -hi
    else:
        lo = common.finite("--extent MIN", args.extent[0])
        hi = common.finite("--extent MAX", args.extent[1])
    if not hi > lo:
        raise InvalidParameterError("--extent MAX", hi, f"greater than MIN = {lo:g} [m]")
    wmap = workspace_map(slice_grid(axis, value, (lo, lo), (hi, hi), n), params)
    cube = params.workspace
    corner, side = cube.q1, cube.side
    markers = {"isotropic": np.zeros(3), "Q1": cube.q1, "Q2": cube.q2}
    csv = wmap.save_csv(args.csv).resolve() if args.csv else None
    plot_slice(wmap, args.index, args.out, cube=(corner, side), markers=markers)
    out = Path(args.out).resolve()
    values = wmap.index(args.index)
    ok = wmap.reachable & np.isfinite(values)
    payload: dict[str, Any] = {
        "out": str(out),
        "csv": None if csv is None else str(csv),
        "index": args.index,
        "slice": {"axis": axis, "value": value},
        "extent": [lo, hi],
        "resolution": n,
        "cube": cube.to_dict(),
        "reachable_fraction": float(wmap.reachable.mean()),
        "min": None,
        "min_at": None,
        "max": None,
        "max_at": None,
    }
    if ok.any():
        masked = np.where(ok, values, np.nan).reshape(-1)
        i_min, i_max = int(np.nanargmin(masked)), int(np.nanargmax(masked))
        payload.update(
            min=float(masked[i_min]),
            min_at=wmap.grid.point(i_min).tolist(),
            max=float(masked[i_max]),
            max_at=wmap.grid.point(i_max).tolist(),
        )
    lines = [
        f"{args.index} on the plane {axis} = {value:g} m, {n} x {n} points over "
        f"[{lo:g}, {hi:g}] m, {100 * payload['reachable_fraction']:.1f}% reachable",
        f"  workspace: {cube.describe()}",
    ]
    if payload["min"] is not None:
        lines.append(f"  min {payload['min']:.6g} at {common.fmt(payload['min_at'])} m")
        lines.append(f"  max {payload['max']:.6g} at {common.fmt(payload['max_at'])} m")
    lines.append(f"  heat map written to {out}")
    if csv is not None:
        lines.append(f"  numbers written to {csv}")
    return common.emit(args, payload, "\n".join(lines))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the design and performance commands to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "design",
        _cmd_design,
        "design the machine of a prescribed cube (side [m], bounds on the transmission factors)",
    )
    p.add_argument("--workspace", required=True, metavar="LW", help="cube side [m]")
    p.add_argument(
        "--psi", required=True, nargs=2, metavar=("MIN", "MAX"), help="bounds, MIN < 1 < MAX"
    )
    p.add_argument(
        "--grid", type=int, default=101, metavar="N", help="verification grid, N^3 points"
    )
    p.add_argument(
        "--write-config",
        metavar="FILE.yaml",
        help="save the designed machine (on top of --config/--param), its cube and its "
        "criterion (psi_min, psi_max), atomically",
    )
    p.add_argument(
        "--no-certify",
        action="store_true",
        help="skip the proof of the bounds over the whole cube (interval arithmetic, ~1 s)",
    )
    p = common.add_command(
        sub,
        parent,
        "indices",
        _cmd_indices,
        "transmission factors, condition, manipulability and ellipsoids at a tool point",
    )
    common.add_point(p)
    p.add_argument("--method", choices=("closed-form", "pinocchio"), default="closed-form")
    p = common.add_command(
        sub, parent, "map", _cmd_map, "heat map of an index on a plane slice (PNG, CSV)"
    )
    p.add_argument("--slice", default="z=0.0", metavar="AXIS=VALUE", help="plane [m]")
    p.add_argument("--index", default="condition", choices=INDEX_NAMES)
    p.add_argument("--out", required=True, metavar="FILE.png", help="heat map (PNG)")
    p.add_argument("--csv", metavar="FILE", help="also write the numbers as CSV")
    common.add_cube_options(p)
    p.add_argument(
        "--resolution", type=int, default=DEFAULT_RESOLUTION, metavar="N", help="N x N points"
    )
    p.add_argument(
        "--extent",
        nargs=2,
        metavar=("MIN", "MAX"),
        help=f"in-plane bounds [m] (default: +-{DEFAULT_EXTENT} L)",
    )
