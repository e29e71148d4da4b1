"""Shared by the machining tests: a short program and its cutting conditions."""

from __future__ import annotations

from orthoglide_pin.planning.limits import PlanLimits

#: Sampling step [s].
DT = 0.004
#: A contour 2 mm deep: rapid, plunge (line 3), three cutting lines (4 to 6), rapid out.
PROGRAM = """G21 G90 G17
G0 X-20 Y-10 Z5
G1 Z-2 F600
G1 X20 F3000
G1 Y10
G1 X-20
G0 Z5
"""
CUT = {
    "tool": {"diameter": 0.01, "teeth": 3, "helix_angle": 0.5},
    "material": "aluminium_7075",
    "engagement": {"axial_depth": 0.002, "radial_width": 0.001, "milling": "down"},
    "spindle_speed": 10000,
}
LIMITS = PlanLimits(slider_speed=1.2, slider_acceleration=20.0)
