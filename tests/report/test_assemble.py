"""Assembly of the torque-requirement report: its numbers and its verdict."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG

import orthoglide_pin as og
from orthoglide_pin.elasticity.mass import reflected_mass
from orthoglide_pin.report.assemble import ReportData, VerdictRow, assemble_report
from orthoglide_pin.report.vibration import CRITERION

EXAMPLE_DRIVE = Path(str(og.example_drive_file()))  # shipped in the package
#: Coarse grids keep these tests fast; the cube grid keeps its corners.
RESOLUTION, CUBE_RESOLUTION = 5, 3
#: Same computation through different calls (rounding).
EXACT_RTOL = 1e-9
#: Lead of the default drive [m/rev].
LEAD = 0.025


@pytest.fixture(scope="module")
def with_motor(params: og.OrthoglideParams) -> ReportData:
    return assemble_report(
        params,
        og.load_drive(EXAMPLE_DRIVE),
        resolution=RESOLUTION,
        cube_resolution=CUBE_RESOLUTION,
    )


@pytest.fixture(scope="module")
def without_motor(params: og.OrthoglideParams) -> ReportData:
    return assemble_report(params, resolution=RESOLUTION, cube_resolution=CUBE_RESOLUTION)


def far_corner_rpm(leg: float = PROTOTYPE_LEG) -> float:
    """Largest motor speed over the cube: slider speed ``v L / eta`` at a far corner."""
    far = CUBE_CORNER + CUBE_SIDE
    return 1.2 * leg / math.sqrt(leg**2 - 2 * far**2) / LEAD * 60.0


def test_example_drive_file(with_motor: ReportData) -> None:
    drive = og.load_drive(EXAMPLE_DRIVE)
    assert drive.motor is not None
    assert drive.train.lead == LEAD and drive.train.efficiency == 0.9
    assert drive.motor.peak_torque == 3.8 and drive.motor.max_speed == 5000.0
    # the illustrative motor is enough for the prototype, with margins on every criterion
    assert with_motor.passed is True
    assert all(r.margin is not None and r.margin > 0.2 for r in with_motor.verdict)


def test_cube_slices_and_cycle_of_the_prototype(with_motor: ReportData) -> None:
    d = with_motor
    np.testing.assert_allclose(d.corner, CUBE_CORNER)
    assert d.side == pytest.approx(CUBE_SIDE)
    assert len(d.cube) == CUBE_RESOLUTION**3
    levels = [s.value for s in d.slices]
    np.testing.assert_allclose(levels, CUBE_CORNER + CUBE_SIDE * np.array([0.0, 0.5, 1.0]))
    for s in d.slices:
        assert len(s.worst) == RESOLUTION**2
        np.testing.assert_allclose(s.worst.points[:, 2], s.value)
        assert s.worst.points[:, :2].min() == pytest.approx(CUBE_CORNER)
        assert s.worst.points[:, :2].max() == pytest.approx(CUBE_CORNER + CUBE_SIDE)
    # the cycle runs at the specification and its forces are the dynamics'
    assert d.cycle.speed.max() == pytest.approx(1.2)
    ref = og.ClosedLoopDynamics().inverse_dynamics(
        d.cycle.p[::500], d.cycle.v[::500], d.cycle.a[::500]
    )
    np.testing.assert_allclose(
        d.cycle_dynamics.forces[::500], ref.forces, rtol=EXACT_RTOL, atol=1e-9
    )
    assert d.sizing.statistics.peak_speed_rpm == pytest.approx(1.2 / LEAD * 60.0)


def test_worst_motions_are_checked_by_direct_dynamics(with_motor: ReportData) -> None:
    dyn = og.ClosedLoopDynamics()
    for i, motion in enumerate(with_motor.worst_motions):
        np.testing.assert_array_equal(motion["point"], with_motor.cube.max_force_at[i])
        assert np.linalg.norm(motion["velocity"]) <= 1.2 * (1 + 1e-12)
        assert np.linalg.norm(motion["acceleration"]) == pytest.approx(20.0)
        force = dyn.inverse_dynamics(motion["point"], motion["velocity"], motion["acceleration"])
        assert abs(force.forces[0, i]) == pytest.approx(
            with_motor.cube.max_force[i], rel=EXACT_RTOL
        )
        assert motion["force"] == pytest.approx(force.forces[0, i], rel=EXACT_RTOL)


def test_verdict_rows(with_motor: ReportData) -> None:
    drive, rows = with_motor.drive, with_motor.verdict
    assert drive.motor is not None
    assert len(rows) == 3 * 6
    check = with_motor.sizing.check
    assert check is not None
    for r in rows:
        if r.criterion.startswith("cycle") and "curve" not in r.criterion:
            assert r.available is not None
            assert r.margin == pytest.approx(1.0 - r.required / r.available, rel=EXACT_RTOL)
        if r.criterion == "cycle: RMS torque vs rated torque":
            assert r.margin == check.margins["rms_torque"][r.motor - 1]
        if r.criterion == "worst case: speed vs maximum speed":
            assert r.required == pytest.approx(far_corner_rpm(), rel=EXACT_RTOL)
            assert r.available == 5000.0
        if r.criterion == "worst case: torque vs torque available":
            # at the corner speed the curve (3.8 N.m to 3000 rpm, 2.5 at 5000) is falling
            expected = 3.8 - (far_corner_rpm() - 3000.0) / 2000.0 * 1.3
            assert r.available == pytest.approx(expected, rel=EXACT_RTOL)
            assert r.required <= with_motor.cube.max_torque[r.motor - 1]


def test_without_motor_no_verdict(without_motor: ReportData, with_motor: ReportData) -> None:
    assert without_motor.passed is None and not without_motor.motor_given
    assert all(r.margin is None and r.passed is None for r in without_motor.verdict)
    assert len(without_motor.verdict) == 3 * 5
    required = {(r.motor, r.criterion): r.required for r in without_motor.verdict}
    speed = required[(1, "worst case: speed vs maximum speed")]
    assert speed == pytest.approx(far_corner_rpm(), rel=EXACT_RTOL)
    g = without_motor.cube.guarantees
    assert g.speed is None and g.acceleration_at_rest is None
    # the forces do not depend on the motor data
    np.testing.assert_array_equal(without_motor.cube.force, with_motor.cube.force)


def test_the_vibration_row_judges_without_motor_data(
    without_motor: ReportData, with_motor: ReportData
) -> None:
    plain, driven = without_motor.vibration, with_motor.vibration
    assert plain is not None and driven is not None and plain.min_frequency is None
    # no drive given: the carriages alone; the motor file's drive: its reflected inertia
    assert plain.worst.drive_mass == 0.0
    assert driven.worst.drive_mass == pytest.approx(reflected_mass(with_motor.drive))
    assert driven.lowest_frequency < plain.lowest_frequency
    row = VerdictRow(None, CRITERION, 50.0, 100.0, "Hz", 0.5)
    assert replace(without_motor, verdict=(*without_motor.verdict, row)).passed is True
    failed = replace(row, margin=-0.1)
    assert replace(without_motor, verdict=(*without_motor.verdict, failed)).passed is False
    assert replace(with_motor, verdict=(*with_motor.verdict, failed)).passed is False


def test_safety_factor_multiplies_the_required_torques(
    params: og.OrthoglideParams, with_motor: ReportData
) -> None:
    k = 1.5
    safe = assemble_report(
        params,
        with_motor.drive,
        resolution=RESOLUTION,
        cube_resolution=CUBE_RESOLUTION,
        safety_factor=k,
    )
    assert safe.safety_factor == k and with_motor.safety_factor == 1.0
    assert len(safe.verdict) == len(with_motor.verdict)
    least = math.inf  # the factor that uses up the least torque margin
    for plain, row in zip(with_motor.verdict, safe.verdict, strict=True):
        assert (plain.motor, plain.criterion) == (row.motor, row.criterion)
        assert plain.margin is not None and row.margin is not None
        if row.unit == "N.m":  # k times the torque, the same torque available
            assert row.required == pytest.approx(k * plain.required, rel=EXACT_RTOL)
            assert 1.0 - row.margin == pytest.approx(k * (1.0 - plain.margin), rel=EXACT_RTOL)
            least = min(least, 1.0 / (1.0 - plain.margin))
        else:  # speeds are not multiplied
            assert (row.required, row.margin) == (plain.required, plain.margin)
    # the figures themselves are as computed
    np.testing.assert_array_equal(safe.cube.torque, with_motor.cube.torque)
    np.testing.assert_array_equal(safe.sizing.statistics.peak_torque,
                                  with_motor.sizing.statistics.peak_torque)  # fmt: skip
    assert safe.passed is True and 1.5 < least < 2.5
    grid = {"resolution": 2, "cube_resolution": CUBE_RESOLUTION}
    verdicts = [
        assemble_report(params, with_motor.drive, safety_factor=f * least, **grid).passed
        for f in (0.999, 1.001)
    ]
    assert verdicts == [True, False]
    with pytest.raises(og.InvalidParameterError, match="safety_factor"):
        assemble_report(params, with_motor.drive, safety_factor=0.8, **grid)


def test_failing_motor_and_gravity(params: og.OrthoglideParams) -> None:
    weak = og.Drive(motor=og.MotorData(name="weak", peak_torque=1.0, max_speed=3000.0))
    d = assemble_report(params, weak, resolution=3, cube_resolution=2, gravity=(0.0, 0.0, 0.0))
    assert d.passed is False
    speed = [r for r in d.verdict if r.criterion == "worst case: speed vs maximum speed"]
    assert [r.margin for r in speed] == pytest.approx([1.0 - far_corner_rpm() / 3000.0] * 3)
    assert any("Gravity (0, 0, 0)" in line for line in d.assumptions["inertia"])
    # without gravity the vertical slider holds nothing at rest
    assert d.cycle_dynamics.forces[0, 2] == pytest.approx(0.0, abs=1e-9)


def test_bad_settings(params: og.OrthoglideParams) -> None:
    for kwargs in (
        {"resolution": 1},
        {"cube_resolution": 0},
        {"resolution": 2.5},
        {"v_max": -1.0},
        {"a_max": math.nan},
        {"gravity": (0.0, math.inf, 0.0)},
    ):
        with pytest.raises(og.InvalidParameterError):
            assemble_report(params, **kwargs)  # type: ignore[arg-type]


def test_the_program_bar_follows_the_plans_progress() -> None:
    from orthoglide_pin.report.assemble import _plan_progress

    made: list[tuple[str, int]] = []
    steps: list[int] = []

    class FakeBar:
        def update(self, n: int = 1) -> None:
            steps.append(n)

        def close(self) -> None:
            steps.append(-1)

    def factory(description: str, total: int) -> FakeBar:
        made.append((description, total))
        return FakeBar()

    update, close = _plan_progress(factory)
    assert update is not None
    for done in (3, 7, 10):
        update(done, 10)
    close()
    assert made == [("program", 10)] and steps == [3, 4, 3, -1]
    assert _plan_progress(None)[0] is None
