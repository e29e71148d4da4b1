from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import random_states

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import KINDS, assumptions, inertia_table
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: Hand formulas against the xacro's derivation (relative).
MASS_TOL = 1e-12
#: Prototype assumptions (README): aluminium, tube 20 x 1.5 mm, links 24 mm x 80 mm,
#: carriages 100 x 100 x 40 mm, an 80 mm platform, a 2 kg spindle 60 x 150 mm.
RHO = 2700.0
L = 0.31
BAR_MASS = RHO * math.pi * (0.010**2 - 0.0085**2) * L
LINK_MASS = RHO * math.pi * 0.012**2 * 0.080
CARRIAGE_MASS = RHO * 0.100 * 0.100 * 0.040
PLATFORM_MASS = RHO * 0.080**3
SPINDLE_MASS = 2.0


def test_prototype_masses_follow_from_the_stated_sections() -> None:
    by_kind = inertia_table().by_kind()
    assert list(by_kind) == list(KINDS)
    expected = {
        "carriage": (3, CARRIAGE_MASS),
        "small_link": (6, LINK_MASS),
        "bar": (6, BAR_MASS),
        "platform": (1, PLATFORM_MASS),
        "spindle": (1, SPINDLE_MASS),
    }
    for kind, (count, mass) in expected.items():
        assert by_kind[kind].count == count
        assert by_kind[kind].mass_each == pytest.approx(mass, rel=MASS_TOL)
        assert by_kind[kind].total == pytest.approx(count * mass, rel=MASS_TOL)
    table = inertia_table()
    total = 3 * CARRIAGE_MASS + 6 * LINK_MASS + 6 * BAR_MASS + PLATFORM_MASS + SPINDLE_MASS
    assert table.total_moving_mass == pytest.approx(total, rel=MASS_TOL)
    assert table.platform_mass == pytest.approx(PLATFORM_MASS + SPINDLE_MASS, rel=MASS_TOL)


def test_centres_of_mass_and_inertias_are_those_of_the_shapes() -> None:
    table = inertia_table()
    bar = table.kind("bar")[0]
    ro, ri = 0.010, 0.0085
    np.testing.assert_allclose(bar.com, [L / 2, 0.0, 0.0])
    axial, transverse = (
        BAR_MASS * (ro**2 + ri**2) / 2,
        BAR_MASS * (3 * (ro**2 + ri**2) + L**2) / 12,
    )
    np.testing.assert_allclose(np.diag(bar.inertia), [axial, transverse, transverse], rtol=1e-12)
    end_link = next(b for b in table.kind("small_link") if b.link == "leg2_end_link")
    np.testing.assert_allclose(end_link.com, [0.0, -0.040, 0.0])
    assert end_link.leg == 2 and end_link.joint == "leg2_bar_a_tip"
    carriage = table.kind("carriage")[0]
    a, b, c = 0.100, 0.100, 0.040
    box = CARRIAGE_MASS / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(np.diag(carriage.inertia), box, rtol=1e-12)
    spindle = table.kind("spindle")[0]
    assert spindle.joint == "leg1_end_revolute" and spindle.leg is None
    assert spindle.inertia[2, 2] == pytest.approx(SPINDLE_MASS * 0.03**2 / 2, rel=1e-12)
    for body in table.bodies:
        assert np.allclose(body.inertia, body.inertia.T)
        assert np.all(np.linalg.eigvalsh(body.inertia) > 0.0)


def test_the_table_is_what_pinocchio_loads(model: ClosedLoopModel) -> None:
    """Second route: Pinocchio's parser merges the links joint by joint."""
    table = inertia_table()
    pm = model.model
    assert table.total_moving_mass == pytest.approx(sum(i.mass for i in pm.inertias), rel=MASS_TOL)
    for j in range(1, pm.njoints):
        name = str(pm.names[j])
        assert pm.inertias[j].mass == pytest.approx(
            sum(b.mass for b in table.bodies if b.joint == name), rel=MASS_TOL, abs=1e-15
        )
    # leg 1's third of the platform + spindle: spindle centred spindle_length / 2 along
    # the tool axis; legs 2 and 3 hold a third each, centred on the platform
    platform = pm.frames[model.platform_frame]
    merged = platform.placement.actInv(pm.inertias[platform.parentJoint])
    com = SPINDLE_MASS * np.array([0.0, 0.0, 0.075]) / (SPINDLE_MASS + PLATFORM_MASS / 3)
    np.testing.assert_allclose(merged.lever, com, atol=1e-15)
    for leg in (2, 3):
        closure = pm.frames[pm.getFrameId(f"leg{leg}_closure")]
        share = closure.placement.actInv(pm.inertias[closure.parentJoint])
        assert share.mass == pytest.approx(PLATFORM_MASS / 3, rel=MASS_TOL)
        np.testing.assert_allclose(share.lever, 0.0, atol=1e-15)
        cube = PLATFORM_MASS / 3 * 0.080**2 / 6
        np.testing.assert_allclose(share.inertia, cube * np.eye(3), rtol=1e-12, atol=1e-18)
    shares = table.kind("platform")
    assert [(b.link, b.leg, b.joint) for b in shares] == [
        (f"leg{i}_end_mount", i, f"leg{i}_end_revolute") for i in (1, 2, 3)
    ]


def test_masses_are_overridden_by_the_parameters_and_yaml() -> None:
    params = og.OrthoglideParams.from_yaml("bar_mass: 0.2\ncarriage_mass: 0\nspindle_mass: 3.5\n")
    table = inertia_table(params)
    by_kind = table.by_kind()
    assert by_kind["bar"].mass_each == 0.2
    assert by_kind["carriage"].total == 0.0
    assert by_kind["spindle"].mass_each == 3.5
    assert by_kind["small_link"].mass_each == pytest.approx(LINK_MASS, rel=MASS_TOL)
    # the inertia scales with the mass (same shape)
    ratio = table.kind("bar")[0].inertia / inertia_table().kind("bar")[0].inertia[0, 0]
    assert ratio[0, 0] == pytest.approx(0.2 / BAR_MASS, rel=1e-12)
    lines = assumptions(params)
    assert any("Parallelogram bars" in s and "given (bar_mass = 0.2 kg)" in s for s in lines)
    assert any("Carriages" in s and "given (carriage_mass = 0 kg)" in s for s in lines)
    assert any("Spindle and tool: 3.5 kg (given)" in s for s in lines)


def test_assumptions_state_every_material_and_section() -> None:
    lines = og.inertia_assumptions()
    text = "\n".join(lines)
    assert "no masses" in lines[0]
    for fragment in (
        f"{BAR_MASS:.4f} kg",
        "tube 20.0 mm outer diameter x 1.5 mm wall, 310 mm long",
        "solid cylinder 24.0 mm in diameter x 80 mm",
        "solid box 100 x 100 x 40 mm",
        "solid cube of 80 mm",
        "Spindle and tool: 2 kg (assumed value of the prototype)",
        "aluminium (2700 kg/m^3)",
    ):
        assert fragment in text, fragment
    steel = "\n".join(assumptions(og.prototype().replace(density=7850.0, bar_wall=0.01)))
    assert "steel (7850 kg/m^3)" in steel and "solid rod 20.0 mm" in steel


def test_table_as_json_and_bad_urdf() -> None:
    data = json.loads(json.dumps(inertia_table().to_dict()))
    assert len(data["bodies"]) == 19  # the platform in three shares
    assert data["by_kind"]["platform"]["count"] == 1
    assert data["by_kind"]["bar"]["count"] == 6
    with pytest.raises(og.DescriptionError):
        inertia_table(urdf="<robot><link")
    bad = '<robot name="r"><link name="a"><inertial><mass value="x"/></inertial></link></robot>'
    with pytest.raises(og.DescriptionError):
        inertia_table(urdf=bad)


# CAD inertias flow into the dynamics: the change in the slider forces they make.

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
CAD_DESIGNS = {
    "prototype": og.prototype(),
    "long_leg": og.prototype().replace(leg_length=0.36, tool_offset=(0.01, 0.0, 0.18)),
}


def _rel_change(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


@pytest.mark.parametrize("name", sorted(CAD_DESIGNS))
def test_a_cad_platform_changes_the_forces_by_j_transpose_dm_a_minus_g(name: str) -> None:
    """Virtual work: the platform only translates, so of its CAD inertia only the
    mass changes the actuator forces, by J^T (m_cad - m_default)(a - g); its
    centre of mass and tensor load the passive joints only."""
    base = CAD_DESIGNS[name]
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
    assert _rel_change(f1 - f0, expected) <= DELTA_TOL
    assert np.max(np.abs(f1 - f0)) > 10.0  # a change of tens of newtons, not noise
    # The projection route (Pinocchio's constraint models) sees the same change.
    f1_proj = after.inverse_dynamics(p[:4], pd[:4], pdd[:4], method="projection").forces
    assert _rel_change(f1_proj, f1[:4]) <= DELTA_TOL


@pytest.mark.parametrize("name", sorted(CAD_DESIGNS))
def test_cad_values_equal_to_the_derived_ones_change_nothing(name: str) -> None:
    """Each leg part given from CAD with the values the sizes give: same forces."""
    base = CAD_DESIGNS[name]
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
    assert _rel_change(f1, f0) <= SAME_TOL


def test_the_assumptions_say_which_inertias_are_measured() -> None:
    params = og.prototype().replace(inertias={"platform": CAD_PLATFORM})
    lines = assumptions(params)
    assert lines[0].startswith("Measured (CAD mass, centre of mass and inertia): platform;")
    platform = next(line for line in lines if line.startswith("Platform:"))
    assert "3.2000 kg" in platform and "measured (CAD" in platform
    assert "(4.0, -6.0, 11.0) mm" in platform
    bars = next(line for line in lines if line.startswith("Parallelogram bars"))
    assert "derived from its size" in bars
    assert not any("measured (CAD" in line or "Measured" in line for line in assumptions())
