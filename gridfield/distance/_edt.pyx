# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled Euclidean transform behind :func:`gridfield.distance.brushfire.brushfire` (private;
imported on first use). The memory pool, the components, the labels and the GVD are
:mod:`gridfield.distance._brushfire`; chessboard and taxicab :mod:`gridfield.distance._chamfer`.

Euclidean (:func:`column_block`, :func:`edt_rows`)
    Separable: for every cell the nearest obstacle row in its column, then per row the lower envelope
    of the parabolas ``(x - i)**2 + g_i**2`` (Meijster, Roerdink & Hesselink 2000), whose winning
    column gives the exact nearest obstacle cell. Columns, then rows, are independent. The row pass
    first takes the least parabola among the 4 columns either side of each cell (a vectorized
    minimum, ``_brushfire_rows.h``), which is the envelope's answer wherever it is below 25; the
    other cells get an exact search outwards, and rows with many of them the envelope itself. With
    labels, each row gathers the label of its nearest obstacles (``_gather_labels32`` of
    ``_brushfire.pxd``).

The lower envelope ``_edt_1d`` is exported through ``_edt.pxd`` (cimported by
:mod:`gridfield.distance._incremental` and :mod:`gridfield.chunked._chunked`, so that all of them
use one compiled envelope).

Every kernel is sequential and releases the GIL; :mod:`gridfield.distance.brushfire` runs the
column blocks and row ranges on several threads. Conventions as in
:mod:`gridfield.distance._brushfire`: C-contiguous ``[row, col]`` arrays, occupancy as ``uint8``, the
wall border the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols``.
"""


from libc.math cimport sqrt
from libc.stdint cimport int16_t, int32_t, int64_t, uint8_t
from libc.stdlib cimport free

from ._brushfire cimport _alloc, _gather_labels32, f64_2d, i32_2d, occ_t


cdef extern from "_brushfire_rows.h" nogil:
    # the vectorizable row loops, in C (int32, one clone per ISA level: see the header)
    void gf_column_down(const uint8_t* occ, const int32_t* prev, int32_t* vrow, int32_t r, int64_t c0, int64_t c1)
    void gf_column_up(const int32_t* prev, int32_t* vrow, int32_t r, int64_t c0, int64_t c1)
    void gf_edt_gather(const int32_t* v, int32_t r, int32_t inf, int64_t* g, int64_t* rowv, int64_t cols)
    void gf_edt_distance(const int64_t* val, double res, double* d, int64_t cols)
    enum:
        GF_EDT_K
        GF_EDT_T
    void gf_edt_local_gather(const int32_t* v, int32_t r, int32_t* rv, int16_t* h, int64_t cols)
    void gf_edt_local_keys(const int16_t* h, int16_t* key, int64_t cols)
    int gf_edt_local_out(const int16_t* key, double res, double* d, int32_t* ncol, int64_t cols)
    void gf_edt_local_rows(const int32_t* rv, const int32_t* ncol, int32_t* nrow, int64_t cols)

#: Sentinel row for "no obstacle above/below" (far beyond any real grid).
BIG = 1 << 30
DEF _BIG = 1 << 30


def column_block(int64_t c0, int64_t c1, occ_t occ, bint wall, i32_2d vr):
    """Columns ``c0:c1``: ``vr[r, c]`` = row of the obstacle nearest to ``(r, c)`` in column ``c``
    (ties: the one above). Wall border: rows ``-1`` and ``rows`` count as obstacles. No obstacle in
    the column: ``+-BIG``. Two sweeps over the rows, each a branch-free loop over the columns."""
    cdef int64_t rows = occ.shape[0], cols = occ.shape[1], r, c, last
    if rows == 0 or c1 <= c0:
        return
    cdef int64_t top = -1 if wall else -_BIG
    cdef int64_t bottom = rows if wall else _BIG
    with nogil:
        for c in range(c0, c1):
            vr[0, c] = 0 if occ[0, c] else <int32_t>top
        for r in range(1, rows):
            # nearest obstacle at or above: r on an obstacle, else the one of the row above
            gf_column_down(&occ[r, 0], &vr[r - 1, 0], &vr[r, 0], <int32_t>r, c0, c1)
        last = rows - 1
        for c in range(c0, c1):
            if bottom - last < last - vr[last, c]:
                vr[last, c] = <int32_t>bottom
        for r in range(rows - 2, -1, -1):
            # The row below holds its final nearest row b. If b lies below r, it is also r's nearest
            # obstacle below (r is free, or b == r); keep the one above (a) unless b is strictly nearer.
            gf_column_up(&vr[r + 1, 0], &vr[r, 0], <int32_t>r, c0, c1)


cdef inline int64_t _floordiv_exact(int64_t a, int64_t b) noexcept nogil:
    # floor(a / b) for b > 0 and |a| < 2**53 by one double division: the quotient is exact when a / b
    # is an integer, and otherwise lies at least 1 / b from one, farther than its rounding error
    # (|a / b| * 2**-53 < 1 / b), so truncation and the sign correction give Python's a // b
    cdef double q = <double>a / <double>b
    cdef int64_t t = <int64_t>q
    return t - ((<double>t != q) & (q < 0))


cdef bint _edt_1d_sq(const int64_t* g, int64_t n, int64_t inf, int64_t* s, int64_t* t, int64_t* fs, int64_t* val,
                     int64_t* arg) noexcept nogil:
    # The lower envelope (Meijster et al. 2000): the stack holds the site s[q], the first x it wins,
    # t[q] (strictly increasing: a site is pushed only where it is strictly nearer than the top), and
    # its g**2, fs[q], so that a comparison does not wait for the load of g[s[q]] after that of s[q].
    cdef int64_t q = -1, u, gu, fu, sq, tq, fq, w, x, d1, d2, lo, hi
    for u in range(n + 2):
        gu = g[u]
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
            t[0] = 1
            fs[0] = fu
        else:
            sq = s[q]
            # first x where u is strictly nearer than s[q] (floor division of an integer ratio)
            w = 1 + _floordiv_exact(u * u - sq * sq + fu - fs[q], 2 * (u - sq))
            if w <= n:
                q += 1
                s[q] = u
                t[q] = w
                fs[q] = fu
    if q < 0:
        return False
    # site s[q] wins x in t[q] .. t[q + 1] - 1 (t[0] = 1): one branch-free loop per site
    hi = n
    while q >= 0:
        sq = s[q]
        fq = fs[q]
        lo = t[q]
        for x in range(lo, hi + 1):
            d1 = x - sq
            val[x - 1] = d1 * d1 + fq
            arg[x - 1] = sq
        hi = lo - 1
        q -= 1
    return True


cdef bint _edt_1d(const int64_t* g, int64_t n, int64_t inf, int64_t* s, int64_t* t, int64_t* val,
                  int64_t* arg) noexcept nogil:
    # the envelope for callers without a buffer for the stack's g**2 (_incremental, _chunked)
    cdef int64_t* fs = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
    cdef bint found = _edt_1d_sq(g, n, inf, s, t, fs, val, arg)
    free(fs)
    return found


def edt_1d(const int64_t[::1] g, int64_t n, int64_t inf, int64_t[::1] s, int64_t[::1] t, int64_t[::1] val,
           int64_t[::1] arg):
    """Lower envelope of ``f_i(x) = (x - i)**2 + g[i]**2`` over the sites ``i`` in ``0..n+1`` with
    ``g[i] < inf``, for ``x`` in ``1..n``: ``val[x - 1]`` (squared distance) and ``arg[x - 1]``
    (winning site). Returns False if there is no site. All arrays int64."""
    if n <= 0:
        return False
    return _edt_1d(&g[0], n, inf, &s[0], &t[0], &val[0], &arg[0])


# When edt_rows gives a row to the lower envelope instead of the local window (results are the same;
# only the time differs). Measured on 4096^2 maps, one thread: 20 % random (nearly every row local),
# 2 % random and the benchmark's maze (mostly envelope rows): the window pass costs those maps nothing
# against the envelope-only build.
DEF _EXC_RATIO = 64  # more exceptions than 1 in 64 cells: the envelope, without searching
DEF _EXC_BUDGET = 4  # the exact searches of a row may take n / 4 + 16 radii, then the envelope
DEF _RETRY = 16  # after a row that needed the envelope, the next rows go straight to it, but every
                 # 16th row of a chunk tries the window again


cdef bint _edt_exceptions(const int16_t* key, const int32_t* rv, int64_t n, int64_t r, bint wall, int64_t inf,
                          double resolution, double* drow, int32_t* crow, int64_t budget) noexcept nogil:
    # The cells the local window of _brushfire_rows.h cannot vouch for (window minimum >= GF_EDT_T): an
    # exact search outwards from the cell's own column, radius R = 0, 1, ... (left site first), keeping
    # the least f = R**2 + g**2, ties to the smaller site, until R**2 exceeds the best f. Writes drow and
    # crow. Returns False when the row's searches take more than `budget` radii (or find no site): the
    # caller then runs the lower envelope on the whole row.
    cdef int64_t c, a, rad, side, site, g, f, bf, bs, spent = 0
    for c in range(n):
        if (key[c] >> 4) < GF_EDT_T:
            continue
        a = c + 1
        bf = -1
        bs = -1
        rad = 0
        while bf < 0 or rad * rad <= bf:
            if a - rad < 0 and a + rad > n + 1:
                break
            spent += 1
            if spent > budget:
                return False
            for side in range(2):
                if side == 0:
                    site = a - rad
                    if site < 0:
                        continue
                else:
                    site = a + rad
                    if rad == 0 or site > n + 1:
                        continue
                if site == 0 or site == n + 1:
                    g = 0 if wall else inf
                else:
                    g = r - rv[site]
                    g = -g if g < 0 else g
                    g = inf if g > inf else g
                if g >= inf:
                    continue
                f = rad * rad + g * g
                if bf < 0 or f < bf or (f == bf and site < bs):
                    bf = f
                    bs = site
            rad += 1
        if bs < 0:
            return False
        drow[c] = sqrt(<double>bf) * resolution
        crow[c] = <int32_t>(bs - 1)
    return True


def edt_rows(int64_t r0, int64_t r1, const int32_t[:, ::1] vr, bint wall, double resolution, f64_2d distance,
             i32_2d nearest_row, i32_2d nearest_col, bint want_nearest, const int32_t[::1] flat,
             const int32_t[::1] comp_map, bint use_map, bint want_label, i32_2d label):
    """Rows ``r0:r1`` of the Euclidean transform's row pass: ``distance`` and optionally the nearest
    obstacle and its label.

    ``vr`` holds the column pass result; it may be the very array ``nearest_row`` (each row is copied
    to a buffer before it is overwritten). Labels: see :func:`_gather_labels`.

    Each row is first solved in a window of ``GF_EDT_K`` columns either side of every cell
    (``_brushfire_rows.h``: exact wherever some site within the window lies nearer than
    ``GF_EDT_K + 1``); the other cells by an exact search outwards (:func:`_edt_exceptions`), or, when
    those searches grow long (open maps), the whole row by the lower envelope (:func:`_edt_1d_sq`).
    The answer is the same either way: the least squared distance, ties to the leftmost site.
    """
    cdef int64_t rows = vr.shape[0], cols = vr.shape[1], r, c, bad
    cdef bint envelope_last = False
    cdef int64_t n = cols
    if rows == 0 or cols == 0 or r1 <= r0:
        return
    cdef int64_t inf = rows + cols + 4
    cdef bint need_rows = want_nearest or want_label
    cdef int64_t* g
    cdef int64_t* rowv
    cdef int64_t* s
    cdef int64_t* t
    cdef int64_t* fs
    cdef int64_t* val
    cdef int64_t* arg
    cdef int32_t* rv
    cdef int16_t* h
    cdef int16_t* key
    cdef int32_t* bnr
    cdef int32_t* bnc
    cdef int32_t* rrow
    cdef int32_t* crow
    cdef double* drow
    with nogil:
        g = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        rowv = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        s = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        t = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        fs = <int64_t*>_alloc((n + 2) * sizeof(int64_t))
        val = <int64_t*>_alloc(n * sizeof(int64_t))
        arg = <int64_t*>_alloc(n * sizeof(int64_t))
        rv = <int32_t*>_alloc((n + 2) * sizeof(int32_t))
        h = <int16_t*>_alloc((n + 2 * GF_EDT_K) * sizeof(int16_t))
        key = <int16_t*>_alloc(n * sizeof(int16_t))
        bnr = <int32_t*>_alloc(n * sizeof(int32_t))
        bnc = <int32_t*>_alloc(n * sizeof(int32_t))
        # the window's pad: sites beyond the wall columns never win; the wall columns (sites 0 and
        # n + 1) are obstacles in every row with a wall border
        for c in range(n + 2 * GF_EDT_K):
            h[c] = <int16_t>(GF_EDT_T * 16)
        h[GF_EDT_K - 1] = <int16_t>(0 if wall else GF_EDT_T * 16)
        h[n + GF_EDT_K] = <int16_t>(0 if wall else GF_EDT_T * 16)
        for r in range(r0, r1):
            drow = &distance[r, 0]
            rrow = &nearest_row[r, 0] if want_nearest else bnr
            crow = &nearest_col[r, 0] if want_nearest else bnc
            rv[0] = <int32_t>r
            rv[n + 1] = <int32_t>r
            g[0] = 0 if wall else inf
            g[n + 1] = 0 if wall else inf
            rowv[0] = r
            rowv[n + 1] = r
            if envelope_last and (r - r0) % _RETRY != 0:  # the row before needed the envelope: likely this one too
                gf_edt_gather(&vr[r, 0], <int32_t>r, <int32_t>inf, g, rowv, n)
                for c in range(n):
                    rv[c + 1] = <int32_t>rowv[c + 1]
                bad = -1
            else:
                gf_edt_local_gather(&vr[r, 0], <int32_t>r, rv, h, n)  # vr's row is read before rrow is written
                gf_edt_local_keys(h, key, n)
                bad = gf_edt_local_out(key, resolution, drow, crow, n)
                if bad and (bad * _EXC_RATIO > n or not _edt_exceptions(key, rv, n, r, wall, inf, resolution, drow,
                                                                        crow, n // _EXC_BUDGET + 16)):
                    gf_edt_gather(&rv[1], <int32_t>r, <int32_t>inf, g, rowv, n)
                    bad = -1
            envelope_last = bad < 0
            if envelope_last:
                _edt_1d_sq(g, n, inf, s, t, fs, val, arg)
                gf_edt_distance(val, resolution, drow, n)
                for c in range(n):
                    crow[c] = <int32_t>(arg[c] - 1)
            if need_rows:
                gf_edt_local_rows(rv, crow, rrow, n)
            if want_label:
                _gather_labels32(rrow, crow, n, rows, cols, &flat[0], &comp_map[0], use_map, &label[r, 0])
        free(g)
        free(rowv)
        free(s)
        free(t)
        free(fs)
        free(val)
        free(arg)
        free(rv)
        free(h)
        free(key)
        free(bnr)
        free(bnc)
