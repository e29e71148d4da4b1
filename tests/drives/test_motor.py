from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import (
    RPM_PER_RAD_S,
    Drive,
    DriveTrain,
    MotorData,
    load_drive,
    motor_demand,
)
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.machine.ranges import DRIVE_RANGES
from tests.conftest import run

#: Drive values that may be 0 (no friction, an inertia neglected).
_ZERO_ALLOWED = frozenset(
    {"coulomb_torque", "viscous_coefficient", "rotor_inertia", "screw_inertia"}
)

#: Energy integrals over a rest-to-rest move (trapezoidal rule, 20001 samples).
ENERGY_TOL = 1e-6
#: The paper's design speed at the isotropic point [m/s] (section 4).
DESIGN_SPEED = 1.2


def _move(n: int = 20001) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A rest-to-rest move q = d (1 - cos(pi t / T)) / 2 on three sliders, and its forces.

    The forces change sign during the move, so the motors both drive and are back-driven.
    """
    t = np.linspace(0.0, 0.5, n)
    d, T = np.array([0.1, -0.05, 0.2]), 0.5
    w = math.pi / T
    qd = 0.5 * d * w * np.sin(w * t)[:, None]
    qdd = 0.5 * d * w * w * np.cos(w * t)[:, None]
    forces = 50.0 * qdd + np.array([0.0, 10.0, -40.0])
    return t, forces, qd, qdd


def _integral(y: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)[:, None], axis=0)


def test_default_drive_train_is_the_stated_prototype_assumption() -> None:
    train = DriveTrain()
    screw = math.pi * 7850.0 * 0.5 * 0.016**4 / 32.0  # solid steel cylinder 16 x 500 mm
    assert train.screw_inertia_value == pytest.approx(screw, rel=1e-12)
    assert train.reflected_inertia == pytest.approx(1.2e-4 + screw, rel=1e-12)
    # 1.2 m/s on a 25 mm lead: 48 rev/s
    speed = train.motor_speed(DESIGN_SPEED) * RPM_PER_RAD_S
    assert speed == pytest.approx(2880.0, rel=1e-12)
    text = "\n".join(train.assumptions())
    for fragment in (
        "lead 25 mm/rev",
        "efficiency 0.9",
        "solid cylinder 16 mm x 500 mm",
        "rotor inertia 0.00012 kg.m^2",
    ):
        assert fragment in text, fragment


def test_torque_of_a_steady_load_with_and_against_the_motion() -> None:
    """Driving divides by the efficiency, back-driving multiplies (no inertia or friction)."""
    train = DriveTrain(coulomb_torque=0.0, viscous_coefficient=0.0)
    forces = np.array([[100.0, 100.0, -100.0]])
    velocities = np.array([[0.5, -0.5, 0.0]])
    demand = motor_demand(forces, velocities, np.zeros((1, 3)), train)
    screw = 100.0 * 0.025 / (2 * math.pi)
    np.testing.assert_allclose(demand.torque[0], [screw / 0.9, screw * 0.9, -screw / 0.9])
    np.testing.assert_allclose(demand.speed_rpm[0], [1200.0, -1200.0, 0.0])


def test_gear_ratio_and_friction() -> None:
    train = DriveTrain(gear_ratio=4.0, coulomb_torque=0.1, viscous_coefficient=2e-4)
    demand = motor_demand(np.zeros((3, 3)), np.diag([1.0, -1.0, 0.0]), np.zeros((3, 3)), train)
    w = 2 * math.pi * 4.0 / 0.025  # rad/s at 1 m/s
    assert demand.speed[0, 0] == pytest.approx(w)
    # far above the smoothing speed the friction is T_c sign(w) + b w; at rest it is 0
    assert demand.torque[0, 0] == pytest.approx(0.1 + 2e-4 * w, rel=1e-12)
    assert demand.torque[1, 1] == pytest.approx(-(0.1 + 2e-4 * w), rel=1e-12)
    assert demand.torque[2, 2] == 0.0
    geared = motor_demand(np.full((1, 3), 100.0), np.zeros((1, 3)), np.ones((1, 3)), train)
    load = 100.0 * 0.025 / (2 * math.pi * 4.0 * 0.9)
    inertia = (1.2e-4 + train.screw_inertia_value / 16.0) * w
    np.testing.assert_allclose(geared.torque[0], load + inertia, rtol=1e-12)


def test_energy_balance_of_the_transmission() -> None:
    """Over a rest-to-rest move the rotor's kinetic energy comes back to 0, so
    int T w_m dt = int F q' / eta^s dt + int T_f w_m dt, with eta^s by the sign of F q'.
    """
    t, forces, qd, qdd = _move()
    train = DriveTrain(coulomb_torque=0.05, viscous_coefficient=3e-4, gear_ratio=2.0)
    demand = motor_demand(forces, qd, qdd, train)
    slider_power = forces * qd
    load_power = np.where(slider_power >= 0.0, slider_power / 0.9, slider_power * 0.9)
    friction_power = train.friction(demand.speed) * demand.speed
    motor_energy = _integral(demand.power, t)
    expected = _integral(load_power, t) + _integral(friction_power, t)
    scale = _integral(np.abs(demand.power), t)
    assert np.all(np.abs(motor_energy - expected) <= ENERGY_TOL * scale)
    # the inertia's power alone integrates to zero but is not small
    inertia_power = train.reflected_inertia * demand.acceleration * demand.speed
    assert np.max(np.abs(inertia_power)) > 0.05 * np.max(np.abs(demand.power))
    assert np.any(slider_power < 0.0) and np.any(slider_power > 0.0)


def test_drive_from_yaml(tmp_path: Path) -> None:
    path = tmp_path / "motor.yaml"
    path.write_text(
        "drive_train: {lead: 0.02, gear_ratio: 2, rotor_inertia: 3.0e-4}\n"
        "motor:\n  name: BMH0701\n  rated_torque: 1.4\n  peak_torque: 4.2\n"
        "  max_speed: 5000\n  speed_torque_curve: [[0, 4.2], [3000, 3.5], [5000, 2.0]]\n"
    )
    drive = load_drive(path)
    assert drive.train.lead == 0.02 and drive.train.gear_ratio == 2.0
    assert drive.train.efficiency == 0.9  # default kept
    assert drive.motor is not None and drive.motor.name == "BMH0701"
    assert drive.motor.speed_torque_curve == ((0.0, 4.2), (3000.0, 3.5), (5000.0, 2.0))
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    assert load_drive(empty) == Drive()


@pytest.mark.parametrize(
    "text",
    [
        "drive_train: {lead: 0}\n",
        "drive_train: {efficiency: 1.2}\n",
        "drive_train: {pitch: 0.01}\n",
        "gearbox: {}\n",
        "motor: {max_speed: -3000}\n",
        "motor: {speed_torque_curve: [[100, 2.0], [3000, 1.0]]}\n",
        "motor: {speed_torque_curve: [[0, 2.0], [0, 1.0]]}\n",
        "drive_train: [1, 2]\n",
        "motor: {rated_torque: [1\n",
    ],
)
def test_bad_drive_files_are_reported(tmp_path: Path, text: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(og.InvalidParameterError):
        load_drive(path)


@pytest.mark.parametrize(
    "text",
    [
        "motor: {name: m, peak_torque: 4.0}\n",
        "drive_train: {lead: 0.02}\nmotor: {name: m, peak_torque: 4.0}\n",
        "drive_train:\nmotor: {peak_torque: 4.0}\n",
    ],
)
def test_a_motor_without_its_rotor_inertia_is_refused(tmp_path: Path, text: str) -> None:
    """Never completed silently with the assumed rotor inertia of the default drive train."""
    path = tmp_path / "motor.yaml"
    path.write_text(text)
    with pytest.raises(og.InvalidParameterError, match="rotor_inertia") as info:
        load_drive(path)
    assert "drive --example" in str(info.value)
    # with its rotor inertia the same motor is read; a drive train alone needs none
    path.write_text("drive_train: {rotor_inertia: 2.0e-4}\nmotor: {name: m, peak_torque: 4.0}\n")
    drive = load_drive(path)
    assert drive.motor is not None and drive.train.rotor_inertia == 2.0e-4
    path.write_text("drive_train: {lead: 0.02}\n")
    assert load_drive(path).motor is None


def test_bad_values_are_reported() -> None:
    with pytest.raises(og.InvalidParameterError, match="lead"):
        DriveTrain(lead=float("nan"))
    # a lead in mm/rev by mistake: refused with the value meant
    with pytest.raises(og.InvalidParameterError, match=r"did you mean 0\.025\?"):
        DriveTrain(lead=25.0)
    assert DriveTrain(lead=0.005).lead == 0.005  # a fine-pitch screw is plausible
    with pytest.raises(og.InvalidParameterError, match="rated_torque"):
        MotorData(rated_torque=True)  # type: ignore[arg-type]
    with pytest.raises(og.InvalidParameterError):
        load_drive("/nonexistent/motor.yaml")
    with pytest.raises(og.InvalidParameterError):
        motor_demand(np.zeros((2, 3)), np.zeros((3, 3)), np.zeros((2, 3)))
    with pytest.raises(og.InvalidParameterError):
        motor_demand(np.zeros((2, 3)), np.full((2, 3), np.inf), np.zeros((2, 3)))


# ------------------------------------------------------- plausible ranges
#: Values of the drive that gave tracebacks from the arithmetic (overflow, 1/0).
ABSURD = [
    ("gear_ratio", 1e300),
    ("gear_ratio", 1e-300),
    ("screw_diameter", 1e300),
    ("screw_length", 1e300),
    ("rotor_inertia", 1e300),
    ("friction_speed", 1e-300),
    ("efficiency", 1e-300),
]


@pytest.mark.parametrize(("name", "value"), ABSURD)
def test_absurd_drive_values_are_refused_by_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, value: float
) -> None:
    low, high, _ = DRIVE_RANGES[name]
    with pytest.raises(og.InvalidParameterError, match=rf"^invalid {name}=") as info:
        DriveTrain(**{name: value})  # type: ignore[arg-type]
    assert f"[{low:g}, {high:g}]" in str(info.value) and "did you mean" not in str(info.value)
    path = tmp_path / "drive.yaml"
    path.write_text(f"drive_train:\n  {name}: {value!r}\n")
    code, out, err = run(capsys, "report", "--motor", str(path), "--out", str(tmp_path / "r"))
    assert (code, out) == (2, "") and err.count("\n") == 1
    assert err.startswith(f"orthoglide report: error: invalid {name}=")
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize(
    ("name", "value", "meant"),
    [
        ("lead", 25.0, "0.025"),  # mm/rev
        ("screw_diameter", 16.0, "0.016"),  # mm
        ("screw_length", 500.0, "0.5"),  # mm
        ("screw_density", 7.85, "7850"),  # g/cm^3
        ("efficiency", 90.0, "0.9"),  # percent
        ("rotor_inertia", 1.2, "0.00012"),  # kg.cm^2, the data sheets' unit
        ("screw_inertia", 50.0, "0.005"),  # kg.cm^2
        ("coulomb_torque", 200.0, "0.2"),  # mN.m
    ],
)
def test_drive_values_in_the_wrong_unit_get_the_value_meant(
    name: str, value: float, meant: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        DriveTrain(**{name: value})  # type: ignore[arg-type]
    assert f"did you mean {meant}?" in str(info.value)


@pytest.mark.parametrize(
    ("fields", "fragment"),
    [
        ({"max_speed": 3e6}, "invalid max_speed=3000000.0: expected a value in [1, 100000] rpm"),
        ({"peak_torque": 4e5}, "did you mean 400?"),  # mN.m
        ({"rated_torque": 1e-300}, "invalid rated_torque=1e-300"),
        ({"speed_torque_curve": [[0, 4.0], [1e9, 3.0]]}, "speed_torque_curve speed=1000000000.0"),
        ({"speed_torque_curve": [[0, 4e300], [3000, 3.0]]}, "speed_torque_curve torque=4e+300"),
    ],
)
def test_motor_data_have_plausible_ranges(fields: dict[str, object], fragment: str) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        MotorData(**fields)  # type: ignore[arg-type]
    assert fragment in str(info.value)


def test_no_gear_ratio_or_speed_is_guessed() -> None:
    for fields in ({"gear_ratio": 5000.0}, {"gear_ratio": 0.005}):
        with pytest.raises(og.InvalidParameterError) as info:
            DriveTrain(**fields)  # type: ignore[arg-type]
        assert "did you mean" not in str(info.value)
    with pytest.raises(og.InvalidParameterError) as info:
        MotorData(max_speed=0.5)
    assert "did you mean" not in str(info.value)


def test_every_drive_value_has_a_range_that_holds_the_defaults_and_the_example() -> None:
    numeric = {f.name for f in dataclasses.fields(DriveTrain)}
    numeric |= {"rated_torque", "peak_torque", "max_speed"}
    assert set(DRIVE_RANGES) == numeric
    example = load_drive(str(example_drive_file()))
    assert example.motor is not None
    for source in (DriveTrain(), example.train, example.motor):
        for name, value in dataclasses.asdict(source).items():
            if name in DRIVE_RANGES and value is not None:
                low, high, _ = DRIVE_RANGES[name]
                assert low <= value <= high, (name, value)


@pytest.mark.parametrize("end", [0, 1])
def test_the_ends_of_the_ranges_give_finite_motor_demands(end: int) -> None:
    """Every value at its lowest (or highest) plausible value: finite torques and speeds."""
    values = {}
    for name, (low, high, _) in DRIVE_RANGES.items():
        if name in ("rated_torque", "peak_torque", "max_speed"):
            continue
        value = (low, high)[end]
        values[name] = value if value > 0.0 or name in _ZERO_ALLOWED else high
    train = DriveTrain(**values)
    _, forces, qd, qdd = _move(201)
    demand = motor_demand(1e4 * forces, 1e2 * qd, 1e2 * qdd, train)  # far beyond the machine's
    for array in (demand.torque, demand.speed, demand.power):
        assert np.isfinite(array).all()
