# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled chessboard and taxicab transforms behind :func:`gridfield.distance.brushfire.brushfire`
(private; imported on first use). The memory pool, the components, the labels and the GVD are
:mod:`gridfield.distance._brushfire`; the Euclidean transform is :mod:`gridfield.distance._edt`.

Chessboard and taxicab (:func:`chamfer_steps`, :func:`chamfer_nearest`)
    The classic two-pass raster transform with a 3x3 mask (Rosenfeld & Pfaltz 1966), exact for both
    metrics. Each row is done in two stages: the neighbours in the previous row (a branch-free loop
    the compiler vectorizes; C in ``_brushfire_rows.h``), then the left (right) neighbour (a scan:
    a blocked prefix minimum in ``_brushfire_rows.h`` for the distance alone, 4 interleaved chains
    here when the nearest cell rides along).
    The nearest obstacle cell is carried along: the neighbour that gives a cell its final value has a
    nearest obstacle at exactly that distance, so the carried cell is an exact nearest obstacle.
    Sequential over the rows.

Then :func:`finish_window` (a strip's rows out of its window) and :func:`decode_rows` (the nearest
cell of the packed index), independent over rows.

Every kernel is sequential and releases the GIL; :mod:`gridfield.distance.brushfire` runs the
strips and row ranges on several threads. Conventions as in :mod:`gridfield.distance._brushfire`:
C-contiguous ``[row, col]`` arrays, occupancy as ``uint8``, the wall border the ring of cells at rows
``-1``/``rows`` and columns ``-1``/``cols``.
"""


from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free

from ._brushfire cimport _alloc, _lmax, f64_2d, i32_2d, occ_t


cdef extern from "_brushfire_rows.h" nogil:
    # the vectorizable row loops, in C (int32, one clone per ISA level: see the header)
    void gf_chamfer_fwd_pre(const int32_t* up, int32_t edge_row, int32_t pad, const uint8_t* occ, int32_t* t,
                            int64_t cols, int conn8)
    void gf_chamfer_bwd_pre(const int32_t* down, int32_t edge_row, int32_t pad, const int32_t* s, int32_t* t,
                            int64_t cols, int conn8)
    void gf_scale_row(const int32_t* s, double res, double* d, int64_t cols, const double* next_d, int stream)
    void gf_scan_right(const int32_t* t, int32_t* s, int64_t cols, int32_t edge)
    void gf_scan_left(const int32_t* t, int32_t* s, int64_t cols, int32_t edge)

ctypedef fused nidx_t:
    int32_t
    int64_t

cdef int64_t _NOINFO = 1 << 30  # initial carry of the inner segments: never wins


# ----------------------------------------------------------------------------------------------
# chessboard / taxicab: two-pass raster transform
# ----------------------------------------------------------------------------------------------
# The index-carrying scans s[c] = min(t[c], s[c -+ 1] + 1) are latency bound (one compare-select chain
# per row): they run as 4 interleaved chains over 4 segments of the row, then the carry of each
# segment's end is pushed into the next segment for as long as it improves it (a few cells at most
# in practice). The distance-only scans are gf_scan_right/gf_scan_left of _brushfire_rows.h.
cdef inline void _scan_right_idx(const int32_t* t, const int64_t* ti, int32_t* s, nidx_t* si, int64_t cols,
                                 int64_t edge, int64_t edge_i) noexcept nogil:
    """:func:`_scan_right` carrying the nearest-cell index ``si`` of the winner."""
    cdef int64_t n = _lmax(0, cols // 4 - 17)
    cdef int64_t l0 = edge, l1 = _NOINFO, l2 = _NOINFO, l3 = _NOINFO
    cdef int64_t i0 = edge_i, i1 = 0, i2 = 0, i3 = 0, a, m, j, c, k, end, v, vi
    for j in range(n):
        c = j
        a = t[c]
        m = (l0 + 1 < a)
        a += (l0 + 1 - a) * m
        i0 = ti[c] + (i0 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i0
        l0 = a
        c = n + j
        a = t[c]
        m = (l1 + 1 < a)
        a += (l1 + 1 - a) * m
        i1 = ti[c] + (i1 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i1
        l1 = a
        c = 2 * n + j
        a = t[c]
        m = (l2 + 1 < a)
        a += (l2 + 1 - a) * m
        i2 = ti[c] + (i2 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i2
        l2 = a
        c = 3 * n + j
        a = t[c]
        m = (l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i3
        l3 = a
    if n == 0:
        l3 = edge
        i3 = edge_i
    for c in range(4 * n, cols):
        a = t[c]
        m = (l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i3
        l3 = a
    for k in range(1, 4):
        c = k * n
        end = cols if k == 3 else c + n
        if c == 0:
            continue
        v = <int64_t>s[c - 1] + 1
        vi = si[c - 1]
        while c < end and v < s[c]:
            s[c] = <int32_t>v
            si[c] = <nidx_t>vi
            v += 1
            c += 1


cdef inline void _scan_left_idx(const int32_t* t, const int64_t* ti, int32_t* s, nidx_t* si, int64_t cols,
                                int64_t edge, int64_t edge_i) noexcept nogil:
    """:func:`_scan_left` carrying the nearest-cell index ``si`` of the winner."""
    cdef int64_t n = _lmax(0, cols // 4 - 17)
    cdef int64_t top = cols - 1
    cdef int64_t l0 = edge, l1 = _NOINFO, l2 = _NOINFO, l3 = _NOINFO
    cdef int64_t i0 = edge_i, i1 = 0, i2 = 0, i3 = 0, a, m, j, c, k, end, v, vi, x
    for j in range(n):
        c = top - j
        a = t[c]
        m = (l0 + 1 < a)
        a += (l0 + 1 - a) * m
        i0 = ti[c] + (i0 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i0
        l0 = a
        c = top - n - j
        a = t[c]
        m = (l1 + 1 < a)
        a += (l1 + 1 - a) * m
        i1 = ti[c] + (i1 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i1
        l1 = a
        c = top - 2 * n - j
        a = t[c]
        m = (l2 + 1 < a)
        a += (l2 + 1 - a) * m
        i2 = ti[c] + (i2 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i2
        l2 = a
        c = top - 3 * n - j
        a = t[c]
        m = (l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i3
        l3 = a
    if n == 0:
        l3 = edge
        i3 = edge_i
    for x in range(4 * n, cols):
        c = top - x
        a = t[c]
        m = (l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = <int32_t>a
        si[c] = <nidx_t>i3
        l3 = a
    for k in range(1, 4):
        x = k * n
        end = cols if k == 3 else x + n
        if x == 0:
            continue
        c = top - x + 1
        v = <int64_t>s[c] + 1
        vi = si[c]
        while x < end and v < s[top - x]:
            c = top - x
            s[c] = <int32_t>v
            si[c] = <nidx_t>vi
            v += 1
            x += 1


#: Grids of at least this many cells write the chamfer distance with non-temporal stores
#: (gf_scale_row): 32 MiB of float64, beyond what the caches would keep for the caller anyway.
DEF _STREAM_CELLS = 1 << 22


def chamfer_steps(occ_t occ, bint top, bint bottom, bint side, bint conn8, i32_2d steps, f64_2d distance,
                  double resolution, bint write_distance):
    """Chessboard (``conn8``) or taxicab steps; also ``distance = steps * resolution`` if asked.

    ``top``, ``bottom``, ``side``: whether the rows above / below the array and the columns beside it
    are a wall (obstacles) or open."""
    cdef int64_t rows = occ.shape[0], cols = occ.shape[1], r
    if rows == 0 or cols == 0:
        return
    cdef int64_t inf = rows + cols + 4
    cdef int64_t top_edge = 0 if top else inf
    cdef int64_t bottom_edge = 0 if bottom else inf
    cdef int64_t edge = 0 if side else inf
    cdef int32_t pad = <int32_t>inf  # the columns beside the row: never win
    cdef int stream = rows * cols >= _STREAM_CELLS  # distance far larger than the caches: streamed
    cdef int32_t* t
    cdef int32_t* srow
    with nogil:
        t = <int32_t*>_alloc(cols * sizeof(int32_t))
        for r in range(rows):  # forward: up-left, up, up-right, left
            srow = &steps[r, 0]
            gf_chamfer_fwd_pre(NULL if r == 0 else &steps[r - 1, 0], <int32_t>top_edge, pad, &occ[r, 0], t, cols,
                               conn8)
            gf_scan_right(t, srow, cols, <int32_t>edge)
        for r in range(rows - 1, -1, -1):  # backward: down-right, down, down-left, right
            srow = &steps[r, 0]
            gf_chamfer_bwd_pre(NULL if r == rows - 1 else &steps[r + 1, 0], <int32_t>bottom_edge, pad, srow, t, cols,
                               conn8)
            gf_scan_left(t, srow, cols, <int32_t>edge)
            if write_distance:
                gf_scale_row(srow, resolution, &distance[r, 0], cols, NULL if r == 0 else &distance[r - 1, 0], stream)
        free(t)


cdef void _chamfer_nearest(occ_t occ, bint top, bint bottom, bint side, int64_t row0, bint conn8, i32_2d steps,
                           nidx_t[:, ::1] nidx, f64_2d distance, double resolution,
                           bint write_distance) noexcept nogil:
    cdef int64_t rows = occ.shape[0], cols = occ.shape[1], r, c, a, ai, b, m, o, own, cur
    cdef int64_t w = cols + 2
    cdef int64_t inf = rows + cols + 4
    cdef int64_t top_edge = 0 if top else inf
    cdef int64_t bottom_edge = 0 if bottom else inf
    cdef int64_t edge = 0 if side else inf
    cdef int32_t* p = <int32_t*>_alloc((cols + 2) * sizeof(int32_t))  # the neighbouring row, padded
    cdef int64_t* pi = <int64_t*>_alloc((cols + 2) * sizeof(int64_t))
    cdef int32_t* t = <int32_t*>_alloc(cols * sizeof(int32_t))
    cdef int64_t* ti = <int64_t*>_alloc(cols * sizeof(int64_t))
    cdef const uint8_t* orow
    cdef int32_t* srow
    cdef nidx_t* irow
    cdef const int32_t* prev
    cdef const nidx_t* previ
    cdef double* drow
    pi[0] = 0
    pi[cols + 1] = 0
    p[0] = <int32_t>inf
    p[cols + 1] = <int32_t>inf
    for r in range(rows):  # forward: up-left, up, up-right, then left
        orow = &occ[r, 0]
        srow = &steps[r, 0]
        irow = &nidx[r, 0]
        if r == 0:
            for c in range(cols):
                p[c + 1] = <int32_t>top_edge
                pi[c + 1] = row0 * w + c + 1  # wall cell (row0 - 1, c)
        else:
            prev = &steps[r - 1, 0]
            previ = &nidx[r - 1, 0]
            for c in range(cols):
                p[c + 1] = prev[c]
                pi[c + 1] = previ[c]
        own = (row0 + r + 1) * w + 1
        for c in range(cols):
            a = p[c + 1]
            ai = pi[c + 1]
            if conn8:
                b = p[c]
                m = b < a
                a += (b - a) * m
                ai += (pi[c] - ai) * m
                b = p[c + 2]
                m = b < a
                a += (b - a) * m
                ai += (pi[c + 2] - ai) * m
            a += 1
            o = orow[c]
            t[c] = <int32_t>(a - a * o)
            ti[c] = ai + (own + c - ai) * o
        _scan_right_idx(t, ti, srow, irow, cols, edge, own - 1)  # wall cell (r, -1)
    for r in range(rows - 1, -1, -1):  # backward: down-right, down, down-left, then right
        srow = &steps[r, 0]
        irow = &nidx[r, 0]
        if r == rows - 1:
            for c in range(cols):
                p[c + 1] = <int32_t>bottom_edge
                pi[c + 1] = (row0 + rows + 1) * w + c + 1  # wall cell (row0 + rows, c)
        else:
            prev = &steps[r + 1, 0]
            previ = &nidx[r + 1, 0]
            for c in range(cols):
                p[c + 1] = prev[c]
                pi[c + 1] = previ[c]
        for c in range(cols):
            a = p[c + 1]
            ai = pi[c + 1]
            if conn8:
                b = p[c]
                m = b < a
                a += (b - a) * m
                ai += (pi[c] - ai) * m
                b = p[c + 2]
                m = b < a
                a += (b - a) * m
                ai += (pi[c + 2] - ai) * m
            t[c] = <int32_t>(a + 1)
            ti[c] = ai
        for c in range(cols):  # a separate loop: fewer arrays, so the compiler vectorizes both
            a = t[c]
            cur = srow[c]
            m = a < cur
            t[c] = <int32_t>(cur + (a - cur) * m)
            ti[c] = irow[c] + (ti[c] - irow[c]) * m
        _scan_left_idx(t, ti, srow, irow, cols, edge, (row0 + r + 1) * w + cols + 1)  # wall cell (r, cols)
        if write_distance:
            drow = &distance[r, 0]
            for c in range(cols):
                drow[c] = srow[c] * resolution
    free(p)
    free(pi)
    free(t)
    free(ti)


def chamfer_nearest(occ_t occ, bint top, bint bottom, bint side, int64_t row0, bint conn8, i32_2d steps,
                    nidx_t[:, ::1] nidx, f64_2d distance, double resolution, bint write_distance):
    """:func:`chamfer_steps` carrying the nearest obstacle cell along, packed as
    ``nidx = (row + 1) * (cols + 2) + (col + 1)`` with ``row`` counted from ``row0`` (the first row of
    ``occ`` in the whole grid; see :func:`decode_row`); ``nidx`` is ``int32`` or ``int64``. Selects are
    branch-free: ``x += (y - x) * m`` with ``m`` in {0, 1}."""
    if occ.shape[0] == 0 or occ.shape[1] == 0:
        return
    with nogil:
        _chamfer_nearest(occ, top, bottom, side, row0, conn8, steps, nidx, distance, resolution, write_distance)


cdef inline void _decode_row(const nidx_t* irow, int64_t cols, int64_t* nr, int64_t* nc) noexcept nogil:
    """Unpack one row of :func:`chamfer_nearest`'s packed cells into ``nr``, ``nc``."""
    cdef int64_t w = cols + 2, c, i, q
    cdef double inv = 1.0 / (cols + 2)
    for c in range(cols):
        i = irow[c]
        q = <int64_t>(i * inv)  # i // w in floating point, then corrected
        q += <int64_t>(i - q * w >= w) - <int64_t>(i - q * w < 0)
        nr[c] = q - 1
        nc[c] = i - q * w - 1


def decode_row(nidx_t[::1] irow, int64_t cols, int64_t[::1] nr, int64_t[::1] nc):
    """Unpack one row of :func:`chamfer_nearest`'s packed cells into ``nr``, ``nc`` (int64)."""
    if cols > 0:
        _decode_row(&irow[0], cols, &nr[0], &nc[0])


cdef bint _finish_window(int64_t a, int64_t b, int64_t lo, int64_t margin, bint checked, const int32_t[:, ::1] ws,
                         const nidx_t[:, ::1] wi, bint want_idx, i32_2d steps, i32_2d nearest_row,
                         i32_2d nearest_col, f64_2d distance, double resolution, bint write_distance) noexcept nogil:
    cdef int64_t cols = ws.shape[1], r, c, v
    cdef int64_t worst = 0
    cdef int64_t* br = <int64_t*>_alloc(cols * sizeof(int64_t))
    cdef int64_t* bc = <int64_t*>_alloc(cols * sizeof(int64_t))
    cdef const int32_t* src
    cdef int32_t* srow
    cdef double* drow
    cdef int32_t* rrow
    cdef int32_t* crow
    for r in range(a, b):
        src = &ws[r - lo, 0]
        srow = &steps[r, 0]
        for c in range(cols):
            v = src[c]
            worst = worst if worst > v else v
            srow[c] = <int32_t>v
        if write_distance:
            drow = &distance[r, 0]
            for c in range(cols):
                drow[c] = src[c] * resolution
        if want_idx:
            _decode_row(&wi[r - lo, 0], cols, br, bc)
            rrow = &nearest_row[r, 0]
            crow = &nearest_col[r, 0]
            for c in range(cols):
                rrow[c] = <int32_t>br[c]
                crow[c] = <int32_t>bc[c]
    free(br)
    free(bc)
    return not checked or worst <= margin


def finish_window(int64_t a, int64_t b, int64_t lo, int64_t margin, bint checked, const int32_t[:, ::1] ws,
                  const nidx_t[:, ::1] wi, bint want_idx, i32_2d steps, i32_2d nearest_row, i32_2d nearest_col,
                  f64_2d distance, double resolution, bint write_distance):
    """Copy rows ``a:b`` of a window transform (``ws``/``wi``: rows ``lo:lo + len(ws)`` of the grid) into
    the outputs, unpacking the nearest cells. Returns False if ``checked`` and some copied cell lies
    farther than ``margin`` from its nearest obstacle in the window: an obstacle outside the window
    might then be nearer (one within ``margin`` rows of the cell always lies inside it)."""
    cdef bint ok
    if ws.shape[1] == 0 or b <= a:
        return True
    with nogil:
        ok = _finish_window(a, b, lo, margin, checked, ws, wi, want_idx, steps, nearest_row, nearest_col, distance,
                            resolution, write_distance)
    return ok


def decode_rows(int64_t r0, int64_t r1, const nidx_t[:, ::1] nidx, i32_2d nearest_row, i32_2d nearest_col):
    """Rows ``r0:r1``: unpack ``nidx`` into ``nearest_row``/``nearest_col`` (which may be ``nidx``)."""
    cdef int64_t cols = nidx.shape[1], r, c
    if cols == 0:
        return
    cdef int64_t* br
    cdef int64_t* bc
    cdef int32_t* rrow
    cdef int32_t* crow
    with nogil:
        br = <int64_t*>_alloc(cols * sizeof(int64_t))
        bc = <int64_t*>_alloc(cols * sizeof(int64_t))
        for r in range(r0, r1):
            _decode_row(&nidx[r, 0], cols, br, bc)
            rrow = &nearest_row[r, 0]
            crow = &nearest_col[r, 0]
            for c in range(cols):
                rrow[c] = <int32_t>br[c]
                crow[c] = <int32_t>bc[c]
        free(br)
        free(bc)
