"""A plan commanded through a calibration: the real tool follows the programmed path."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og
from orthoglide_pin.calibration.model import GeometricModel
from orthoglide_pin.calibration.result import Calibration, write_calibration
from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.planning import PlanLimits, plan_program
from orthoglide_pin.planning.calibrated import slider_motion
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.sampling import sample_plan
from orthoglide_pin.program.axes import ProgramAxes

#: Program axes equal to the world axes: the programs here name world points.
WORLD = ProgramAxes((1, 2, 3))

pytest.importorskip("toppra")

#: Errors of the built machine: 0.1 mm anchors and lengths, 0.1 mrad tilts.
ERROR_SIZE = 1e-4
#: The real tool against the programmed path [m].
FOLLOW_TOL = 1e-9
#: Central differences of the calibrated inverse kinematics (step H [s]).
H, FD_TOL = 1e-4, 1e-6
#: The nominal model through the closed form and through the closed-loop dynamics.
SAME_TOL = 1e-10
PROGRAM = "G21 G90 G64 P0.02\nG0 X40 Y-30 Z10\nG1 Y30 F6000\nG2 X0 Y30 I-20 J0\nG0 X0 Y0 Z0\nM2\n"
LIMITS = {"--max-slider-speed": "0.8", "--max-slider-acceleration": "8"}


def _calibration(model: GeometricModel, leg: float) -> Calibration:
    return Calibration(
        model=model,
        nominal=GeometricModel.nominal(leg),
        std=np.zeros(18),
        noise_estimate=0.0,
        rms_before=0.0,
        rms_after=0.0,
        outliers=(),
        unidentifiable=(),
        poses=60,
        measurements_sha256="ab" * 32,
        design=og.design_digest(og.prototype().replace(leg_length=leg)),
    )


def _built(leg: float, seed: int) -> Calibration:
    nominal = GeometricModel.nominal(leg)
    rng = np.random.default_rng(seed)
    return _calibration(
        GeometricModel.from_vector(nominal.vector() + rng.normal(0, ERROR_SIZE, 18)), leg
    )


def test_slider_motion_is_the_derivative_of_the_inverse_kinematics() -> None:
    cal = _built(0.33, 3)  # another design than the prototype
    rng = np.random.default_rng(11)
    p = rng.uniform(-0.05, 0.05, (50, 3))
    v = rng.normal(0, 0.5, (50, 3))
    a = rng.normal(0, 5.0, (50, 3))
    q, qd, qdd = slider_motion(cal, p, v, a)
    at = [cal.inverse_kinematics(p + v * t + 0.5 * a * t * t) for t in (-H, 0.0, H)]
    np.testing.assert_allclose(q, at[1], atol=0.0)
    np.testing.assert_allclose(qd, (at[2] - at[0]) / (2 * H), atol=FD_TOL)
    np.testing.assert_allclose(qdd, (at[2] - 2 * at[1] + at[0]) / H**2, atol=100 * FD_TOL)


def test_the_drawing_gives_the_nominal_commands(dyn: og.ClosedLoopDynamics) -> None:
    cal = _calibration(GeometricModel.nominal(dyn.closed_loop.params.leg_length), 0.31)
    rng = np.random.default_rng(5)
    p, v, a = rng.uniform(-0.05, 0.05, (20, 3)), rng.normal(size=(20, 3)), rng.normal(size=(20, 3))
    res = dyn.inverse_dynamics(p, v, a)
    q, qd, qdd = slider_motion(cal, p, v, a)
    np.testing.assert_allclose(q, res.slider_positions, atol=SAME_TOL)
    np.testing.assert_allclose(qd, res.slider_velocities, atol=SAME_TOL)
    np.testing.assert_allclose(qdd, res.slider_accelerations, atol=SAME_TOL)


def _columns(path: Path) -> dict[str, np.ndarray]:
    with open(path) as fh:
        rows = list(csv.reader(fh))[1:]  # after the design
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def test_the_real_tool_follows_the_program(tmp_path: Path, capsys) -> None:
    cal = _built(0.31, 1)
    file = tmp_path / "calibration.yaml"
    write_calibration(file, cal)
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    limits = [x for kv in LIMITS.items() for x in kv]
    base = ["plan", str(prog), *limits, "--dt", "0.002"]
    data = run_json(capsys, *base, "--calibration", str(file), "--out", str(tmp_path / "c"))
    assert data["calibration"] == str(file)
    assert all(row["peak_use"] <= 1.0 + 1e-3 for row in data["limits"])
    run_json(capsys, *base, "--out", str(tmp_path / "n"))
    real = og.load_calibration(file)
    for folder, follows in (("c", True), ("n", False)):
        col = _columns(tmp_path / folder / "trajectory.csv")
        q = np.column_stack([col[f"q{i}"] for i in (1, 2, 3)])
        path = np.column_stack([col["x"], col["y"], col["z"]])
        miss = np.linalg.norm(real.direct_kinematics(q) - path, axis=1).max()
        if follows:
            assert miss < FOLLOW_TOL
            qd = np.column_stack([col[f"qd{i}"] for i in (1, 2, 3)])
            assert np.abs(qd).max() <= float(LIMITS["--max-slider-speed"]) * (1 + 1e-3)
        else:  # the drawing's commands miss by the size of the errors
            assert 0.3 * ERROR_SIZE < miss < 10 * ERROR_SIZE


def test_the_slider_limits_are_checked_on_the_calibrated_commands(
    dyn: og.ClosedLoopDynamics,
) -> None:
    params = dyn.closed_loop.params
    nominal = GeometricModel.nominal(params.leg_length)
    u = nominal.directions
    # carriages mounted 0.1 mm back along their rails: every command 0.1 mm longer
    shifted = GeometricModel(
        nominal.anchors - ERROR_SIZE * u, nominal.alpha, nominal.beta, nominal.lengths
    )
    far = 1e3 * (params.workspace.q2 - 1e-7)
    program = read_program(f"G21\nG0 X{far[0]:.4f} Y{far[1]:.4f} Z{far[2]:.4f}\n", axes=WORLD)
    limits = PlanLimits(slider_speed=1.0, slider_acceleration=10.0)
    plan_program(program, dyn, limits)  # the drawing reaches Q2
    with pytest.raises(ProgramError, match=r"program line 2: .* calibrated machine"):
        plan_program(program, dyn, limits, calibration=_calibration(shifted, params.leg_length))
    cal = _calibration(shifted, params.leg_length)
    ok = plan_program(read_program("G21\nG0 X20\n", axes=WORLD), dyn, limits, calibration=cal)
    col = sample_plan(ok, dyn, 0.01)
    q = np.column_stack([col[f"q{i}"] for i in (1, 2, 3)])
    np.testing.assert_allclose(q[0] - ERROR_SIZE, 0.0, atol=1e-12)  # home, 0.1 mm longer


def test_a_bad_calibration_file_is_one_line(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "part.nc"
    prog.write_text(PROGRAM)
    bad = tmp_path / "bad.yaml"
    bad.write_text("parameters: [1, 2\n")
    out = tmp_path / "o"
    for file, says in ((tmp_path / "none.yaml", "calibration"), (bad, "calibration")):
        code, text, err = run(
            capsys, "plan", str(prog), "--max-slider-acceleration", "5",
            "--calibration", str(file), "--out", str(out),
        )  # fmt: skip
        assert (code, text) == (2, "") and says in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
