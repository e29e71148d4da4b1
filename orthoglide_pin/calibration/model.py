"""The geometric error model of a built Orthoglide: 18 parameters, closed forms.

With ideal parallelograms the platform only translates, and each leg is a
distance constraint between the tool point ``P`` and a point of its carriage::

    || P - a_i - q_i u_i || = L_i,        i = 1, 2, 3

with the carriage reference point ``a_i`` [m] (the joint point of the leg when
the slider reads 0), the unit slider direction ``u_i`` and the effective leg
length ``L_i`` [m]. The nominal machine has ``a_i = -L e_i``, ``u_i = e_i`` and
``L_i = L``: the closed form of :mod:`orthoglide_pin.kinematics.closed_form`.

The direction is held by two angles, for leg ``i`` with ``(i, j, k)`` cyclic::

    u_i = cos(beta_i) (cos(alpha_i) e_i + sin(alpha_i) e_j) + sin(beta_i) e_k

so ``alpha_i`` tilts the rail towards ``e_j`` and ``beta_i`` towards ``e_k``
[rad]. Per leg the parameters are ``(a_ix, a_iy, a_iz, alpha_i, beta_i, L_i)``,
18 in all (:data:`PARAMETER_NAMES`). This covers encoder offsets (a shift of
``a_i`` along ``u_i``), carriage and platform mount offsets, tilted rails and
leg-length errors. Parallelogram defects that would turn the platform are
outside the model.

Kinematics, vectorised over points (shapes ``(3,)`` or ``(N, 3)``):

* inverse: ``q_i = u_i . d_i - sqrt((u_i . d_i)^2 - |d_i|^2 + L_i^2)``,
  ``d_i = P - a_i`` (the working branch, ``q_i = p_i + L - eta_i`` when
  nominal);
* direct: the intersection of the three spheres of centres
  ``c_i = a_i + q_i u_i`` and radii ``L_i`` (trilateration), on the side of the
  plane of the centres where the nominal home pose lies;
* Jacobian: from ``F_i = |P - c_i|^2 - L_i^2 = 0``, row ``i`` of ``J^-1`` is
  ``w_i^T / (w_i . u_i)`` with ``w_i = P - c_i``, the paper's eq. 2 when
  nominal;
* the identification Jacobian ``dP/dtheta`` at fixed slider values, by the
  implicit function theorem: ``dP/dtheta = -(dF/dP)^-1 dF/dtheta``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_vector, points_array, positive_length
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    NoAssemblyError,
    SingularConfigurationError,
    UnreachablePointError,
)
from orthoglide_pin.machine.legs import LegGeometry

FloatArray = NDArray[np.float64]

#: Names of the 18 parameters, in the order of :meth:`GeometricModel.vector`.
PARAMETER_NAMES: Final[tuple[str, ...]] = tuple(
    name
    for i in (1, 2, 3)
    for name in (f"a{i}_x", f"a{i}_y", f"a{i}_z", f"alpha{i}", f"beta{i}", f"L{i}")
)
#: Unit of each parameter, by position in a leg's six.
PARAMETER_UNITS: Final[tuple[str, ...]] = ("m", "m", "m", "rad", "rad", "m") * 3
#: Parameters per leg.
PER_LEG: Final[int] = 6
#: A leg whose ``w_i . u_i`` falls below this fraction of ``L_i`` is orthogonal
#: to its rail (serial singularity), as ``SERIAL_TOL`` of the closed form.
SERIAL_TOL: Final[float] = 1e-9
#: Height of the tool above the plane of the sphere centres, relative to the
#: mean leg length, below which the three legs count as coplanar.
PARALLEL_TOL: Final[float] = 1e-9
#: Largest tilt of a rail accepted by the model [rad]: a built machine is close
#: to its drawing, and the direct kinematics' branch rule assumes it.
MAX_TILT: Final[float] = 0.2

_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


def _directions(alpha: FloatArray, beta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Unit directions ``u_i`` (3, 3) and their derivatives by alpha and beta."""
    u, du_da, du_db = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
    for i, j, k in _CYCLIC:
        ca, sa, cb, sb = np.cos(alpha[i]), np.sin(alpha[i]), np.cos(beta[i]), np.sin(beta[i])
        u[i, i], u[i, j], u[i, k] = cb * ca, cb * sa, sb
        du_da[i, i], du_da[i, j] = -cb * sa, cb * ca
        du_db[i, i], du_db[i, j], du_db[i, k] = -sb * ca, -sb * sa, cb
    return u, du_da, du_db


@dataclass(frozen=True)
class GeometricModel:
    """The 18-parameter geometry of one built Orthoglide.

    Attributes:
        anchors: Carriage reference points ``a_i`` as rows [m], shape (3, 3).
        alpha: First tilt angle of each rail [rad], shape (3,).
        beta: Second tilt angle of each rail [rad], shape (3,).
        lengths: Effective leg lengths ``L_i`` [m], shape (3,).
    """

    anchors: FloatArray
    alpha: FloatArray
    beta: FloatArray
    lengths: FloatArray

    def __post_init__(self) -> None:
        anchors = points_array(self.anchors, "anchors")
        if anchors.shape != (3, 3):
            raise InvalidParameterError("anchors.shape", anchors.shape, "(3, 3) [m]")
        alpha = finite_vector("alpha", self.alpha, 3, "[rad]")
        beta = finite_vector("beta", self.beta, 3, "[rad]")
        for name, angles in (("alpha", alpha), ("beta", beta)):
            if np.any(np.abs(angles) > MAX_TILT):
                raise InvalidParameterError(name, angles, f"tilts within +-{MAX_TILT} rad")
        lengths = finite_vector("lengths", self.lengths, 3, "[m]")
        for value in lengths:
            positive_length("lengths", value)
        for name, value in (
            ("anchors", anchors),
            ("alpha", alpha),
            ("beta", beta),
            ("lengths", lengths),
        ):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    # ----------------------------------------------------------- construction
    @classmethod
    def nominal(cls, leg_length: float) -> GeometricModel:
        """The drawing: ``a_i = -L e_i``, ``u_i = e_i``, ``L_i = L``."""
        L = positive_length("leg_length", leg_length)
        return cls(-L * np.eye(3), np.zeros(3), np.zeros(3), np.full(3, L))

    @classmethod
    def from_vector(cls, theta: ArrayLike) -> GeometricModel:
        """The model of a parameter vector in :data:`PARAMETER_NAMES` order."""
        t = finite_vector("theta", theta, 3 * PER_LEG).reshape(3, PER_LEG)
        return cls(t[:, :3].copy(), t[:, 3].copy(), t[:, 4].copy(), t[:, 5].copy())

    def vector(self) -> FloatArray:
        """The 18 parameters in :data:`PARAMETER_NAMES` order, shape (18,)."""
        t = np.column_stack([self.anchors, self.alpha, self.beta, self.lengths])
        return t.reshape(-1)

    def legs(self, leg_length: float) -> LegGeometry:
        """This geometry for the description of a drawing of leg ``leg_length`` [m].

        ``render_urdf(params, legs=model.legs(params.leg_length))`` draws the
        built machine; its closed-loop Pinocchio model then agrees with this
        model's kinematics.
        """
        return LegGeometry.from_points(self.anchors, self.directions, self.lengths, leg_length)

    @property
    def directions(self) -> FloatArray:
        """Unit slider directions ``u_i`` as rows, shape (3, 3)."""
        return _directions(self.alpha, self.beta)[0]

    @property
    def mean_length(self) -> float:
        """Mean of the three leg lengths [m]."""
        return float(np.mean(self.lengths))

    # ------------------------------------------------------------- kinematics
    def inverse_kinematics(self, points: ArrayLike) -> FloatArray:
        """Slider values of the working branch for tool points.

        Args:
            points: Tool points [m], shape (3,) or (N, 3).

        Returns:
            Slider values [m], the shape of ``points``.

        Raises:
            UnreachablePointError: First point out of reach of a leg.
            SingularConfigurationError: First point where a leg is orthogonal
                to its rail.
        """
        p = points_array(points, "points")
        d = p[..., np.newaxis, :] - self.anchors  # (..., 3, 3): d_i = P - a_i
        ud = np.einsum("...ij,ij->...i", d, self.directions)
        disc = ud * ud - np.einsum("...ij,...ij->...i", d, d) + self.lengths**2
        bad = disc < 0.0
        if bad.any():
            idx = int(np.argmax(bad.reshape(-1, 3).any(axis=1)))
            leg = int(np.argmax(bad.reshape(-1, 3)[idx])) + 1
            raise UnreachablePointError(
                p.reshape(-1, 3)[idx], leg, "its rail is farther than the leg's length"
            )
        eta = np.sqrt(disc)
        if (eta <= SERIAL_TOL * self.lengths).any():
            flat = (eta <= SERIAL_TOL * self.lengths).reshape(-1, 3)
            idx = int(np.argmax(flat.any(axis=1)))
            leg = int(np.argmax(flat[idx])) + 1
            why = "the leg is orthogonal to its rail"
            raise SingularConfigurationError(p.reshape(-1, 3)[idx], leg, "serial", why)
        q: FloatArray = ud - eta
        return q

    def direct_kinematics(self, q: ArrayLike) -> FloatArray:
        """Tool points for slider values, by trilateration (working assembly).

        The centres ``c_i = a_i + q_i u_i`` span a plane; with ``c_1`` as
        origin and the orthonormal frame ``(x, y, n)`` of that plane, the tool
        point is ``c_1 + X x + Y y + h n`` with ``X, Y`` from the two linear
        sphere differences and ``h = sqrt(L_1^2 - X^2 - Y^2) > 0`` on the side
        of the nominal home pose (``n`` along ``(c_2 - c_1) x (c_3 - c_1)``).

        Args:
            q: Slider values [m], shape (3,) or (N, 3).

        Returns:
            Tool points [m], the shape of ``q``.

        Raises:
            NoAssemblyError: First ``q`` where the spheres do not meet or the
                centres are aligned.
        """
        qa = points_array(q, "q")
        c = self.anchors + qa[..., :, np.newaxis] * self.directions  # (..., 3, 3)
        e12, e13 = c[..., 1, :] - c[..., 0, :], c[..., 2, :] - c[..., 0, :]
        d = np.linalg.norm(e12, axis=-1)
        with np.errstate(all="ignore"):
            ex = e12 / d[..., np.newaxis]
            i_ = np.einsum("...k,...k->...", ex, e13)
            ey_raw = e13 - i_[..., np.newaxis] * ex
            j_ = np.linalg.norm(ey_raw, axis=-1)
            ey = ey_raw / j_[..., np.newaxis]
            ez = np.cross(ex, ey)
            L1, L2, L3 = self.lengths
            x = (L1**2 - L2**2 + d**2) / (2.0 * d)
            y = (L1**2 - L3**2 + i_**2 + j_**2) / (2.0 * j_) - (i_ / j_) * x
            h2 = L1**2 - x**2 - y**2
        bad = ~np.isfinite(h2) | (h2 < 0.0) | ~(j_ > SERIAL_TOL * self.mean_length)
        if bad.any():
            idx = int(np.argmax(bad.reshape(-1)))
            why = "the leg spheres do not meet" if np.isfinite(h2.reshape(-1)[idx]) else ""
            raise NoAssemblyError(qa.reshape(-1, 3)[idx], why or "the rail points are aligned")
        h = np.sqrt(h2)
        if (h <= PARALLEL_TOL * self.mean_length).any():
            idx = int(np.argmax((h <= PARALLEL_TOL * self.mean_length).reshape(-1)))
            raise NoAssemblyError(
                qa.reshape(-1, 3)[idx], "the legs are coplanar (parallel singularity)"
            )
        p: FloatArray = (
            c[..., 0, :]
            + x[..., np.newaxis] * ex
            + y[..., np.newaxis] * ey
            + h[..., np.newaxis] * ez
        )
        return p

    def _legs(self, points: FloatArray, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``w_i = P - c_i`` (..., 3, 3) and ``w_i . u_i`` (..., 3)."""
        w = points[..., np.newaxis, :] - self.anchors - q[..., :, np.newaxis] * self.directions
        return w, np.einsum("...ij,ij->...i", w, self.directions)

    def inverse_jacobian(self, points: ArrayLike) -> FloatArray:
        """``J^-1 = dq/dP`` at tool points, shape (3, 3) or (N, 3, 3)."""
        p = points_array(points, "points")
        w, wu = self._legs(p, self.inverse_kinematics(p))
        out: FloatArray = w / wu[..., np.newaxis]
        return out

    def jacobian(self, points: ArrayLike) -> FloatArray:
        """``J = dP/dq`` at tool points, shape (3, 3) or (N, 3, 3)."""
        inv = self.inverse_jacobian(points)
        det = np.linalg.det(inv)
        if not np.all(np.abs(det) > PARALLEL_TOL):
            idx = int(np.argmax(~(np.abs(det) > PARALLEL_TOL).reshape(-1)))
            point = points_array(points, "points").reshape(-1, 3)[idx]
            raise SingularConfigurationError(point, None, "parallel", "J^-1 is singular")
        out: FloatArray = np.linalg.inv(inv).astype(np.float64, copy=False)
        return out

    def parameter_jacobian(self, q: ArrayLike, points: ArrayLike | None = None) -> FloatArray:
        """``dP/dtheta`` at fixed slider values, shape (N, 3, 18) [m per unit].

        Args:
            q: Slider values [m], shape (N, 3) (or (3,)).
            points: The tool points of ``q`` [m], when already known (saves a
                direct kinematics); computed otherwise.

        Returns:
            The tool point's derivative by each parameter, in
            :data:`PARAMETER_NAMES` order: [m/m] for lengths, [m/rad] for
            angles; shape (N, 3, 18) (or (3, 18) for a single ``q``).
        """
        qa = points_array(q, "q")
        single = qa.ndim == 1
        qa = qa.reshape(-1, 3)
        p = self.direct_kinematics(qa) if points is None else points_array(points, "points")
        p = p.reshape(-1, 3)
        w, _ = self._legs(p, qa)  # (N, 3, 3)
        _, du_da, du_db = _directions(self.alpha, self.beta)
        n = len(qa)
        dF = np.zeros((n, 3, 3 * PER_LEG))  # dF_i/dtheta, F_i = |w_i|^2 - L_i^2 (halved)
        for i in range(3):
            col = PER_LEG * i
            dF[:, i, col : col + 3] = -w[:, i, :]
            dF[:, i, col + 3] = -qa[:, i] * (w[:, i, :] @ du_da[i])
            dF[:, i, col + 4] = -qa[:, i] * (w[:, i, :] @ du_db[i])
            dF[:, i, col + 5] = -self.lengths[i]
        out: FloatArray = -np.linalg.solve(w, dF).astype(np.float64, copy=False)  # dF/dP = w
        return out[0] if single else out
