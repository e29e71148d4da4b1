"""CAD inertias flow into the dynamics: the change in the slider forces they make."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_states

import orthoglide_pin as og
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: Change of the slider forces against J^T dm (a - g) (relative to the change).
DELTA_TOL = 1e-9
#: CAD values equal to the derived ones give the same forces (relative).
SAME_TOL = 1e-12
#: A CAD platform: heavier than the 80 mm aluminium cube, off-centre, with products
#: of inertia (none of which a translating platform's slider forces may feel but its mass).
CAD_PLATFORM = {
    "mass": 3.2,
    "com": [0.004, -0.006, 0.011],
    "inertia": [[4.1e-3, 2.0e-4, -3.0e-4], [2.0e-4, 3.6e-3, 1.5e-4], [-3.0e-4, 1.5e-4, 5.2e-3]],
}
DESIGNS = {
    "prototype": og.prototype(),
    "long_leg": og.prototype().replace(leg_length=0.36, tool_offset=(0.01, 0.0, 0.18)),
}


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_a_cad_platform_changes_the_forces_by_j_transpose_dm_a_minus_g(name: str) -> None:
    """Virtual work: the platform only translates, so of its CAD inertia only the
    mass changes the actuator forces, by J^T (m_cad - m_default)(a - g); its
    centre of mass and tensor load the passive joints only."""
    base = DESIGNS[name]
    cad = base.replace(inertias={"platform": CAD_PLATFORM})
    gravity = (0.0, 3.0, -9.81)
    p, pd, pdd = random_states(16, seed=15)
    p = p * (base.leg_length / 0.31)  # inside each design's reach
    before = ClosedLoopDynamics(ClosedLoopModel(base), gravity=gravity)
    after = ClosedLoopDynamics(ClosedLoopModel(cad), gravity=gravity)
    f0 = before.inverse_dynamics(p, pd, pdd).forces
    f1 = after.inverse_dynamics(p, pd, pdd).forces
    dm = CAD_PLATFORM["mass"] - og.inertia_table(base).by_kind()["platform"].total
    assert dm == pytest.approx(3.2 - 0.08**3 * 2700.0, rel=1e-12)
    J = og.jacobian(p, base.leg_length)
    expected = np.einsum("nji,nj->ni", J, dm * (pdd - np.asarray(gravity)))
    assert _rel(f1 - f0, expected) <= DELTA_TOL
    assert np.max(np.abs(f1 - f0)) > 10.0  # a change of tens of newtons, not noise
    # The projection route (Pinocchio's constraint models) sees the same change.
    f1_proj = after.inverse_dynamics(p[:4], pd[:4], pdd[:4], method="projection").forces
    assert _rel(f1_proj, f1[:4]) <= DELTA_TOL


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_cad_values_equal_to_the_derived_ones_change_nothing(name: str) -> None:
    """Each leg part given from CAD with the values the sizes give: same forces."""
    base = DESIGNS[name]
    table = og.inertia_table(base)
    inertias = {}
    for kind in ("carriage", "bar", "small_link"):
        # The first body of each kind has its link frame on its part frame (for the
        # small links, the base link, centred on its joint).
        body = table.kind(kind)[0]
        inertias[kind] = {"mass": body.mass, "com": body.com.tolist(), "inertia": body.inertia}
    cad = base.replace(inertias=inertias)
    assert og.inertia_table(cad).total_moving_mass == pytest.approx(table.total_moving_mass)
    p, pd, pdd = random_states(10, seed=16)
    p = p * (base.leg_length / 0.31)
    f0 = ClosedLoopDynamics(ClosedLoopModel(base)).inverse_dynamics(p, pd, pdd).forces
    f1 = ClosedLoopDynamics(ClosedLoopModel(cad)).inverse_dynamics(p, pd, pdd).forces
    assert _rel(f1, f0) <= SAME_TOL
