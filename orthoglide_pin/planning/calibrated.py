"""Slider commands of a calibrated machine: the real tool follows the program.

A built machine is not its drawing (:mod:`orthoglide_pin.calibration`). Planned
with a calibration (``plan --calibration FILE``), the sliders are commanded
through the **calibrated** kinematics, so that the real tool, not the drawing's,
follows the programmed path. Each leg ``i`` is the distance constraint
``||w_i|| = L_i``, ``w_i = p - a_i - q_i u_i``; differentiating it once and
twice along the tool motion ``(p, v, a)`` gives the slider motion in closed
form:

* ``q_i``: the calibrated inverse kinematics
  (:meth:`~orthoglide_pin.calibration.result.Calibration.inverse_kinematics`);
* ``qd_i = (J^-1 v)_i = w_i . v / (w_i . u_i)``, the calibrated inverse Jacobian
  (:meth:`~orthoglide_pin.calibration.model.GeometricModel.inverse_jacobian`);
* ``qdd_i = (J^-1 a)_i + ||v - qd_i u_i||^2 / (w_i . u_i)``.

The same formulas with ``(p', p'')`` of the path, ``'`` along the arc length,
give ``dq`` and ``ddq`` of the path forms
(:class:`~orthoglide_pin.dynamics.path_forms.PathForms`): the slider limits, the
motor speeds and the motors' inertia torque are planned and verified on the
calibrated commands. The slider **forces** stay those of the drawing's inertial
model at the programmed tool point: the geometric errors are tenths of a
millimetre, which change the masses' motion and the forces by a relative
amount of that order (about 1e-3), within the model's own accuracy.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.exceptions import OrthoglideError, ProgramError
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: A slider value this far beyond its limit is still inside [m], as the nominal check.
INSIDE_TOL = 1e-9


@runtime_checkable
class CalibratedKinematics(Protocol):
    """What a calibration offers (:class:`~orthoglide_pin.calibration.result.Calibration` does)."""

    @property
    def model(self) -> Any:
        """The identified geometry (``anchors``, ``directions``, ``inverse_jacobian``)."""

    def inverse_kinematics(self, points: Any) -> FloatArray:
        """Slider values [m] that put the real tool at ``points`` [m], (N, 3)."""

    def check_design(self, params: OrthoglideParams | None, what: str = ...) -> None:
        """Refuse another design than the one it was made for (``DesignMismatchError``)."""


def slider_motion(
    calibration: CalibratedKinematics, p: FloatArray, v: FloatArray, a: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Slider positions [m], speeds [m/s] and accelerations [m/s^2] that move the real tool.

    Args:
        calibration: The calibration.
        p: Tool points [m], (N, 3).
        v: Tool velocities [m/s], (N, 3) (or ``p'`` along a path [-]).
        a: Tool accelerations [m/s^2], (N, 3) (or ``p''`` along a path [1/m]).

    Returns:
        ``q``, ``qd``, ``qdd``, each (N, 3).
    """
    model = calibration.model
    q = calibration.inverse_kinematics(p)
    inv = model.inverse_jacobian(p)  # (N, 3, 3): rows w_i / (w_i . u_i)
    u = np.asarray(model.directions)
    w = p[:, None, :] - np.asarray(model.anchors) - q[:, :, None] * u
    wu = np.einsum("nij,ij->ni", w, u)
    qd = np.einsum("nij,nj->ni", inv, v)
    rel = v[:, None, :] - qd[:, :, None] * u  # v - qd_i u_i
    qdd = np.einsum("nij,nj->ni", inv, a) + np.einsum("nij,nij->ni", rel, rel) / wu
    return q, qd, qdd


def calibrated_forms(
    calibration: CalibratedKinematics,
    forms: PathForms,
    p: FloatArray,
    dp: FloatArray,
    ddp: FloatArray,
) -> PathForms:
    """The path forms with the calibrated ``q``, ``dq``, ``ddq`` (forces kept; see the module)."""
    q, dq, ddq = slider_motion(calibration, p, dp, ddp)
    return dataclasses.replace(forms, q=q, dq=dq, ddq=ddq)


def check_sliders(
    calibration: CalibratedKinematics,
    params: OrthoglideParams,
    points: FloatArray,
    lines: NDArray[np.intp],
) -> None:
    """Refuse the first point whose calibrated command leaves the slider limits.

    Raises:
        ProgramError: Naming the program line, the point in mm and the slider.
    """
    try:
        q = calibration.inverse_kinematics(points)
    except OrthoglideError:  # out of the built machine's reach: find the first such point
        for k in range(len(points)):
            try:
                calibration.inverse_kinematics(points[k : k + 1])
            except OrthoglideError as exc:
                why = " ".join(str(exc).split())
                raise ProgramError(int(lines[k]), f"the calibrated machine: {why}") from None
        raise  # pragma: no cover (the batch and the points agree)
    out = (q < params.slider_lower - INSIDE_TOL) | (q > params.slider_upper + INSIDE_TOL)
    if out.any():
        row, col = (int(i[0]) for i in np.nonzero(out))
        shown = ", ".join(f"{1e3 * x:.4f}" for x in points[row])
        raise ProgramError(
            int(lines[row]),
            f"the point ({shown}) mm needs slider {col + 1} of the calibrated machine at "
            f"{1e3 * q[row, col]:.4f} mm, outside its limits [{1e3 * params.slider_lower:.4f}, "
            f"{1e3 * params.slider_upper:.4f}] mm",
        )
