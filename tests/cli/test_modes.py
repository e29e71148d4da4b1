"""The ``modes`` command: keys, values against the Python API, the drive, errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og


def test_json_platform_model_matches_the_api(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "modes", "0.02", "-0.03", "0.01", "--model", "platform")
    expected = og.natural_frequencies(og.prototype(), [0.02, -0.03, 0.01])
    assert data["model"] == "platform"
    np.testing.assert_allclose(data["frequencies"], expected.frequencies, rtol=1e-12)
    assert data["frequencies"] == sorted(data["frequencies"])
    assert len(data["shapes"]) == 6 and data["drive_mass"] == 0.0
    for shape in data["shapes"]:
        assert set(shape) == {"frequency", "tool_direction", "platform_rotation", "energy"}
        assert sum(shape["energy"].values()) == pytest.approx(1.0)
        assert np.linalg.norm(shape["tool_direction"]) == pytest.approx(1.0)
    assert any("No drive" in line for line in data["assumptions"])


def test_full_model_with_the_example_drive(capsys: pytest.CaptureFixture[str]) -> None:
    motor = str(og.example_drive_file())
    data = run_json(capsys, "modes", "0", "0", "0", "--motor", motor, "--count", "3")
    assert data["model"] == "full" and len(data["frequencies"]) == 3
    assert data["drive_mass"] == pytest.approx(9.175, abs=1e-3)
    assert data["segments"] >= 3
    # the prototype's lowest two are a close pair near 212 Hz at home
    assert data["frequencies"][0] == pytest.approx(212.1, abs=0.3)
    assert data["frequencies"][1] / data["frequencies"][0] - 1.0 < 0.01


def test_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(capsys, "modes", "0", "0", "0", "--model", "platform", "--count", "2")
    assert status == 0
    assert "Natural frequencies" in out and "No drive" in out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (("0", "0", "0", "--count", "0"), "count"),
        (("0", "0", "0", "--count", "7", "--model", "platform"), "count"),
        (("0", "0", "0", "--model", "beam"), "model"),
        (("1", "0", "0"), "unreachable"),
        (("0.31", "0", "0", "--model", "platform"), ""),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    capsys: pytest.CaptureFixture[str], argv: tuple[str, ...], needle: str
) -> None:
    status, out, err = run(capsys, "modes", *argv)
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and needle in err


def test_a_drive_with_non_finite_inertia(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "drive.yaml"
    path.write_text("drive_train:\n  rotor_inertia: .inf\n")
    status, _, err = run(capsys, "modes", "0", "0", "0", "--motor", str(path))
    assert status == 2 and len(err.strip().splitlines()) == 1 and "rotor_inertia" in err
