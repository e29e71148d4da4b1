"""An independent 3D frame finite-element model of the Orthoglide, built with PyNite.

PyNiteFEA is a pure-Python structural FEA library (numpy/scipy only): it
installs anywhere pip does, its 3D frame elements are Euler-Bernoulli beams
with end releases in their local axes and it has support springs, which is all
this model needs. (OpenSeesPy would give exact multi-point constraints, but it
is a large native binary tied to given platforms and Python versions.)

The model has the members of the package's elastostatic model, built here from
nodes and PyNite's own element matrices:

* per leg, nodes C (carriage revolute), A0/B0 and A1/B1 (bar ends) and D (end
  revolute); four small-link halves C-A0, C-B0, D-A1, D-B1 and the two bars,
  each bar released for bending about the parallelogram's axis at both ends
  (the two revolutes of that bar);
* C supported on the carriage: free along the slider (a spring support of the
  actuator's stiffness, or fixed) and free to turn about the leg's revolute
  axis; every other support fixed;
* the platform: members from its centre to each D, released at D about the
  leg's revolute axis (the end revolute), and from its centre to the tool tip,
  all of a material ``rigid`` times stiffer than the structure (PyNite has
  no rigid links).

Six unit load cases at the tool tip give the compliance matrix column by
column.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from Pynite import FEModel3D

from orthoglide_pin import OrthoglideParams
from orthoglide_pin.kinematics.closed_form import leg_vectors

FloatArray = NDArray[np.float64]

#: Stiffness ratio of the platform's members to the structure's material (higher
#: ratios make PyNite's solver report some configurations as unstable).
RIGID = 1e4
_AXES = "XYZ"
_LOADS = ("FX", "FY", "FZ", "MX", "MY", "MZ")


def _tube(outer: float, wall: float) -> tuple[float, float, float]:
    inner = max(outer - wall, 0.0)
    area = math.pi * (outer**2 - inner**2)
    inertia = math.pi * (outer**4 - inner**4) / 4.0
    return area, inertia, 2.0 * inertia


def _orient(model: FEModel3D, name: str, z_axis: FloatArray) -> None:
    """Turn a member about its axis so that its local z is ``z_axis``."""
    member = model.members[name]
    direction = member.T()[:3, :3]  # rows: local x, y, z in global axes
    y, z = direction[1], direction[2]
    member.rotation = math.degrees(math.atan2(-float(z_axis @ y), float(z_axis @ z)))
    assert abs(abs(float(member.T()[2, :3] @ z_axis)) - 1.0) < 1e-9


def frame_compliance(
    point: FloatArray, params: OrthoglideParams, *, actuators: bool = True, rigid: float = RIGID
) -> FloatArray:
    """Compliance of the tool tip, 6x6, from the PyNite frame model.

    Args:
        point: Tool point [m], shape (3,).
        params: Machine parameters.
        actuators: Elastic actuators (else rigid).
        rigid: Stiffness ratio of the platform's members to the structure.

    Returns:
        ``C`` with ``(dp, dtheta) = C (f, m)`` at the tool tip, world axes.
    """
    e, g = params.youngs_modulus, params.shear_modulus
    model = FEModel3D()
    model.add_material("metal", e, g, e / (2.0 * g) - 1.0, 2700.0)
    model.add_material("rigid", e * rigid, g * rigid, e / (2.0 * g) - 1.0, 2700.0)
    model.add_section("bar", *_section(*_tube(params.bar_radius, params.bar_wall)))
    model.add_section("link", *_section(*_tube(params.link_radius, params.link_radius)))
    model.add_section("plate", *_section(*_tube(0.02, 0.02)))
    tool = np.asarray(point, dtype=float)
    centre = tool - np.asarray(params.tool_offset)
    model.add_node("Pc", *centre)
    loaded = "Pc"
    if np.linalg.norm(tool - centre) > 0.0:
        model.add_node("P", *tool)
        model.add_member("tool", "Pc", "P", "rigid", "plate")
        loaded = "P"
    legs = leg_vectors(tool, params.leg_length)
    half = params.parallelogram_width / 2.0
    for i in range(3):
        e_i, axis = np.eye(3)[i], np.eye(3)[(i + 1) % 3]
        d = centre - params.platform_offset * e_i
        c = d - legs[i]
        nodes = {
            "C": c,
            "A0": c + half * axis,
            "B0": c - half * axis,
            "A1": d + half * axis,
            "B1": d - half * axis,
            "D": d,
        }
        for key, xyz in nodes.items():
            model.add_node(f"{key}{i}", *xyz)
        for a, b in (("C", "A0"), ("C", "B0"), ("D", "A1"), ("D", "B1")):
            model.add_member(f"{a}{b}{i}", f"{a}{i}", f"{b}{i}", "metal", "link")
        normal = np.cross(legs[i], axis)
        normal /= np.linalg.norm(normal)
        for a, b in (("A0", "A1"), ("B0", "B1")):
            name = f"bar{a}{i}"
            model.add_member(name, f"{a}{i}", f"{b}{i}", "metal", "bar")
            _orient(model, name, normal)
            model.def_releases(name, Rzi=True, Rzj=True)
        model.add_member(f"plate{i}", "Pc", f"D{i}", "rigid", "plate")
        _orient(model, f"plate{i}", axis)
        model.def_releases(f"plate{i}", Rzj=True)
        support = [True] * 6
        support[i] = not actuators
        support[3 + (i + 1) % 3] = False
        model.def_support(f"C{i}", *support)
        if actuators:
            model.def_support_spring(f"C{i}", "D" + _AXES[i], params.actuator_stiffness)
    for load in _LOADS:
        model.add_node_load(loaded, load, 1.0, case=load)
        model.add_load_combo(load, {load: 1.0})
    model.analyze_linear(check_statics=False)
    node = model.nodes[loaded]
    columns = [
        [getattr(node, dof)[load] for dof in ("DX", "DY", "DZ", "RX", "RY", "RZ")]
        for load in _LOADS
    ]
    return np.array(columns, dtype=float).T


def _section(area: float, inertia: float, torsion: float) -> tuple[float, float, float, float]:
    return area, inertia, inertia, torsion
