# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.chunked` (private; imported on first use by the tasks).

The separable transforms of :func:`gridfield.brushfire.brushfire` on a block of whole rows of a larger grid:
the column pass (:func:`gridfield._kernels_brushfire.column_block`, run on a block of whole columns, gives
each cell the global row of the obstacle nearest to it in its column); then, here, the row pass on a block
of whole rows whose first row is ``row0`` of a grid of ``rows`` rows:

- :func:`edt_rows_block`: the Euclidean lower envelope (the one compiled envelope of
  :mod:`gridfield._kernels_brushfire`, cimported), with the same arithmetic as ``edt_rows`` there, so
  the distance and the nearest obstacle are bit-identical to the in-memory transform;
- :func:`l1_rows_block` (taxicab: a forward and a backward min-plus scan) and :func:`linf_rows_block`
  (chessboard: the lower envelope of ``max(|x - i|, g_i)``, Meijster, Roerdink & Hesselink 2000, sec. 5),
  exact integer distances in cells, times the resolution as ``gf_scale_row`` does.

The wall border is the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols`` (sites 0 and
``n + 1`` of each row with ``g = 0``). A row without any site (an open border and no obstacle in the
whole grid) gets ``inf`` and nearest cell ``-1``, as the in-memory brushfire does.
"""

from libc.stdint cimport int32_t, int64_t
from libc.stdlib cimport free, malloc
from libc.math cimport sqrt, INFINITY

from gridfield._kernels_brushfire cimport _edt_1d


cdef inline void* _alloc(size_t n) noexcept nogil:
    cdef void* p = malloc(n if n > 0 else 1)
    if p == NULL:
        with gil:
            raise MemoryError()
    return p


cdef inline void _gather(const int32_t* v, int64_t r, int64_t inf, int64_t* g, int64_t* rowv, int64_t n,
                         bint wall) noexcept nogil:
    """``g[c + 1] = min(|r - v[c]|, inf)``, ``rowv[c + 1] = v[c]``; the wall sites 0 and ``n + 1``."""
    cdef int64_t c, x, d
    g[0] = 0 if wall else inf
    g[n + 1] = 0 if wall else inf
    rowv[0] = r
    rowv[n + 1] = r
    for c in range(n):
        x = v[c]
        d = r - x if r >= x else x - r
        g[c + 1] = d if d < inf else inf
        rowv[c + 1] = x


def edt_rows_block(const int32_t[:, ::1] vr, int64_t row0, int64_t rows, bint wall, double resolution,
                   double[:, ::1] distance, int32_t[:, ::1] nearest_row, int32_t[:, ::1] nearest_col,
                   bint want_nearest):
    """Euclidean row pass of the block ``vr`` (column pass result, global rows) = rows ``row0..`` of a grid
    of ``rows`` rows: ``distance`` and, if ``want_nearest``, the nearest obstacle cell."""
    cdef int64_t nb = vr.shape[0], n = vr.shape[1], i, r, c, a
    if nb == 0 or n == 0:
        return
    cdef int64_t inf = rows + n + 4  # as edt_rows: beyond any distance in the grid
    cdef int64_t* g
    cdef int64_t* rowv
    cdef int64_t* s
    cdef int64_t* t
    cdef int64_t* val
    cdef int64_t* arg
    cdef double* drow
    with nogil:
        g = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        rowv = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        s = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        t = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        val = <int64_t*>_alloc(n * sizeof(int64_t))
        arg = <int64_t*>_alloc(n * sizeof(int64_t))
        for i in range(nb):
            r = row0 + i
            _gather(&vr[i, 0], r, inf, g, rowv, n, wall)
            drow = &distance[i, 0]
            if not _edt_1d(g, n, inf, s, t, val, arg):
                for c in range(n):
                    drow[c] = INFINITY
                    if want_nearest:
                        nearest_row[i, c] = -1
                        nearest_col[i, c] = -1
                continue
            for c in range(n):
                drow[c] = sqrt(<double>val[c]) * resolution
            if want_nearest:
                for c in range(n):
                    a = arg[c]
                    nearest_row[i, c] = <int32_t>rowv[a]
                    nearest_col[i, c] = <int32_t>(a - 1)
        free(g)
        free(rowv)
        free(s)
        free(t)
        free(val)
        free(arg)


def l1_rows_block(const int32_t[:, ::1] vr, int64_t row0, int64_t rows, bint wall, double resolution,
                  double[:, ::1] distance):
    """Taxicab row pass: ``d[x] = min_i (g_i + |x - i|)`` by a forward and a backward scan, in cells, then
    times ``resolution``."""
    cdef int64_t nb = vr.shape[0], n = vr.shape[1], i, r, c, cur
    if nb == 0 or n == 0:
        return
    cdef int64_t inf = rows + n + 4
    cdef int64_t* g
    cdef int64_t* rowv
    cdef int64_t* d
    cdef double* drow
    with nogil:
        g = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        rowv = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        d = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        for i in range(nb):
            r = row0 + i
            _gather(&vr[i, 0], r, inf, g, rowv, n, wall)
            cur = 4 * inf
            for c in range(n + 2):
                cur = cur + 1
                if g[c] < cur:
                    cur = g[c]
                d[c] = cur
            cur = 4 * inf
            for c in range(n + 1, -1, -1):
                cur = cur + 1
                if g[c] < cur:
                    cur = g[c]
                if cur < d[c]:
                    d[c] = cur
            drow = &distance[i, 0]
            for c in range(n):
                drow[c] = INFINITY if d[c + 1] >= inf else <double><int32_t>d[c + 1] * resolution
        free(g)
        free(rowv)
        free(d)


cdef inline int64_t _fdiv2(int64_t a) noexcept nogil:
    # floor(a / 2)
    return (a - (a & 1)) // 2


def linf_rows_block(const int32_t[:, ::1] vr, int64_t row0, int64_t rows, bint wall, double resolution,
                    double[:, ::1] distance):
    """Chessboard row pass: ``d[x] = min_i max(|x - i|, g_i)`` over the sites ``i`` with ``g_i < inf``, by the
    lower envelope of Meijster et al. (2000) for the L-infinity metric, in cells, then times ``resolution``."""
    cdef int64_t nb = vr.shape[0], n = vr.shape[1], i, r, c, q, u, gu, sq, gs, w, x, dx, fq, fu
    if nb == 0 or n == 0:
        return
    cdef int64_t inf = rows + n + 4
    cdef int64_t* g
    cdef int64_t* rowv
    cdef int64_t* s
    cdef int64_t* t
    cdef double* drow
    with nogil:
        g = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        rowv = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        s = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        t = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        for i in range(nb):
            r = row0 + i
            _gather(&vr[i, 0], r, inf, g, rowv, n, wall)
            drow = &distance[i, 0]
            # positions x = 1..n (the cells); sites u = 0..n+1
            q = -1
            for u in range(n + 2):
                gu = g[u]
                if gu >= inf:
                    continue
                while q >= 0:
                    sq = s[q]
                    gs = g[sq]
                    x = t[q]
                    dx = x - sq if x >= sq else sq - x
                    fq = dx if dx > gs else gs
                    dx = x - u if x >= u else u - x
                    fu = dx if dx > gu else gu
                    if fq <= fu:
                        break
                    q -= 1
                if q < 0:
                    q = 0
                    s[0] = u
                    t[0] = 1
                else:
                    sq = s[q]
                    gs = g[sq]
                    # last x where s[q] is at most as far as u (Meijster's Sep for L-infinity)
                    if gs <= gu:
                        w = sq + gu
                        x = _fdiv2(sq + u)
                        if x > w:
                            w = x
                    else:
                        w = u - gs
                        x = _fdiv2(sq + u)
                        if x < w:
                            w = x
                    w += 1
                    if w <= n:
                        if w < 1:
                            w = 1
                        q += 1
                        s[q] = u
                        t[q] = w
            if q < 0:
                for c in range(n):
                    drow[c] = INFINITY
                continue
            for x in range(n, 0, -1):
                sq = s[q]
                gs = g[sq]
                dx = x - sq if x >= sq else sq - x
                fq = dx if dx > gs else gs
                drow[x - 1] = <double><int32_t>fq * resolution
                if x == t[q]:
                    q -= 1
        free(g)
        free(rowv)
        free(s)
        free(t)


# ----------------------------------------------------------------------------------------------
# the classic (khatib) field on a block, in the grid's global frame
# ----------------------------------------------------------------------------------------------
from libc.stdint cimport uint8_t

cdef extern from "_potential_rows.h" nogil:
    void gf_khatib_row(int64_t r, int64_t c0, int64_t c1, const uint8_t* occ, const int32_t* nr, const int32_t* nc,
                       double x0, double y0, double res, double goal_x, double goal_y, double zeta, double d_star,
                       double ds2, int conic, int metric, double eta, double q_star, double inv_q, int ipow,
                       double sat, double far, double* U, double* GX, double* GY)


def khatib_block(const uint8_t[:, ::1] occ, const int32_t[:, ::1] nr, const int32_t[:, ::1] nc, int64_t row0,
                 int64_t col0, double x0, double y0, double res, double goal_x, double goal_y, double zeta,
                 double d_star, bint conic, int metric, double eta, double q_star, int ipow, double sat, double far,
                 double[:, ::1] U, double[:, ::1] GX, double[:, ::1] GY):
    """The fused attractive + nearest-obstacle repulsive row loop of :mod:`gridfield._kernels_potential`
    (the same C, ``_potential_rows.h``) on a block whose first cell is ``(row0, col0)`` of the grid, with
    the global row and column indices: every value is computed by the same operations as in the
    whole-grid kernel, so the block equals that kernel's window bit for bit. ``nr``/``nc`` are global
    nearest cells (``-1, -1``: none)."""
    cdef Py_ssize_t rows = occ.shape[0], cols = occ.shape[1], i
    cdef double ds2 = d_star * d_star
    cdef double inv_q = 1.0 / q_star
    if rows == 0 or cols == 0:
        return
    with nogil:
        for i in range(rows):
            # the row loop indexes its arrays by the global column c in col0..col0+cols-1: pass the
            # row pointers moved back by col0 (only elements col0.. of them are ever read or written)
            gf_khatib_row(row0 + i, col0, col0 + cols, &occ[i, 0] - col0, &nr[i, 0] - col0, &nc[i, 0] - col0,
                          x0, y0, res, goal_x, goal_y, zeta, d_star, ds2, conic, metric, eta, q_star, inv_q, ipow,
                          sat, far, &U[i, 0] - col0, &GX[i, 0] - col0, &GY[i, 0] - col0)
