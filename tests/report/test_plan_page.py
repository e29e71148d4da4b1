"""The plan's page: units as on every page, every limit's value, the speed limits drawn."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.drives.motor import RPM_PER_RAD_S, load_drive
from orthoglide_pin.drives.shipped import example_drive_file
from orthoglide_pin.planning import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.sampling import sample_plan
from orthoglide_pin.report import plan_page
from orthoglide_pin.report.plan_page import limit_text, peaks_text, plan_html, slider_speed_limits

pytest.importorskip("toppra")

#: A line at 6000 mm/min then a rapid move.
PROGRAM = "G21 G90 G64 P0.02\nG1 X20 F6000\nG0 X-20 Y10\nM2\n"
DT = 0.002
#: A limit line is drawn at the limit within this [mm/s].
SPEED_TOL = 1e-9


@pytest.fixture(scope="module")
def planned(model: og.ClosedLoopModel) -> tuple[Any, dict[str, Any]]:
    """A plan limited by the motor alone (no slider speed limit), and its samples."""
    dyn = og.ClosedLoopDynamics(model)
    limits = PlanLimits(drive=load_drive(str(example_drive_file())))
    plan = plan_program(read_program(PROGRAM), dyn, limits)
    return plan, sample_plan(plan, dyn, DT)


def test_every_limit_shows_its_value_in_the_display_unit(planned: tuple[Any, Any]) -> None:
    plan, columns = planned
    html = plan_html(plan, columns, "part.nc", ["trajectory.csv", "plan.json"])
    lim = plan.limits
    torque = f"{lim.reference_torque():.4g} N.m"
    speed = f"{lim.motor_speed * RPM_PER_RAD_S:.4g} rpm"
    assert limit_text(plan, "motor_torque") == torque and f"<td>{torque}</td>" in html
    assert limit_text(plan, "motor_speed") == speed and f"<td>{speed}</td>" in html
    assert "<td>F up to 6000 mm/min</td>" in html
    for name in plan.worst:
        assert limit_text(plan, name) != "", name  # no empty value
    assert "rad/s" not in html
    feed = float(np.max(columns["path_speed"]))
    assert f"peak feed {6e4 * feed:.0f} mm/min" in peaks_text(columns) in html


def test_the_slider_speed_plot_draws_the_motor_speed_limit(
    planned: tuple[Any, Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    plan, columns = planned
    limits = slider_speed_limits(plan)
    assert set(limits) == {"motor speed limit"}  # no --max-slider-speed: the motor's
    k = float(plan.limits.drive.train.motor_speed(1.0))
    assert limits["motor speed limit"] == pytest.approx(plan.limits.motor_speed / k)
    drawn: list[Any] = []
    monkeypatch.setattr(plan_page, "_png", lambda fig: drawn.append(fig) or b"")
    plan_page._time_figure(plan, columns)
    ax = drawn[0].axes[0]
    assert ax.get_ylabel() == "slider speed [mm/s]"
    top = 1e3 * limits["motor speed limit"]
    flat = [float(y[0]) for y in (line.get_ydata() for line in ax.lines) if y[0] == y[-1]]
    assert any(abs(y - top) < SPEED_TOL for y in flat)
    assert any(abs(y + top) < SPEED_TOL for y in flat)
    assert "motor speed limit" in ax.get_legend_handles_labels()[1]
    peak = max(np.abs(line.get_ydata()).max() for line in ax.lines[:3])
    assert peak == pytest.approx(1e3 * max(np.abs(columns[f"qd{i}"]).max() for i in (1, 2, 3)))
