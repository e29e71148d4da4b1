"""The error budget at points of the part: what each source moves the tool by.

Four terms, each a vector [m] (world frame) at every point, each optional:

* ``geometric``: what a calibration leaves, the identified parameters'
  standard deviations (:attr:`~orthoglide_pin.calibration.result.Calibration.std`)
  propagated to the tool through the sensitivities
  (:func:`~orthoglide_pin.calibration.sensitivities.sensitivity`): per world
  axis, the one-sigma tool error ``sqrt(diag(S diag(std^2) S^T))``;
* ``servo``: the servo's contour error (a simulation's, given as an array:
  vectors, or distances put along the surface normal given);
* ``compliance``: the tool's static deflection under the cutting force
  (:mod:`~orthoglide_pin.machining.surface_error`);
* ``thermal``: a uniform temperature rise ``dT`` [K]. Each ball screw, fixed
  at the lower end of its stroke, grows by ``alpha_s dT (q_i - q_lower)``, so
  slider ``i`` stands that much further along ``+e_i`` than commanded (at most
  ``alpha_s dT`` times the stroke: 3.0 um per kelvin on the prototype's 257 mm);
  the spindle grows along the tool offset (``alpha_s dT`` times it), and the
  platform's leg attachments move out by ``alpha_p dT`` times the
  ``platform_offset``. With every leg's end kept on its sphere to first order
  (``u_i . dp = u_i . (dq_i e_i + delta_i)``, ``u_i`` the leg's vector), the
  tool moves by ``dp``. ``alpha_s`` = :data:`STEEL_EXPANSION` (steel screws
  and spindle), ``alpha_p`` = :data:`ALUMINIUM_EXPANSION` (the platform's
  material is aluminium by default: density 2700 kg/m^3).

The terms combine as the **worst case** (the sum of their norms: every source
at its worst, aligned) and the **root sum of squares** (independent sources);
the **dominant** term at a point is the one of largest norm.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, float_array, instance_of, number_in
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.kinematics.closed_form import inverse_kinematics, leg_vectors
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams

if TYPE_CHECKING:  # the calibration layer imports scipy: loaded when a calibration is given
    from orthoglide_pin.calibration.result import Calibration

FloatArray = NDArray[np.float64]

#: Thermal expansion of steel (screws, spindle) [1/K] (carbon steel, 20 to 100 C).
STEEL_EXPANSION: Final[float] = 11.5e-6
#: Thermal expansion of aluminium alloys (the platform) [1/K].
ALUMINIUM_EXPANSION: Final[float] = 23.0e-6
#: The terms of the budget, in order.
TERMS: Final = ("geometric", "servo", "compliance", "thermal")
#: Largest temperature rise accepted [K].
MAX_TEMPERATURE_RISE: Final[float] = 100.0


@dataclass(frozen=True)
class ErrorBudget:
    """The error budget at ``n`` points.

    Attributes:
        points: The points [m], (n, 3), world frame.
        terms: Term name -> tool error [m], (n, 3), for the terms given
            (of :data:`TERMS`).
        worst_case: Sum of the terms' norms [m], (n,).
        rss: Root sum of squares of the terms' norms [m], (n,).
        dominant: Name of the term of largest norm at each point, (n,) (``""``
            when no term is given).
    """

    points: FloatArray
    terms: dict[str, FloatArray]
    worst_case: FloatArray
    rss: FloatArray
    dominant: tuple[str, ...]

    def norms(self) -> dict[str, FloatArray]:
        """Term name -> norm of its vector [m], (n,)."""
        return {k: np.linalg.norm(v, axis=1) for k, v in self.terms.items()}

    def summary(self) -> dict[str, object]:
        """Largest norm of each term, of the combinations, and how often each dominates."""
        norms = self.norms()
        count = {k: int(sum(d == k for d in self.dominant)) for k in self.terms}
        return {
            "max": {k: float(v.max(initial=0.0)) for k, v in norms.items()},
            "worst_case_max": float(self.worst_case.max(initial=0.0)),
            "rss_max": float(self.rss.max(initial=0.0)),
            "dominant_count": count,
        }


def geometric_error(
    calibration: Calibration, points: FloatArray, params: OrthoglideParams
) -> FloatArray:
    """One-sigma tool error per world axis left by a calibration [m], (n, 3) (see the module)."""
    from orthoglide_pin.calibration.sensitivities import sensitivity

    s = sensitivity(params, points)  # (n, 3, 18)
    std = np.asarray(calibration.std, dtype=np.float64)
    return np.asarray(np.sqrt(np.einsum("nij,j->ni", s * s, std * std)), dtype=np.float64)


def thermal_error(
    points: FloatArray,
    params: OrthoglideParams,
    temperature_rise: float,
    *,
    screw_expansion: float = STEEL_EXPANSION,
    spindle_expansion: float = STEEL_EXPANSION,
    platform_expansion: float = ALUMINIUM_EXPANSION,
) -> FloatArray:
    """The tool's displacement under a uniform temperature rise [m], (n, 3) (see the module).

    Args:
        points: Tool points [m], (n, 3).
        params: The machine.
        temperature_rise: dT [K].
        screw_expansion: The screws' expansion coefficient [1/K].
        spindle_expansion: The spindle's (along the tool offset) [1/K].
        platform_expansion: The platform's (the leg attachments) [1/K].
    """
    dt = float(temperature_rise)
    q = inverse_kinematics(points, params.leg_length)  # (n, 3)
    lower = float(params.slider_lower)
    dq = screw_expansion * dt * (q - lower)  # each screw grows from its fixed end
    u = leg_vectors(points, params.leg_length)  # (n, 3 legs, 3)
    spindle = spindle_expansion * dt * np.asarray(params.tool_offset, dtype=np.float64)
    eye = np.eye(3)
    # leg i's end on the platform is at P - tool_offset - platform_offset e_i: it moves
    # by -(growth of that vector) relative to P; the slider's joint by dq_i e_i
    delta = -(spindle[None, :] + platform_expansion * dt * params.platform_offset * eye)
    b = np.einsum("nij,nij->ni", u, dq[:, :, None] * eye[None] - delta[None])
    return np.asarray(np.linalg.solve(u, b[..., None])[..., 0], dtype=np.float64)


def _servo(servo: ArrayLike, normals: ArrayLike | None, n: int) -> FloatArray:
    arr = float_array(servo)
    if arr.shape == (n, 3) and np.isfinite(arr).all():
        return arr
    if arr.shape == (n,) and np.isfinite(arr).all():
        if normals is None:
            raise InvalidParameterError(
                "normals", None, "the surface normals (n, 3) to place servo distances along"
            )
        return arr[:, None] * finite_rows("normals", normals, 3)
    raise InvalidParameterError("servo", servo, f"{n} distances or (n, 3) vectors [m]")


def error_budget(
    points: ArrayLike,
    params: OrthoglideParams | None = None,
    *,
    compliance: ArrayLike | None = None,
    servo: ArrayLike | None = None,
    normals: ArrayLike | None = None,
    calibration: Calibration | None = None,
    temperature_rise: float | None = None,
) -> ErrorBudget:
    """The error budget at tool points (see the module).

    Args:
        points: Tool points [m], (n, 3), world frame.
        params: The machine (the prototype when ``None``).
        compliance: The tool's static deflection [m], (n, 3), or ``None``.
        servo: The contour error [m]: (n, 3) vectors, or (n,) distances placed
            along ``normals``; or ``None``.
        normals: Unit surface normals (n, 3) for servo distances.
        calibration: A calibration of this machine, or ``None``.
        temperature_rise: Uniform temperature rise [K] in [-100, 100], or ``None``.

    Returns:
        The terms given, their worst-case and root-sum-of-squares combinations,
        and the dominant term at each point.

    Raises:
        InvalidParameterError: Bad points or terms of another shape.
        DesignMismatchError: The calibration was made for another design.
    """
    p = finite_rows("points", points, 3, "[m]")
    machine = as_params(params)
    n = p.shape[0]
    terms: dict[str, FloatArray] = {}
    if calibration is not None:
        from orthoglide_pin.calibration.result import Calibration

        instance_of("calibration", calibration, Calibration, "a Calibration (load_calibration)")
        calibration.check_design(machine)
        terms["geometric"] = geometric_error(calibration, p, machine)
    if servo is not None:
        terms["servo"] = _servo(servo, normals, n)
    if compliance is not None:
        c = float_array(compliance)
        if c.shape != (n, 3) or not np.isfinite(c).all():
            raise InvalidParameterError("compliance", compliance, f"({n}, 3) deflections [m]")
        terms["compliance"] = c
    if temperature_rise is not None:
        rise = number_in("temperature_rise", temperature_rise, -MAX_TEMPERATURE_RISE,
                         MAX_TEMPERATURE_RISE, "[K]")  # fmt: skip
        terms["thermal"] = thermal_error(p, machine, rise)
    norms = (
        np.stack([np.linalg.norm(v, axis=1) for v in terms.values()], axis=1)
        if terms
        else (np.zeros((n, 0)))
    )
    names = list(terms)
    dominant = tuple(names[int(k)] for k in np.argmax(norms, axis=1)) if names else ("",) * n
    return ErrorBudget(p, terms, norms.sum(axis=1), np.sqrt((norms**2).sum(axis=1)), dominant)
