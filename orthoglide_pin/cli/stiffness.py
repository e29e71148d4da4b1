"""Stiffness command: ``stiffness X Y Z [--sources ...] [--wrench FX FY FZ MX MY MZ]``.

Prints the Cartesian stiffness of the tool tip at a point and its deflection
under a tool wrench, in SI units, with the model's assumptions (see
:mod:`orthoglide_pin.elasticity.stiffness`). ``--json`` prints::

    {"point": [3], "K": 3x3 [N/m], "K6": 6x6 or null, "compliance": 6x6,
     "min_stiffness": [N/m], "wrench": [6], "deflection": [6] ([m], [rad]),
     "actuator_stiffness": [N/m] or null, "sources": [...], "assumptions": {...}}

``K6`` is ``null`` when it is infinite (rigid links: ``--sources actuators``);
``actuator_stiffness`` is ``null`` when the actuators are rigid.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any, Final

import numpy as np

from orthoglide_pin.cli import _common as common

#: Default tool wrench: a 100 N transverse cutting force along x [N, N.m].
DEFAULT_WRENCH: Final = (100.0, 0.0, 0.0, 0.0, 0.0, 0.0)
_WRENCH_NAMES: Final = ("FX", "FY", "FZ", "MX", "MY", "MZ")


def _wrench(values: Sequence[str] | None) -> np.ndarray[Any, Any]:
    if values is None:
        return np.array(DEFAULT_WRENCH)
    return common.numbers("--wrench", values, "FX FY FZ [N] MX MY MZ [N.m]", 6)


def _cmd_stiffness(args: argparse.Namespace) -> int:
    from orthoglide_pin.elasticity.stiffness import cartesian_stiffness

    params = common.build_params(args)
    point = common.triple(args, ("x", "y", "z"))
    wrench = _wrench(args.wrench)
    result = cartesian_stiffness(point, params, args.sources)
    deflection = result.deflection(wrench)
    k_min = float(result.min_stiffness())
    actuators = "actuators" in result.sources
    payload: dict[str, Any] = {
        "point": point.tolist(),
        "K": result.K.tolist(),
        "K6": None if result.K6 is None else result.K6.tolist(),
        "compliance": result.compliance.tolist(),
        "min_stiffness": k_min,
        "wrench": wrench.tolist(),
        "deflection": deflection.tolist(),
        "actuator_stiffness": params.actuator_stiffness if actuators else None,
        "sources": list(result.sources),
        "assumptions": result.assumptions,
    }
    facts = result.assumptions
    moduli = (
        f"E = {params.youngs_modulus / 1e9:.4g} GPa, G = {params.shear_modulus / 1e9:.4g} GPa"
        if "links" in result.sources
        else "rigid links"
    )
    drives = f"k_a = {params.actuator_stiffness / 1e6:.4g} N/um" if actuators else "rigid drives"
    if "joints" in result.sources:
        drives += (
            f"; bearings {params.joint_stiffness / 1e6:.4g} N/um, "
            f"{params.joint_tilt_stiffness:.4g} N.m/rad"
        )
    k6_text = (
        "K6: infinite (rigid links: the platform cannot tilt)"
        if result.K6 is None
        else "K6 [N/m, N/rad; N.m/m, N.m/rad]:\n" + common.fmt_matrix(result.K6)
    )
    text = "\n".join(
        [
            f"Stiffness of the tool tip at p = {common.fmt(point)} m "
            f"(sources: {', '.join(result.sources)}; {moduli}; {drives})",
            f"K [N/um] (pure force, platform free to tilt):\n{common.fmt_matrix(result.K / 1e6)}",
            f"softest direction: {k_min / 1e6:.6g} N/um",
            k6_text,
            f"wrench {common.fmt(wrench)} [N, N.m]: displacement "
            f"{common.fmt(deflection[:3], 1e6, '.6g')} um, rotation "
            f"{common.fmt(deflection[3:], 1e6, '.6g')} urad",
            f"assumptions: {facts['joints']}; {facts['small_links']}; rigid: "
            + ", ".join(facts["rigid_parts"]),
        ]
    )
    return common.emit(args, payload, text)


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``stiffness`` command to the ``orthoglide`` parser."""
    p = common.add_command(
        sub,
        parent,
        "stiffness",
        _cmd_stiffness,
        "Cartesian stiffness of the tool tip at a point and its deflection under a wrench",
    )
    common.add_point(p)
    p.add_argument(
        "--sources",
        default="actuators,links",
        metavar="LIST",
        help="compliance sources, comma-separated: actuators (axial drive stiffness), "
        "links (bars and small links as beams), joints (the revolutes' bearings: "
        "joint_stiffness, joint_tilt_stiffness); without joints they are ideal revolutes",
    )
    p.add_argument(
        "--wrench",
        nargs="+",
        metavar="W",
        help="tool wrench FX FY FZ [N] MX MY MZ [N.m] about the tool tip, six numbers "
        "or one comma-separated list (default: 100 N along x)",
    )
