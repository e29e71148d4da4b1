"""Identification of the 18 geometric parameters from measured tool positions.

Each pose ``n`` gives the slider values ``q_n`` (commanded, or read from the
encoders) and the tool position ``m_n`` measured in the world frame (a laser
tracker registered to it, say). The residual of a pose is
``r_n(theta) = P(q_n; theta) - m_n`` (3 numbers [m]), with ``P`` the direct
kinematics of :class:`~orthoglide_pin.calibration.model.GeometricModel`.

The fit, in three steps:

1. **Identifiability.** The identification Jacobian ``A = dr/dtheta`` at the
   nominal geometry, in physical units (``A S``, :func:`parameter_scales`), is
   split by its SVD. A singular value below ``RANK_TOL`` times the largest marks a
   combination of parameters that the poses cannot determine (too few poses,
   poses on a plane or a line); its right singular vector, brought back to the
   parameters' units (``S v``), is reported. The fit then runs in the
   identifiable subspace, ``theta = theta_0 + S V_r z``, so that the other
   combinations stay at their nominal values.
2. **A robust start.** ``scipy.optimize.least_squares`` (trust region) with the
   ``soft_l1`` loss, which turns linear beyond ``ROBUST_SCALE``: gross outliers
   pull on the estimate as little as possible. A pose is an outlier when its
   squared residual over the robust noise scale (``1.4826 MAD``) exceeds the
   chi-square quantile of 3 degrees of freedom at ``1 - OUTLIER_ALPHA``.
3. **Levenberg-Marquardt** (``method="lm"``) on the inliers, started from step
   2, repeated while the outlier set changes. The noise is
   ``sigma^2 = RSS / (3 n - r)`` with ``r`` the identified combinations, and
   the covariance of the parameters ``sigma^2 S V_r (J_z^T J_z)^-1 V_r^T S``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares
from scipy.stats import chi2

from orthoglide_pin._validation import finite_rows, flag, float_array, instance_of, size_within
from orthoglide_pin.calibration.model import PARAMETER_NAMES, PARAMETER_UNITS, GeometricModel
from orthoglide_pin.exceptions import CalibrationError, NoAssemblyError, OrthoglideError

FloatArray = NDArray[np.float64]

#: Relative singular value under which a combination counts as unidentifiable.
RANK_TOL: Final[float] = 1e-4
#: Residual [m] beyond which the robust start's loss turns linear.
ROBUST_SCALE: Final[float] = 5e-5
#: Probability that an inlier is wrongly taken for an outlier (chi-square test).
OUTLIER_ALPHA: Final[float] = 1e-4
#: Fewest poses accepted (at three residuals each, 30 numbers for 18 unknowns).
MIN_POSES: Final[int] = 10
#: Most poses identified at once, as a measurement CSV holds (a stacked Jacobian
#: of 100,000 poses is 43 MB).
MAX_POSES: Final[int] = 100_000
#: Most refits while the outlier set changes.
MAX_ROUNDS: Final[int] = 5
#: Coefficients of an unidentifiable combination smaller than this share of its
#: largest are left out of its description.
COMBINATION_CUTOFF: Final[float] = 0.05


@dataclass(frozen=True)
class Identification:
    """The result of :func:`identify`.

    Attributes:
        model: The identified geometry.
        nominal: The geometry the fit started from (the drawing).
        std: Standard deviation of each parameter [m or rad], shape (18,);
            0 for a parameter held entirely at its nominal value.
        noise_estimate: Estimated measurement noise, per axis [m].
        outliers: 0-based rows of the poses left out of the fit.
        unidentifiable: Combinations the poses cannot determine, each a
            mapping of parameter names to coefficients (unit vector in the
            scaled parameters); held at their nominal values.
        singular_values: Of the scaled identification Jacobian, descending.
        residuals_before: ``P(q; nominal) - measured``, shape (N, 3) [m].
        residuals_after: ``P(q; identified) - measured``, shape (N, 3) [m].
    """

    model: GeometricModel
    nominal: GeometricModel
    std: FloatArray
    noise_estimate: float
    outliers: tuple[int, ...]
    unidentifiable: tuple[dict[str, float], ...]
    singular_values: FloatArray
    residuals_before: FloatArray = field(repr=False)
    residuals_after: FloatArray = field(repr=False)

    @property
    def inliers(self) -> NDArray[np.bool_]:
        """Mask of the poses used in the fit, shape (N,)."""
        mask = np.ones(len(self.residuals_after), dtype=bool)
        mask[list(self.outliers)] = False
        return mask

    @property
    def rms_before(self) -> float:
        """RMS of the tool position error of the nominal model over the inliers [m]."""
        return _rms(self.residuals_before[self.inliers])

    @property
    def rms_after(self) -> float:
        """RMS of the tool position error of the identified model over the inliers [m]."""
        return _rms(self.residuals_after[self.inliers])


def _rms(residuals: FloatArray) -> float:
    """Root mean square of the 3D error norms [m]."""
    return float(math.sqrt(np.mean(np.einsum("ij,ij->i", residuals, residuals))))


def stacked_jacobian(model: GeometricModel, q: FloatArray) -> FloatArray:
    """``dr/dtheta`` for all poses stacked, shape (3 N, 18)."""
    return model.parameter_jacobian(q).reshape(-1, len(PARAMETER_NAMES))


def parameter_scales(leg_length: float) -> FloatArray:
    """``S``: 1 for a length, ``1 / L`` for an angle, shape (18,).

    In the scaled parameters ``S^-1 theta`` every entry is a length [m] (an
    angle counts as the displacement it causes at the end of a leg), so that
    the singular values of ``A S`` compare physical effects. Scaling each
    column to unit norm instead would blow up the effect of a parameter that
    the poses barely excite, and hide that it cannot be determined.
    """
    return np.array([1.0 if unit == "m" else 1.0 / leg_length for unit in PARAMETER_UNITS])


def combinations(vectors: FloatArray, scales: FloatArray) -> tuple[dict[str, float], ...]:
    """Name the parameter combinations of right singular vectors (rows)."""
    out = []
    for v in vectors:
        direction = scales * v
        direction /= np.max(np.abs(direction))
        keep = np.abs(direction) >= COMBINATION_CUTOFF
        out.append(
            {
                name: float(c)
                for name, c, k in zip(PARAMETER_NAMES, direction, keep, strict=True)
                if k
            }
        )
    return tuple(out)


def _outliers(residuals: FloatArray, sigma: float) -> NDArray[np.bool_]:
    """Poses whose squared residual over ``sigma^2`` fails the chi-square test."""
    threshold = float(chi2.ppf(1.0 - OUTLIER_ALPHA, df=3))
    score = np.einsum("ij,ij->i", residuals, residuals) / max(sigma, 1e-300) ** 2
    mask: NDArray[np.bool_] = score > threshold
    return mask


def _robust_sigma(residuals: FloatArray) -> float:
    """Noise scale per axis from the median absolute deviation [m]."""
    return float(1.4826 * np.median(np.abs(residuals - np.median(residuals, axis=0))))


def identify(
    q: ArrayLike,
    measured: ArrayLike,
    nominal: GeometricModel,
    *,
    allow_partial: bool = False,
) -> Identification:
    """Identify the geometry of a built machine from measured tool positions.

    Args:
        q: Slider values of the poses [m], shape (N, 3).
        measured: Tool positions measured in the world frame [m], shape (N, 3).
        nominal: The geometry of the drawing, the fit's start and the values
            of unidentifiable combinations.
        allow_partial: Hold unidentifiable combinations at their nominal
            values instead of refusing the data set.

    Returns:
        The identified geometry, its uncertainty and the diagnostics.

    Raises:
        InvalidParameterError: Bad arrays, or more than :data:`MAX_POSES` poses.
        CalibrationError: Fewer than :data:`MIN_POSES` poses, poses whose
            nominal direct kinematics fails, or (without ``allow_partial``)
            poses that cannot determine every parameter.
    """
    for name, value in (("q", q), ("measured", measured)):  # counted before read
        given = float_array(value)
        rows = given.shape[0] if given.ndim == 2 else 1
        size_within(name, given.shape, rows, MAX_POSES, "poses")
    qa, m = finite_rows("q", q, 3, "[m]"), finite_rows("measured", measured, 3, "[m]")
    instance_of("nominal", nominal, GeometricModel, "a GeometricModel (GeometricModel.nominal)")
    allow_partial = flag("allow_partial", allow_partial)
    n_par = len(PARAMETER_NAMES)
    if m.shape != qa.shape:
        raise CalibrationError(
            f"slider values q and measured points must both have shape (N, 3), "
            f"not {qa.shape} and {m.shape}"
        )
    if len(qa) < MIN_POSES:
        raise CalibrationError(f"{len(qa)} poses: at least {MIN_POSES} are needed", len(qa))
    theta0 = nominal.vector()
    try:
        before = nominal.direct_kinematics(qa) - m
        A = stacked_jacobian(nominal, qa)
    except NoAssemblyError as exc:
        raise CalibrationError(f"the nominal machine cannot reach a pose: {exc}") from None
    scales = parameter_scales(nominal.mean_length)
    _, sv, vt = np.linalg.svd(A * scales, full_matrices=True)
    sv_all = np.zeros(n_par)
    sv_all[: len(sv)] = sv
    rank = int(np.sum(sv_all > RANK_TOL * sv_all[0]))
    null = combinations(vt[rank:], scales)
    if null and not allow_partial:
        shown = "; ".join(" ".join(f"{c:+.3g} {k}" for k, c in combo.items()) for combo in null)
        raise CalibrationError(
            f"the poses cannot determine {len(null)} combination(s) of the parameters "
            f"(poses on a plane or a line, or too few): {shown}; measure poses spread over "
            "the cube, or pass --allow-partial to hold them at their nominal values",
            null,
        )
    basis = scales[:, np.newaxis] * vt[:rank].T  # (18, r): theta = theta0 + basis z

    def model_of(z: FloatArray) -> GeometricModel:
        return GeometricModel.from_vector(theta0 + basis @ z)

    def residual(z: FloatArray, rows: NDArray[np.bool_]) -> FloatArray:
        try:
            out: FloatArray = (model_of(z).direct_kinematics(qa[rows]) - m[rows]).ravel()
        except OrthoglideError:  # a trial step out of the model's domain
            out = np.full(3 * int(rows.sum()), 1.0)
        return out

    def jac(z: FloatArray, rows: NDArray[np.bool_]) -> FloatArray:
        try:
            full = stacked_jacobian(model_of(z), qa[rows])
        except OrthoglideError:
            full = stacked_jacobian(nominal, qa[rows])
        out: FloatArray = full @ basis
        return out

    everyone = np.ones(len(qa), dtype=bool)
    z = np.zeros(rank)
    start = least_squares(
        residual, z, jac=jac, args=(everyone,), method="trf", loss="soft_l1",
        f_scale=ROBUST_SCALE, x_scale="jac",
    )  # fmt: skip
    z = start.x
    after = model_of(z).direct_kinematics(qa) - m
    rows = ~_outliers(after, _robust_sigma(after))
    sigma = math.nan
    for _ in range(MAX_ROUNDS):
        if int(rows.sum()) * 3 <= rank:
            raise CalibrationError(
                f"only {int(rows.sum())} poses are not outliers: too few for {rank} parameters"
            )
        fit = least_squares(residual, z, jac=jac, args=(rows,), method="lm", x_scale="jac")
        z = fit.x
        after = model_of(z).direct_kinematics(qa) - m
        dof = 3 * int(rows.sum()) - rank
        sigma = math.sqrt(float(np.sum(after[rows] ** 2)) / max(dof, 1))
        new_rows = ~_outliers(after, sigma)
        if np.array_equal(new_rows, rows):
            break
        rows = new_rows
    jz = jac(z, rows)
    cov_z = sigma**2 * np.linalg.inv(jz.T @ jz)
    cov = basis @ cov_z @ basis.T
    std = np.sqrt(np.maximum(np.diag(cov), 0.0))
    return Identification(
        model=model_of(z),
        nominal=nominal,
        std=std,
        noise_estimate=sigma,
        outliers=tuple(int(i) for i in np.flatnonzero(~rows)),
        unidentifiable=null,
        singular_values=sv_all,
        residuals_before=before,
        residuals_after=after,
    )
