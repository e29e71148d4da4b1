"""The certified Cartesian limits: bounds above every sampled value, joints within limits."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.controller.limits import box_gains, certify_limits
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_jacobian, inverse_kinematics
from orthoglide_pin.machine.params import OrthoglideParams

#: Relative slack of a certified bound over the sampled maximum.
TIGHTNESS = 1e-6
#: Finite-difference step of the velocity-product check [s].
DT = 1e-5
SEED = 20261206


@pytest.fixture(scope="module")
def proto() -> OrthoglideParams:
    return OrthoglideParams()


def test_bounds_hold_and_are_tight(proto: OrthoglideParams) -> None:
    lim = certify_limits(proto, 1.2, 20.0)
    for bound, sampled in zip(
        (lim.speed_gain, lim.acceleration_gain, lim.curvature), lim.sampled, strict=True
    ):
        assert sampled <= bound <= sampled * (1 + TIGHTNESS)
    assert lim.worst_joint_speed() <= 1.2
    assert lim.worst_joint_acceleration() <= 20.0


def test_random_motions_keep_the_joints_within_limits(proto: OrthoglideParams) -> None:
    """Random points, velocities and accelerations within the limits: joints within theirs."""
    lim = certify_limits(proto, 1.2, 20.0)
    rng = np.random.default_rng(SEED)
    n = 2000
    p = np.asarray(proto.workspace_corner) + proto.workspace_side * rng.random((n, 3))
    u = rng.normal(size=(n, 3))
    v = lim.speed * u / np.linalg.norm(u, axis=1, keepdims=True)
    a = lim.acceleration * rng.choice([-1.0, 1.0], size=(n, 3))
    # exact joint speed and acceleration by central differences of q(p(t))
    q = [inverse_kinematics(p + v * t + 0.5 * a * t * t, proto.leg_length) for t in (-DT, 0, DT)]
    qd = (q[2] - q[0]) / (2 * DT)
    qdd = (q[2] - 2 * q[1] + q[0]) / DT**2
    assert np.abs(qd).max() <= 1.2
    assert np.abs(qdd).max() <= 20.0 * (1 + 1e-4)
    m = inverse_jacobian(p, proto.leg_length)
    assert np.allclose(qd, np.einsum("nij,nj->ni", m, v), atol=1e-8)


def test_box_gains_refuse_a_singular_box() -> None:
    with pytest.raises(InvalidParameterError, match="serial"):
        box_gains(np.array([0.0, 0.3, 0.3]), np.array([0.1, 0.35, 0.35]), 0.31)


def test_bad_limits_are_refused(proto: OrthoglideParams) -> None:
    with pytest.raises(InvalidParameterError, match="joint_speed"):
        certify_limits(proto, -1.0, 20.0)


def test_program_axes_change_no_limit(proto: OrthoglideParams) -> None:
    """A rotation of the program axes moves which axis is which, not any bound."""
    turned = proto.replace(program_axes=(1, -2, -3))
    assert certify_limits(turned, 1.2, 20.0) == certify_limits(proto, 1.2, 20.0)
