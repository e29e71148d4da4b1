"""A recorded scene and its ways out: an HTML file, a notebook cell, a live server.

:class:`SceneOutput` holds a :class:`~orthoglide_pin.viewer.scene.Scene` and
publishes it: one self-contained HTML page (offline, animation included), an
iframe for a notebook cell (``_repr_html_``), or a live server on 127.0.0.1
only (:mod:`orthoglide_pin.viewer.server`, started on demand) to which later
changes of the scene are pushed at once.
:class:`~orthoglide_pin.viewer.visualizer.Viewer` builds on it.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._paths import given_path
from orthoglide_pin._validation import integer, path_argument, text
from orthoglide_pin.viewer.html import iframe_html, static_html
from orthoglide_pin.viewer.scene import Scene

#: Tallest iframe :meth:`SceneOutput.iframe` makes [px].
MAX_HEIGHT = 100_000

if TYPE_CHECKING:
    from orthoglide_pin.viewer.server import SceneServer

_Output = TypeVar("_Output", bound="SceneOutput")


class SceneOutput:
    """A scene and its outputs (HTML page, notebook iframe, live server).

    Args:
        title: Title of the page.

    Attributes:
        scene: The recorded scene.
        title: Title of the page.
    """

    def __init__(self, title: str = "Orthoglide") -> None:
        self.title = text("title", title, "a page title (str)")
        self.scene = Scene()
        self._server: SceneServer | None = None

    # --------------------------------------------------------------- output
    def html(self) -> str:
        """The scene as one self-contained HTML page (works offline, no server)."""
        return static_html(self.scene, title=self.title)

    def save_html(self, path: str | Path) -> Path:
        """Write :meth:`html` to ``path`` atomically; return the path."""
        target = given_path(path_argument("path", path))
        atomic_write_text(target, self.html())
        return target

    def iframe(self, height: int = 500) -> str:
        """The static page in an iframe, for a notebook cell (``height`` pixels)."""
        return iframe_html(self.html(), height=integer("height", height, 1, MAX_HEIGHT))

    def _repr_html_(self) -> str:
        link = ""
        if self.url() is not None:
            link = f'<p>Live viewer: <a href="{self.url()}" target="_blank">{self.url()}</a></p>'
        return self.iframe() + link

    # --------------------------------------------------------------- server
    def serve(self, port: int = 7000) -> str:
        """Serve the scene live on ``http://127.0.0.1:<port>/`` (background thread).

        Later changes to the scene reach the open pages at once. ``port`` 0
        picks a free port.

        Returns:
            The URL.

        Raises:
            PortInUseError: If the port is in use.
        """
        from orthoglide_pin.viewer.server import SceneServer

        if self._server is None or not self._server.running:
            self._server = SceneServer(self.scene, port, title=self.title)
            self._server.start()
        return self._server.url

    def serve_forever(self, port: int = 7000) -> None:
        """Serve until Ctrl-C, then shut down cleanly (call from the main thread)."""
        self.serve(port)
        assert self._server is not None
        self._server.serve_forever()

    def url(self) -> str | None:
        """The live server's URL, or ``None`` when not serving."""
        return self._server.url if self._server is not None and self._server.running else None

    def close(self) -> None:
        """Stop the live server, if any (idempotent)."""
        if self._server is not None:
            self._server.close()
            self._server = None

    def __enter__(self: _Output) -> _Output:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
