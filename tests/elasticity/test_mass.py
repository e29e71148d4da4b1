"""Masses of the vibration model against the description's inertial table."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.elasticity.mass import (
    beam_mass,
    member_masses,
    platform_inertia,
    reflected_mass,
    spatial_inertia,
)
from orthoglide_pin.exceptions import InvalidParameterError

SEED = 7
#: Relative agreement of two exact routes (rounding only).
EXACT_TOL = 1e-9


def _rigid_motion(nodes: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(6 * len(nodes), 6): node motions of a rigid body moving as (v_point, omega)."""
    out = np.zeros((6 * len(nodes), 6))
    for k, x in enumerate(nodes):
        r = x - point
        out[6 * k : 6 * k + 3, :3] = np.eye(3)
        out[6 * k : 6 * k + 3, 3:] = -np.array(
            [[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]]
        )
        out[6 * k + 3 : 6 * k + 6, 3:] = np.eye(3)
    return out


@pytest.mark.parametrize("kind", ["bar", "small_link"])
def test_a_member_moving_rigidly_has_the_description_inertia(kind: str) -> None:
    params = og.prototype()
    table = og.inertia_table(params)
    bar, link = member_masses(params, table)
    body = table.kind(kind)[0]
    member, length = (
        (bar, params.leg_length) if kind == "bar" else (link, params.parallelogram_width)
    )
    rng = np.random.default_rng(SEED)
    x = rng.normal(size=3)
    x /= np.linalg.norm(x)
    y = np.cross(x, rng.normal(size=3))
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    a = rng.normal(size=3) * 0.1
    n = 3  # three elements in a row: still a rigid body
    ends = [a + x * length * k / n for k in range(n + 1)]
    m = np.zeros((6 * (n + 1), 6 * (n + 1)))
    for e in range(n):
        m[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += beam_mass(x, y, z, length / n, member)
    t = _rigid_motion(np.array(ends), np.zeros(3))
    got = t.T @ m @ t
    # the description's body: a uniform member along its own axis (x for a bar,
    # y for a small link), its centre of mass at the member's middle
    axis = 0 if kind == "bar" else 1
    local = np.eye(3)[[axis, (axis + 1) % 3, (axis + 2) % 3]]  # rows: member x, y, z
    rot = np.stack([x, y, z], axis=1) @ local  # description axes -> world
    com = a + x * length / 2.0
    expected = spatial_inertia(body.mass, com, rot @ body.inertia @ rot.T, np.zeros(3))
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)


def test_the_platform_body_is_platform_spindle_and_tool() -> None:
    params = og.prototype()
    table = og.inertia_table(params)
    plat = platform_inertia(params, table)
    assert plat[0, 0] == pytest.approx(table.platform_mass, rel=EXACT_TOL)
    np.testing.assert_allclose(plat, plat.T, atol=1e-14)
    # the spindle's centre of mass lies on the tool axis: its moment about the
    # tool tip, m r, over the platform mass gives the centre of mass height
    com_height = plat[1, 3] / plat[0, 0]
    spindle = table.kind("spindle")[0].mass
    assert 0.0 < com_height < params.tool_offset[2] + params.spindle_length
    lighter = dataclasses.replace(params, spindle_mass=0.5 * spindle)
    plat2 = platform_inertia(lighter, og.inertia_table(lighter))
    assert plat[0, 0] - plat2[0, 0] == pytest.approx(0.5 * spindle, rel=EXACT_TOL)
    assert np.all(np.linalg.eigvalsh(plat) > 0.0)
    # a model passed in (the one the platform model shares) gives the same body
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    shared = platform_inertia(lighter, og.inertia_table(lighter), ClosedLoopModel(lighter))
    np.testing.assert_array_equal(shared, plat2)


def test_reflected_mass_of_the_example_drive() -> None:
    drive = og.load_drive(str(og.example_drive_file()))
    train = drive.train
    expected = (train.rotor_inertia * train.gear_ratio**2 + train.screw_inertia_value) * (
        2.0 * math.pi / train.lead
    ) ** 2
    assert reflected_mass(drive) == pytest.approx(expected, rel=EXACT_TOL)
    assert reflected_mass(train) == reflected_mass(drive)
    carriage = og.inertia_table().kind("carriage")[0].mass
    assert reflected_mass(drive) / carriage == pytest.approx(8.5, abs=0.05)  # the design notes
    assert reflected_mass(None) == 0.0
    with pytest.raises(InvalidParameterError, match="drive"):
        reflected_mass("motor.yaml")  # type: ignore[arg-type]
