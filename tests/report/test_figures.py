"""The report's figures: PNG images of the maps, the cycle and the operating points."""

from __future__ import annotations

import io

import pytest
from matplotlib.image import imread

import orthoglide_pin as og
from orthoglide_pin.report import figures as report_figures
from orthoglide_pin.report.assemble import assemble_report
from orthoglide_pin.report.figures import FIGURES, figures

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class Counter:
    """A progress bar that counts."""

    def __init__(self) -> None:
        self.made: list[tuple[str, int]] = []
        self.done = 0
        self.closed = False

    def __call__(self, description: str, total: int) -> Counter:
        self.made.append((description, total))
        return self

    def update(self, n: int = 1) -> None:
        self.done += n

    def close(self) -> None:
        self.closed = True


def test_figures_without_motor(params: og.OrthoglideParams) -> None:
    data = assemble_report(params, resolution=4, cube_resolution=2)
    bar = Counter()
    images = figures(data, progress=bar)
    assert list(images) == [n for n in FIGURES if n != "guarantee_maps"]
    assert bar.made == [("figures", 5)] and bar.done == 5 and bar.closed
    for name, png in images.items():
        assert png.startswith(PNG_MAGIC), name
        assert b"matplotlib.org" not in png  # no software metadata with a URL
        pixels = imread(io.BytesIO(png))
        assert pixels.shape[0] > 300 and pixels.shape[1] > 500
        assert pixels[..., :3].std() > 0.05  # not a blank canvas


def test_guarantee_maps_need_a_motor_datum(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    for name in ("_maps", "_cycle", "_operating_points"):  # what is drawn, not how
        monkeypatch.setattr(report_figures, name, lambda *_, **__: PNG_MAGIC)
    rated_only = og.Drive(motor=og.MotorData(rated_torque=1.0))
    data = assemble_report(params, rated_only, resolution=3, cube_resolution=2)
    assert "guarantee_maps" not in figures(data)
    speed_only = og.Drive(motor=og.MotorData(max_speed=4000.0))
    data = assemble_report(params, speed_only, resolution=3, cube_resolution=2)
    assert set(figures(data)) == set(FIGURES)
