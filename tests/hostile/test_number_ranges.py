"""Numbers out of their documented range: refused before use, on the command line and in the API.

Each case gives exit status 2 and one line on the command line (no traceback,
nothing written), an :class:`~orthoglide_pin.exceptions.OrthoglideError` in the
API, and a message that names the value and what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.experiment import MAX_NOISE, MIN_NOISE
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    ProgramError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.planning.gcode import MAX_DWELL, MAX_FEED, MIN_FEED
from orthoglide_pin.planning.sampling import MAX_DT, MIN_DT, sample_plan
from orthoglide_pin.simulation.servo import MIN_PERIODS_PER_BLOCK, MIN_RATE
from tests.conftest import run

#: The parallel singular point of the prototype's main diagonal [m].
T_SINGULAR = 0.31 / math.sqrt(3.0)
#: A coordinate of 5000 digits, and a feed of 400 nines (both read as inf by float()).
HUGE_COORDINATE = "1" * 5000
HUGE_FEED = "9" * 400
#: Longest error line accepted for a huge word [characters].
MAX_LINE = 300
#: Two short blocks under exact stop: about 9 ms of motion at 20 m/s^2.
SHORT_PROGRAM = "G61\nG1 X0.1 F3000\nG1 X0.2\n"


def _refused(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    """Run the command; check it is refused in one line without a traceback; the line."""
    code, out, err = run(capsys, *argv)
    assert code == 2, err
    assert out == "" and err.count("\n") == 1, err
    assert "Traceback" not in err and len(err) < MAX_LINE
    return err


@pytest.fixture
def pocket(tmp_path: Path) -> Path:
    path = tmp_path / "pocket.nc"
    path.write_text(og.example_program_text("pocket"), encoding="utf-8")
    return path


PLAN = ("--max-slider-acceleration", "20")


# ----------------------------------------------------- coordinates and offsets
@pytest.mark.parametrize(
    ("option", "values"),
    [
        ("--origin", ("1e300", "0", "0")),
        ("--start", ("1e300", "0", "0")),
        ("--origin", ("2000", "0", "0")),
        ("--start", ("0", "-1000.5", "0")),
    ],
)
def test_plan_refuses_an_offset_beyond_1000_m(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, pocket: Path, option: str, values: tuple
) -> None:
    out = tmp_path / "out"
    err = _refused(capsys, "plan", str(pocket), "--out", str(out), *PLAN, option, *values)
    assert f"invalid {option.strip('-')}=" in err and "within +-1000 [m]" in err
    assert not out.exists()


@pytest.mark.parametrize("name", ["origin", "start"])
@pytest.mark.parametrize("value", [1e300, -1000.001, math.inf])
def test_read_program_refuses_an_offset_beyond_1000_m(name: str, value: float) -> None:
    allowed = "finite numbers" if math.isinf(value) else r"within \+-1000"
    with pytest.raises(InvalidParameterError, match=rf"invalid {name}=.*{allowed}") as info:
        og.read_program("G0 X1\n", **{name: (value, 0.0, 0.0)})
    assert info.value.name == name


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        (f"G0 X{HUGE_COORDINATE}\n", "expected a finite number"),
        (f"G1 X1 F{HUGE_FEED}\n", "expected a finite number"),
        (f"G{HUGE_FEED}\n", "expected a finite number"),
        (f"N{HUGE_FEED} G0 X1\n", "expected a finite number"),
        ("G0 X1000001\n", "beyond +-1000 m"),
        ("G2 X1 Y0 I2000000 J0 F600\n", "beyond +-1000 m"),
        ("G91\nG0 X600000\nG0 X600000\n", "beyond +-1000 m"),
        ("G0 X1\n", None),  # the baseline: read
        ("G1 X1 F60000001\n", f"to {MAX_FEED * 60e3:g} mm/min"),
        ("G1 X1 F0.00001\n", f"from {MIN_FEED * 60e3:g} to"),
        ("G20\nG1 X1 F2400000\n", "in/min"),
        (f"G4 P{MAX_DWELL + 1:g}\n", f"dwell time [s] in [0, {MAX_DWELL:g}]"),
        ("G64 P2000000\nG0 X1\n", "tolerance must be in [0, 1000] m"),
    ],
)
def test_read_program_refuses_numbers_out_of_range(text: str, needle: str | None) -> None:
    if needle is None:
        og.read_program(text)
        return
    with pytest.raises(ProgramError) as info:
        og.read_program(text)
    message = str(info.value)
    assert needle in message and len(message) < MAX_LINE
    assert HUGE_FEED[:100] not in message and info.value.line >= 1


@pytest.mark.parametrize(
    ("program", "needle"),
    [
        (f"G0 X{HUGE_COORDINATE}\n", "expected a finite number"),
        (f"G1 X1 F{HUGE_FEED}\n", "expected a finite number"),
        ("G1 X1 F99999999\n", "mm/min"),
    ],
)
def test_plan_refuses_a_program_number_out_of_range(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, program: str, needle: str
) -> None:
    path, out = tmp_path / "p.nc", tmp_path / "out"
    path.write_text(program, encoding="utf-8")
    err = _refused(capsys, "plan", str(path), "--out", str(out), *PLAN)
    assert "program line 1:" in err and needle in err and "1" * 100 not in err
    assert not out.exists()


# ----------------------------------------------------------- the plan's numbers
@pytest.mark.parametrize("dt", ["1e300", "1e-12", "0", "-0.001", "nan", "0.5"])
def test_plan_refuses_a_sampling_step_out_of_range(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, pocket: Path, dt: str
) -> None:
    out = tmp_path / "out"
    err = _refused(capsys, "plan", str(pocket), "--out", str(out), *PLAN, "--dt", dt)
    assert "invalid --dt=" in err and f"[{MIN_DT:g}, {MAX_DT:g}] [s]" in err
    assert not out.exists()


@pytest.mark.parametrize("dt", [1e300, 1e-12, 0.0, math.nan])
def test_sample_plan_refuses_a_step_out_of_range_first(dt: float) -> None:
    with pytest.raises(InvalidParameterError, match=r"invalid dt=.*\[1e-06, 0.1\] \[s\]"):
        sample_plan(None, None, dt)  # type: ignore[arg-type]  # refused before either is read


@pytest.mark.parametrize(
    ("option", "value", "cap"),
    [
        ("--max-slider-speed", "1001", "(0, 1000] [m/s]"),
        ("--max-slider-acceleration", "1e6", "(0, 100000] [m/s^2]"),
        ("--max-slider-jerk", "1e300", "(0, 1e+09] [m/s^3]"),
    ],
)
def test_plan_refuses_slider_limits_beyond_the_caps(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    pocket: Path,
    option: str,
    value: str,
    cap: str,
) -> None:
    out = tmp_path / "out"
    err = _refused(capsys, "plan", str(pocket), "--out", str(out), *PLAN, option, value)
    assert f"invalid {option}=" in err and cap in err


@pytest.mark.parametrize(
    ("name", "value"),
    [("slider_speed", 1001.0), ("slider_acceleration", 2e5), ("slider_jerk", 1e10)],
)
def test_plan_limits_refuse_values_beyond_the_caps(name: str, value: float) -> None:
    with pytest.raises(InvalidParameterError, match=rf"invalid {name}=") as info:
        og.PlanLimits(**{name: value})
    assert info.value.name == name


def test_plan_program_refuses_a_huge_wrench(dyn: og.ClosedLoopDynamics) -> None:
    program = og.read_program("G1 X1 F600\n")
    limits = og.PlanLimits(slider_acceleration=20.0)
    with pytest.raises(InvalidParameterError, match=r"invalid wrench=1e\+300.*1e\+09"):
        og.plan_program(program, dyn, limits, wrench=(1e300, 0.0, 0.0))


def test_plan_refuses_a_huge_wrench(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, pocket: Path
) -> None:
    out = tmp_path / "out"
    err = _refused(
        capsys, "plan", str(pocket), "--out", str(out), *PLAN, "--wrench", "1e300", "0", "0"
    )
    assert "invalid wrench=1e+300" in err and "+-1e+09 [N, N.m]" in err
    assert not out.exists()


# ---------------------------------------------------------------- gravity
@pytest.mark.parametrize(
    "gravity", [("1e300", "0", "0"), ("0", "800", "800"), ("-1001", "0", "0")]
)
def test_mjcf_refuses_a_gravity_beyond_1000(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, gravity: tuple[str, str, str]
) -> None:
    target = tmp_path / "m.xml"
    err = _refused(capsys, "mjcf", "-o", str(target), "--gravity", *gravity)
    assert "invalid gravity=" in err and "magnitude at most 1000 m/s^2" in err
    assert not target.exists()


def test_mjcf_text_and_write_mjcf_refuse_a_gravity_beyond_1000(tmp_path: Path) -> None:
    with pytest.raises(InvalidParameterError, match="magnitude at most 1000 m/s"):
        og.mjcf_text(gravity=(1e300, 0.0, 0.0))
    target = tmp_path / "m.xml"
    with pytest.raises(InvalidParameterError, match="magnitude at most 1000 m/s"):
        og.write_mjcf(target, gravity=(0.0, 0.0, 1000.5))
    assert not target.exists()


# ------------------------------------------------------------- servo rate
@pytest.mark.parametrize("rate", ["1", "1e-300", "499", "1e300"])
def test_simulate_refuses_a_rate_out_of_range(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, rate: str
) -> None:
    drive = tmp_path / "drive.yaml"
    drive.write_text(og.example_drive_text(), encoding="utf-8")
    out = tmp_path / "out"
    argv = ("simulate", "--example", "pocket", "--motor", str(drive), "--rate", rate)
    err = _refused(capsys, *argv, "--out", str(out))
    assert "invalid rate=" in err and f"[{MIN_RATE:g}, 100000] [Hz]" in err
    assert not out.exists()


@pytest.mark.parametrize("rate", [1.0, 1e-300, MIN_RATE - 1.0, math.inf])
def test_servo_settings_refuse_a_rate_out_of_range(rate: float) -> None:
    with pytest.raises(InvalidParameterError, match=r"invalid rate=.*\[500, 100000\] \[Hz\]"):
        og.ServoSettings(rate=rate)


def test_a_rate_must_give_every_block_its_periods() -> None:
    settings = og.ServoSettings(rate=1000.0)
    settings.check_sampling(10.0, 12)  # 10,000 periods for 12 blocks
    with pytest.raises(
        InvalidParameterError, match=r"invalid rate=1000.0: expected at least"
    ) as info:
        settings.check_sampling(0.1, 12)  # 100 periods for 12 blocks
    assert f"{MIN_PERIODS_PER_BLOCK} servo periods per block (12 blocks in 0.1 s)" in str(
        info.value
    )
    assert "1200 Hz" in str(info.value)
    with pytest.raises(InvalidParameterError, match="at most 1,000,000 servo periods"):
        og.ServoSettings(rate=100_000.0).check_sampling(20.0, 1)


@pytest.fixture(scope="module")
def short_plan(model: og.ClosedLoopModel) -> og.Plan:
    limits = og.PlanLimits(slider_acceleration=20.0)
    return og.plan_program(og.read_program(SHORT_PROGRAM), model.params, limits)


def test_simulate_refuses_a_rate_that_steps_over_the_blocks(
    short_plan: og.Plan, dyn: og.ClosedLoopDynamics
) -> None:
    settings = og.ServoSettings(rate=1000.0)
    assert short_plan.cycle_time * settings.rate < MIN_PERIODS_PER_BLOCK * 2
    with pytest.raises(InvalidParameterError, match=r"invalid rate=1000.0: expected at least"):
        og.simulate(short_plan, dyn, None, settings)


def test_the_command_refuses_a_rate_that_steps_over_the_blocks(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    drive, program, out = tmp_path / "drive.yaml", tmp_path / "p.nc", tmp_path / "out"
    drive.write_text(og.example_drive_text(), encoding="utf-8")
    program.write_text(SHORT_PROGRAM, encoding="utf-8")
    argv = ("simulate", str(program), "--motor", str(drive), "--rate", "600")
    err = _refused(capsys, *argv, "--out", str(out))
    assert "invalid rate=600.0: expected at least" in err and "servo periods per block" in err
    assert not out.exists()


# ------------------------------------------------------------ tracker noise
@pytest.mark.parametrize("noise", ["1e300", "1e-300", "1", "0"])
def test_calibrate_refuses_a_noise_out_of_range(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, noise: str
) -> None:
    out = tmp_path / "out"
    err = _refused(capsys, "calibrate", "--plan", "30", "--noise", noise, "--out", str(out))
    assert "invalid --noise=" in err and f"[{MIN_NOISE:g}, {MAX_NOISE:g}] [m]" in err
    assert not out.exists()


@pytest.mark.parametrize("noise", [1e300, 1e-300, 1.0, -5e-6])
def test_plan_poses_refuses_a_noise_out_of_range(noise: float) -> None:
    with pytest.raises(InvalidParameterError, match=r"invalid noise=.*\[1e-09, 0.01\] \[m\]"):
        og.plan_poses(og.prototype(), 30, noise=noise)


# -------------------------------------------------------------- sensitivity
@pytest.mark.parametrize("t", [T_SINGULAR, 0.1789])
def test_sensitivity_refuses_next_to_the_parallel_singularity_as_the_command(
    capsys: pytest.CaptureFixture[str], t: float
) -> None:
    err = _refused(capsys, "sensitivity", str(t), str(t), str(t))
    assert "unreachable by leg 1" in err
    with pytest.raises(UnreachablePointError, match="outside the slider limits"):
        og.sensitivity(og.prototype(), [t, t, t])
    with pytest.raises(UnreachablePointError, match="outside the slider limits"):
        og.sensitivity_indices(og.prototype(), [[0.0, 0.0, 0.0], [t, t, t]])


def test_sensitivity_of_a_leg_length_refuses_the_singular_point() -> None:
    t = T_SINGULAR
    with pytest.raises(SingularConfigurationError, match="parallel singularity"):
        og.sensitivity(0.31, [t, t, t])
    with pytest.raises(UnreachablePointError):
        og.sensitivity(0.31, [0.4, 0.0, 0.0])
    assert og.sensitivity(0.31, [0.01, 0.02, 0.03]).shape == (3, 18)
    assert np.isfinite(og.sensitivity(og.prototype(), np.zeros((4, 3)))).all()
