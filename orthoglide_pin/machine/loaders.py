"""One-line loaders of the machine for Pinocchio, yourdfpy and the closed-loop model.

Each loader takes the machine's parameters (an :class:`OrthoglideParams`, with
its prescribed workspace) or nothing for the prototype (anything else is an
:class:`~orthoglide_pin.exceptions.InvalidParameterError` naming ``params``),
renders the URDF through the cached xacro path, validates it with yourdfpy and
hands out the object a robotics user expects::

    import orthoglide_pin as og

    model, loops = og.load_pinocchio()            # pinocchio.Model + loop data
    robot = og.load_yourdfpy()                    # yourdfpy.URDF, scene built
    robot.scene.show()                            # or robot.scene.export("machine.glb")
    closed = og.load_closed_loop(og.prototype().replace(leg_length=0.35))

The URDF is a cut tree: Pinocchio and yourdfpy see a tree whose loops are given
beside it as data (:class:`~orthoglide_pin.machine.description.LoopSpec`), and
:func:`load_closed_loop` is the model with the loops closed for real.

Validation (:func:`validated_urdf`) runs yourdfpy's ``validate()`` on every
URDF handed out, and ``validate_filenames()`` when it refers to mesh files: a
description that fails raises :class:`~orthoglide_pin.exceptions.DescriptionError`
naming the element. Mesh file names are resolved without ROS: relative to
``mesh_dir`` (the URDF's folder), ``file://`` URIs, or through a resolver given
by the caller (``package://`` is refused without one).
"""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any
from urllib.parse import unquote, urlparse

from orthoglide_pin._validation import optional_callable
from orthoglide_pin.exceptions import DescriptionError, short_repr
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.description import LoopSpec, load_loops, render_urdf
from orthoglide_pin.machine.params import OrthoglideParams

if TYPE_CHECKING:
    import pinocchio as pin
    import yourdfpy

    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

#: Maps a mesh file name of the URDF to a path on disk.
Resolver = Callable[[str], str]


def mesh_resolver(mesh_dir: str | Path | None = None, package: Resolver | None = None) -> Resolver:
    """A resolver of URDF mesh file names that needs no ROS.

    Args:
        mesh_dir: Folder against which relative file names are resolved (the
            URDF's folder); the current directory when ``None``.
        package: Resolver of ``package://`` URIs; without it they are refused.

    Returns:
        ``f(filename) -> path``: relative names are joined to ``mesh_dir``,
        ``file://`` URIs decoded, absolute paths kept.

    Raises:
        DescriptionError: (from the resolver) for ``package://`` without
            ``package``, or another URI scheme.
    """
    base = Path.cwd() if mesh_dir is None else Path(mesh_dir)

    def resolve(fname: str) -> str:  # yourdfpy passes the keyword fname
        parsed = urlparse(fname)
        if parsed.scheme == "package":
            if package is None:
                raise DescriptionError(
                    f"mesh {short_repr(fname)} uses package://, which needs ROS: give a path "
                    "relative to the URDF, a file:// URI, or a package resolver",
                    fname,
                )
            return package(fname)
        if parsed.scheme == "file":
            return unquote(parsed.path)
        if parsed.scheme:
            raise DescriptionError(
                f"mesh {short_repr(fname)}: unsupported URI scheme {short_repr(parsed.scheme)} "
                "(allowed: a relative or absolute path, file://)",
                fname,
            )
        path = Path(fname)
        return str(path if path.is_absolute() else base / path)

    return resolve


def validated_urdf(
    urdf: str, *, resolver: Resolver | None = None, build_scene: bool = False
) -> yourdfpy.URDF:
    """Load a URDF string with yourdfpy and validate it.

    Args:
        urdf: The URDF document.
        resolver: Mesh file resolver (:func:`mesh_resolver` when ``None``).
        build_scene: Build the trimesh scene (and load the meshes).

    Returns:
        The yourdfpy robot.

    Raises:
        DescriptionError: The XML does not parse, ``validate()`` reports an
            error (named), or a mesh file is missing.
    """
    import yourdfpy

    resolve = mesh_resolver() if resolver is None else resolver
    try:
        robot = yourdfpy.URDF.load(
            io.BytesIO(urdf.encode()),
            build_scene_graph=build_scene,
            load_meshes=build_scene,
            filename_handler=lambda fname: resolve(fname),  # called with fname=
        )
    except DescriptionError:
        raise
    except Exception as exc:  # lxml and yourdfpy raise a variety of errors
        raise DescriptionError(f"the URDF does not load in yourdfpy: {exc}") from exc
    if not robot.validate(validation_fn=lambda errors: not errors):
        first = robot.errors[0] if robot.errors else "unknown error"
        raise DescriptionError(f"the URDF is not valid: {first}", str(first))
    if _has_meshes(robot) and not robot.validate_filenames():
        missing = next(name for name in _mesh_names(robot) if not Path(resolve(name)).is_file())
        raise DescriptionError(f"mesh file not found: {short_repr(missing)}", missing)
    return robot


def _mesh_names(robot: Any) -> list[str]:
    return [
        str(geometry.geometry.mesh.filename)
        for link in robot.robot.links
        for geometry in link.visuals + link.collisions
        if geometry.geometry is not None and geometry.geometry.mesh is not None
    ]


def _has_meshes(robot: Any) -> bool:
    return bool(_mesh_names(robot))


def load_yourdfpy(
    params: OrthoglideParams | None = None, *, resolver: Resolver | None = None
) -> yourdfpy.URDF:
    """The machine as a :class:`yourdfpy.URDF`, validated, with its scene built.

    Args:
        params: Machine parameters; the prototype when ``None``.
        resolver: Mesh file resolver (:func:`mesh_resolver` when ``None``).

    Returns:
        The robot at its zero configuration (the isotropic pose of the cut
        tree's sliders; the passive joints at zero do not close the loops: use
        :func:`load_closed_loop` for an assembled pose). ``robot.scene`` is
        ready for ``show()`` or ``export()``.

    Raises:
        DescriptionError: The description does not validate.
    """
    resolver = optional_callable("resolver", resolver, "a mesh file resolver or None")
    return validated_urdf(render_urdf(as_params(params)), resolver=resolver, build_scene=True)


def load_pinocchio(params: OrthoglideParams | None = None) -> tuple[pin.Model, LoopSpec]:
    """The machine's cut tree as a :class:`pinocchio.Model`, and its loop data.

    Args:
        params: Machine parameters; the prototype when ``None``.

    Returns:
        ``(model, loops)``: the Pinocchio model of the cut tree (18 joints) and
        the loop closures and actuated joints that close it.

    Raises:
        DescriptionError: The description does not validate or Pinocchio
            cannot load it.
    """
    from orthoglide_pin.machine.loading import load_model

    urdf = render_urdf(as_params(params))
    validated_urdf(urdf)
    return load_model(urdf), load_loops()  # masses checked against the URDF


def load_closed_loop(params: OrthoglideParams | None = None) -> ClosedLoopModel:
    """The closed-loop Pinocchio model (:class:`ClosedLoopModel`), validated.

    Args:
        params: Machine parameters; the prototype when ``None``.

    Returns:
        The model with its five closures, ready for ``solve``, ``jacobian``,
        dynamics and the viewer.

    Raises:
        DescriptionError: The description does not validate.
    """
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel

    params = as_params(params)
    urdf = render_urdf(params)
    validated_urdf(urdf)
    return ClosedLoopModel(params, urdf=urdf)


__all__ = [
    "Resolver",
    "load_closed_loop",
    "load_pinocchio",
    "load_yourdfpy",
    "mesh_resolver",
    "validated_urdf",
]
