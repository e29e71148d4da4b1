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
in one compiled loop over chunks of :data:`CHUNK` points: the checks and the
Jacobian point by point,
then the joint motion, the basis, the expansion's sums and the forces for the
whole chunk, the points innermost (rows of a few kilobytes that stay in the
cache and that the compiler turns into vector operations). It makes the same
checks: at a point where any of them fails or comes near failing (an
unreachable or nearly serially or parallel singular point, a slider beyond
half the tolerance past its limit, a form that is not finite) it stops and
says so, and the caller takes the array route, which raises the right error
(or gives the same numbers). The sums are those of the array version in the
same order but the expansion's (a matrix product there), so the forms agree
with it to rounding (``tests/dynamics/test_forms_compiled.py``).

numba comes with the ``[plan]`` and ``[sim]`` extras; without it (:data:`AVAILABLE` false)
the array route runs alone.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin import _compiled
from orthoglide_pin._compiled import jit

FloatArray = NDArray[np.float64]

#: Whether the compiled loop can run (numba is installed).
AVAILABLE: Final[bool] = _compiled.AVAILABLE
#: The checks' margin: a point this close (as a factor on the tolerance) to
#: failing one takes the array route, which decides [-].
MARGIN: Final[float] = 2.0
#: Points whose expansion sums are taken together (the scratch stays in the cache).
CHUNK: Final[int] = 128


def _kinematics(
    p: FloatArray,
    t: FloatArray,
    k: FloatArray,
    start: int,
    size: int,
    bounds: FloatArray,
    rows: FloatArray,
    jac: FloatArray,
) -> int:
    """A chunk's checks and Jacobians, point by point; the first bad point, or -1.

    Fills ``rows`` (12, CHUNK): ``p``, ``p'``, ``p''`` and ``eta`` as rows, and
    ``jac`` (9, CHUNK): ``J`` row by row, as ``ik_and_jacobian``'s adjugate over
    the determinant.
    """
    L, q_lo, q_hi, eta_min, det_max = bounds[0], bounds[1], bounds[2], bounds[3], bounds[4]
    for ii in range(size):
        i = start + ii
        x, y, z = p[i, 0], p[i, 1], p[i, 2]
        e0 = L * L - (y * y + z * z)  # the radicands, then eta
        e1 = L * L - (z * z + x * x)
        e2 = L * L - (x * x + y * y)
        if not (e0 >= 0.0 and e1 >= 0.0 and e2 >= 0.0):
            return i
        e0, e1, e2 = math.sqrt(e0), math.sqrt(e1), math.sqrt(e2)
        q0, q1, q2 = x + (L - e0), y + (L - e1), z + (L - e2)  # as the limit check does
        if not (e0 > eta_min and e1 > eta_min and e2 > eta_min):
            return i
        if not (q_lo <= q0 <= q_hi and q_lo <= q1 <= q_hi and q_lo <= q2 <= q_hi):
            return i
        b0, b1, b2 = x - e0, y - e1, z - e2
        g0, g1, g2 = e1 * e2 - y * z, e2 * e0 - z * x, e0 * e1 - x * y
        inv = 1.0 / ((y * b2 + z * b1) * x + e0 * g0)
        if not abs(inv) <= det_max:
            return i
        f0, f1, f2 = e0 * inv, e1 * inv, e2 * inv
        w0, w1, w2 = x * f0, y * f1, z * f2
        jac[0, ii], jac[1, ii], jac[2, ii] = g0 * f0, b2 * w1, b1 * w2
        jac[3, ii], jac[4, ii], jac[5, ii] = b2 * w0, g1 * f1, b0 * w2
        jac[6, ii], jac[7, ii], jac[8, ii] = b1 * w0, b0 * w1, g2 * f2
        for c in range(3):
            rows[c, ii], rows[3 + c, ii], rows[6 + c, ii] = p[i, c], t[i, c], k[i, c]
        rows[9, ii], rows[10, ii], rows[11, ii] = e0, e1, e2
    return -1


def _motion(L: float, size: int, rows: FloatArray, motion: FloatArray) -> None:
    """A chunk's joint motion along the path, leg by leg, the points innermost.

    As :func:`~orthoglide_pin.kinematics.joint_motion.path_motion`: ``motion``
    (3 legs, 14, CHUNK) gets ``f'`` (3), ``f''`` (3), the theta and phi gradients
    (3), ``cos theta``, ``sin theta``, ``cos phi``, ``sin phi`` and the slider value.
    """
    for leg in range(3):  # leg coordinates (x, y, z) = LEG_AXES[leg]
        ax, ay, az = leg, (leg + 1) % 3, (leg + 2) % 3
        xs, ys, zs, es = rows[ax], rows[ay], rows[az], rows[9 + leg]
        xd, yds, zds = rows[3 + ax], rows[3 + ay], rows[3 + az]
        xdd, ydds, zdds = rows[6 + ax], rows[6 + ay], rows[6 + az]
        m = motion[leg]
        for ii in range(size):
            y, z, e = ys[ii], zs[ii], es[ii]
            yd, zd, ydd, zdd = yds[ii], zds[ii], ydds[ii], zdds[ii]
            c2 = L * L - y * y
            cc = math.sqrt(c2)
            ed = -(y * yd + z * zd) / e
            edd = -(yd * yd + zd * zd + y * ydd + z * zdd + ed * ed) / e
            phd = yd / cc
            thd = (z * ed - e * zd) / c2
            m[0, ii], m[1, ii], m[2, ii] = xd[ii] - ed, thd, phd
            m[3, ii] = xdd[ii] - edd
            m[4, ii] = (z * edd - e * zdd + 2.0 * y * yd * thd) / c2
            m[5, ii] = (ydd + y * phd * phd) / cc
            m[6, ii], m[7, ii], m[8, ii] = -y * z / (e * c2), -1.0 / e, 1.0 / cc
            m[9, ii], m[10, ii], m[11, ii], m[12, ii] = e / cc, -z / cc, cc / L, y / L
            m[13, ii] = xs[ii] + L - e


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


def _sums(coef: FloatArray, basis: FloatArray, values: FloatArray, size: int) -> None:
    """``values[leg, o] = sum_j coef[leg, o, j] basis[leg, j]``: basis order, points innermost."""
    for leg in range(3):
        for o in range(coef.shape[1]):
            row = values[leg, o]
            c = coef[leg, o, 0]
            for ii in range(size):
                row[ii] = c * basis[leg, 0, ii]
            for j in range(1, coef.shape[2]):
                c = coef[leg, o, j]
                for ii in range(size):
                    row[ii] += c * basis[leg, j, ii]


def _forces(
    start: int,
    size: int,
    f_ext: FloatArray,
    legs: NDArray[np.intp],
    jac: FloatArray,
    motion: FloatArray,
    values: FloatArray,
    tau: FloatArray,
    world: FloatArray,
    out: FloatArray,
) -> int:
    """A chunk's outputs from its rows (see :func:`_motion`); the first non-finite point, or -1.

    ``values[leg, :, ii]``: ``M_f`` (9), the velocity terms (9), ``Gamma g`` (3);
    ``tau`` (3 forms, 3 legs, 3 functions, CHUNK) and ``world`` (3, CHUNK): scratch.
    """
    for leg in range(3):
        m, v = motion[leg], values[leg]
        for ii in range(size):
            out[0, start + ii, leg], out[1, start + ii, leg] = m[13, ii], m[0, ii]
            out[2, start + ii, leg] = m[3, ii]
        for fn in range(3):  # M_f f', M_f f'' + C(f', f'), Gamma g
            m0, m1, m2 = v[3 * fn], v[3 * fn + 1], v[3 * fn + 2]
            ctt, cpp, ctp, weight = v[9 + fn], v[12 + fn], v[15 + fn], v[18 + fn]
            t0, t1, t2 = tau[0, leg, fn], tau[1, leg, fn], tau[2, leg, fn]
            for ii in range(size):
                f0, f1, f2 = m[0, ii], m[1, ii], m[2, ii]
                t0[ii] = m0[ii] * f0 + m1[ii] * f1 + m2[ii] * f2
                inertial = m0[ii] * m[3, ii] + m1[ii] * m[4, ii] + m2[ii] * m[5, ii]
                inertial += ctt[ii] * (f1 * f1) + cpp[ii] * (f2 * f2)
                t1[ii] = inertial + ctp[ii] * (f1 * f2)
                t2[ii] = weight[ii]
    for form in range(3):  # F = tau_q + J^T (the legs' theta and phi parts - f_ext)
        for axis in range(3):
            ly, lz = legs[0, axis], legs[1, axis]
            a, b, c = tau[form, ly, 1], tau[form, ly, 2], tau[form, lz, 1]
            gy, gphi, gz, w = motion[ly, 6], motion[ly, 8], motion[lz, 7], world[axis]
            for ii in range(size):
                w[ii] = (a[ii] * gy[ii] + b[ii] * gphi[ii]) + c[ii] * gz[ii]
            if form == 2:
                for ii in range(size):
                    w[ii] -= f_ext[start + ii, axis]
        for s in range(3):
            tq = tau[form, s, 0]
            for ii in range(size):
                f = tq[ii] + world[0, ii] * jac[s, ii]
                f += world[1, ii] * jac[3 + s, ii]
                f += world[2, ii] * jac[6 + s, ii]
                if not math.isfinite(f):
                    return start + ii
                out[3 + form, start + ii, s] = f
    return -1


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

    Chunks of :data:`CHUNK` points: their checks and Jacobians point by point,
    then each step for the whole chunk, the points innermost (rows the
    compiler turns into vector operations). ``coef``: the expansion's
    coefficients per leg, output and basis function, (3, 21, 2K + 1); ``legs``:
    the leg whose ``y`` (row 0) and ``z`` (row 1) axis each world axis is;
    ``bounds``: ``L``, the lowest and highest slider value allowed, the smallest
    ``eta`` and the largest ``1 / |det|`` (:func:`forms_compiled`).
    """
    n, n_out, n_basis = p.shape[0], coef.shape[1], coef.shape[2]
    top = 0
    for j in range(harmonics.shape[0]):
        top = max(top, harmonics[j, 0], abs(harmonics[j, 1]))
    rows, jac, world = np.empty((12, CHUNK)), np.empty((9, CHUNK)), np.empty((3, CHUNK))
    motion, powers = np.empty((3, 14, CHUNK)), np.empty((2, top + 1, 2, CHUNK))
    basis, values = np.empty((3, n_basis, CHUNK)), np.empty((3, n_out, CHUNK))
    tau = np.empty((3, 3, 3, CHUNK))
    for start in range(0, n, CHUNK):
        size = min(CHUNK, n - start)
        bad = _kinematics(p, t, k, start, size, bounds, rows, jac)
        if bad >= 0:
            return bad
        _motion(bounds[0], size, rows, motion)
        _basis(harmonics, motion, powers, basis, size)
        _sums(coef, basis, values, size)
        bad = _forces(start, size, f_ext, legs, jac, motion, values, tau, world, out)
        if bad >= 0:
            return bad
    return -1


if AVAILABLE:
    _kinematics = jit(_kinematics)
    _motion = jit(_motion)
    _basis = jit(_basis)
    _sums = jit(_sums)
    _forces = jit(_forces)
    _forms = jit(_forms)


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
