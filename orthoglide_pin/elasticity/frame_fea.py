"""An independent check of the elastostatic model: a 3D frame finite-element model.

:func:`frame_compliance` builds the members of
:mod:`~orthoglide_pin.elasticity.stiffness` a second time, as a 3D frame in
PyNite (PyNiteFEA, the optional extra ``pip install 'orthoglide-pin[fea]'``),
from nodes and PyNite's own element matrices, and returns the tool tip's 6x6
compliance. It is the same structure by another route (a general-purpose FEA
solver instead of the package's static condensation), so the two agree to
about 0.1 %, the gap being the FEA platform's own compliance; it is a check,
not a faster model (about 0.1 s per point).

The frame:

* per leg, nodes C (carriage revolute), A0/B0 and A1/B1 (bar ends) and D (end
  revolute); four small-link halves C-A0, C-B0, D-A1, D-B1 and the two bars,
  each bar released for bending about the parallelogram's axis at both ends
  (the two revolutes of that bar);
* C supported on the carriage: free along the slider (a spring support of
  ``actuator_stiffness``, or fixed with rigid actuators) and free to turn
  about the leg's revolute axis; every other support fixed;
* the platform: members from its centre to each D, released at D about the
  leg's revolute axis (the end revolute), and from its centre to the tool tip,
  all of a material ``rigid`` times stiffer than the structure (PyNite has no
  rigid links).

Six unit load cases at the tool tip give the compliance matrix column by
column.

Why PyNite: it is pure Python on numpy and scipy (one wheel for every
platform), maintained, and its 3D frame elements are Euler-Bernoulli beams
with end releases in their local axes and support springs, which is all this
model needs. Its releases from 3.0 need Python 3.11 and numpy 2.4; on
Python 3.10 the extra installs its 1.6 series, which has the same interface.
"""

from __future__ import annotations

import math
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._lazy import optional_import
from orthoglide_pin._validation import finite_vector, flag, positive_number
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, jacobian, leg_vectors
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.limits import check_slider_limits
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Stiffness ratio of the platform's members to the structure's material (higher
#: ratios make PyNite's solver report some configurations as unstable).
RIGID: Final[float] = 1e4
#: Radius of the platform's (rigid) members [m]: any value, since they are
#: ``RIGID`` times stiffer than the structure.
PLATFORM_RADIUS: Final[float] = 0.02
#: Density given to PyNite's materials [kg/m^3] (unused: no self-weight case).
DENSITY: Final[float] = 2700.0
_AXES: Final = "XYZ"
_LOADS: Final = ("FX", "FY", "FZ", "MX", "MY", "MZ")
_DOFS: Final = ("DX", "DY", "DZ", "RX", "RY", "RZ")


def _tube(outer: float, wall: float) -> tuple[float, float, float, float]:
    """Area [m^2], the two bending inertias and the torsion constant [m^4] of a tube."""
    inner = max(outer - wall, 0.0)
    area = math.pi * (outer**2 - inner**2)
    inertia = math.pi * (outer**4 - inner**4) / 4.0
    return area, inertia, inertia, 2.0 * inertia


def _orient(model: Any, name: str, z_axis: FloatArray) -> None:
    """Turn a member about its axis so that its local z is ``z_axis``."""
    member = model.members[name]
    direction = member.T()[:3, :3]  # rows: local x, y, z in global axes
    y, z = direction[1], direction[2]
    member.rotation = math.degrees(math.atan2(-float(z_axis @ y), float(z_axis @ z)))


def _leg(model: Any, i: int, centre: FloatArray, leg: FloatArray, p: OrthoglideParams) -> None:
    """Nodes, members, releases and supports of leg ``i`` (see the module)."""
    e_i, axis = np.eye(3)[i], np.eye(3)[(i + 1) % 3]
    half = p.parallelogram_width / 2.0
    d = centre - p.platform_offset * e_i
    c = d - leg
    nodes = {
        "C": c,
        "A0": c + half * axis,
        "B0": c - half * axis,
        "A1": d + half * axis,
        "B1": d - half * axis,
        "D": d,
    }
    for key, xyz in nodes.items():
        model.add_node(f"{key}{i}", *xyz.tolist())
    for a, b in (("C", "A0"), ("C", "B0"), ("D", "A1"), ("D", "B1")):
        model.add_member(f"{a}{b}{i}", f"{a}{i}", f"{b}{i}", "metal", "link")
    normal = np.cross(leg, axis)
    normal /= np.linalg.norm(normal)
    for a, b in (("A0", "A1"), ("B0", "B1")):
        name = f"bar{a}{i}"
        model.add_member(name, f"{a}{i}", f"{b}{i}", "metal", "bar")
        _orient(model, name, normal)
        model.def_releases(name, Rzi=True, Rzj=True)
    model.add_member(f"plate{i}", "Pc", f"D{i}", "rigid", "plate")
    _orient(model, f"plate{i}", axis)
    model.def_releases(f"plate{i}", Rzj=True)


def frame_compliance(
    point: ArrayLike,
    params: OrthoglideParams | None = None,
    *,
    actuators: bool = True,
    rigid: float = RIGID,
    check_limits: bool = True,
) -> FloatArray:
    """Compliance of the tool tip, 6x6, from the frame FEA model (see the module).

    Args:
        point: Tool point [m], shape (3,).
        params: Machine parameters; the prototype when ``None``.
        actuators: Elastic actuators (``actuator_stiffness``), else rigid.
        rigid: Stiffness ratio of the platform's members to the structure (> 0).
        check_limits: Refuse a point whose slider values leave the machine's
            slider limits, as :func:`~orthoglide_pin.elasticity.stiffness.cartesian_stiffness`
            does.

    Returns:
        ``C`` with ``(dp, dtheta) = C (f, m)`` at the tool tip, world axes:
        ``dp`` [m], ``dtheta`` [rad], ``f`` [N], ``m`` [N.m]; shape (6, 6).

    Raises:
        MissingExtraError: PyNite is not installed (the ``[fea]`` extra).
        InvalidParameterError: A bad point, parameters, flag or ratio.
        UnreachablePointError, SingularConfigurationError: The point is out of
            reach (or beyond the slider limits), or singular.
    """
    pynite = optional_import("Pynite", "fea", "the frame FEA check")
    p = as_params(params)
    tool = finite_vector("point", point, 3, "[m]")
    actuators = flag("actuators", actuators)
    ratio = positive_number("rigid", rigid, "a positive finite stiffness ratio")
    if flag("check_limits", check_limits):
        check_slider_limits(p, tool)
    inverse_kinematics(tool, p.leg_length)  # reach and serial singularities
    jacobian(tool, p.leg_length)  # parallel singularities
    e, g = p.youngs_modulus, p.shear_modulus
    nu = e / (2.0 * g) - 1.0
    model = pynite.FEModel3D()
    model.add_material("metal", e, g, nu, DENSITY)
    model.add_material("rigid", e * ratio, g * ratio, nu, DENSITY)
    model.add_section("bar", *_tube(p.bar_radius, p.bar_wall))
    model.add_section("link", *_tube(p.link_radius, p.link_radius))
    model.add_section("plate", *_tube(PLATFORM_RADIUS, PLATFORM_RADIUS))
    centre = tool - np.asarray(p.tool_offset, dtype=float)
    model.add_node("Pc", *centre.tolist())
    loaded = "Pc"
    if np.linalg.norm(tool - centre) > 0.0:
        model.add_node("P", *tool.tolist())
        model.add_member("tool", "Pc", "P", "rigid", "plate")
        loaded = "P"
    legs = leg_vectors(tool, p.leg_length)
    for i in range(3):
        _leg(model, i, centre, legs[i], p)
        support = [True] * 6
        support[i] = not actuators
        support[3 + (i + 1) % 3] = False
        model.def_support(f"C{i}", *support)
        if actuators:
            model.def_support_spring(f"C{i}", "D" + _AXES[i], p.actuator_stiffness)
    for load in _LOADS:
        model.add_node_load(loaded, load, 1.0, case=load)
        model.add_load_combo(load, {load: 1.0})
    model.analyze_linear(check_statics=False)
    node = model.nodes[loaded]
    columns = [[float(getattr(node, dof)[load]) for dof in _DOFS] for load in _LOADS]
    out: FloatArray = np.array(columns, dtype=float).T
    return out


__all__ = ["RIGID", "frame_compliance"]
