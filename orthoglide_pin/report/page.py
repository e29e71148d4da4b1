"""The kit of the package's self-contained HTML pages: style, tables, images.

Every page the package writes (the torque-requirement report, the calibration
page) is one file: the figures are PNG bytes embedded as base64 ``data:``
URIs, the style is inline and nothing refers outside the page, so it can be
moved, mailed or archived alone. :func:`page` assembles one from its sections;
:func:`figure` and :func:`png` draw the figures with matplotlib's Agg canvas
(no display, pyplot's global state untouched).
"""

from __future__ import annotations

import base64
import html
import io
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, Final

from orthoglide_pin.kinetostatics.plotting import new_figure

#: Resolution of the embedded figures [dots per inch].
DPI: Final = 90
#: The pages' style sheet (inline).
STYLE: Final = """
body { font-family: sans-serif; max-width: 1150px; margin: 2em auto; color: #222; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; }
table { border-collapse: collapse; margin: .8em 0; font-size: .92em; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: right; }
th { background: #f2f2f2; } td.text, th.text { text-align: left; }
.pass { background: #d8f0d8; } .fail { background: #f6d0d0; } .none { background: #eee; }
.banner { padding: .6em 1em; font-size: 1.15em; font-weight: bold; display: inline-block; }
img { max-width: 100%; } .note { color: #555; font-size: .92em; }
"""


def escape(text: object) -> str:
    """``text`` as HTML text."""
    return html.escape(str(text))


def table(
    header: Sequence[str], rows: Iterable[Sequence[object]], classes: Sequence[str] = ()
) -> str:
    """A table; the first column is text. ``classes`` gives a CSS class per row."""
    head = "".join(
        f'<th class="text">{escape(h)}</th>' if k == 0 else f"<th>{escape(h)}</th>"
        for k, h in enumerate(header)
    )
    body = []
    for k, row in enumerate(rows):
        cls = f' class="{classes[k]}"' if k < len(classes) and classes[k] else ""
        cells = "".join(
            f'<td class="text">{escape(c)}</td>' if j == 0 else f"<td>{escape(c)}</td>"
            for j, c in enumerate(row)
        )
        body.append(f"<tr{cls}>{cells}</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def image(images: Mapping[str, bytes], name: str, alt: str) -> str:
    """The PNG ``images[name]`` embedded in a paragraph ("" when absent)."""
    if name not in images:
        return ""
    data = base64.b64encode(images[name]).decode("ascii")
    return f'<p><img alt="{escape(alt)}" src="data:image/png;base64,{data}"></p>'


def page(title: str, subtitle: str, sections: Sequence[tuple[str, str]]) -> str:
    """A whole page: ``sections`` are ``(heading, HTML content)`` pairs.

    Args:
        title: The page's title and first heading (text).
        subtitle: A paragraph under the title (HTML).
        sections: The sections in order.
    """
    body = "".join(f"<h2>{escape(heading)}</h2>{content}" for heading, content in sections)
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{escape(title)}</title>"
        f"<style>{STYLE}</style></head><body>"
        f"<h1>{escape(title)}</h1><p>{subtitle}</p>{body}</body></html>\n"
    )


def figure(width: float, height: float) -> Any:
    """A new matplotlib figure of ``width`` x ``height`` inches, constrained layout."""
    return new_figure(width, height, layout="constrained")


def png(fig: Any) -> bytes:
    """The figure as PNG bytes (no metadata that changes from run to run)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    return buf.getvalue()
