"""A meshcat scene recorded as commands, without any server.

meshcat's browser viewer is driven by commands (``set_object``,
``set_transform``, ``set_property``, ``delete``, ``set_animation``), each a
small dictionary sent as msgpack bytes. :class:`Scene` keeps the current state
of a scene as those commands, like meshcat's own server does, so that it can be
replayed into a self-contained HTML file (:mod:`orthoglide_pin.viewer.html`) or
sent to browsers by a live server (:mod:`orthoglide_pin.viewer.server`).
Listeners are told of every command as it is recorded.

Paths are meshcat paths such as ``/meshcat/orthoglide/machine/leg1_rail_0``;
transforms are 4 x 4 homogeneous matrices in the frame of the parent path [m].
"""

from __future__ import annotations

import importlib
import threading
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from orthoglide_pin.exceptions import InvalidParameterError

#: A recorded command in its lowered (msgpack-ready) form.
Command = dict[str, Any]
#: Called with each new command, or with ``{"type": "legend", ...}`` on a legend change.
Listener = Callable[[Command], None]


def meshcat(module: str) -> ModuleType:
    """A module of meshcat (``"geometry"``, ``"animation"``...), imported on first use.

    Importing meshcat imports pyzmq's deprecated ``zmq.eventloop.ioloop``, which
    emits a ``DeprecationWarning``: it is silenced here, for that import only.
    Only meshcat's scene-description modules are used: nothing starts a server.
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        return importlib.import_module(f"meshcat.{module}")


def _path(path: str) -> str:
    """Normalise a meshcat path: one leading slash, no trailing or doubled slash."""
    parts = [p for p in str(path).split("/") if p]
    if not parts:
        raise InvalidParameterError("path", path, "a non-empty meshcat path such as /meshcat/a")
    return "/" + "/".join(parts)


def matrix_list(matrix: ArrayLike) -> list[float]:
    """A 4 x 4 homogeneous matrix in meshcat's column-major list form (16 floats).

    Raises:
        InvalidParameterError: If ``matrix`` is not a finite 4 x 4 array.
    """
    m = np.asarray(matrix, dtype=float)
    if m.shape != (4, 4) or not np.isfinite(m).all():
        raise InvalidParameterError("matrix", matrix, "a finite 4 x 4 homogeneous matrix")
    return [float(v) for v in m.T.ravel()]


@dataclass
class _Node:
    """The state of one path: its object, properties and transform (lowered)."""

    object: Command | None = None
    properties: dict[str, Command] = field(default_factory=dict)
    transform: Command | None = None


class Scene:
    """The commands that build a meshcat scene, recorded without a server.

    The state is kept per path, as meshcat's server keeps it: a new object or
    transform on a path replaces the previous one, ``delete`` drops a path and
    everything below it. :meth:`commands` replays the state in recording order,
    the animation last (it needs its objects). Thread-safe.

    Attributes:
        legend: Description of the colour legend shown over the scene (see
            :func:`orthoglide_pin.viewer.html.legend_script`), or ``None``.
    """

    def __init__(self) -> None:
        self._nodes: dict[str, _Node] = {}
        self._animation: Command | None = None
        self._listeners: list[Listener] = []
        self._lock = threading.RLock()
        self.legend: dict[str, Any] | None = None

    # ---------------------------------------------------------------- recording
    def _record(self, command: Command) -> None:
        for listener in list(self._listeners):
            listener(command)

    def _node(self, path: str) -> _Node:
        return self._nodes.setdefault(path, _Node())

    def set_object(self, path: str, obj: Any) -> None:
        """Set the object at ``path``: a meshcat ``Object`` (mesh, lines, points).

        Args:
            path: meshcat path.
            obj: A ``meshcat.geometry.Object``, or its lowered dictionary.
        """
        path = _path(path)
        lowered = obj if isinstance(obj, dict) else obj.lower()
        command = {"type": "set_object", "path": path, "object": lowered}
        with self._lock:
            node = self._node(path)
            node.object, node.properties = command, {}
        self._record(command)

    def set_transform(self, path: str, matrix: ArrayLike) -> None:
        """Set the transform of ``path`` in its parent's frame (4 x 4, [m])."""
        path = _path(path)
        command = {"type": "set_transform", "path": path, "matrix": matrix_list(matrix)}
        with self._lock:
            self._node(path).transform = command
        self._record(command)

    def set_property(self, path: str, key: str, value: Any) -> None:
        """Set a property (``visible``, ``position``, ``top_color``...) of ``path``."""
        path = _path(path)
        command = {"type": "set_property", "path": path, "property": key, "value": value}
        with self._lock:
            self._node(path).properties[key] = command
        self._record(command)

    def delete(self, path: str) -> None:
        """Delete ``path`` and everything below it (nothing if it does not exist)."""
        path = _path(path)
        with self._lock:
            for p in [p for p in self._nodes if p == path or p.startswith(path + "/")]:
                del self._nodes[p]
        self._record({"type": "delete", "path": path})

    def set_animation(self, animation: Any, *, play: bool = True, repetitions: int = 1) -> None:
        """Set the animation: a ``meshcat.animation.Animation`` (or its lowered list).

        Args:
            animation: The animation; its paths must exist when it is replayed.
            play: Start playing as soon as the scene is loaded.
            repetitions: Number of times the clip plays (loops) before it stops.
        """
        lowered = animation if isinstance(animation, list) else animation.lower()
        command = {
            "type": "set_animation",
            "path": "",
            "animations": lowered,
            "options": {"play": bool(play), "repetitions": int(repetitions)},
        }
        with self._lock:
            self._animation = command
        self._record(command)

    def set_legend(self, legend: dict[str, Any] | None) -> None:
        """Set (or clear, with ``None``) the colour legend shown over the scene."""
        with self._lock:
            self.legend = legend
        self._record({"type": "legend", "legend": legend})

    # ------------------------------------------------------------------ reading
    def commands(self) -> list[Command]:
        """The commands that rebuild the current state, in replay order."""
        with self._lock:
            out: list[Command] = []
            for node in self._nodes.values():
                if node.object is not None:
                    out.append(node.object)
                out.extend(node.properties.values())
                if node.transform is not None:
                    out.append(node.transform)
            if self._animation is not None:
                out.append(self._animation)
            return out

    def packed(self) -> list[bytes]:
        """:meth:`commands` packed as msgpack, the form the browser viewer reads."""
        return [pack(c) for c in self.commands()]

    def paths(self, prefix: str = "/", *, with_object: bool = True) -> list[str]:
        """Paths below ``prefix`` (that hold an object, when ``with_object``)."""
        root = "/" if prefix in ("", "/") else _path(prefix)
        with self._lock:
            return [
                p
                for p, n in self._nodes.items()
                if (root == "/" or p == root or p.startswith(root + "/"))
                and (n.object is not None or not with_object)
            ]

    def transform(self, path: str) -> np.ndarray[Any, Any] | None:
        """The current 4 x 4 transform of ``path``, or ``None`` if it has none."""
        with self._lock:
            node = self._nodes.get(_path(path))
            if node is None or node.transform is None:
                return None
            flat = np.array(node.transform["matrix"], dtype=float)
            m: np.ndarray[Any, Any] = flat.reshape(4, 4).T
            return m

    def animation(self) -> Command | None:
        """The ``set_animation`` command, or ``None``."""
        with self._lock:
            return self._animation

    # ---------------------------------------------------------------- listeners
    def subscribe(self, listener: Listener) -> None:
        """Call ``listener`` with every command recorded from now on."""
        with self._lock:
            self._listeners.append(listener)

    def unsubscribe(self, listener: Listener) -> None:
        """Stop calling ``listener`` (no error if it was not subscribed)."""
        with self._lock:
            if listener in self._listeners:
                self._listeners.remove(listener)


def pack(command: Command) -> bytes:
    """Pack one command as msgpack bytes (meshcat's wire format)."""
    import umsgpack

    return bytes(umsgpack.packb(command))


def unpack(data: bytes) -> Command:
    """Unpack msgpack bytes into a command (the inverse of :func:`pack`)."""
    import umsgpack

    out: Command = umsgpack.unpackb(data)
    return out
