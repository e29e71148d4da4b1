"""The machine in MuJoCo: the MJCF compiled, written, and set to a state of our dynamics.

:func:`compile_mjcf` gives MuJoCo's model of a document, :func:`write_mjcf`
writes one atomically once MuJoCo accepts it, and :func:`joint_order` /
:func:`mujoco_state` map a closed-loop state of Pinocchio's model (every joint,
loops closed, :class:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics`) to
MuJoCo's joint order, which is the URDF's (one coordinate per joint).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._lazy import optional_import
from orthoglide_pin._paths import given_path, output_file
from orthoglide_pin._validation import path_argument
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.exceptions import DescriptionError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.simulation.mjcf import mjcf_text

FloatArray = NDArray[np.float64]


def compile_mjcf(text: str) -> Any:
    """MuJoCo's model of an MJCF document (``mujoco.MjModel``).

    Raises:
        MissingExtraError: MuJoCo is not installed (the ``[sim]`` extra).
        DescriptionError: MuJoCo refuses the document (its message, one line).
    """
    mujoco = optional_import("mujoco", "sim", "the MJCF export")
    try:
        return mujoco.MjModel.from_xml_string(text)
    except ValueError as exc:
        message = " ".join(str(exc).split())
        raise DescriptionError(f"MuJoCo refuses the MJCF: {message}", message) from None


def write_mjcf(
    path: str | Path,
    params: OrthoglideParams | None = None,
    drive: Drive | None = None,
    *,
    gravity: ArrayLike | None = None,
) -> Path:
    """Write the MJCF of a design to ``path`` atomically (see :func:`mjcf_text`).

    MuJoCo compiles the document first: a file it would refuse is not
    written. Relative mesh names are resolved against the current directory
    and written as absolute paths.

    Returns:
        The path written.

    Raises:
        InvalidParameterError, DescriptionError: As :func:`mjcf_text`.
        OutputPathError: ``path`` is a directory or a special file.
        MissingExtraError: MuJoCo is not installed (the ``[sim]`` extra).
    """
    target = output_file(given_path(path_argument("path", path)))
    text = mjcf_text(params, drive, gravity=gravity, mesh_dir=Path.cwd())
    compile_mjcf(text)
    atomic_write_text(target, text)
    return target


def joint_order(model: Any, pinocchio_model: Any) -> NDArray[np.intp]:
    """Pinocchio's velocity index of each MuJoCo joint, shape (njnt,).

    Raises:
        DescriptionError: The two models do not have the same one-coordinate joints.
    """
    names = [model.joint(i).name for i in range(model.njnt)]
    if model.nq != model.njnt or model.nv != model.njnt or model.njnt != pinocchio_model.nv:
        raise DescriptionError("MuJoCo's and Pinocchio's joints differ", str(names))
    out = []
    for name in names:
        if not pinocchio_model.existJointName(name):
            raise DescriptionError(f"joint {name!r} is not in Pinocchio's model", name)
        jid = pinocchio_model.getJointId(name)
        if pinocchio_model.idx_qs[jid] != pinocchio_model.idx_vs[jid]:
            raise DescriptionError(f"joint {name!r} has other coordinates than velocities", name)
        out.append(pinocchio_model.idx_vs[jid])
    return np.asarray(out, dtype=np.intp)


def mujoco_state(
    order: NDArray[np.intp], q: ArrayLike, v: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """MuJoCo's ``qpos`` and ``qvel`` of Pinocchio's ``q`` and ``v`` (one coordinate a joint)."""
    return np.asarray(q, dtype=float)[order], np.asarray(v, dtype=float)[order]
