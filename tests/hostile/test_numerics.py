"""Extreme numbers: refused by range before use, never NaN or inf out, sizes capped first."""

from __future__ import annotations

import re
import tracemalloc
import warnings

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin._validation import (
    MAX_ACCELERATION,
    MAX_GRAVITY,
    MAX_SPEED,
    MAX_WRENCH,
)
from orthoglide_pin.drives.motor import motor_demand
from orthoglide_pin.dynamics.requirements import worst_case_requirements
from orthoglide_pin.exceptions import DescriptionError, InvalidParameterError
from orthoglide_pin.kinetostatics.design import MAX_VERIFY_POINTS, design_from_workspace
from orthoglide_pin.kinetostatics.workspace import MAX_GRID_POINTS, cube_grid, slice_grid
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.description import render_urdf
from orthoglide_pin.motion.profiles import MotionLimits, s_curve_profile, trapezoidal_profile
from tests.conftest import run

#: Most memory a refused size may cost before its refusal [bytes].
REFUSAL_MEMORY = 1_000_000
#: A point of the prototype's cube [m].
POINT = np.array([0.02, -0.01, 0.03])


def _peak_memory_of_refusal(call: object, *args: object) -> tuple[int, InvalidParameterError]:
    tracemalloc.start()
    try:
        with pytest.raises(InvalidParameterError) as info:
            call(*args)  # type: ignore[operator]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, info.value


# ------------------------------------------------------------------- sizes
@pytest.mark.parametrize("n", [369, 10**9, 2**62])
def test_cube_grids_are_refused_before_allocation(n: int) -> None:
    peak, error = _peak_memory_of_refusal(cube_grid, [0.0, 0.0, 0.0], 0.1, n)
    assert peak < REFUSAL_MEMORY and "at most 368 points per axis" in str(error)
    assert error.value == n


def test_the_largest_cube_grid_is_accepted() -> None:
    assert 368**3 <= MAX_GRID_POINTS < 369**3
    assert slice_grid("z", 0.0, (0.0, 0.0), (0.1, 0.1), 7071).size <= MAX_GRID_POINTS


@pytest.mark.parametrize("n", [7072, 10**9])
def test_slice_grids_are_refused_before_allocation(n: int) -> None:
    peak, error = _peak_memory_of_refusal(slice_grid, "z", 0.0, (0.0, 0.0), (0.1, 0.1), n)
    assert peak < REFUSAL_MEMORY and "at most 7071 points per axis" in str(error)


def test_the_design_verification_grid_is_capped() -> None:
    peak, error = _peak_memory_of_refusal(
        lambda: design_from_workspace(0.2, 0.5, 2.0, grid_points=10**9)
    )
    assert peak < REFUSAL_MEMORY and f"[2, {MAX_VERIFY_POINTS}]" in str(error)
    assert design_from_workspace(0.2, 0.5, 2.0, grid_points=3).grid_points == 3


def test_the_cli_grid_of_a_billion_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(
        capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "1000000000"
    )
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "grid" in err and "201" in err


# ---------------------------------------------------------- input ranges
@pytest.mark.parametrize(
    ("name", "bad", "limit"),
    [("v_max", 1e300, MAX_SPEED), ("a_max", 1e300, MAX_ACCELERATION), ("v_max", 1001.0, 0)],
)
def test_motion_limits_are_bounded(name: str, bad: float, limit: float) -> None:
    kwargs = {"v_max": 1.2, "a_max": 20.0, name: bad}
    with pytest.raises(InvalidParameterError) as info:
        MotionLimits(**kwargs)
    assert info.value.name == name and info.value.value == bad
    with pytest.raises(InvalidParameterError, match=name):
        trapezoidal_profile(0.1, kwargs["v_max"], kwargs["a_max"])
    with pytest.raises(InvalidParameterError, match="jerk"):
        s_curve_profile(0.1, 1.2, 20.0, 1e300)


def test_the_largest_motion_limits_still_give_finite_laws() -> None:
    law = s_curve_profile(1.0, MAX_SPEED, MAX_ACCELERATION, 1e9)
    sample = law.sample(np.linspace(0.0, law.duration, 101))
    for values in sample:
        assert np.isfinite(values).all()
    assert sample.s[-1] == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"p_dot": [1e300, 0.0, 0.0]}, "p_dot"),
        ({"p_dot": [0.0, -1001.0, 0.0]}, "p_dot"),
        ({"p_ddot": [0.0, 0.0, 1e300]}, "p_ddot"),
        ({"gravity": [0.0, 0.0, -1e300]}, "gravity"),
        ({"gravity": [0.0, 0.0, -1001.0]}, "gravity"),
        ({"wrench": [1e308, 1e308, 0.0]}, "wrench"),
        ({"wrench": [0.0, 0.0, 0.0, 0.0, 0.0, -2e9]}, "wrench"),
    ],
)
def test_dynamics_inputs_are_bounded_and_named(
    dyn: og.ClosedLoopDynamics, kwargs: dict[str, list[float]], name: str
) -> None:
    args = {"p_dot": np.zeros(3), "p_ddot": np.zeros(3)}
    extra = {k: v for k, v in kwargs.items() if k not in args}
    args.update({k: np.array(v) for k, v in kwargs.items() if k in args})
    with pytest.raises(InvalidParameterError) as info:
        dyn.inverse_dynamics(POINT, args["p_dot"], args["p_ddot"], **extra)  # type: ignore[arg-type]
    assert info.value.name == name
    assert "forces" not in str(info.value)


def test_dynamics_at_the_limits_are_finite(dyn: og.ClosedLoopDynamics) -> None:
    res = dyn.inverse_dynamics(
        POINT,
        [MAX_SPEED, 0.0, 0.0],
        [0.0, MAX_ACCELERATION, 0.0],
        wrench=[MAX_WRENCH] * 3,
        gravity=[0.0, 0.0, -MAX_GRAVITY],
    )
    assert np.isfinite(res.forces).all() and np.abs(res.forces).max() > MAX_WRENCH


def test_worst_case_speeds_are_bounded() -> None:
    for name in ("v_max", "a_max"):
        with pytest.raises(InvalidParameterError) as info:
            worst_case_requirements(None, POINT, **{name: 1e300})  # type: ignore[arg-type]
        assert info.value.name == name


@pytest.mark.parametrize(
    "argv",
    [
        ["dynamics", "--point", "0", "0", "0", "--velocity", "1e300", "0", "0"],
        ["dynamics", "--point", "0", "0", "0", "--gravity", "1e300", "0", "0"],
        ["report", "--v-max", "1e300", "--quiet"],
        ["report", "--a-max", "1e300", "--quiet"],
    ],
)
def test_cli_overflows_are_one_line_naming_the_value(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "1e+300" in err and "forces" not in err and "Warning" not in err


def test_motor_demand_names_the_bad_array_and_value() -> None:
    zeros = np.zeros((4, 3))
    forces = zeros.copy()
    forces[2, 1] = np.inf
    with pytest.raises(InvalidParameterError) as info:
        motor_demand(forces, zeros, zeros)
    assert info.value.name == "forces" and info.value.value == np.inf
    with pytest.raises(InvalidParameterError) as info:
        motor_demand(zeros, zeros, np.zeros((4, 2)))
    assert info.value.name == "slider_accelerations.shape"


# ------------------------------------------------------- dropped inertials
def _with_mass(urdf: str, link: str, value: str) -> str:
    pattern = rf'(<link name="{link}">.*?<mass value=")[^"]*(")'
    out, count = re.subn(pattern, rf"\g<1>{value}\g<2>", urdf, count=1, flags=re.S)
    assert count == 1
    return out


@pytest.mark.parametrize("value", ["inf", "1e999", "nan", "-1"])
def test_a_mass_the_parser_would_drop_is_refused(value: str) -> None:
    urdf = _with_mass(render_urdf(og.prototype()), "leg2_carriage", value)
    with pytest.raises(DescriptionError) as info:
        ClosedLoopModel(urdf=urdf)
    assert "leg2_carriage" in str(info.value) and value in str(info.value)


def test_an_inertia_the_parser_drops_is_refused(capfd: pytest.CaptureFixture[str]) -> None:
    urdf = render_urdf(og.prototype()).replace('ixx="', 'ixx="x', 1)
    with pytest.raises(DescriptionError, match=r"dropped part of the URDF.*not a valid double"):
        ClosedLoopModel(urdf=urdf)
    assert capfd.readouterr().err == ""  # the parser's own lines do not reach the terminal


def test_a_valid_model_carries_the_urdf_masses(model: og.ClosedLoopModel) -> None:
    masses = [float(m) for m in re.findall(r'<mass value="([^"]+)"', model.urdf)]
    loaded = sum(inertia.mass for inertia in model.model.inertias)
    assert loaded == pytest.approx(sum(masses), rel=1e-12) and loaded > 1.0


def test_density_beyond_any_material_is_refused_with_its_name(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, err = run(capsys, "summary", "--param", "density=1e308", "--json")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "density" in err and "Could not parse" not in err


# ----------------------------------------------------- viewer and design caps
def test_viewer_grids_and_ellipsoids_are_capped_before_drawing(
    model: og.ClosedLoopModel,
) -> None:
    from orthoglide_pin.viewer import Viewer
    from orthoglide_pin.viewer.overlays import MAX_ELLIPSOIDS, MAX_GRID_EDGE, ellipsoids

    viewer = Viewer(model)
    for n in (MAX_GRID_EDGE + 1, 10**9, 2.5, True):
        with pytest.raises(InvalidParameterError) as info:
            viewer.grid_points(n)  # type: ignore[arg-type]
        assert info.value.name == "n" and f"[2, {MAX_GRID_EDGE}]" in str(info.value)
    assert viewer.grid_points(2).shape == (8, 3)
    many = np.zeros((MAX_ELLIPSOIDS + 1, 3))
    with pytest.raises(InvalidParameterError, match=f"at most {MAX_ELLIPSOIDS} points"):
        ellipsoids(many, 0.31)


@pytest.mark.parametrize(("psi_min", "psi_max"), [(0.5, 1e300), (1e-300, 2.0), (1e-9, 2.0)])
def test_design_bounds_beyond_the_condition_limit_are_refused(
    psi_min: float, psi_max: float
) -> None:
    with pytest.raises(InvalidParameterError) as info:
        design_from_workspace(0.2, psi_min, psi_max, grid_points=3)
    assert info.value.name == "psi_max / psi_min" and "1e+06" in str(info.value)
    design = design_from_workspace(0.2, 0.001, 999.0, grid_points=5)  # just within
    assert np.isfinite(design.psi_max_found) and design.leg_length > 0.0


@pytest.mark.parametrize(("name", "value"), [("speed", 1e300), ("acceleration", 1e300)])
def test_sweep_requirements_are_bounded_before_any_worker_starts(name: str, value: float) -> None:
    from orthoglide_pin.sweep.spec import SweepSpec

    with pytest.raises(InvalidParameterError) as info:
        SweepSpec(**{name: value})  # type: ignore[arg-type]
    assert info.value.name == name and info.value.value == value
    assert SweepSpec(speed=MAX_SPEED, acceleration=MAX_ACCELERATION).speed == MAX_SPEED


def test_trajectory_samples_are_capped_before_allocation() -> None:
    from orthoglide_pin.motion.segments import line_move
    from orthoglide_pin.motion.trajectory import MAX_SAMPLES, build_trajectory

    limits = MotionLimits(1.2, 20.0)
    there, back = (
        line_move([0, 0, 0], [0.1, 0, 0], limits),
        line_move([0.1, 0, 0], [0, 0, 0], limits),
    )
    for kwargs, name in (
        ({"dt": 1e-300}, "dt"),
        ({"dt": 5e-324}, "dt"),  # subnormal: the number of samples is infinite
        ({"dwell_time": 1e300}, "dwell_time"),
        ({"dwell_time": 1e5}, "dwell_time"),
    ):
        peak, error = _peak_memory_of_refusal(
            lambda kw=kwargs: build_trajectory([there, back], **kw)
        )
        assert error.name == name and peak < REFUSAL_MEMORY
        assert f"at most {MAX_SAMPLES} samples" in str(error)
    assert len(build_trajectory([there, back], dt=1e-3, dwell_time=0.5).t) > 500


def test_forward_dynamics_forces_are_bounded(dyn: og.ClosedLoopDynamics) -> None:
    from orthoglide_pin.dynamics.forward import ForwardDynamics

    fwd = ForwardDynamics(dyn)
    q = dyn.closed_loop.configuration(POINT)[np.newaxis]
    v = np.zeros_like(q)
    with pytest.raises(InvalidParameterError) as info:
        fwd.accelerations(q, v, [[1e300, 0.0, 0.0]])
    assert info.value.name == "forces" and info.value.value == 1e300
    assert np.isfinite(fwd.accelerations(q, v, [[MAX_WRENCH, 0.0, 0.0]])).all()


@pytest.mark.parametrize("side", [1e300, 1e-300, 1e-3])
def test_design_sides_giving_implausible_legs_are_refused(side: float) -> None:
    with pytest.raises(InvalidParameterError) as info:
        design_from_workspace(side, 0.5, 2.0, grid_points=3)
    assert info.value.name == "side" and info.value.value == side
    assert "plausible leg length" in str(info.value)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: og.inverse_kinematics([0.1, 0.0, 0.0], 1e300), "leg_length"),
        (lambda: og.direct_kinematics([0.0, 0.0, 0.0], 1e-300), "leg_length"),
        (lambda: og.direct_kinematics([-1e300, -1e300, -1e300], 0.31), "q"),
        (lambda: og.transmission_factors([0.1, 0.1, 0.0], 1e200), "leg_length"),
        (lambda: og.ik_and_jacobian([1e199, 0.0, 0.0], 0.31), "points"),
        (lambda: og.slider_range_over_cube(0.31, [0.0, 0.0, 0.0], 1e300), "side"),
        (lambda: og.leg_motion([[0, 0, 0]], [[1e300, 0, 0]], [[0, 0, 0]], 0.31), "velocities"),
        (
            lambda: og.tool_motion_from_sliders([[0, 0, 0]], [[0, 0, 0]], [[0, 1e300, 0]], 0.31),
            "q_ddot",
        ),
    ],
)
def test_kinematic_lengths_and_coordinates_are_bounded(call: object, name: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warning before the refusal
        with pytest.raises(InvalidParameterError) as info:
            call()  # type: ignore[operator]
    assert info.value.name == name


def test_the_extreme_accepted_lengths_give_finite_results() -> None:
    from orthoglide_pin._validation import MAX_LENGTH, MIN_LENGTH

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for L in (MIN_LENGTH, MAX_LENGTH):
            point = np.array([0.1, -0.2, 0.05]) * L
            q = og.inverse_kinematics(point, L)
            np.testing.assert_allclose(og.direct_kinematics(q, L), point, rtol=1e-9, atol=1e-9 * L)
            assert np.isfinite(og.transmission_factors(point, L)).all()
