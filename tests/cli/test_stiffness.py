"""The ``stiffness`` command: keys, units, negative numbers, errors."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.kinematics.closed_form import inverse_jacobian


def test_json_keys_and_values(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "stiffness", "-0.03", "0.05", "-0.02")
    for key in ("K", "K6", "deflection", "actuator_stiffness", "sources", "assumptions"):
        assert key in data
    point = np.array([-0.03, 0.05, -0.02])
    expected = og.cartesian_stiffness(point)
    np.testing.assert_allclose(data["K"], expected.K, rtol=1e-12)
    assert expected.K6 is not None
    np.testing.assert_allclose(data["K6"], expected.K6, rtol=1e-12, atol=1e-6)
    assert data["sources"] == ["actuators", "links"]
    assert data["actuator_stiffness"] == og.prototype().actuator_stiffness
    assert data["assumptions"]["youngs_modulus"] == og.prototype().youngs_modulus
    # Default wrench: 100 N along x.
    assert data["wrench"] == [100.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    np.testing.assert_allclose(data["deflection"], expected.compliance @ data["wrench"])


def test_actuators_only_has_no_k6(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(
        capsys, "stiffness", "0.02", "-0.04", "0.06", "--sources", "actuators",
        "--param", "actuator_stiffness=5e7",
    )  # fmt: skip
    assert data["K6"] is None
    j_inv = inverse_jacobian([0.02, -0.04, 0.06], og.prototype().leg_length)
    np.testing.assert_allclose(data["K"], 5e7 * j_inv.T @ j_inv, rtol=1e-9)
    assert data["actuator_stiffness"] == 5e7
    assert data["assumptions"]["links"] == "rigid"


def test_negative_wrench_and_list_form(capsys: pytest.CaptureFixture[str]) -> None:
    words = run_json(
        capsys, "stiffness", "0", "0", "0", "--wrench", "-10", "0", "-200", "0", "-1", "0"
    )
    listed = run_json(capsys, "stiffness", "0", "0", "0", "--wrench", "-10,0,-200,0,-1,0")
    assert words["deflection"] == listed["deflection"]
    assert words["wrench"] == [-10.0, 0.0, -200.0, 0.0, -1.0, 0.0]
    links = run_json(capsys, "stiffness", "0", "0", "0", "--sources", "links")
    assert links["actuator_stiffness"] is None


def test_text_states_the_assumptions(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "stiffness", "0", "0", "0")
    assert code == 0
    assert "E = 70 GPa" in out and "k_a = 100 N/um" in out and "revolutes" in out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (("0", "0", "0", "--sources", "bearings"), "joints"),
        (("0", "0", "0", "--sources", "springs"), "sources"),
        (("0", "0", "0", "--wrench", "1", "2", "3"), "--wrench"),
        (("0", "0", "0", "--wrench", "1", "2", "3", "4", "5", "nan"), "--wrench"),
        (("0.5", "0", "0"), "leg"),
        (("0", "0", "0", "--param", "youngs_modulus=-1"), "youngs_modulus"),
    ],
)
def test_errors_are_one_line(
    capsys: pytest.CaptureFixture[str], argv: tuple[str, ...], needle: str
) -> None:
    code, out, err = run(capsys, "stiffness", *argv)
    assert code == 2
    assert out == ""
    assert err.startswith("orthoglide stiffness: error:") and err.count("\n") == 1
    assert needle in err


def test_joints_source(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "stiffness", "0.01", "0.02", "0.03", "--sources", "links,joints")
    assert data["sources"] == ["links", "joints"]
    assert data["actuator_stiffness"] is None
    assert data["assumptions"]["joint_stiffness"] == og.prototype().joint_stiffness
    expected = og.cartesian_stiffness([0.01, 0.02, 0.03], sources="links,joints")
    np.testing.assert_allclose(data["K"], expected.K, rtol=1e-12)
    code, out, _ = run(capsys, "stiffness", "0", "0", "0", "--sources", "joints")
    assert code == 0 and "bearings 100 N/um" in out and "compliant bearings" in out
