"""The HTML kit of the package's pages: escaped text, tables, embedded images."""

from __future__ import annotations

import base64

from orthoglide_pin.report import page


def test_table_escapes_and_classes_rows() -> None:
    out = page.table(["name", "value"], [["<b>", 1.5], ["x", "&"]], classes=["fail", ""])
    assert '<td class="text">&lt;b&gt;</td><td>1.5</td>' in out
    assert '<tr class="fail">' in out and out.count("<tr") == 3
    assert "&amp;" in out


def test_image_embeds_the_bytes_or_nothing() -> None:
    data = b"\x89PNG fake"
    out = page.image({"a": data}, "a", 'alt "text"')
    assert base64.b64encode(data).decode() in out and "&quot;" in out
    assert page.image({}, "a", "x") == ""


def test_page_is_self_contained() -> None:
    html = page.page("T <1>", "sub", [("S & S", "<p>x</p>")])
    assert html.startswith("<!DOCTYPE html>") and "<title>T &lt;1&gt;</title>" in html
    assert "<h2>S &amp; S</h2><p>x</p>" in html
    assert "http" not in html and "<link" not in html


def test_png_is_reproducible() -> None:
    def draw() -> bytes:
        fig = page.figure(2.0, 1.5)
        fig.add_subplot().plot([0, 1], [1, 0])
        return page.png(fig)

    first = draw()
    assert first.startswith(b"\x89PNG") and first == draw()
