"""The accuracy page: self-contained, its figures embedded, its verdict from the margins."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from orthoglide_pin.program.axes import design_axes
from orthoglide_pin.report.accuracy_page import PLOT_POINTS, accuracy_html, plot_rows

FILES = ["accuracy.csv", "accuracy.json"]


def _columns(n: int, margin: float) -> dict[str, np.ndarray]:
    t = np.linspace(0.0, 1.0, n)
    cutting = (t > 0.1) & (t < 0.9)
    cols = {"t": t, "x": 0.02 * np.cos(6 * t), "y": 0.02 * np.sin(6 * t), "z": np.zeros(n)}
    cols["cutting"] = cutting.astype(float)
    cols["line"] = np.where(t < 0.5, 3.0, 4.0)
    for name, scale in (("static", 3e-5), ("generated", 8e-5), ("peak", 1.4e-4)):
        cols[f"surface_error_{name}"] = np.where(cutting, scale * (1 + 0.1 * np.sin(9 * t)), 0.0)
    cols["stability_margin"] = np.where(cutting, np.where(t < 0.5, margin, 2 * margin), np.nan)
    return cols


def _block(line: int, margin: float) -> dict[str, Any]:
    return {"line": line, "point": [0.01, 0.0, 0.0], "feed_angle": 0.0, "depth": 0.002,
            "limit": 0.002 * margin, "margin": margin}  # fmt: skip


def _summary(margin: float | None) -> dict[str, Any]:
    cuts = margin is not None
    at = {"t": 0.3, "point": [0.01, 0.0, 0.0], "line": 3} if cuts else None
    blocks = [_block(3, margin), _block(4, 4 * margin)] if margin is not None else []
    speeds = np.linspace(2000.0, 24000.0, 50)
    return {
        "samples": 400,
        "cutting_samples": 320 if cuts else 0,
        "material": {"name": "aluminium_7075", "source": "s"},
        "spindle_speed_rpm": 12000.0,
        "force_mean_max": 35.0,
        "force_peak_max": 138.8,
        "surface_error_static_max": 3.3e-5,
        "surface_error_generated_max": 8.8e-5,
        "surface_error_peak_max": 1.54e-4,
        "surface_error_at": {"static": at, "generated": at, "peak": at},
        "blocks": [
            {
                "line": b["line"],
                "samples": 160,
                "force_mean": 35.0,
                "force_peak": 138.8,
                "surface_static": 3e-5,
                "surface_generated": 8e-5,
                "surface_peak": 1.4e-4,
            }
            for b in blocks
        ],
        "budget": {
            "max": {"compliance": 4.5e-5, "thermal": 5.4e-6},
            "worst_case_max": 5e-5,
            "rss_max": 4.6e-5,
            "dominant_count": {"compliance": 320, "thermal": 0},
        },
        "stability": {
            "margin_min": margin,
            "cutting_blocks": len(blocks),
            "unstable_blocks": sum(b["margin"] <= 1 for b in blocks),
            "points_per_block": 5,
            "worst": blocks[0] if blocks else None,
            "blocks": blocks,
        },
        "lobes": {
            "speeds_rpm": speeds.tolist(),
            "limit_depth_mm": (0.2 + 0.01 * speeds / 1000).tolist(),
            "zero_order_depth_mm": (0.19 + 0.01 * speeds / 1000).tolist(),
        }
        if cuts
        else None,
    }


def test_page_says_which_lines_chatter() -> None:
    page = accuracy_html(_columns(400, 0.5), _summary(0.5), design_axes(), "p.nc", FILES)
    assert page.count("data:image/png;base64,") == 4
    assert "1 of 2 cutting lines chatter: smallest margin 0.500" in page
    assert "88.00 µm" in page and "(line 3, t = 0.300 s" in page
    assert 'src="http' not in page and "href=" not in page
    assert "Error budget" in page and "compliance" in page and "45.00 µm" in page
    assert '<tr class="fail"><td class="text">3</td>' in page


@pytest.fixture
def no_png(monkeypatch: pytest.MonkeyPatch) -> None:
    """The page without drawing its figures (they are drawn in the first test)."""
    from orthoglide_pin.report import accuracy_page

    monkeypatch.setattr(accuracy_page, "_png", lambda fig: b"png")


@pytest.mark.usefixtures("no_png")
def test_page_of_a_stable_cut() -> None:
    page = accuracy_html(_columns(200, 3.0), _summary(3.0), design_axes(), "p.nc", FILES)
    assert "Every cutting line is stable: smallest margin 3.000" in page
    assert page.count('<tr class="pass">') == 2


@pytest.mark.usefixtures("no_png")
def test_page_of_a_program_that_never_cuts() -> None:
    cols = _columns(100, 1.0)
    cols["cutting"][:] = 0.0
    cols["stability_margin"][:] = np.nan
    page = accuracy_html(cols, _summary(None), design_axes(), "p.nc", FILES)
    assert "Nothing cuts" in page and page.count("data:image/png;base64,") == 3


def test_long_runs_are_plotted_from_few_rows_with_their_extremes() -> None:
    n = 5 * PLOT_POINTS
    cols = _columns(n, 0.5)
    rng = np.random.default_rng(7)
    spike, dip = rng.integers(0, n, 2)
    cols["surface_error_generated"][spike] = 1.0
    cols["stability_margin"][dip] = 1e-3
    rows = plot_rows(cols)
    assert rows.size <= PLOT_POINTS + 1 and spike in rows and dip in rows
    assert rows[0] == 0 and rows[-1] == n - 1
    assert np.array_equal(plot_rows(_columns(50, 1.0)), np.arange(50))
    noisy = {k: rng.normal(size=n) for k in cols}  # every extreme in another row
    assert plot_rows(noisy).size <= PLOT_POINTS + 1
