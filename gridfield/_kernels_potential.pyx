# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels of the potentials: the fused attractive + nearest-obstacle repulsive pass.

Only kernels live here; parameters, models and the :class:`~gridfield.potential.Field` are in
:mod:`gridfield.potential`. Arrays follow the grid conventions (``[row, col]``, row 0 at the
lowest y, cell centres at ``origin + (col + 0.5, row + 0.5) * res``); all are C-contiguous, ``occ``
``bool``, the nearest cells ``int32``, the outputs ``float64``.

Cython with OpenMP, compiled at install: the two full-grid kernels split their rows over
:func:`get_num_threads` threads (static schedule) and release the GIL.
"""

from cython.parallel cimport prange
from libc.math cimport pow, sqrt, INFINITY

cimport openmp

__all__ = ["_attractive_kernel", "_khatib_kernel", "_rep_accumulate", "get_num_threads", "set_num_threads"]

ctypedef const unsigned char[:, ::1] occ_t
ctypedef const int[:, ::1] idx_t
ctypedef double[:, ::1] out_t
# _rep_accumulate works on windows of the grid's arrays: any strides
ctypedef const unsigned char[:, :] socc_t
ctypedef const int[:, :] sidx_t
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


cdef inline double _attraction(double d2, double zeta, double d_star, double ds2, bint conic,
                               double* k) noexcept nogil:
    """``U`` of the attractive potential at squared distance ``d2`` from the goal, and ``k`` with
    ``grad U = k * (p - goal)``: quadratic within ``d_star`` (``ds2 = d_star**2``; ``inf``: everywhere,
    ``0``: the goal only), beyond it conic (``conic``: ``zeta*d``, the ``d_star = 0`` case) or the
    combined ``d_star*zeta*d - 0.5*zeta*d_star**2``. Selects, no jumps, so that the loops vectorize."""
    cdef double d = sqrt(d2)
    cdef bint quad = d2 <= ds2
    k[0] = zeta if quad else (zeta / d if conic else zeta * d_star / d)
    return 0.5 * zeta * d2 if quad else (zeta * d if conic else zeta * d_star * d - 0.5 * zeta * ds2)


cdef inline void _attractive_row(Py_ssize_t r, Py_ssize_t cols, double x0, double y0, double res, double goal_x,
                                 double goal_y, double zeta, double d_star, double ds2, bint conic, double* U,
                                 double* GX, double* GY) noexcept nogil:
    # a function of its own per row: its locals are private to the thread running it
    cdef Py_ssize_t c
    cdef double dy = y0 + (r + 0.5) * res - goal_y
    cdef double dx, u, k
    for c in range(cols):
        dx = x0 + (c + 0.5) * res - goal_x
        u = _attraction(dx * dx + dy * dy, zeta, d_star, ds2, conic, &k)
        U[c] = u
        GX[c] = k * dx
        GY[c] = k * dy


def _attractive_kernel(double x0, double y0, double res, double goal_x, double goal_y, double zeta, double d_star,
                       bint conic, out_t U, out_t GX, out_t GY):
    """Attractive potential; branch-free (selects, no jumps) so that the inner loop vectorizes."""
    cdef Py_ssize_t rows = U.shape[0], cols = U.shape[1], r
    cdef double ds2 = d_star * d_star
    for r in prange(rows, nogil=True, schedule="static", num_threads=_threads):
        _attractive_row(r, cols, x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, &U[r, 0], &GX[r, 0], &GY[r, 0])


cdef inline void _khatib_row(Py_ssize_t r, Py_ssize_t cols, const unsigned char* occ, const int* nr, const int* nc,
                             double x0, double y0, double res, double goal_x, double goal_y, double zeta,
                             double d_star, double ds2, bint conic, int metric, double eta, double q_star,
                             double inv_q, int ipow, double sat, double far, double* U, double* GX,
                             double* GY) noexcept nogil:
    # one row, through raw row pointers (the compiler vectorizes the loop)
    cdef Py_ssize_t c
    cdef double dy = y0 + (r + 0.5) * res - goal_y
    cdef double dx, u, k, gx, gy, fr, fc, dist, length, inv_d, s, inv_d2, den, m
    cdef int a, b
    cdef bint free, inside
    for c in range(cols):
        # attractive
        dx = x0 + (c + 0.5) * res - goal_x
        u = _attraction(dx * dx + dy * dy, zeta, d_star, ds2, conic, &k)
        gx = k * dx
        gy = k * dy
        # repulsive, from the nearest obstacle cell
        a = nr[c]
        b = nc[c]
        fr = <double>(r - a)
        fc = <double>(c - b)
        free = occ[c] == 0
        dist = _rep_distance(fr, fc, res, metric, sat, far, &length)
        inside = free & ((a != -1) | (b != -1)) & (dist < q_star)  # bitwise: no jumps
        dist = dist if inside else 1.0
        length = length if inside else 1.0
        inv_d = 1.0 / dist
        s = inv_d - inv_q
        inv_d2 = inv_d * inv_d
        den = 1.0 if ipow == 0 else (inv_d if ipow == 1 else (inv_d2 if ipow == 2 else (
            inv_d2 * inv_d if ipow == 3 else inv_d2 * inv_d2)))
        m = eta * s * den / length  # |force| / |offset in cells|
        U[c] = (u + 0.5 * eta * s * s if inside else u) if free else INFINITY
        GX[c] = (gx - m * fc if inside else gx) if free else 0.0
        GY[c] = (gy - m * fr if inside else gy) if free else 0.0


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
        _khatib_row(r, cols, &occ[r, 0], &nr[r, 0], &nc[r, 0], x0, y0, res, goal_x, goal_y, zeta, d_star, ds2,
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
