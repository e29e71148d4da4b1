"""A self-contained description folder: the URDF, its loop data and its meshes.

:func:`write_package` (``orthoglide urdf --package-dir DIR``) writes::

    DIR/orthoglide.urdf          the URDF, mesh file names relative to DIR
    DIR/orthoglide.loops.yaml    the loop closures and actuated joints
    DIR/<kind><suffix>           each CAD mesh, copied (carriage.stl, bar.obj...)

so that another tool loads it as it is, from any working directory, without
ROS and without this package: yourdfpy resolves the mesh names against the
URDF's folder (``yourdfpy.URDF.load(DIR / "orthoglide.urdf")``), Pinocchio
against the package directories it is given (``pinocchio.buildGeomFromUrdf(
model, urdf, pinocchio.GeometryType.VISUAL, package_dirs=[DIR])``).

The folder is written whole and atomically, and only where allowed: a new or
empty directory, or one this package wrote (see
:func:`~orthoglide_pin._outdir.atomic_directory`); a non-empty directory it
did not write is refused and left as it was, unless forced (its other files
are then kept). An entry named like one of the folder's files that the
package did not write (a directory, or unless forced a file the folder's
marker does not list) is refused too, and nothing is removed.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import Final

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin._validation import flag, path_argument
from orthoglide_pin.exceptions import DescriptionError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.description import _render, loops_path, loops_text, xacro_args
from orthoglide_pin.machine.params import OrthoglideParams

#: Name of the URDF in a description folder.
PACKAGE_URDF: Final = "orthoglide.urdf"


def mesh_names(params: OrthoglideParams) -> dict[str, str]:
    """File name of each CAD mesh in a description folder: ``<kind><suffix>``.

    Args:
        params: Machine parameters (their ``meshes``).

    Returns:
        Part kind -> file name, e.g. ``{"carriage": "carriage.stl"}``.
    """
    return {kind: kind + mesh.file.suffix.lower() for kind, mesh in params.meshes.items()}


def package_urdf(params: OrthoglideParams | None = None) -> str:
    """The URDF of a description folder: mesh file names relative to the folder.

    Raises:
        DescriptionError: If xacro fails.
    """
    params = as_params(params)
    args = xacro_args(params)
    for kind, name in mesh_names(params).items():
        args[f"{kind}_mesh"] = name
    return _render(args)


def write_package(
    directory: str | os.PathLike[str],
    params: OrthoglideParams | None = None,
    *,
    force: bool = False,
) -> Path:
    """Write a self-contained description folder (see the module).

    Args:
        directory: The folder; created if needed.
        params: Machine parameters; the prototype when ``None``.
        force: Also write into a non-empty directory this package did not
            write (its other files are kept).

    Returns:
        The path of the URDF in the folder.

    Raises:
        OutputPathError: The folder is a non-empty directory that this package
            did not write, holds an entry in the way of one of its files that
            the package did not write, or is not writable (nothing is written
            or removed).
        DescriptionError: xacro fails, or a mesh file cannot be read.
    """
    params = as_params(params)
    directory = path_argument("directory", directory)
    force = flag("force", force)
    text = package_urdf(params)
    with atomic_directory(directory, force=force) as tmp:
        for kind, name in mesh_names(params).items():
            source = params.meshes[kind].file
            try:
                shutil.copyfile(source, tmp / name)
            except OSError as exc:
                raise DescriptionError(
                    f"cannot copy the mesh {source}: {exc}", str(source)
                ) from None
        atomic_write_text(loops_path(tmp / PACKAGE_URDF), loops_text(PACKAGE_URDF))
        atomic_write_text(tmp / PACKAGE_URDF, text)
    return Path(directory) / PACKAGE_URDF


__all__ = ["PACKAGE_URDF", "mesh_names", "package_urdf", "write_package"]
