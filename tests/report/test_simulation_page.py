"""The simulation page: self-contained, its figures embedded, its numbers from the summary."""

from __future__ import annotations

import numpy as np

from orthoglide_pin.report.simulation_page import simulation_html


def _columns(n: int, saturated: bool) -> dict[str, np.ndarray]:
    t = np.linspace(0.0, 1.0, n)
    cols = {"t": t, "x": 0.01 * t, "y": 0.005 * t, "z": np.zeros(n), "path_speed": np.ones(n)}
    for i in (1, 2, 3):
        cols[f"e{i}"] = 1e-7 * np.sin(10 * t)
        cols[f"tau{i}"] = np.sin(t)
        cols[f"tau_available{i}"] = np.full(n, 3.8 if i < 3 else -1.0)
        cols[f"saturated{i}"] = np.where((t > 0.5) & saturated, 1.0, 0.0)
    cols["contour_error"] = 1e-7 * np.abs(np.cos(3 * t))
    cols["line"] = np.where(t < 0.8, 2.0, 3.0)
    cols["rapid"] = np.where(t < 0.8, 0.0, 1.0)
    return cols


def _summary(saturation: float) -> dict[str, object]:
    return {
        "max_contour_error": 1e-7,
        "rms_contour_error": 5e-8,
        "max_contour_error_at": {"t": 0.1, "x": 0.001, "y": 0.0005, "z": 0.0, "line": 2},
        "max_rapid_deviation": 2e-7,
        "max_tracking_error": [1e-7] * 3,
        "rms_tracking_error": [5e-8] * 3,
        "saturation_time": saturation,
        "saturation_time_per_slider": [saturation, 0.0, 0.0],
        "peak_torque": [1.0, 1.0, 1.0],
        "controller": "pid_ff",
        "rate": 4000.0,
        "timestep": 2.5e-4,
        "encoder_counts": None,
        "mass_error": 0.0,
        "friction_error": 0.0,
        "motor": "m",
        "plan_motor": "m",
        "duration": 1.0,
    }


def test_page_is_self_contained_and_says_when_motors_saturate() -> None:
    calm = simulation_html(_columns(400, False), _summary(0.0), "p.nc", ["simulation.csv"])
    assert calm.count("data:image/png;base64,") == 3
    assert "No motor saturates" in calm and "0.100 µm" in calm and "line 2" in calm
    assert 'src="http' not in calm and "href=" not in calm
    hot = simulation_html(_columns(400, True), _summary(0.5), "p.nc", ["simulation.csv"])
    assert "The motors saturate" in hot and "0.5000 s" in hot


def test_page_gives_the_tool_wrench() -> None:
    none = simulation_html(_columns(50, False), _summary(0.0), "p.nc", ["simulation.csv"])
    assert "tool wrench [N, N.m]</td><td>none" in none.replace("\n", "")
    pushed = {**_summary(0.0), "wrench": [30.0, -20.0, 15.0, 1.0, 0.0, -0.5]}
    page = simulation_html(_columns(50, False), pushed, "p.nc", ["simulation.csv"])
    assert "30 -20 15 1 0 -0.5" in page
