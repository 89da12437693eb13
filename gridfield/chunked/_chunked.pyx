# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.chunked` (private; imported on first use by the tasks).

The separable transforms of :func:`gridfield.distance.brushfire.brushfire` on a block of whole rows of a larger grid:
the column pass (:func:`gridfield.distance._edt.column_block`, run on a block of whole columns, gives
each cell the global row of the obstacle nearest to it in its column); then, here, the row pass on a block
of whole rows whose first row is ``row0`` of a grid of ``rows`` rows:

- :func:`edt_rows_block`: the Euclidean lower envelope (the one compiled envelope of
  :mod:`gridfield.distance._edt`, cimported), with the same arithmetic as ``edt_rows`` there, so
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

from gridfield.distance._edt cimport _edt_1d


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


cdef inline int64_t _floordiv_pos(int64_t a, int64_t b) noexcept nogil:
    # Python's a // b for b > 0 (C division truncates)
    cdef int64_t q = a // b
    if (a % b != 0) and (a < 0):
        q -= 1
    return q


cdef inline int64_t _site_g(const int32_t* v, int64_t x, int64_t a, int64_t r, int64_t cols, int64_t inf,
                            bint wall) noexcept nogil:
    """``g`` of the site in global column ``x`` (``-1`` and ``cols``: the wall ring) for row ``r``; ``inf``: none."""
    cdef int64_t y, d
    if x < 0 or x >= cols:
        return 0 if wall else inf
    y = v[x - a]
    d = r - y if r >= y else y - r
    return d if d < inf else inf


def edt_block(const int32_t[:, ::1] vr, int64_t a, int64_t row0, int64_t rows, int64_t cols, bint wall,
              double resolution, int64_t c0, double[:, ::1] distance, int32_t[:, ::1] nearest_row,
              int32_t[:, ::1] nearest_col, bint want_nearest):
    """Euclidean row pass of one output block: rows ``row0..`` and columns ``c0 .. c0 + w - 1`` (``w`` =
    ``distance.shape[1]``) of a grid of ``rows x cols``, from the column pass result ``vr`` of the same rows
    and the global columns ``a .. a + vr.shape[1] - 1`` (a window around the block's columns).

    Only the sites that can be nearest (or tie) inside the block are needed: left of ``c0``, a site ``u``
    with ``(c0 - u)**2`` above the least ``(c0 - v)**2 + g_v**2`` over ``v <= c0`` is strictly farther than
    that ``v`` at every ``x >= c0`` (their difference grows with ``x``); the same on the right of the last
    column. Each row scans outwards from the block's edges until that bound, then builds the lower envelope
    (Meijster et al. 2000, the integer arithmetic of ``gridfield.distance._edt._edt_1d_sq``) over those sites,
    evaluated on the block's columns only. The envelope gives at each ``x`` the least ``(value, site)``
    pair (a site is pushed only where it is strictly nearer), so the result equals that over all sites:
    the in-memory distance and nearest cell bit for bit.

    Returns
    -------
    bool
        False (nothing written) when some row's bound reaches beyond the window: call again with a wider one.
    """
    cdef int64_t nb = vr.shape[0], W = vr.shape[1], w = distance.shape[1], i, r, x, dx, m, f, gu
    cdef int64_t c1 = c0 + w - 1
    cdef int64_t inf = rows + cols + 4  # as edt_rows
    cdef int64_t lo, hi, q, u, fu, sq, tq, fq, d1, d2, wx, top, lx, y, x0, x1
    cdef int64_t* gb
    cdef int32_t* nrow = NULL
    cdef int32_t* ncol = NULL
    cdef const int32_t* v
    cdef double* drow
    cdef int64_t* lo_r
    cdef int64_t* hi_r
    cdef int64_t* s
    cdef int64_t* t
    cdef int64_t* fs
    cdef bint ok = True
    if nb == 0 or w == 0:
        return True
    if c0 < a or c1 >= a + W:
        raise ValueError("the window must hold the block's columns")
    with nogil:
        lo_r = <int64_t*>_alloc(nb * sizeof(int64_t))
        hi_r = <int64_t*>_alloc(nb * sizeof(int64_t))
        # the bounds of every row first: a window too narrow is found before any work
        for i in range(nb):
            r = row0 + i
            v = &vr[i, 0]
            m = -1  # no site yet
            x = c0
            while True:
                dx = c0 - x
                if m >= 0 and dx * dx > m:
                    lo = x + 1
                    break
                if x < a and x >= 0:
                    ok = False
                    break
                gu = _site_g(v, x, a, r, cols, inf, wall)
                if gu < inf:
                    f = dx * dx + gu * gu
                    if m < 0 or f < m:
                        m = f
                if x < 0:
                    lo = -1
                    break
                x -= 1
            if not ok:
                break
            m = -1
            x = c1
            while True:
                dx = x - c1
                if m >= 0 and dx * dx > m:
                    hi = x - 1
                    break
                if x >= a + W and x < cols:
                    ok = False
                    break
                gu = _site_g(v, x, a, r, cols, inf, wall)
                if gu < inf:
                    f = dx * dx + gu * gu
                    if m < 0 or f < m:
                        m = f
                if x >= cols:
                    hi = cols
                    break
                x += 1
            if not ok:
                break
            lo_r[i] = lo
            hi_r[i] = hi
        if ok:
            lx = 0
            for i in range(nb):
                if hi_r[i] - lo_r[i] + 1 > lx:
                    lx = hi_r[i] - lo_r[i] + 1
            s = <int64_t*>_alloc(lx * sizeof(int64_t))
            t = <int64_t*>_alloc(lx * sizeof(int64_t))
            fs = <int64_t*>_alloc(lx * sizeof(int64_t))
            gb = <int64_t*>_alloc(lx * sizeof(int64_t))
            for i in range(nb):
                r = row0 + i
                v = &vr[i, 0]
                drow = &distance[i, 0]
                if want_nearest:
                    nrow = &nearest_row[i, 0]
                    ncol = &nearest_col[i, 0]
                lo = lo_r[i]
                hi = hi_r[i]
                # g of the sites lo..hi (the wall ring's at -1 and cols), one branch-free loop inside
                x0 = lo if lo >= 0 else 0
                x1 = hi if hi < cols else cols - 1
                if lo < 0:
                    gb[0] = 0 if wall else inf
                if hi >= cols:
                    gb[hi - lo] = 0 if wall else inf
                for x in range(x0, x1 + 1):
                    y = v[x - a]
                    d1 = r - y if r >= y else y - r
                    gb[x - lo] = d1 if d1 < inf else inf
                q = -1
                for u in range(lo, hi + 1):
                    gu = gb[u - lo]
                    if gu >= inf:
                        continue
                    fu = gu * gu
                    while q >= 0:
                        sq = s[q]
                        tq = t[q]
                        fq = fs[q]
                        d1 = tq - sq
                        d2 = tq - u
                        if d1 * d1 + fq <= d2 * d2 + fu:
                            break
                        q -= 1
                    if q < 0:
                        q = 0
                        s[0] = u
                        t[0] = c0
                        fs[0] = fu
                    else:
                        sq = s[q]
                        # first x where u is strictly nearer than s[q]
                        wx = 1 + _floordiv_pos(u * u - sq * sq + fu - fs[q], 2 * (u - sq))
                        if wx <= c1:
                            q += 1
                            s[q] = u
                            t[q] = wx
                            fs[q] = fu
                if q < 0:
                    for x in range(w):
                        drow[x] = INFINITY
                        if want_nearest:
                            nrow[x] = -1
                            ncol[x] = -1
                    continue
                top = c1
                while q >= 0:
                    sq = s[q]
                    fq = fs[q]
                    if sq < 0 or sq >= cols:
                        y = r
                    else:
                        y = v[sq - a]
                    for x in range(t[q], top + 1):
                        d1 = x - sq
                        drow[x - c0] = sqrt(<double>(d1 * d1 + fq)) * resolution
                    if want_nearest:
                        for x in range(t[q] - c0, top + 1 - c0):
                            nrow[x] = <int32_t>y
                            ncol[x] = <int32_t>sq
                    top = t[q] - 1
                    q -= 1
            free(s)
            free(t)
            free(fs)
            free(gb)
        free(lo_r)
        free(hi_r)
    return ok


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
    """The fused attractive + nearest-obstacle repulsive row loop of :mod:`gridfield.fields._potential`
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
