"""The report page is self-contained: every image embedded, inline style, no URL out."""

from __future__ import annotations

import base64
import dataclasses
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin.report.assemble import ReportData, assemble_report
from orthoglide_pin.report.figures import figures
from orthoglide_pin.report.files import CSV_FILES, JSON_NAME
from orthoglide_pin.report.html import render_html

EXAMPLE_DRIVE = Path(str(og.example_drive_file()))  # shipped in the package
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
#: A margin shown agrees with required and available to this (same arithmetic).
MARGIN_RTOL = 1e-12


class Collector(HTMLParser):
    """Every tag with its attributes."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))


@pytest.fixture(scope="module")
def data(params: og.OrthoglideParams) -> ReportData:
    return assemble_report(params, og.load_drive(EXAMPLE_DRIVE), resolution=5, cube_resolution=3)


@pytest.fixture(scope="module")
def page(data: ReportData) -> str:
    return render_html(data, figures(data), [JSON_NAME, *CSV_FILES])


def test_page_is_self_contained(page: str) -> None:
    text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "", page)
    assert not re.search(r"(https?:)?//[a-z0-9]|url\(", text, flags=re.IGNORECASE)
    parser = Collector()
    parser.feed(page)
    tags = [t for t, _ in parser.tags]
    assert "script" not in tags and "link" not in tags and "iframe" not in tags
    images = [a["src"] for t, a in parser.tags if t == "img"]
    # force, torque and guarantee maps, cycle, operating points, stiffness and vibration maps
    assert len(images) == 7
    for src in images:
        assert src is not None and src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1]).startswith(PNG_MAGIC)
    assert "<style>" in page


def test_page_content(page: str, data: ReportData) -> None:
    assert "PASS: every motor meets every criterion." in page
    for title in (
        "Verdict",
        "Machine and drive",
        "Assumptions",
        "Worst-case maps",
        "Standard cycle",
    ):
        assert f"<h2>{title}</h2>" in page
    assert "310.0 mm" in page and "257.3 mm" in page  # lengths in mm
    assert f"{data.cube.max_force[2]:.1f} N" in page
    assert "400 W servo motor (illustrative data)" in page
    for line in data.assumptions["method"]:
        assert line.replace(">", "&gt;").replace("<", "&lt;") in page


def test_every_verdict_row_shows_what_is_available(page: str, data: ReportData) -> None:
    curve = [r for r in data.verdict if r.criterion.endswith("speed-torque curve")]
    assert sorted(r.motor for r in curve) == [1, 2, 3]
    for r in data.verdict:
        assert r.available is not None, r.criterion
        assert r.margin == pytest.approx(1.0 - r.required / r.available, rel=MARGIN_RTOL)
        assert f"<td>{r.available:.4g} {r.unit}</td>" in page
    cells = re.findall(r"<td[^>]*>([^<]*)</td>", page)
    assert not {"-", "\u2212", ""} & set(cells)  # no dash, no empty cell for a value


def test_speeds_are_in_mm_per_s(page: str, data: ReportData) -> None:
    assert f"|v| &lt;= {1e3 * data.v_max:.4g} mm/s" in page
    speeds = data.cube.peak("slider_speed")[0]
    assert f"<td>{1e3 * speeds[0]:.1f} mm/s</td>" in page
    other = page.replace("mm/s", "")  # m/s^2 stays: accelerations are in m/s^2
    assert "m/s<" not in other and "m/s " not in other and "m/s)" not in other


def test_page_states_the_safety_factor(data: ReportData, page: str) -> None:
    assert "No safety factor: the required torques are as computed." in page
    safe = dataclasses.replace(data, safety_factor=1.25)
    text = render_html(safe, {}, [JSON_NAME, *CSV_FILES])
    assert "Safety factor 1.25: every required torque below is the computed torque" in text


def test_page_without_motor(data: ReportData) -> None:
    bare = assemble_report(data.params, resolution=3, cube_resolution=2)
    page = render_html(bare, {}, [JSON_NAME, *CSV_FILES])
    assert "No motor data: no verdict on limits" in page
    # how to give motor data, and where the shipped example is
    assert "--motor FILE.yaml" in page and "orthoglide drive --example &gt; drive.yaml" in page
    assert "nothing to guarantee" in page
    assert "<img" not in page  # no figure given, none shown
    assert "<td>no motor datum</td><td>not judged</td><td>no data</td>" in page
