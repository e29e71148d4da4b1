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
    assert list(images) == [n for n in FIGURES if n not in ("guarantee_maps", "accuracy_lobes")]
    assert bar.made == [("figures", 6)] and bar.done == 6 and bar.closed
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
    assert set(figures(data)) == set(FIGURES) - {"accuracy_lobes"}  # only with a cut file


def test_every_axis_is_labelled_in_words_with_its_unit(
    params: og.OrthoglideParams, monkeypatch: pytest.MonkeyPatch
) -> None:
    drawn: list[object] = []

    def keep(fig: object) -> bytes:
        drawn.append(fig)
        return PNG_MAGIC

    monkeypatch.setattr(report_figures, "_png", keep)
    motor = og.MotorData(name="m", rated_torque=1.0, peak_torque=3.0, max_speed=3000.0)
    data = assemble_report(params, og.Drive(motor=motor), resolution=3, cube_resolution=2)
    figures(data)
    assert len(drawn) >= 5  # force, torque and guarantee maps, cycle, operating points
    labels = []
    for fig in drawn:
        for ax in fig.axes:  # type: ignore[attr-defined]
            labels += [t for t in (ax.get_xlabel(), ax.get_ylabel()) if t]
        for text in (fig._supxlabel, fig._supylabel):  # type: ignore[attr-defined]
            if text is not None:
                labels.append(text.get_text())
    assert "worst-case force of slider 1 [N]" in labels
    assert "worst-case torque of motor 3 [N.m]" in labels
    assert "guaranteed tool speed [mm/s]" in labels
    assert "tool position x [mm]" in labels and "motor speed [rpm]" in labels
    for text in labels:
        # Words and a unit in brackets: no column names, no symbols such as |F|.
        assert text.endswith("]") and "_" not in text and "|" not in text, text
        assert len(text.split(" [")[0]) >= 4, text  # a word, not a symbol
