"""Reaching a Dask scheduler: the address's form, then a bounded handshake.

``distributed.Client("tcp://HOST:PORT")`` trusts its peer: it reads the
8-byte length that starts each message and allocates that many bytes before
reading them, so a peer that is not Dask (or a hostile one) announcing
2^64 bytes makes it try to allocate exabytes; and a peer that accepts the
connection but never speaks keeps it waiting. :func:`check_scheduler` runs
first, before any work and even when no work is left (a finished sweep run
again), and refuses in one line:

* an address that is not ``'local'`` or ``tcp://HOST:PORT`` (a missing or
  non-numeric port, another scheme, a path, an empty text);
* a host that does not resolve or refuses the connection;
* a peer that sends no Dask handshake within :data:`PROBE_TIMEOUT` seconds
  (resolution and connection included), announces more than
  :data:`MAX_HANDSHAKE_BYTES`, or sends something that is not a Dask
  handshake.

A Dask scheduler writes its handshake as soon as it accepts a connection: a
small message of msgpack frames, ``{"compression": ..., "python": ...,
"pickle-protocol": ...}``. The probe reads it with its own size bound, then
closes the connection; the scheduler sees a client that left before its
handshake (logged at its info level).
"""

from __future__ import annotations

import ipaddress
import re
import socket
import struct
import threading
import time
import urllib.parse
from collections.abc import Callable
from typing import Any, Final

from orthoglide_pin._lazy import optional_import
from orthoglide_pin.exceptions import InvalidParameterError, short_repr

#: Seconds for the whole probe: name resolution, connection and handshake. A
#: scheduler answers in milliseconds; with the imports before it, a peer that
#: never answers is reported about 12 s after the command starts.
PROBE_TIMEOUT: Final[float] = 8.0
#: Largest handshake accepted from the peer [bytes] (a Dask handshake is ~60 bytes).
MAX_HANDSHAKE_BYTES: Final[int] = 65536
#: Most frames in a handshake message (a Dask handshake has one).
MAX_FRAMES: Final[int] = 16
#: What ``--scheduler`` accepts, for the messages.
ALLOWED: Final = "'local' or tcp://HOST:PORT (PORT from 1 to 65535)"
_WORD: Final = struct.Struct("=Q")  # Dask's frame lengths: native unsigned 64-bit
_HOST_LABEL = re.compile(r"^(?!-)[A-Za-z0-9-]{1,63}(?<!-)$")


def scheduler_address(text: Any) -> tuple[str, int]:
    """The host and port of a ``tcp://HOST:PORT`` address (IPv6 in brackets).

    Raises:
        InvalidParameterError: Naming the address and what is wrong with it.
    """
    if not isinstance(text, str):
        raise InvalidParameterError("scheduler", text, f"{ALLOWED} or a distributed.Client")

    def refuse(why: str) -> InvalidParameterError:
        return InvalidParameterError("scheduler", text, f"{ALLOWED} ({why})")

    if not text.strip():
        raise refuse("it is empty")
    if not text.startswith("tcp://"):
        scheme = text.split("://", 1)[0] if "://" in text else None
        raise refuse(f"{scheme}:// is not supported" if scheme else "no tcp:// scheme")
    parts = urllib.parse.urlsplit(text)
    if parts.username is not None or parts.password is not None:
        raise refuse("no user or password in it")
    if parts.path not in ("", "/") or parts.query or parts.fragment:
        raise refuse("nothing after the port")
    try:
        port = parts.port
    except ValueError:
        given = parts.netloc.rpartition(":")[2]
        why = "out of range" if given.isdigit() else "not a number"
        raise refuse(f"the port {short_repr(given)} is {why}") from None
    host = parts.hostname or ""
    if not host:
        raise refuse("no host")
    if not _valid_host(host):
        raise refuse(f"the host {short_repr(host)} is not a host name or an IP address")
    if port is None:
        raise refuse("no port")
    if not 1 <= port <= 65535:
        raise refuse(f"the port {port} is out of range")
    return host, port


def _valid_host(host: str) -> bool:
    try:
        ipaddress.ip_address(host)
        return True
    except ValueError:
        labels = host.rstrip(".").split(".")
        return len(host) <= 253 and all(_HOST_LABEL.match(label) for label in labels)


def check_scheduler(scheduler: Any, timeout: float | None = None) -> None:
    """Refuse a scheduler that cannot be used, before any work (see the module).

    ``None``, ``'local'`` and anything that is not a string (a
    ``distributed.Client``, checked where it is used) pass; an address is
    parsed, then probed.

    Args:
        scheduler: What ``run_sweep`` or ``--scheduler`` was given.
        timeout: Seconds for the probe (default :data:`PROBE_TIMEOUT`).

    Raises:
        InvalidParameterError: A malformed address, or a peer that is not a
            reachable Dask scheduler (one line, within the timeout).
    """
    if scheduler is None or scheduler == "local" or not isinstance(scheduler, str):
        return
    host, port = scheduler_address(scheduler)
    probe_scheduler(scheduler, host, port, PROBE_TIMEOUT if timeout is None else timeout)


def probe_scheduler(address: str, host: str, port: int, timeout: float) -> None:
    """Connect to ``host:port`` and read a Dask handshake, all within ``timeout`` seconds.

    Nothing the peer announces is allocated beyond :data:`MAX_HANDSHAKE_BYTES`.

    Raises:
        InvalidParameterError: Naming ``address`` and what the peer did.
    """
    deadline = time.monotonic() + timeout

    def refuse(why: str) -> InvalidParameterError:
        return InvalidParameterError("scheduler", address, f"a reachable Dask scheduler ({why})")

    with _connect(host, port, deadline, timeout, refuse) as sock:
        try:
            (total,) = _WORD.unpack(_receive(sock, _WORD.size, deadline))
            if total > MAX_HANDSHAKE_BYTES:
                raise refuse(
                    f"the peer announced a message of {total} bytes, not a Dask handshake "
                    f"of at most {MAX_HANDSHAKE_BYTES}: it does not speak Dask"
                )
            handshake = _handshake(_receive(sock, total, deadline))
        except TimeoutError:
            raise refuse(
                f"the peer accepted the connection but sent no Dask handshake within {timeout:g} s"
            ) from None
        except ConnectionError as exc:
            raise refuse(f"the peer closed the connection before its handshake: {exc}") from None
        except OSError as exc:
            raise refuse(exc.strerror or str(exc)) from None
    if handshake is None:
        raise refuse("the peer's first message is not a Dask handshake: it does not speak Dask")


def _resolve(host: str, port: int, deadline: float) -> list[Any]:
    """``getaddrinfo`` with a deadline (it has none of its own), in a daemon thread."""
    box: dict[str, Any] = {}

    def target() -> None:
        try:
            box["infos"] = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
        except (OSError, UnicodeError) as exc:
            box["error"] = exc

    thread = threading.Thread(target=target, name="scheduler-resolve", daemon=True)
    thread.start()
    thread.join(max(deadline - time.monotonic(), 0.0))
    if thread.is_alive():
        raise TimeoutError(f"{host} did not resolve in time")
    if "error" in box:
        raise box["error"]
    return list(box["infos"])


def _connect(
    host: str,
    port: int,
    deadline: float,
    timeout: float,
    refuse: Callable[[str], InvalidParameterError],
) -> socket.socket:
    """A connected socket to ``host:port`` (the first address that accepts)."""
    try:
        infos = _resolve(host, port, deadline)
    except TimeoutError:
        raise refuse(f"the host {host} did not resolve within {timeout:g} s") from None
    except (OSError, UnicodeError) as exc:
        raise refuse(f"the host {host} does not resolve: {exc}") from None
    last: OSError | None = None
    for family, kind, proto, _, sockaddr in infos:
        sock = socket.socket(family, kind, proto)
        try:
            sock.settimeout(max(deadline - time.monotonic(), 1e-3))
            sock.connect(sockaddr)
            return sock
        except OSError as exc:
            sock.close()
            last = exc
    if isinstance(last, TimeoutError):
        raise refuse(f"no answer to the connection within {timeout:g} s")
    raise refuse((last.strerror or str(last)) if last is not None else "no address to connect to")


def _receive(sock: socket.socket, size: int, deadline: float) -> bytes:
    """Exactly ``size`` bytes (at most :data:`MAX_HANDSHAKE_BYTES`) before ``deadline``.

    Raises:
        TimeoutError: The deadline passed.
        ConnectionError: The peer closed the connection first.
    """
    chunks: list[bytes] = []
    got = 0
    while got < size:
        left = deadline - time.monotonic()
        if left <= 0.0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(min(size - got, MAX_HANDSHAKE_BYTES))
        if not chunk:
            raise ConnectionError(f"{got} of {size} bytes received")
        chunks.append(chunk)
        got += len(chunk)
    return b"".join(chunks)


def _handshake(body: bytes) -> dict[str, Any] | None:
    """The handshake in a Dask message (its frame count, lengths and msgpack frames), or None."""
    if len(body) < _WORD.size:
        return None
    (count,) = _WORD.unpack_from(body)
    start = _WORD.size * (1 + count)
    if not 1 <= count <= MAX_FRAMES or start > len(body):
        return None
    lengths = struct.unpack_from(f"={count}Q", body, _WORD.size)
    if start + sum(lengths) != len(body):
        return None
    msgpack: Any = optional_import("msgpack", "cluster", "a Dask scheduler")
    try:
        message = msgpack.unpackb(body[start : start + lengths[0]], raw=False)
    except Exception:  # msgpack raises several kinds of errors on bytes that are not its own
        return None
    if isinstance(message, dict) and ("python" in message or "compression" in message):
        return message
    return None


__all__ = [
    "MAX_HANDSHAKE_BYTES",
    "PROBE_TIMEOUT",
    "check_scheduler",
    "probe_scheduler",
    "scheduler_address",
]
