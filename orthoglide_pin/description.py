"""The machine description: xacro rendering to URDF, its cache, and the loop data.

The description lives in the ``description/`` folder of the source tree, shipped
in the wheel as the ``orthoglide_pin.description`` resource package:

* ``orthoglide.urdf.xacro``: the top-level xacro, one argument per parameter;
* ``orthoglide_leg.xacro``: the P-R-Pa-R leg macro, instantiated three times;
* ``orthoglide_loops.yaml``: the loop closures and actuated joints of the cut tree;
* ``urdf/orthoglide_prototype.urdf``: the prototype rendered once, for other tools.

Rendering runs the ROS 2 ``xacro`` package from Python, without ROS. Results are
cached in memory and on disk, keyed by a hash of the arguments, the xacro
sources and the xacro version, and written atomically.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.resources
import json
import os
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from importlib.abc import Traversable
from importlib.metadata import version
from pathlib import Path

import yaml

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin.exceptions import DescriptionError
from orthoglide_pin.params import OrthoglideParams, field_names, prototype

#: Environment variable that overrides the on-disk URDF cache directory.
CACHE_ENV = "ORTHOGLIDE_PIN_CACHE"
XACRO_FILE = "orthoglide.urdf.xacro"
LOOPS_FILE = "orthoglide_loops.yaml"
PROTOTYPE_URDF_FILE = "urdf/orthoglide_prototype.urdf"
_SOURCES = ("orthoglide.urdf.xacro", "orthoglide_leg.xacro")
_VECTOR_SUFFIXES = ("_x", "_y", "_z")
# xacro keeps module-level state: one rendering at a time per process.
_XACRO_LOCK = threading.Lock()
_MEMORY_CACHE: dict[str, str] = {}


@dataclass(frozen=True)
class LoopClosure:
    """One loop closure of the cut tree.

    Attributes:
        name: Closure name, e.g. ``"leg2_platform"``.
        kind: ``"point"`` (3D point coincidence) or ``"frame"`` (6D coincidence).
        frame1: Name of the first frame (a URDF link).
        frame2: Name of the second frame (a URDF link).
    """

    name: str
    kind: str
    frame1: str
    frame2: str


@dataclass(frozen=True)
class LoopSpec:
    """Loop closures and actuation of the cut tree (``orthoglide_loops.yaml``).

    Attributes:
        actuated_joints: Names of the three slider joints, in leg order.
        platform_frame: Name of the platform frame.
        tool_frame: Name of the tool-tip frame.
        closures: The loop closures.
    """

    actuated_joints: tuple[str, ...]
    platform_frame: str
    tool_frame: str
    closures: tuple[LoopClosure, ...]


def description_files() -> Traversable:
    """The resource folder that holds the description files."""
    return importlib.resources.files("orthoglide_pin._description")


def xacro_path() -> Path:
    """Absolute path of the top-level xacro file.

    Raises:
        DescriptionError: If the description is not installed as plain files.
    """
    path = Path(str(description_files() / XACRO_FILE))
    if not path.is_file():
        raise DescriptionError(f"description file not found: {path}", str(path))
    return path


def prototype_urdf_path() -> Path:
    """Path of the prototype's URDF shipped with the package."""
    return Path(str(description_files() / PROTOTYPE_URDF_FILE))


@cache
def load_loops() -> LoopSpec:
    """Read the loop closures and actuated joints from ``orthoglide_loops.yaml``."""
    data = yaml.safe_load((description_files() / LOOPS_FILE).read_text())
    closures = tuple(
        LoopClosure(name=c["name"], kind=c["type"], frame1=c["frame1"], frame2=c["frame2"])
        for c in data["closures"]
    )
    for c in closures:
        if c.kind not in ("point", "frame"):
            raise DescriptionError(f"closure {c.name} has unknown type {c.kind!r}", c.kind)
    return LoopSpec(
        actuated_joints=tuple(data["actuated_joints"]),
        platform_frame=str(data["platform_frame"]),
        tool_frame=str(data["tool_frame"]),
        closures=closures,
    )


def xacro_args(params: OrthoglideParams) -> dict[str, str]:
    """Xacro arguments (all strings) for a parameter set.

    Floats are written with ``repr`` so that they round-trip exactly; vector
    parameters become three arguments suffixed ``_x``, ``_y``, ``_z``; a mass
    left to ``None`` becomes ``"auto"``.
    """
    args: dict[str, str] = {}
    for name, value in params.to_dict().items():
        if isinstance(value, list):
            for suffix, component in zip(_VECTOR_SUFFIXES, value, strict=True):
                args[name + suffix] = repr(float(component))
        elif value is None:
            args[name] = "auto"
        else:
            args[name] = repr(float(value))
    return args


def _sources_digest() -> str:
    h = hashlib.sha256()
    for name in _SOURCES:
        h.update((description_files() / name).read_bytes())
    h.update(version("xacro").encode())
    return h.hexdigest()


def cache_key(params: OrthoglideParams) -> str:
    """Hash of everything a rendering depends on (arguments, sources, xacro)."""
    payload = json.dumps(xacro_args(params), sort_keys=True) + _sources_digest()
    return hashlib.sha256(payload.encode()).hexdigest()[:32]


def cache_dir() -> Path:
    """Directory of the on-disk URDF cache.

    ``$ORTHOGLIDE_PIN_CACHE`` if set, else ``$XDG_CACHE_HOME/orthoglide-pin``,
    else ``~/.cache/orthoglide-pin``.
    """
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "orthoglide-pin"


def _render(args: Mapping[str, str]) -> str:
    import xacro  # imported lazily: it is slow to import and keeps global state

    with _XACRO_LOCK:
        try:
            # xacro writes defaults into the mapping: hand it a copy.
            doc = xacro.process_file(str(xacro_path()), mappings=dict(args))
        except Exception as exc:  # xacro raises bare XacroException and others
            raise DescriptionError(f"xacro failed to render the description: {exc}") from exc
    return str(doc.toprettyxml(indent="  "))


def render_urdf(params: OrthoglideParams | None = None, *, use_cache: bool = True) -> str:
    """Render the URDF of a machine.

    Args:
        params: Machine parameters; the prototype when ``None``.
        use_cache: Look up and fill the memory and disk caches.

    Returns:
        The URDF document as a string.

    Raises:
        DescriptionError: If xacro fails.
    """
    params = prototype() if params is None else params
    if not use_cache:
        return _render(xacro_args(params))
    key = cache_key(params)
    if key in _MEMORY_CACHE:
        return _MEMORY_CACHE[key]
    path = cache_dir() / f"orthoglide-{key}.urdf"
    try:
        text = path.read_text()
    except OSError:
        text = _render(xacro_args(params))
        # A read-only cache is not an error: we still have the text.
        with contextlib.suppress(OSError):
            atomic_write_text(path, text)
    _MEMORY_CACHE[key] = text
    return text


def urdf_path(params: OrthoglideParams | None = None) -> Path:
    """Path of a rendered URDF file for ``params`` (in the disk cache).

    Raises:
        DescriptionError: If xacro fails or the cache directory is not writable.
    """
    params = prototype() if params is None else params
    text = render_urdf(params)
    path = cache_dir() / f"orthoglide-{cache_key(params)}.urdf"
    if not path.is_file():
        try:
            atomic_write_text(path, text)
        except OSError as exc:
            raise DescriptionError(f"cannot write URDF cache {path}: {exc}", str(path)) from exc
    return path


def write_urdf(path: str | Path, params: OrthoglideParams | None = None) -> Path:
    """Render the URDF of ``params`` and write it to ``path`` atomically."""
    path = Path(path)
    atomic_write_text(path, render_urdf(params))
    return path


def parameter_arguments() -> tuple[str, ...]:
    """Names of the xacro arguments, derived from the parameter names."""
    names: list[str] = []
    defaults = prototype().to_dict()
    for name in field_names():
        if isinstance(defaults[name], list):
            names.extend(name + s for s in _VECTOR_SUFFIXES)
        else:
            names.append(name)
    return tuple(names)
