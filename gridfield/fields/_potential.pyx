# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels of the potentials: the fused attractive + nearest-obstacle repulsive pass.

Only kernels live here; parameters, models and the :class:`~gridfield.fields.potential.Field` are in
:mod:`gridfield.fields.potential`. Arrays follow the grid conventions (``[row, col]``, row 0 at the
lowest y, cell centres at ``origin + (col + 0.5, row + 0.5) * res``); all are C-contiguous, ``occ``
``bool``, the nearest cells ``int32``, the outputs ``float64``.

Cython with OpenMP, compiled at install: the two full-grid kernels split their rows over
:func:`get_num_threads` threads (static schedule) and release the GIL.
"""

from cython.parallel cimport prange
from libc.math cimport pow, sqrt, INFINITY
from libc.stdint cimport int32_t, int64_t, uint8_t

cimport openmp


cdef extern from "_potential_rows.h" nogil:
    # the row loops, in C so that the compiler vectorizes them (see the header)
    void gf_attractive_row(int64_t r, int64_t cols, double x0, double y0, double res, double goal_x, double goal_y,
                           double zeta, double d_star, double ds2, int conic, double* U, double* GX, double* GY)
    void gf_khatib_row(int64_t r, int64_t c0, int64_t c1, const uint8_t* occ, const int32_t* nr, const int32_t* nc, double x0,
                       double y0, double res, double goal_x, double goal_y, double zeta, double d_star, double ds2,
                       int conic, int metric, double eta, double q_star, double inv_q, int ipow, double sat,
                       double far, double* U, double* GX, double* GY)

__all__ = ["_attractive_kernel", "_khatib_kernel", "_rep_accumulate", "get_num_threads", "set_num_threads"]

ctypedef const unsigned char[:, ::1] occ_t
ctypedef const int32_t[:, ::1] idx_t
ctypedef double[:, ::1] out_t
# _rep_accumulate works on windows of the grid's arrays: any strides
ctypedef const unsigned char[:, :] socc_t
ctypedef const int32_t[:, :] sidx_t
ctypedef double[:, :] sout_t

cdef int _threads = max(1, openmp.omp_get_max_threads())


def get_num_threads():
    """Threads the parallel kernels use (default: OpenMP's, i.e. the cores)."""
    return _threads


def set_num_threads(int n):
    """Set the threads of the parallel kernels (at least 1)."""
    global _threads
    if n < 1:
        raise ValueError(f"the number of threads must be at least 1, got {n}")
    _threads = n


cdef inline double _rep_distance(double fr, double fc, double res, int metric, double sat, double far,
                                 double* length) noexcept nogil:
    """``D`` for a nearest obstacle cell ``(fr, fc)`` cells away, after saturation; ``|offset|`` in cells
    into ``length``."""
    cdef double dist
    length[0] = sqrt(fr * fr + fc * fc)
    if metric == 0:
        dist = length[0] * res
    elif metric == 1:
        dist = max(abs(fr), abs(fc)) * res
    else:
        dist = (abs(fr) + abs(fc)) * res
    return far if dist >= sat else dist


def _attractive_kernel(double x0, double y0, double res, double goal_x, double goal_y, double zeta, double d_star,
                       bint conic, out_t U, out_t GX, out_t GY):
    """Attractive potential; branch-free (selects, no jumps) so that the inner loop vectorizes."""
    cdef Py_ssize_t rows = U.shape[0], cols = U.shape[1], r
    cdef double ds2 = d_star * d_star
    for r in prange(rows, nogil=True, schedule="static", num_threads=_threads):
        gf_attractive_row(r, cols, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, &U[r, 0], &GX[r, 0],
                          &GY[r, 0])


def _khatib_kernel(occ_t occ, idx_t nr, idx_t nc, double x0, double y0, double res, double goal_x, double goal_y,
                   double zeta, double d_star, bint conic, int metric, double eta, double q_star, int ipow,
                   double sat, double far, out_t U, out_t GX, out_t GY):
    """Attractive + nearest-obstacle repulsive potential and gradient in one fused pass.

    Branch-free: every cell computes both terms and selects, so the inner loop vectorizes. The
    repulsive force is ``eta*(1/D - 1/q_star)/D**ipow`` for ``ipow`` in 0..4 (pass ``eta = 0`` for no
    repulsion); there is deliberately no float ``**``: other powers go through :func:`_rep_accumulate`.
    """
    cdef Py_ssize_t rows = occ.shape[0], cols = occ.shape[1], r
    cdef double ds2 = d_star * d_star
    cdef double inv_q = 1.0 / q_star
    for r in prange(rows, nogil=True, schedule="static", num_threads=_threads):
        gf_khatib_row(r, 0, cols, &occ[r, 0], &nr[r, 0], &nc[r, 0], x0, y0, res, goal_x, goal_y, zeta, d_star, ds2,
                      conic, metric, eta, q_star, inv_q, ipow, sat, far, &U[r, 0], &GX[r, 0], &GY[r, 0])


def _rep_accumulate(socc_t occ, sidx_t nr, sidx_t nc, long long r_off, long long c_off, double res, int metric,
                    double eta, double q_star, int ipow, double power, double sat, double far, sout_t U, sout_t GX,
                    sout_t GY):
    """Add a repulsive term over a window (all arrays are that window), for any power.

    ``nr``/``nc`` are nearest obstacle cells in a frame shifted by ``(r_off, c_off)`` from the
    window's; ``(-1, -1)`` in the grid frame means "no obstacle". ``ipow < 0``: use the float ``power``.
    The arrays may be strided views (windows of the grid's arrays).
    """
    cdef Py_ssize_t rows = occ.shape[0], cols = occ.shape[1], r, c
    cdef double inv_q = 1.0 / q_star, fr, fc, dist, length, s, den, k
    cdef int a, b, i
    with nogil:
        for r in range(rows):
            for c in range(cols):
                if occ[r, c]:
                    continue
                a = nr[r, c]
                b = nc[r, c]
                if a == -1 and b == -1:
                    continue
                fr = <double>(r + r_off - a)
                fc = <double>(c + c_off - b)
                dist = _rep_distance(fr, fc, res, metric, sat, far, &length)
                if dist < q_star:
                    s = 1.0 / dist - inv_q
                    if ipow >= 0:
                        den = 1.0
                        for i in range(ipow):
                            den *= dist
                    else:
                        den = pow(dist, power)
                    k = eta * s / (den * length)
                    U[r, c] += 0.5 * eta * s * s
                    GX[r, c] -= k * fc
                    GY[r, c] -= k * fr
