"""The live viewer answers only requests addressed to it by its own name.

Real HTTP requests over 127.0.0.1, with the Host and Origin headers a page of
another site would send after a DNS rebinding.
"""

from __future__ import annotations

import asyncio
import http.client
from collections.abc import Iterator

import pytest

from orthoglide_pin.viewer.scene import Scene
from orthoglide_pin.viewer.server import SceneServer

#: Seconds to wait for an answer.
TIMEOUT = 60.0
#: Paths served to the right Host (the page, a viewer file, the favicon).
PATHS = ("/", "/static/main.min.js", "/favicon.ico")


@pytest.fixture
def server() -> Iterator[SceneServer]:
    with SceneServer(Scene(), 0) as running:
        yield running


def _get(server: SceneServer, path: str, headers: dict[str, str]) -> tuple[int, bytes]:
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=TIMEOUT)
    try:
        conn.putrequest("GET", path, skip_host=True, skip_accept_encoding=True)
        for name, value in headers.items():
            conn.putheader(name, value)
        conn.endheaders()
        response = conn.getresponse()
        return response.status, response.read()
    finally:
        conn.close()


def _upgrade(server: SceneServer, host: str, origin: str | None) -> int:
    """Status of a websocket handshake on /ws with these headers."""
    headers = {
        "Host": host,
        "Upgrade": "websocket",
        "Connection": "Upgrade",
        "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ==",
        "Sec-WebSocket-Version": "13",
    }
    if origin is not None:
        headers["Origin"] = origin
    return _status_only(server, headers)


def _status_only(server: SceneServer, headers: dict[str, str]) -> int:
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=TIMEOUT)
    try:
        conn.putrequest("GET", "/ws", skip_host=True, skip_accept_encoding=True)
        for name, value in headers.items():
            conn.putheader(name, value)
        conn.endheaders()
        return conn.getresponse().status  # 101 leaves the socket open: not read further
    finally:
        conn.close()


@pytest.mark.parametrize("name", ["127.0.0.1", "localhost", "LOCALHOST"])
def test_the_right_host_is_answered(server: SceneServer, name: str) -> None:
    for path in PATHS:
        status, _ = _get(server, path, {"Host": f"{name}:{server.port}"})
        assert status in (200, 204), (path, status)
    assert _upgrade(server, f"{name}:{server.port}", f"http://{name}:{server.port}") == 101


@pytest.mark.parametrize(
    "host",
    [
        "evil.example",
        "evil.example:{port}",
        "127.0.0.1",  # no port: not the server's own address
        "127.0.0.1:1",
        "localhost.evil.example:{port}",
        "127.0.0.1:{port}.evil.example",
        "",
    ],
)
def test_a_foreign_host_is_refused_everywhere(server: SceneServer, host: str) -> None:
    value = host.format(port=server.port)
    for path in (*PATHS, "/nothing-here"):
        status, body = _get(server, path, {"Host": value})
        assert status == 403, (path, value, status)
        assert b"MeshCat" not in body and b"WebSocket" not in body
    assert _upgrade(server, value, f"http://{value}") == 403


def test_a_missing_host_is_refused(server: SceneServer) -> None:
    assert _get(server, "/", {})[0] in (400, 403)  # tornado itself refuses HTTP/1.1 without Host


def test_the_websocket_keeps_its_origin_check(server: SceneServer) -> None:
    host = f"127.0.0.1:{server.port}"
    assert _upgrade(server, host, "http://evil.example") == 403
    assert _upgrade(server, host, f"http://evil.example:{server.port}") == 403
    assert _upgrade(server, host, "null") == 403
    assert _upgrade(server, host, None) == 101  # not a browser: no Origin to check


def test_the_scene_still_streams_to_the_right_client(server: SceneServer) -> None:
    import tornado.websocket

    async def first_message() -> bytes | str | None:
        conn = await tornado.websocket.websocket_connect(f"ws://127.0.0.1:{server.port}/ws")
        try:
            return await asyncio.wait_for(conn.read_message(), TIMEOUT)
        finally:
            conn.close()

    message = asyncio.run(first_message())
    assert isinstance(message, str) and "legend" in message
