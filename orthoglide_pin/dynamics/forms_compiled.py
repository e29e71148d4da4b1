"""The path forms of the leg expansion in one compiled loop over the points (numba).

:func:`~orthoglide_pin.dynamics.path_forms.path_forms` computes, in arrays
block by block, the slider values, the joint functions' derivatives along the
path (:func:`~orthoglide_pin.kinematics.joint_motion.path_motion`), the leg
expansion's basis and coefficients
(:class:`~orthoglide_pin.dynamics.leg_harmonics.LegHarmonics`), the Jacobian
(:func:`~orthoglide_pin.kinematics.closed_form.ik_and_jacobian`) and the
forces; it also checks the points against the slider limits (one more
inverse kinematics) and the forms for finiteness. Each step makes arrays of
(legs, terms, points) numbers. :func:`forms_compiled` runs the same formulas
point by point, with every intermediate in registers, and the same checks:
at a point where any of them fails or comes near failing (an unreachable or
nearly serially or parallel singular point, a slider beyond half the
tolerance past its limit, a form that is not finite) it stops and says
where, and the caller takes the array route, which raises the right error
(or gives the same numbers). The sums are those of the array version in the
same order but the expansion's (a matrix product there), so the forms agree
with it to rounding (``tests/dynamics/test_forms_compiled.py``).

numba comes with the ``[plan]`` extra; without it (:data:`AVAILABLE` false)
the array route runs alone.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

numba: Any
try:  # numba is optional: the array route runs without it
    import numba
except ImportError:  # pragma: no cover - exercised where numba is missing
    numba = None

#: Whether the compiled loop can run (numba is installed).
AVAILABLE: Final[bool] = numba is not None
#: The checks' margin: a point this close (as a factor on the tolerance) to
#: failing one takes the array route, which decides [-].
MARGIN: Final[float] = 2.0
#: Points whose expansion sums are taken together (the scratch stays in the cache).
CHUNK: Final[int] = 64


def _jit(function: Callable[..., Any]) -> Callable[..., Any]:
    """``function`` compiled by numba on first use (cached on disk where it can be)."""
    assert numba is not None
    options = {"nogil": True, "error_model": "numpy"}  # x / 0: inf or nan, as in numpy
    try:
        return numba.njit(cache=True, **options)(function)  # type: ignore[no-any-return,unused-ignore]
    except RuntimeError:  # numba found no folder to cache in
        return numba.njit(**options)(function)  # type: ignore[no-any-return,unused-ignore]


def _point(
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    i: int,
    ii: int,
    bounds: FloatArray,
    scratch: FloatArray,
    jac: FloatArray,
    motion: FloatArray,
    out: FloatArray,
) -> bool:
    """Point ``i`` (slot ``ii`` of its chunk): checks, Jacobian, joint motion.

    ``scratch`` (3, 3): eta, beta, cofactors. Fills ``jac[ii]`` (3, 3),
    ``motion[:, :, ii]`` (per leg: ``f'`` (3), ``f''`` (3), the theta and phi
    gradients (3), ``cos theta``, ``sin theta``, ``cos phi``, ``sin phi``) and the
    slider rows of ``out``; false where a check fails.
    """
    L, q_lo, q_hi, eta_min, det_max = bounds[0], bounds[1], bounds[2], bounds[3], bounds[4]
    eta, beta, cof = scratch[0], scratch[1], scratch[2]
    for a in range(3):  # inverse kinematics: eta_a from the two other coordinates
        b, c = (a + 1) % 3, (a + 2) % 3
        rad = L * L - (p[i, b] * p[i, b] + p[i, c] * p[i, c])
        if not rad >= 0.0:
            return False
        eta[a] = math.sqrt(rad)
        q_check = p[i, a] + (L - eta[a])  # as the slider-limit check computes it
        if not (eta[a] > eta_min and q_lo <= q_check <= q_hi):
            return False
        beta[a] = p[i, a] - eta[a]
    for a in range(3):  # the Jacobian as ik_and_jacobian: adjugate over determinant
        b, c = (a + 1) % 3, (a + 2) % 3
        cof[a] = eta[b] * eta[c] - p[i, b] * p[i, c]
    inv = 1.0 / ((p[i, 1] * beta[2] + p[i, 2] * beta[1]) * p[i, 0] + eta[0] * cof[0])
    if not abs(inv) <= det_max:
        return False
    for a in range(3):
        f = eta[a] * inv
        jac[ii, a, a] = cof[a] * f
        w = p[i, a] * f
        for r in range(3):
            if r != a:
                jac[ii, r, a] = beta[3 - r - a] * w
    for leg in range(3):  # path_motion, leg coordinates (x, y, z) = LEG_AXES[leg]
        ax, ay, az = leg, (leg + 1) % 3, (leg + 2) % 3
        y, z, e = p[i, ay], p[i, az], eta[leg]
        yd, zd, ydd, zdd = t[i, ay], t[i, az], k[i, ay], k[i, az]
        c2 = L * L - y * y
        cc = math.sqrt(c2)
        ed = -(y * yd + z * zd) / e
        edd = -(yd * yd + zd * zd + y * ydd + z * zdd + ed * ed) / e
        phd = yd / cc
        thd = (z * ed - e * zd) / c2
        m = motion[leg]
        m[0, ii], m[1, ii], m[2, ii] = t[i, ax] - ed, thd, phd
        m[3, ii] = k[i, ax] - edd
        m[4, ii] = (z * edd - e * zdd + 2.0 * y * yd * thd) / c2
        m[5, ii] = (ydd + y * phd * phd) / cc
        m[6, ii], m[7, ii], m[8, ii] = -y * z / (e * c2), -1.0 / e, 1.0 / cc
        out[0, i, leg], out[1, i, leg], out[2, i, leg] = p[i, ax] + L - e, m[0, ii], m[3, ii]
        # cos and sin of theta and phi, for the expansion's basis
        m[9, ii], m[10, ii], m[11, ii], m[12, ii] = e / cc, -z / cc, cc / L, y / L
    return True


def _basis(
    harmonics: NDArray[np.intp],
    motion: FloatArray,
    powers: FloatArray,
    basis: FloatArray,
    size: int,
) -> None:
    """The expansion's basis of a chunk's points, by powers of ``e^(i theta)`` and ``e^(i phi)``.

    As :meth:`~orthoglide_pin.dynamics.leg_harmonics.LegHarmonics.basis`, the
    points innermost; ``powers`` (2, top + 1, 2, CHUNK): real and imaginary parts.
    """
    for leg in range(3):
        m = motion[leg]
        for angle in range(2):  # theta, then phi
            c, s, pw = m[9 + 2 * angle], m[10 + 2 * angle], powers[angle]
            for ii in range(size):
                pw[0, 0, ii], pw[0, 1, ii] = 1.0, 0.0
            for j in range(pw.shape[0] - 1):
                re, im, re1, im1 = pw[j, 0], pw[j, 1], pw[j + 1, 0], pw[j + 1, 1]
                for ii in range(size):
                    re1[ii] = re[ii] * c[ii] - im[ii] * s[ii]
                    im1[ii] = re[ii] * s[ii] + im[ii] * c[ii]
        out = basis[leg]
        for ii in range(size):
            out[0, ii] = 1.0
        for j in range(harmonics.shape[0]):
            kt, kp = harmonics[j, 0], harmonics[j, 1]
            ar, ai = powers[0, kt, 0], powers[0, kt, 1]
            br, bi = powers[1, abs(kp), 0], powers[1, abs(kp), 1]
            real, imag = out[2 * j + 1], out[2 * j + 2]
            if kp < 0:  # the conjugate of e^(i |kp| phi)
                for ii in range(size):
                    real[ii] = ar[ii] * br[ii] - ai[ii] * -bi[ii]
                    imag[ii] = ar[ii] * -bi[ii] + ai[ii] * br[ii]
            else:
                for ii in range(size):
                    real[ii] = ar[ii] * br[ii] - ai[ii] * bi[ii]
                    imag[ii] = ar[ii] * bi[ii] + ai[ii] * br[ii]


def _forces(
    i: int,
    ii: int,
    f_ext: FloatArray,
    legs: NDArray[np.intp],
    jac: FloatArray,
    motion: FloatArray,
    values: FloatArray,
    tau: FloatArray,
    out: FloatArray,
) -> bool:
    """The forces of point ``i`` from its chunk's rows (see :func:`_point`); false if not finite.

    ``tau`` (3, 3, 3): per form, leg and function; ``values[leg, :, ii]``: ``M_f``
    (9), the velocity terms (9), ``Gamma g`` (3).
    """
    for leg in range(3):
        m, v = motion[leg], values[leg]
        f0, f1, f2, s0, s1, s2 = m[0, ii], m[1, ii], m[2, ii], m[3, ii], m[4, ii], m[5, ii]
        for fn in range(3):  # M_f f', M_f f'' + C(f', f'), Gamma g
            m0, m1, m2 = v[3 * fn, ii], v[3 * fn + 1, ii], v[3 * fn + 2, ii]
            tau[0, leg, fn] = m0 * f0 + m1 * f1 + m2 * f2
            inertial = m0 * s0 + m1 * s1 + m2 * s2
            inertial += v[9 + fn, ii] * (f1 * f1) + v[12 + fn, ii] * (f2 * f2)
            tau[1, leg, fn] = inertial + v[15 + fn, ii] * (f1 * f2)
            tau[2, leg, fn] = v[18 + fn, ii]
    for form in range(3):  # F = tau_q + J^T (the legs' theta and phi parts - f_ext)
        w = (0.0, 0.0, 0.0)
        for axis in range(3):
            ly, lz = legs[0, axis], legs[1, axis]
            m_y, m_z = motion[ly], motion[lz]
            wa = (tau[form, ly, 1] * m_y[6, ii] + tau[form, ly, 2] * m_y[8, ii]) + tau[
                form, lz, 1
            ] * m_z[7, ii]
            if form == 2:
                wa -= f_ext[i, axis]
            w = (wa, w[0], w[1])  # (w2, w1, w0) at the end
        for s in range(3):
            f = tau[form, s, 0] + w[2] * jac[ii, 0, s]
            f += w[1] * jac[ii, 1, s]
            f += w[0] * jac[ii, 2, s]
            if not math.isfinite(f):
                return False
            out[3 + form, i, s] = f
    return True


def _forms(
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    f_ext: FloatArray,
    coef: FloatArray,
    harmonics: NDArray[np.intp],
    legs: NDArray[np.intp],
    bounds: FloatArray,
    out: FloatArray,
) -> int:
    """Fill ``out`` (6, n, 3) with ``q, dq, ddq, a, b, c``; the first bad point, or -1.

    Chunks of :data:`CHUNK` points: each point's motion, then the chunk's basis
    and expansion sums (the points innermost), then each point's forces.
    ``coef``: the expansion's coefficients per leg, output and basis function,
    (3, 21, 2K + 1); ``legs``: the leg whose ``y`` (row 0) and ``z`` (row 1) axis
    each world axis is; ``bounds``: ``L``, the lowest and highest slider value
    allowed, the smallest ``eta`` and the largest ``1 / |det|`` (:func:`forms_compiled`).
    """
    n, n_out, n_basis = p.shape[0], coef.shape[1], coef.shape[2]
    top = 0
    for j in range(harmonics.shape[0]):
        top = max(top, harmonics[j, 0], abs(harmonics[j, 1]))
    scratch, powers = np.empty((3, 3)), np.empty((2, top + 1, 2, CHUNK))
    jac, tau = np.empty((CHUNK, 3, 3)), np.empty((3, 3, 3))
    motion, basis = np.empty((3, 13, CHUNK)), np.empty((3, n_basis, CHUNK))
    values = np.empty((3, n_out, CHUNK))
    for start in range(0, n, CHUNK):
        size = min(CHUNK, n - start)
        for ii in range(size):
            if not _point(p, t, k, start + ii, ii, bounds, scratch, jac, motion, out):
                return start + ii
        _basis(harmonics, motion, powers, basis, size)
        for leg in range(3):  # each output's sum in basis order, the points together
            for o in range(n_out):
                row = values[leg, o]
                c = coef[leg, o, 0]
                for ii in range(size):
                    row[ii] = c * basis[leg, 0, ii]
                for j in range(1, n_basis):
                    c = coef[leg, o, j]
                    for ii in range(size):
                        row[ii] += c * basis[leg, j, ii]
        for ii in range(size):
            if not _forces(start + ii, ii, f_ext, legs, jac, motion, values, tau, out):
                return start + ii
    return -1


if AVAILABLE:
    _point = _jit(_point)
    _basis = _jit(_basis)
    _forces = _jit(_forces)
    _forms = _jit(_forms)


def forms_compiled(
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    f_ext: FloatArray,
    coef: FloatArray,
    harmonics: NDArray[np.intp],
    legs: NDArray[np.intp],
    limits: tuple[float, float, float, float, float, float],
) -> FloatArray | None:
    """``q, dq, ddq, a, b, c`` stacked (6, n, 3), or ``None`` where a check fails (see the module).

    Args:
        p: Path points [m], (n, 3).
        t: Tangents ``dp/ds`` [-], (n, 3).
        k: Curvature vectors ``d2p/ds2`` [1/m], (n, 3).
        f_ext: The tool force [N], (n, 3).
        coef: The expansion's coefficients with gravity, (3, 21, 2K + 1)
            (:meth:`~orthoglide_pin.dynamics.leg_harmonics.LegHarmonics.coefficients`).
        harmonics: Its harmonics, (K, 2).
        legs: For each world axis, the leg whose ``y`` axis (row 0) and ``z``
            axis (row 1) it is, (2, 3).
        limits: Leg length ``L`` [m], the slider limits [m] and their
            tolerance [m], the serial and the parallel singularity tolerances
            (relative to ``L``, and of ``|det|`` of the unit legs) [-].

    Raises:
        RuntimeError: numba is not installed.
    """
    if not AVAILABLE:
        raise RuntimeError(
            "the compiled path forms need numba (pip install 'orthoglide-pin[plan]')"
        )
    L, lower, upper, tol, serial, parallel = limits
    bounds = np.array(
        [
            L,
            lower - tol / MARGIN,
            upper + tol / MARGIN,
            MARGIN * serial * L,
            1.0 / (MARGIN * parallel * L**3),
        ]
    )
    out = np.empty((6, p.shape[0], 3))
    rows = [np.ascontiguousarray(x, dtype=np.float64) for x in (p, t, k, f_ext, coef)]
    bad = _forms(
        rows[0],
        rows[1],
        rows[2],
        rows[3],
        rows[4],
        np.ascontiguousarray(harmonics, dtype=np.intp),
        np.ascontiguousarray(legs, dtype=np.intp),
        bounds,
        out,
    )
    return None if bad >= 0 else out
