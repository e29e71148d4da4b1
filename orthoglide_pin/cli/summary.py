"""The ``summary`` command: the machine in brief (and its URDF with ``-o``)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.kinetostatics.factor_range import DEFAULT_GRID, MAX_GRID
from orthoglide_pin.machine.params import OPTIONAL_FIELDS
from orthoglide_pin.machine.parts import MASS_FIELDS

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel


def _masses(model: ClosedLoopModel) -> dict[str, Any]:
    """Moving masses [kg] of the Pinocchio model, per joint and grouped.

    Groups: the carriages (``*_slider`` joints), the platform with its spindle
    (the joint that carries the platform frame), and the rest of each leg.
    """
    pm = model.model
    bodies = {str(pm.names[j]): float(pm.inertias[j].mass) for j in range(1, pm.njoints)}
    platform_joint = str(pm.names[pm.frames[model.platform_frame].parentJoint])
    carriages = {n: m for n, m in bodies.items() if n.endswith("_slider")}
    legs: dict[str, float] = {}
    for name, mass in bodies.items():
        if name not in carriages and name != platform_joint:
            leg = name.split("_", 1)[0]
            legs[leg] = legs.get(leg, 0.0) + mass
    return {
        "bodies": bodies,
        "carriages": carriages,
        "legs": legs,
        "platform_joint": platform_joint,
        "platform_and_spindle": bodies[platform_joint],
        "total_moving": sum(bodies.values()),
    }


def _summary_text(s: dict[str, Any]) -> str:
    """Readable report of :func:`_cmd_summary`'s content (lengths in mm)."""
    lines = ["Orthoglide summary (parameters in SI; lengths shown in mm)", "Parameters:"]
    inertias = s["parameters"].get("inertias", {"value": {}})["value"]
    cad = {MASS_FIELDS[kind]: entry for kind, entry in inertias.items()}
    for name, entry in s["parameters"].items():
        value, unit = entry["value"], entry["unit"]
        if name == "meshes":  # CAD: part kind -> mesh file
            shown = ", ".join(f"{k}: {Path(v['file']).name}" for k, v in value.items())
        elif name == "inertias":
            shown = "measured (CAD) for " + ", ".join(value)
        elif cad.get(name) is not None:  # the CAD mass replaces the parameter
            shown = f"{cad[name]['mass']:g} kg, measured (CAD)"
        elif value is None:
            shown = "derived from sizes and density"
        elif unit == "-":
            shown = f"{value:g}"
        elif unit == "m":
            vals = value if isinstance(value, list) else [value]
            shown = ", ".join(f"{1e3 * v:.1f}" for v in vals) + " mm"
        elif isinstance(value, list):
            shown = ", ".join(f"{v:g}" for v in value) + f" {unit}"
        else:
            shown = f"{value:g} {unit}"
        lines.append(f"  {name:<20} {shown}")
    lo, hi = s["slider_limits"]
    m = s["masses"]
    how = "derived from the cube" if s["derived_limits"] else "given"
    if 0 < len(s["derived_limits"]) < 2:
        how = ", ".join(s["derived_limits"]) + " derived from the cube"
    fr = s["factor_range"]
    where = (
        ""
        if fr["highest"] is None
        else f" (lowest at {common.fmt(fr['lowest_at'], 1e3, '.1f')} mm, "
        f"highest at {common.fmt(fr['highest_at'], 1e3, '.1f')} mm)"
    )
    lines += [
        f"Workspace: {s['workspace_text']}",
        f"Criterion: {s['criterion_text']}: {s['factor_range_verdict']} over the cube",
        f"  factors {s['factor_range_text']}{where}",
        *([] if s["note"] is None else [f"  note: {s['note']}"]),
        f"Slider limits: [{1e3 * lo:.1f}, {1e3 * hi:.1f}] mm ({how}), "
        f"stroke {1e3 * s['stroke']:.1f} mm",
        f"Design digest: {s['design']} (recorded by its calibrations, plans and runs)",
        "Moving masses (Pinocchio model):",
        "  carriages: " + ", ".join(f"{n} {v:.4f} kg" for n, v in m["carriages"].items()),
    ]
    lines += [f"  {leg} bars and links: {v:.4f} kg" for leg, v in m["legs"].items()]
    lines += [
        f"  platform + spindle ({m['platform_joint']}): {m['platform_and_spindle']:.4f} kg",
        f"  total moving mass: {m['total_moving']:.4f} kg",
        f"Constraints: {s['joints']} joints, {s['constraint_rows']} rows of rank "
        f"{s['constraint_rank']}, mobility {s['mobility']}",
        "Tool Jacobian at home (p_dot = J q_dot):",
        common.fmt_matrix(np.asarray(s["jacobian_home"])),
        f"Assumptions: {s['assumptions']}",
    ]
    if s["urdf_path"] is not None:
        lines.append(f"URDF written to {s['urdf_path']}")
    return "\n".join(lines)


def _cmd_summary(args: argparse.Namespace) -> int:
    from orthoglide_pin.kinetostatics.design import prototype_note
    from orthoglide_pin.kinetostatics.factor_range import factor_range
    from orthoglide_pin.machine import description
    from orthoglide_pin.machine.digest import design_digest

    params = common.with_criterion(args, common.build_params(args))
    factors = factor_range(params, grid_points=args.grid)  # before the model: quick to refuse
    criterion, criterion_text = common.criterion_info(args, params, factors.tolerance)
    model = common.closed_loop_model(params)
    home = model.solve(np.zeros(3)).q
    cad = {MASS_FIELDS[k] for k in params.inertias}
    derived = [
        n
        for n in params.to_dict()
        if n in OPTIONAL_FIELDS and getattr(params, n) is None and n not in cad
    ]
    if derived:
        assumptions = (
            f"{', '.join(derived)} derived from the link sizes and "
            f"density = {params.density:g} kg/m^3 (assumed, not measured)"
        )
    else:
        assumptions = "none: every mass is given explicitly"
    if params.inertias:
        assumptions += "; measured (CAD): " + ", ".join(params.inertias)
    path = None if args.output is None else description.write_urdf(args.output, params).resolve()
    summary: dict[str, Any] = {
        "parameters": {
            name: {"value": value, "unit": common.unit(name)}
            for name, value in params.to_dict().items()
        },
        "workspace": params.workspace.to_dict(),
        "workspace_text": params.workspace.describe(),
        "criterion": criterion,
        "criterion_text": criterion_text,
        "factor_range": factors.to_dict(),
        "factor_range_text": factors.describe(),
        "factor_range_verdict": factors.verdict,
        "note": prototype_note(params),
        "slider_limits": [params.slider_lower, params.slider_upper],
        "derived_limits": list(params.derived_limits),
        "stroke": params.stroke,
        "design": design_digest(params),
        "masses": _masses(model),
        "joints": model.nv,
        "constraint_rows": model.constraint_size,
        "constraint_rank": model.constraint_rank(home),
        "mobility": model.mobility(home),
        "jacobian_home": model.jacobian(home).tolist(),
        "derived_masses": derived,
        "assumptions": assumptions,
        "urdf_path": None if path is None else str(path),
    }
    return common.emit(args, summary, _summary_text(summary))


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``summary`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub, parent, "summary", _cmd_summary, "machine summary (and its URDF with -o)"
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE.urdf",
        help="also write the URDF there (default: write no file)",
    )
    common.add_psi_option(p)
    p.add_argument(
        "--grid",
        type=int,
        default=DEFAULT_GRID,
        metavar="N",
        help=f"N^3 points of the cube for the factor range (at most {MAX_GRID})",
    )
