"""HTML pages of a scene: one self-contained file, the live page, a notebook iframe.

Every page holds meshcat's browser viewer (three.js), a colour legend drawn over
the scene, and a way to feed it the scene's commands:

* :func:`static_html`: the viewer script and every command are inlined (the
  commands as base64 msgpack, replayed in order), so the file opens offline in
  any browser, animation included;
* :func:`live_html`: the page served by :mod:`orthoglide_pin.viewer.server`; it
  loads the viewer script from the server and reads the commands from a
  websocket, legend updates included;
* :func:`iframe_html`: a static page embedded in a notebook cell.

The viewer script is the ``viewer/dist/main.min.js`` shipped in the meshcat
package, read from disk without importing meshcat.
"""

from __future__ import annotations

import base64
import html
import importlib.util
import json
from functools import cache
from pathlib import Path
from typing import Any

from orthoglide_pin.exceptions import DescriptionError
from orthoglide_pin.viewer.scene import Scene

#: Path of the websocket of the live page (see :mod:`orthoglide_pin.viewer.server`).
WEBSOCKET_PATH = "/ws"
#: Path under which the live server serves meshcat's viewer files.
STATIC_PREFIX = "/static/"
VIEWER_SCRIPT = "main.min.js"

_STYLE = """
body { margin: 0; font-family: sans-serif; }
#meshcat-pane { width: 100vw; height: 100vh; overflow: hidden; }
#og-legend { position: absolute; left: 12px; bottom: 12px; padding: 8px 10px;
  background: rgba(255, 255, 255, 0.92); color: #222; font-size: 13px;
  border-radius: 4px; box-shadow: 0 1px 4px rgba(0, 0, 0, 0.3); max-width: 240px; }
#og-legend .og-title { font-weight: bold; margin-bottom: 4px; }
#og-legend .og-bar { width: 220px; height: 14px; border: 1px solid #555; }
#og-legend .og-ticks { display: flex; justify-content: space-between; width: 222px; }
#og-legend .og-item { margin-top: 3px; }
#og-legend .og-swatch { display: inline-block; width: 11px; height: 11px;
  margin-right: 6px; border: 1px solid #555; vertical-align: -1px; }
"""

# Builds the legend from its description with DOM calls (no HTML injection).
_LEGEND_SCRIPT = """
function ogLegend(spec) {
  var box = document.getElementById("og-legend");
  while (box.firstChild) { box.removeChild(box.firstChild); }
  if (!spec) { box.hidden = true; return; }
  function add(parent, cls, text) {
    var el = document.createElement("div");
    el.className = cls;
    if (text !== undefined) { el.textContent = text; }
    parent.appendChild(el);
    return el;
  }
  if (spec.title) { add(box, "og-title", spec.title); }
  if (spec.stops && spec.stops.length) {
    var bar = add(box, "og-bar");
    bar.style.background = "linear-gradient(to right, " + spec.stops.join(", ") + ")";
    var ticks = add(box, "og-ticks");
    add(ticks, "og-tick", spec.min_label);
    add(ticks, "og-tick", spec.max_label);
  }
  (spec.items || []).forEach(function (item) {
    var row = add(box, "og-item");
    var sw = document.createElement("span");
    sw.className = "og-swatch";
    sw.style.background = item.color;
    row.appendChild(sw);
    row.appendChild(document.createTextNode(item.label));
  });
  box.hidden = false;
}
"""

_STATIC_FEED = """
function ogBytes(text) {
  var raw = atob(text), out = new Uint8Array(raw.length);
  for (var i = 0; i < raw.length; i++) { out[i] = raw.charCodeAt(i); }
  return out;
}
ogCommands.forEach(function (c) { viewer.handle_command_bytearray(ogBytes(c)); });
ogLegend(ogLegendSpec);
"""

_LIVE_FEED = """
var scheme = location.protocol === "https:" ? "wss://" : "ws://";
var ogSocket = new WebSocket(scheme + location.host + "%s");
ogSocket.binaryType = "arraybuffer";
ogSocket.onmessage = function (msg) {
  if (typeof msg.data === "string") {
    ogLegend(JSON.parse(msg.data).legend);
  } else {
    viewer.handle_command_bytearray(new Uint8Array(msg.data));
  }
};
"""


def viewer_dist() -> Path:
    """Folder of meshcat's browser viewer files (``meshcat/viewer/dist``).

    Raises:
        DescriptionError: If meshcat or its viewer files are not installed.
    """
    spec = importlib.util.find_spec("meshcat")
    locations = list(spec.submodule_search_locations or []) if spec else []
    for location in locations:
        dist = Path(location) / "viewer" / "dist"
        if (dist / VIEWER_SCRIPT).is_file():
            return dist
    raise DescriptionError(
        "meshcat's viewer files (viewer/dist/main.min.js) are not installed: "
        "pip install 'meshcat>=0.3.2,<0.4'"
    )


@cache
def viewer_script() -> str:
    """The viewer script of meshcat (three.js and the viewer, ~850 kB), ready to inline."""
    text = (viewer_dist() / VIEWER_SCRIPT).read_text(encoding="utf-8")
    return text.replace("</script", "<\\/script")


def _json(value: Any) -> str:
    """JSON for an inline script (no ``</`` that would close the script)."""
    return json.dumps(value).replace("</", "<\\/")


def _page(title: str, script: str, body_script: str) -> str:
    return (
        '<!DOCTYPE html>\n<html>\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
        '<div id="meshcat-pane"></div>\n<div id="og-legend" hidden></div>\n'
        f"{script}\n<script>{_LEGEND_SCRIPT}\n"
        'var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));\n'
        f"{body_script}</script>\n</body>\n</html>\n"
    )


def static_html(scene: Scene, *, title: str = "Orthoglide") -> str:
    """One self-contained HTML page of ``scene``: opens offline, animation included.

    Args:
        scene: The recorded scene.
        title: Title of the page.

    Returns:
        The page (UTF-8 text, about 0.9 MB plus the scene).
    """
    commands = [base64.b64encode(data).decode("ascii") for data in scene.packed()]
    feed = (
        f"var ogCommands = {_json(commands)};\nvar ogLegendSpec = {_json(scene.legend)};\n"
        + _STATIC_FEED
    )
    return _page(title, f"<script>{viewer_script()}</script>", feed)


def live_html(*, title: str = "Orthoglide") -> str:
    """The page of the live server: viewer script and commands come from the server."""
    script = f'<script src="{STATIC_PREFIX}{VIEWER_SCRIPT}"></script>'
    return _page(title, script, _LIVE_FEED % WEBSOCKET_PATH)


def iframe_html(page: str, *, height: int = 500) -> str:
    """``page`` in an iframe (``srcdoc``) for a notebook cell, ``height`` pixels tall."""
    return (
        f'<iframe srcdoc="{html.escape(page, quote=True)}" '
        f'style="width: 100%; height: {int(height)}px; border: none"></iframe>'
    )
