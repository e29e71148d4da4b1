"""A live meshcat server for a :class:`~orthoglide_pin.viewer.scene.Scene`, on 127.0.0.1 only.

meshcat 0.3.2's own server listens on every interface and cannot be told
otherwise, so this module serves the scene itself with tornado (which comes
with meshcat), on the loopback address only:

* ``GET /``: the viewer page (:func:`~orthoglide_pin.viewer.html.live_html`);
* ``GET /static/...``: meshcat's viewer files (``main.min.js``);
* ``/ws``: a websocket that sends the scene's commands (msgpack) on connection,
  then every new command as it is recorded, and the legend as JSON text.

Only requests addressed to the server by its own name are answered: the
``Host`` header must be ``127.0.0.1:PORT`` or ``localhost:PORT``, else the
answer is ``403 Forbidden``. A page of another site that re-points its own name
at 127.0.0.1 (DNS rebinding) sends its own name as ``Host`` and is refused; the
websocket also requires an ``Origin`` of ``http://127.0.0.1:PORT`` or
``http://localhost:PORT``.

The server runs its own event loop in a background thread, so it works from a
script, a notebook (whose kernel has its own loop) or the command line. It
starts only when asked (:meth:`SceneServer.start`), and :meth:`SceneServer.close`
stops it, closes its connections and frees the port.
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import json
import signal
import socket
import threading
from typing import Any, Final

import tornado.httpserver
import tornado.web
import tornado.websocket

from orthoglide_pin.exceptions import InvalidParameterError, OrthoglideError, PortInUseError
from orthoglide_pin.viewer.html import STATIC_PREFIX, WEBSOCKET_PATH, live_html, viewer_dist
from orthoglide_pin.viewer.scene import Command, Scene, pack

#: The only address the server listens on.
HOST: Final[str] = "127.0.0.1"
#: Default port (meshcat's).
DEFAULT_PORT: Final[int] = 7000
#: Names of the server accepted in the ``Host`` header (with the port).
LOCAL_NAMES: Final = (HOST, "localhost")
#: Longest wait for the server thread to start or stop [s].
THREAD_TIMEOUT: Final[float] = 10.0


def _check_port(port: int) -> int:
    if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
        raise InvalidParameterError("port", port, "an integer in [0, 65535] (0: any free port)")
    return port


def bind(port: int) -> socket.socket:
    """A listening TCP socket on ``127.0.0.1:port`` (``port`` 0: any free port).

    Raises:
        PortInUseError: If another program holds the port.
        OrthoglideError: If the port cannot be bound for another reason.
    """
    port = _check_port(port)
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((HOST, port))
        sock.listen(128)
    except OSError as exc:
        sock.close()
        if exc.errno == errno.EADDRINUSE:
            raise PortInUseError(HOST, port) from exc
        raise OrthoglideError(
            f"cannot listen on {HOST}:{port}: {exc.strerror or exc}", port
        ) from exc
    sock.setblocking(False)
    return sock


class SceneServer:
    """Serves a scene to browsers on ``http://127.0.0.1:<port>/``.

    The port is bound on construction (so an error comes at once); nothing is
    served before :meth:`start`.

    Args:
        scene: The scene to serve; its later commands are sent live.
        port: TCP port, 0 for any free port.
        title: Title of the page.

    Raises:
        PortInUseError: If the port is in use.
    """

    def __init__(
        self, scene: Scene, port: int = DEFAULT_PORT, *, title: str = "Orthoglide"
    ) -> None:
        self.scene = scene
        self.title = title
        self._socket: socket.socket | None = bind(port)
        self.port: int = self._socket.getsockname()[1]
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._clients: set[_SocketHandler] = set()
        self._ready = threading.Event()
        self._error: BaseException | None = None

    @property
    def url(self) -> str:
        """The page's address."""
        return f"http://{HOST}:{self.port}/"

    @property
    def running(self) -> bool:
        """Whether the server thread is serving."""
        return self._thread is not None and self._thread.is_alive()

    @property
    def clients(self) -> int:
        """Number of connected browsers."""
        return len(self._clients)

    # ------------------------------------------------------------------ control
    def start(self) -> str:
        """Start serving in a background thread; return the URL.

        Raises:
            OrthoglideError: If the server is closed or fails to start.
        """
        if self.running:
            return self.url
        if self._socket is None:
            raise OrthoglideError("the server is closed: create a new one")
        self._ready.clear()
        self._thread = threading.Thread(target=self._run, name="orthoglide-viewer", daemon=True)
        self._thread.start()
        if not self._ready.wait(THREAD_TIMEOUT) or self._error is not None:
            self.close()
            raise OrthoglideError(f"the viewer server failed to start: {self._error}")
        self.scene.subscribe(self._on_command)
        return self.url

    def close(self) -> None:
        """Stop serving, close every connection and free the port (idempotent)."""
        self.scene.unsubscribe(self._on_command)
        loop, thread = self._loop, self._thread
        if loop is not None and thread is not None and thread.is_alive():
            with contextlib.suppress(RuntimeError):  # the loop closed meanwhile
                loop.call_soon_threadsafe(loop.stop)
            thread.join(THREAD_TIMEOUT)
        self._thread = None
        if self._socket is not None:
            self._socket.close()
            self._socket = None

    def serve_forever(self) -> None:
        """Serve until Ctrl-C (SIGINT) or SIGTERM, then shut down cleanly.

        Call it from the main thread (signals are delivered there).
        """
        self.start()
        # Ctrl-C even where SIGINT was inherited as ignored (a background job).
        previous = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
        for s in previous:
            signal.signal(s, signal.default_int_handler)
        try:
            while self.running:
                assert self._thread is not None
                self._thread.join(0.25)
        except KeyboardInterrupt:
            pass
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)
            self.close()

    def __enter__(self) -> SceneServer:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ----------------------------------------------------------- server thread
    def _run(self) -> None:
        loop = asyncio.new_event_loop()
        asyncio.set_event_loop(loop)
        self._loop = loop
        try:
            server = loop.run_until_complete(self._listen())
        except BaseException as exc:  # reported by start()
            self._error = exc
            self._ready.set()
            loop.close()
            return
        self._ready.set()
        try:
            loop.run_forever()
        finally:
            server.stop()
            for client in list(self._clients):
                client.close()
            with contextlib.suppress(Exception):
                loop.run_until_complete(asyncio.wait_for(server.close_all_connections(), 2.0))
            self._clients.clear()
            loop.close()

    @property
    def allowed_hosts(self) -> frozenset[str]:
        """``Host`` header values answered (lower case): ``127.0.0.1:PORT``, ``localhost:PORT``."""
        return frozenset(f"{name}:{self.port}" for name in LOCAL_NAMES)

    async def _listen(self) -> Any:
        hosts = {"hosts": self.allowed_hosts}
        handlers: list[Any] = [
            (r"/", _PageHandler, {"title": self.title, **hosts}),
            (STATIC_PREFIX + r"(.*)", _StaticHandler, {"path": str(viewer_dist()), **hosts}),
            (WEBSOCKET_PATH, _SocketHandler, {"server": self, **hosts}),
            (r"/favicon.ico", _NoContentHandler, hosts),
        ]
        app = tornado.web.Application(
            handlers, default_handler_class=_NotFoundHandler, default_handler_args=hosts
        )
        server = tornado.httpserver.HTTPServer(app)
        assert self._socket is not None
        server.add_sockets([self._socket])
        return server

    def _on_command(self, command: Command) -> None:
        loop = self._loop
        if loop is not None and not loop.is_closed():
            with contextlib.suppress(RuntimeError):
                loop.call_soon_threadsafe(self._broadcast, command)

    def _broadcast(self, command: Command) -> None:
        for client in list(self._clients):
            client.send(command)


def _message(command: Command) -> tuple[bytes | str, bool]:
    """A command as a websocket message: ``(payload, binary)``."""
    if command.get("type") == "legend":
        return json.dumps({"legend": command["legend"]}), False
    return pack(command), True


class _LocalOnly(tornado.web.RequestHandler):
    """Refuses (403) any request whose ``Host`` is not one of ``hosts``."""

    hosts: frozenset[str] = frozenset()

    def prepare(self) -> None:
        if self.request.headers.get("Host", "").strip().lower() not in self.hosts:
            raise tornado.web.HTTPError(403, reason="Forbidden: unknown Host")


class _NotFoundHandler(_LocalOnly):
    """Any other path: 404 (after the Host check)."""

    def initialize(self, hosts: frozenset[str]) -> None:
        self.hosts = hosts

    def prepare(self) -> None:
        super().prepare()
        raise tornado.web.HTTPError(404)


class _StaticHandler(tornado.web.StaticFileHandler, _LocalOnly):
    """meshcat's viewer files, behind the Host check."""

    def initialize(  # type: ignore[override]
        self, path: str, hosts: frozenset[str], default_filename: str | None = None
    ) -> None:
        super().initialize(path, default_filename)
        self.hosts = hosts

    def prepare(self) -> None:
        _LocalOnly.prepare(self)


class _PageHandler(_LocalOnly):
    """``GET /``: the viewer page."""

    def initialize(self, title: str, hosts: frozenset[str]) -> None:
        self.page = live_html(title=title)
        self.hosts = hosts

    def get(self) -> None:
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.set_header("Cache-Control", "no-store")
        self.write(self.page)


class _NoContentHandler(_LocalOnly):
    """A quiet ``204 No Content`` (the browser's favicon request)."""

    def initialize(self, hosts: frozenset[str]) -> None:
        self.hosts = hosts

    def get(self) -> None:
        self.set_status(204)


class _SocketHandler(tornado.websocket.WebSocketHandler, _LocalOnly):
    """``/ws``: the scene's commands, then every new one as it is recorded."""

    def initialize(self, server: SceneServer, hosts: frozenset[str]) -> None:
        self.server = server
        self.hosts = hosts

    def prepare(self) -> None:
        _LocalOnly.prepare(self)

    def check_origin(self, origin: str) -> bool:
        """Only the viewer's own page: ``http://127.0.0.1:PORT`` or ``http://localhost:PORT``."""
        return origin.strip().lower() in {f"http://{host}" for host in self.hosts}

    def open(self, *args: str, **kwargs: str) -> None:
        self.server._clients.add(self)
        self.send({"type": "legend", "legend": self.server.scene.legend})
        for command in self.server.scene.commands():
            self.send(command)

    def send(self, command: Command) -> None:
        payload, binary = _message(command)
        try:
            sent = self.write_message(payload, binary=binary)
        except tornado.websocket.WebSocketClosedError:
            return
        # A browser that leaves mid-send fails the future: retrieve it, quietly.
        sent.add_done_callback(lambda f: None if f.cancelled() else f.exception())

    def on_close(self) -> None:
        self.server._clients.discard(self)
