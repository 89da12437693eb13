# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled linear solver behind :func:`gridfield.fields.navigation.harmonic` (Cython, compiled at install;
imported lazily): conjugate gradients on the 5-point Dirichlet Laplacian of the free cells, preconditioned
by the modified incomplete Cholesky factorization MIC(0) (:func:`mic0_factor`, :func:`mic0_apply`,
:func:`pcg_laplace`).

The unknowns are numbered in row-major order; ``left/down/right/up[i]`` is the index of that neighbour
among the unknowns, or -1 (a boundary value, folded into the right-hand side by the caller). Index
arrays are ``int64`` with any strides; nothing here validates input, :mod:`gridfield.fields.navigation`
does. Every kernel releases the GIL while it runs.
"""


from libc.math cimport sqrt
from libc.stdint cimport int64_t
from libc.stdlib cimport free as c_free, malloc

import numpy as np

ctypedef const int64_t[:] idx_t


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


cdef void _mic0_factor(idx_t left, idx_t down, idx_t right, idx_t up, double omega, double* d) noexcept nogil:
    cdef int64_t n = left.shape[0], i, j
    cdef double v, v0
    for i in range(n):
        v = 4.0
        v0 = 4.0
        j = left[i]
        if j >= 0:
            v0 -= 1.0 / d[j]
            v -= (1.0 + (omega if up[j] >= 0 else 0.0)) / d[j]
        j = down[i]
        if j >= 0:
            v0 -= 1.0 / d[j]
            v -= (1.0 + (omega if right[j] >= 0 else 0.0)) / d[j]
        d[i] = v if v > 1e-3 else v0


def mic0_factor(idx_t left, idx_t down, idx_t right, idx_t up, double omega):
    """Pivots ``d`` of the modified incomplete Cholesky factorization ``A ~ L D^-1 L^T`` of the
    5-point Dirichlet Laplacian (diagonal 4, ``-1`` between neighbouring unknowns) on unknowns in
    row-major order. ``left/down/right/up[i]`` is the index of that neighbour among the unknowns, or -1.
    ``omega`` in ``[0, 1)`` blends IC(0) (0) and MIC(0) (-> 1). A pivot that would fall below 1e-3
    falls back to the IC(0) value, which for this M-matrix is at least 2.
    """
    d = np.empty(left.shape[0])
    cdef double[::1] dv = d
    if left.shape[0]:
        with nogil:
            _mic0_factor(left, down, right, up, omega, &dv[0])
    return d


cdef void _mic0_apply(idx_t left, idx_t down, idx_t right, idx_t up, const double* d, const double* r,
                      double* y) noexcept nogil:
    cdef int64_t n = left.shape[0], i, j
    cdef double v
    for i in range(n):
        v = r[i]
        j = left[i]
        if j >= 0:
            v += y[j] / d[j]
        j = down[i]
        if j >= 0:
            v += y[j] / d[j]
        y[i] = v
    for i in range(n - 1, -1, -1):
        v = y[i]
        j = right[i]
        if j >= 0:
            v += y[j]
        j = up[i]
        if j >= 0:
            v += y[j]
        y[i] = v / d[i]


def mic0_apply(idx_t left, idx_t down, idx_t right, idx_t up, const double[::1] d, const double[:] r):
    """Solve ``(L D^-1 L^T) z = r`` for the factorization of :func:`mic0_factor`."""
    cdef int64_t n = left.shape[0]
    rc = np.ascontiguousarray(r)
    cdef const double[::1] rv = rc
    y = np.empty(n)
    cdef double[::1] yv = y
    if n:
        with nogil:
            _mic0_apply(left, down, right, up, &d[0], &rv[0], &yv[0])
    return y


cdef void _laplace_matvec(idx_t left, idx_t down, idx_t right, idx_t up, const double* x,
                          double* out) noexcept nogil:
    cdef int64_t n = left.shape[0], i, j
    cdef double v
    for i in range(n):
        v = 4.0 * x[i]
        j = left[i]
        if j >= 0:
            v -= x[j]
        j = right[i]
        if j >= 0:
            v -= x[j]
        j = down[i]
        if j >= 0:
            v -= x[j]
        j = up[i]
        if j >= 0:
            v -= x[j]
        out[i] = v


def pcg_laplace(idx_t left, idx_t down, idx_t right, idx_t up, const double[:] b, double omega, double rtol,
                int64_t maxiter):
    """Conjugate gradients on the 5-point Dirichlet Laplacian (see :func:`mic0_factor`) preconditioned by
    MIC(0). Stops when ``|r| <= rtol * |b|``. Returns ``(x, iterations, relative residual)``."""
    cdef int64_t n = left.shape[0], i, it = 0
    if n == 0:
        return np.zeros(0), 0, 0.0
    bc = np.ascontiguousarray(b)
    cdef const double[::1] bv = bc
    xa = np.empty(n)
    cdef double[::1] xv = xa
    cdef double* x = &xv[0]
    cdef double* d = <double*>_alloc(n * sizeof(double))
    cdef double* r = <double*>_alloc(n * sizeof(double))
    cdef double* ap = <double*>_alloc(n * sizeof(double))
    cdef double* z = <double*>_alloc(n * sizeof(double))
    cdef double* p = <double*>_alloc(n * sizeof(double))
    cdef double bb = 0.0, rr = 0.0, bnorm, rz, pap, alpha, rz_new, beta
    cdef bint zero = False
    with nogil:
        _mic0_factor(left, down, right, up, omega, d)
        _mic0_apply(left, down, right, up, d, &bv[0], x)  # the preconditioner's guess
        _laplace_matvec(left, down, right, up, x, ap)
        for i in range(n):
            r[i] = bv[i] - ap[i]
            bb += bv[i] * bv[i]
            rr += r[i] * r[i]
        bnorm = sqrt(bb)
        if bnorm == 0.0:
            zero = True
        else:
            _mic0_apply(left, down, right, up, d, r, z)
            for i in range(n):
                p[i] = z[i]
            rz = 0.0
            for i in range(n):
                rz += r[i] * z[i]
            while sqrt(rr) > rtol * bnorm and it < maxiter:
                it += 1
                _laplace_matvec(left, down, right, up, p, ap)
                pap = 0.0
                for i in range(n):
                    pap += p[i] * ap[i]
                if pap <= 0.0:
                    break
                alpha = rz / pap
                rr = 0.0
                for i in range(n):
                    x[i] += alpha * p[i]
                    r[i] -= alpha * ap[i]
                    rr += r[i] * r[i]
                _mic0_apply(left, down, right, up, d, r, z)
                rz_new = 0.0
                for i in range(n):
                    rz_new += r[i] * z[i]
                beta = rz_new / rz
                rz = rz_new
                for i in range(n):
                    p[i] = z[i] + beta * p[i]
        c_free(d)
        c_free(r)
        c_free(ap)
        c_free(z)
        c_free(p)
    if zero:
        return np.zeros(n), 0, 0.0
    return xa, it, sqrt(rr) / bnorm
