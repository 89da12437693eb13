# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :func:`gridfield.distance.brushfire.brushfire` (private; imported on first use).

Chessboard and taxicab (:func:`chamfer_steps`, :func:`chamfer_nearest`)
    The classic two-pass raster transform with a 3x3 mask (Rosenfeld & Pfaltz 1966), exact for both
    metrics. Each row is done in two stages: the neighbours in the previous row (a branch-free loop
    the compiler vectorizes; C in ``_brushfire_rows.h``), then the left (right) neighbour (a scan:
    a blocked prefix minimum in ``_brushfire_rows.h`` for the distance alone, 4 interleaved chains
    here when the nearest cell rides along).
    The nearest obstacle cell is carried along: the neighbour that gives a cell its final value has a
    nearest obstacle at exactly that distance, so the carried cell is an exact nearest obstacle.
    Sequential over the rows.

Euclidean (:func:`column_block`, :func:`edt_rows`)
    Separable: for every cell the nearest obstacle row in its column, then per row the lower envelope
    of the parabolas ``(x - i)**2 + g_i**2`` (Meijster, Roerdink & Hesselink 2000), whose winning
    column gives the exact nearest obstacle cell. Columns, then rows, are independent. The row pass
    first takes the least parabola among the 4 columns either side of each cell (a vectorized
    minimum, ``_brushfire_rows.h``), which is the envelope's answer wherever it is below 25; the
    other cells get an exact search outwards, and rows with many of them the envelope itself.

Components (:func:`label_strip`, :func:`merge_strips`, :func:`relabel_rows`)
    8-connected, two-pass union-find on horizontal strips, joined across the strip boundaries;
    components are numbered in raster order of their first cell (row 0 first), the numbering of
    ``scipy.ndimage.label``. Strips are independent.

Then :func:`decode_rows` (nearest cell and label of the chamfer path), :func:`gvd_rows` and
:func:`saturate_rows`, again independent over rows.

Every kernel is sequential and releases the GIL; the ones taking a range of rows or
columns (``r0, r1`` / ``c0, c1``) are run by :mod:`gridfield.brushfire` on several threads that take
chunks of the range as they become free, and the sequential ones run beside each other.

Conventions: arrays are C-contiguous ``[row, col]``; occupancy is passed as ``uint8``; the wall
border is the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols`` (never its corners).

Cython, compiled at install (see "Building the kernels" in ``benchmarks/README.md``): the hot loops
run on raw row pointers; indices are guarded as in the reference code, so bounds checks are off.
"""


from libc.math cimport sqrt
from libc.stdint cimport int16_t, int32_t, int64_t, uint8_t
from libc.stdlib cimport free, malloc


cdef extern from "_brushfire_rows.h" nogil:
    # the vectorizable row loops, in C (int32, one clone per ISA level: see the header)
    void gf_chamfer_fwd_pre(const int32_t* up, int32_t edge_row, int32_t pad, const uint8_t* occ, int32_t* t,
                            int64_t cols, int conn8)
    void gf_chamfer_bwd_pre(const int32_t* down, int32_t edge_row, int32_t pad, const int32_t* s, int32_t* t,
                            int64_t cols, int conn8)
    void gf_scale_row(const int32_t* s, double res, double* d, int64_t cols, const double* next_d, int stream)
    void gf_scan_right(const int32_t* t, int32_t* s, int64_t cols, int32_t edge)
    void gf_scan_left(const int32_t* t, int32_t* s, int64_t cols, int32_t edge)
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
    void* gf_map(size_t n)
    void gf_unmap(void* p, size_t n)

from cython.view cimport array as cvarray

import numpy as np

#: Sentinel row for "no obstacle above/below" (far beyond any real grid).
BIG = 1 << 30
DEF _BIG = 1 << 30

ctypedef const uint8_t[:, ::1] occ_t
ctypedef int32_t[:, ::1] i32_2d
ctypedef double[:, ::1] f64_2d

ctypedef fused nidx_t:
    int32_t
    int64_t

ctypedef fused key_t:
    int32_t
    double

cdef int64_t _NOINFO = 1 << 30  # initial carry of the inner segments: never wins


cdef inline int64_t _lmin(int64_t a, int64_t b) noexcept nogil:
    return a if a < b else b


cdef inline int64_t _lmax(int64_t a, int64_t b) noexcept nogil:
    return a if a > b else b


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


# ----------------------------------------------------------------------------------------------
# memory of the large output arrays, reused from call to call
# ----------------------------------------------------------------------------------------------
# A fresh array of several MB costs the kernel a page fault and the zeroing of every page when it is
# first written (clear_page: a third of the samples of a 4096^2 chessboard call, whose 192 MB of steps
# and distance are written once). `empty` takes its memory from blocks that earlier results gave back
# when they were freed, so a program that computes map after map of one size (replanning) writes into
# pages it already has. The blocks of the dropped results are kept, oldest dropped first when more
# than `pool_limit()` bytes (or _SLOTS blocks) would be kept; those bytes stay resident. Blocks are
# anonymous mappings (gf_map) with a header of _HDR bytes holding the mapping's length. All of it runs
# with the GIL held (allocation in `empty`, release in the array's deallocation): no lock needed.
DEF _SLOTS = 16
DEF _HDR = 64
DEF _MIN_POOLED = 1 << 20  # smaller arrays: numpy's own allocation
DEF _ROUND = 1 << 21  # mapping lengths are multiples of 2 MiB (a huge page)
cdef char* _pool_ptr[_SLOTS]
cdef size_t _pool_len[_SLOTS]
cdef int _pool_n = 0
cdef size_t _pool_bytes = 0
cdef size_t _pool_limit = 512 << 20


cdef void _evict_oldest() noexcept:
    global _pool_n, _pool_bytes
    cdef int i
    gf_unmap(_pool_ptr[0], _pool_len[0])
    _pool_bytes -= _pool_len[0]
    for i in range(1, _pool_n):
        _pool_ptr[i - 1] = _pool_ptr[i]
        _pool_len[i - 1] = _pool_len[i]
    _pool_n -= 1


cdef void _release(void* data) noexcept:
    """``callback_free_data`` of the arrays made by :func:`empty`: keep the block for the next call."""
    global _pool_n, _pool_bytes
    cdef char* base = <char*>data - _HDR
    cdef size_t n = (<size_t*>base)[0]
    if n > _pool_limit:
        gf_unmap(base, n)
        return
    while _pool_n > 0 and (_pool_n == _SLOTS or _pool_bytes + n > _pool_limit):
        _evict_oldest()
    _pool_ptr[_pool_n] = base
    _pool_len[_pool_n] = n
    _pool_n += 1
    _pool_bytes += n


cdef char* _take(size_t nbytes):
    """The data pointer of a block of at least ``nbytes``: a kept one of at most 5/4 the length
    needed (the smallest such), else a new mapping."""
    global _pool_n, _pool_bytes
    cdef size_t need = (nbytes + _HDR + _ROUND - 1) // _ROUND * _ROUND
    cdef int i, best = -1
    cdef char* base
    for i in range(_pool_n):
        if need <= _pool_len[i] <= need + need // 4 and (best < 0 or _pool_len[i] < _pool_len[best]):
            best = i
    if best >= 0:
        base = _pool_ptr[best]
        _pool_bytes -= _pool_len[best]
        for i in range(best + 1, _pool_n):
            _pool_ptr[i - 1] = _pool_ptr[i]
            _pool_len[i - 1] = _pool_len[i]
        _pool_n -= 1
        return base + _HDR
    base = <char*>gf_map(need)
    if base == NULL:
        raise MemoryError(f"cannot allocate {nbytes} bytes")
    (<size_t*>base)[0] = need
    return base + _HDR


_FORMATS = {np.dtype(np.int32): "i", np.dtype(np.float64): "d", np.dtype(np.bool_): "?"}


def empty(shape, dtype):
    """``np.empty(shape, dtype)`` (C order; int32, float64 or bool) whose memory, when the array is
    at least 1 MiB, is a block given back by an earlier array of this function if one fits (see
    :func:`pool_limit`). The array does not own its memory (``flags.owndata`` is False): its base
    frees the block."""
    dt = np.dtype(dtype)
    shape = tuple(int(x) for x in shape)
    cdef size_t nbytes = dt.itemsize
    for x in shape:
        nbytes *= <size_t>x
    if nbytes < _MIN_POOLED or dt not in _FORMATS:
        return np.empty(shape, dt)
    cdef cvarray block = cvarray(shape=shape, itemsize=dt.itemsize, format=_FORMATS[dt], mode="c",
                                 allocate_buffer=False)
    block.data = _take(nbytes)
    block.callback_free_data = _release
    return np.asarray(block)


def pool_limit(limit=None):
    """The most bytes :func:`empty` keeps for reuse (default 512 MiB); with ``limit``, set it (0: keep
    none; kept blocks beyond it are unmapped now) and return the previous one."""
    global _pool_limit
    cdef size_t old = _pool_limit
    if limit is not None:
        if limit < 0:
            raise ValueError(f"limit must be >= 0 bytes, got {limit!r}")
        _pool_limit = <size_t>limit
        while _pool_n > 0 and _pool_bytes > _pool_limit:
            _evict_oldest()
    return old


def pool_bytes():
    """Bytes kept for reuse now, and in how many blocks."""
    return _pool_bytes, _pool_n


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


cdef inline void _gather_labels(const int64_t* nr, const int64_t* nc, int64_t n, int64_t rows, int64_t cols,
                                const int32_t* flat, const int32_t* comp_map, bint use_map,
                                int32_t* out) noexcept nogil:
    """``out[c]`` = label of the cell ``(nr[c], nc[c])``: ``flat[nr * cols + nc]``, mapped through
    ``comp_map`` if ``use_map``. ``flat`` is the label grid raveled plus one last element for any cell
    outside the grid (the wall), so that the loop is a plain gather."""
    cdef int64_t outside = rows * cols, c, a, b, inside
    if use_map:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = comp_map[flat[outside + (a * cols + b - outside) * inside]]
    else:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = flat[outside + (a * cols + b - outside) * inside]


cdef inline void _gather_labels32(const int32_t* nr, const int32_t* nc, int64_t n, int64_t rows, int64_t cols,
                                  const int32_t* flat, const int32_t* comp_map, bint use_map,
                                  int32_t* out) noexcept nogil:
    """:func:`_gather_labels` for int32 nearest cells."""
    cdef int64_t outside = rows * cols, c, a, b, inside
    if use_map:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = comp_map[flat[outside + (a * cols + b - outside) * inside]]
    else:
        for c in range(n):
            a = nr[c]
            b = nc[c]
            inside = (a >= 0) & (a < rows) & (b >= 0) & (b < cols)
            out[c] = flat[outside + (a * cols + b - outside) * inside]


cdef inline void _gvd_dir(const int32_t* la, const key_t* da, const int32_t* lb, const key_t* db,
                          const uint8_t* fb, uint8_t* mark, int64_t a0, int64_t a1, int64_t off) noexcept nogil:
    # cells a in a0:a1 against b = a + off of a neighbouring (or the same) row: a is marked if b is a
    # free cell of another label and a is farther from its obstacle (on a tie: a has the smaller label)
    cdef int64_t c, b
    cdef int32_t lab_a, lab_b
    for c in range(a0, a1):
        b = c + off
        lab_a = la[c]
        lab_b = lb[b]
        mark[c] |= (lab_a != lab_b) & (fb[b] == 0) & ((da[c] > db[b]) | ((da[c] == db[b]) & (lab_a < lab_b)))


cdef inline void _gvd_row(int64_t r, int64_t rows, int64_t cols, const int32_t* la, const int32_t* labels,
                          int64_t nlab, const key_t* key, const uint8_t* occ, uint8_t* mark,
                          uint8_t* out) noexcept nogil:
    # labels is the label grid (nlab = rows) or a ring of 3 rows (nlab = 3): either way row r + dr is
    # labels row (r + dr) % nlab; key and occ are whole grids
    cdef const key_t* da = key + r * cols
    cdef const uint8_t* fa = occ + r * cols
    cdef const int32_t* lb
    cdef const key_t* db
    cdef const uint8_t* fb
    cdef int64_t c, dr, rr
    for c in range(cols):
        mark[c] = 0
    for dr in range(-1, 2):
        rr = r + dr
        if rr < 0 or rr >= rows:
            continue
        lb = labels + (rr % nlab) * cols
        db = key + rr * cols
        fb = occ + rr * cols
        if dr != 0:
            _gvd_dir(la, da, lb, db, fb, mark, 0, cols, 0)
        _gvd_dir(la, da, lb, db, fb, mark, 1, cols, -1)
        _gvd_dir(la, da, lb, db, fb, mark, 0, cols - 1, 1)
    for c in range(cols):
        out[c] = mark[c] & (fa[c] == 0)


def label_gvd_rows(int64_t r0, int64_t r1, const int32_t[:, ::1] nearest_row, const int32_t[:, ::1] nearest_col,
                   const int32_t[::1] flat, const int32_t[::1] comp_map, bint use_map, i32_2d label, bint want_gvd,
                   const int32_t[:, ::1] key, occ_t occ, uint8_t[:, ::1] gvd):
    """Rows ``r0:r1``: ``label`` (see :func:`_gather_labels`) and, if ``want_gvd``, the GVD (see
    :func:`gvd_rows`) from the labels of each row and its two neighbours, kept in a 3-row ring (the
    neighbour rows outside ``r0:r1`` are gathered again, not read back). ``gvd`` is ``bool``."""
    cdef int64_t rows = nearest_row.shape[0], cols = nearest_row.shape[1], r, rr, c
    if rows == 0 or cols == 0 or r1 <= r0:
        return
    cdef int32_t* ring
    cdef uint8_t* mark
    cdef int32_t* la
    cdef int32_t* lrow
    with nogil:
        ring = <int32_t*>_alloc(3 * cols * sizeof(int32_t))
        mark = <uint8_t*>_alloc(cols)
        for c in range(3 * cols):
            ring[c] = 0
        for rr in range(_lmax(0, r0 - 1), _lmin(rows, r0 + 1)):
            _gather_labels32(&nearest_row[rr, 0], &nearest_col[rr, 0], cols, rows, cols, &flat[0], &comp_map[0],
                             use_map, ring + (rr % 3) * cols)
        for r in range(r0, r1):
            if r + 1 < rows:
                _gather_labels32(&nearest_row[r + 1, 0], &nearest_col[r + 1, 0], cols, rows, cols, &flat[0],
                                 &comp_map[0], use_map, ring + ((r + 1) % 3) * cols)
            la = ring + (r % 3) * cols
            lrow = &label[r, 0]
            for c in range(cols):
                lrow[c] = la[c]
            if want_gvd:
                _gvd_row(r, rows, cols, la, ring, 3, &key[0, 0], &occ[0, 0], mark, &gvd[r, 0])
        free(ring)
        free(mark)


# ----------------------------------------------------------------------------------------------
# Euclidean: separable lower-envelope transform
# ----------------------------------------------------------------------------------------------
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

cdef inline int64_t _floordiv(int64_t a, int64_t b) noexcept nogil:
    # Python's floor division for b > 0
    cdef int64_t q = a // b  # C truncation (cdivision)
    if (a % b != 0) and (a < 0):
        q -= 1
    return q


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
    # the envelope for callers without a buffer for the stack's g**2 (_kernels_incremental)
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


# ----------------------------------------------------------------------------------------------
# connected components (8-connected) of the obstacle cells
# ----------------------------------------------------------------------------------------------
cdef inline int64_t _find(int32_t* parent, int64_t x) noexcept nogil:
    cdef int64_t root = x, nxt
    while parent[root] != root:
        root = parent[root]
    while parent[x] != root:
        nxt = parent[x]
        parent[x] = <int32_t>root
        x = nxt
    return root


cdef inline void _union(int32_t* parent, int64_t a, int64_t b) noexcept nogil:
    cdef int64_t ra = _find(parent, a)
    cdef int64_t rb = _find(parent, b)
    if ra < rb:
        parent[rb] = <int32_t>ra
    elif rb < ra:
        parent[ra] = <int32_t>rb


def strip_cap(rows, cols):
    """Most provisional labels a strip of ``rows`` x ``cols`` cells can create: they are only created
    at cells with no labelled neighbour before them, so no two are 8-adjacent."""
    return ((rows + 1) // 2) * ((cols + 1) // 2)


cdef int64_t _label_strip(int64_t r0, int64_t r1, occ_t occ, i32_2d comp, int32_t* parent,
                          int64_t base) noexcept nogil:
    cdef int64_t cols = occ.shape[1], r, c, left, u, ur, ul, lf
    cdef int64_t nxt = base + 1
    cdef const uint8_t* orow
    cdef int32_t* crow
    cdef const int32_t* up
    for r in range(r0, r1):
        orow = &occ[r, 0]
        crow = &comp[r, 0]
        if r == r0:
            left = 0
            for c in range(cols):
                if not orow[c]:
                    crow[c] = 0
                    left = 0
                    continue
                if left == 0:
                    parent[nxt] = <int32_t>nxt
                    left = nxt
                    nxt += 1
                crow[c] = <int32_t>left
            continue
        up = &comp[r - 1, 0]
        for c in range(cols):
            if not orow[c]:
                crow[c] = 0
                continue
            u = up[c]
            if u:
                crow[c] = <int32_t>u
                continue
            ur = up[c + 1] if c + 1 < cols else 0
            ul = up[c - 1] if c > 0 else 0
            lf = crow[c - 1] if c > 0 else 0
            if ur:  # up-left and left are neighbours of each other: one union is enough
                if ul:
                    _union(parent, ur, ul)
                elif lf:
                    _union(parent, ur, lf)
                crow[c] = <int32_t>ur
            elif ul:
                crow[c] = <int32_t>ul
            elif lf:
                crow[c] = <int32_t>lf
            else:
                parent[nxt] = <int32_t>nxt
                crow[c] = <int32_t>nxt
                nxt += 1
    return nxt - 1


def label_strip(int64_t r0, int64_t r1, occ_t occ, i32_2d comp, int32_t[::1] parent, int64_t base):
    """First pass of the 8-connected labelling on rows ``r0:r1`` alone: provisional labels
    ``base + 1, base + 2, ...`` in raster order (0 on free cells), unions in ``parent`` (each set's
    root is its smallest label). Returns the last label used (``base`` if none)."""
    cdef int64_t last
    if occ.shape[1] == 0 or r1 <= r0:
        return base
    with nogil:
        last = _label_strip(r0, r1, occ, comp, &parent[0], base)
    return last


def merge_strips(occ_t occ, i32_2d comp, int32_t[::1] parent, const int64_t[::1] firsts,
                 const int64_t[::1] bases, const int64_t[::1] lasts, int32_t[::1] comp_map):
    """Join the strips (first rows ``firsts``, label ranges ``bases[k] + 1 .. lasts[k]``) across their
    boundaries and number the components 1.. in raster order of their first cell (the numbering of
    ``scipy.ndimage.label``): ``comp_map[i]`` becomes the final label of provisional label ``i`` (only
    the labels in use are written; ``comp_map[0] = 0``). Returns the number of components."""
    cdef int64_t cols = occ.shape[1], k, b, c, cc, i, p, count = 0
    cdef int64_t nstrips = firsts.shape[0]
    cdef int32_t* par = &parent[0]
    with nogil:
        for k in range(1, nstrips):
            b = firsts[k]
            for c in range(cols):
                if not occ[b, c]:
                    continue
                for cc in range(_lmax(0, c - 1), _lmin(cols, c + 2)):
                    if occ[b - 1, cc]:
                        _union(par, comp[b, c], comp[b - 1, cc])
        comp_map[0] = 0
        for k in range(nstrips):  # labels grow with the strips: every root comes before its members
            for i in range(bases[k] + 1, lasts[k] + 1):
                p = par[i]
                if p == i:
                    count += 1
                    comp_map[i] = <int32_t>count
                else:
                    comp_map[i] = comp_map[_find(par, p)]
    return count


def relabel_rows(int64_t r0, int64_t r1, i32_2d comp, const int32_t[::1] comp_map):
    """Rows ``r0:r1``, in place: ``comp = comp_map[comp]``."""
    cdef int64_t cols = comp.shape[1], r, c
    cdef int32_t* crow
    if cols == 0:
        return
    with nogil:
        for r in range(r0, r1):
            crow = &comp[r, 0]
            for c in range(cols):
                crow[c] = comp_map[crow[c]]


def label_components(occ, comp, strips=1):
    """8-connected labels of the obstacle cells into ``comp`` (0 on free cells), numbered 1.. in raster
    order of each component's first cell; returns their number. Sequential reference use of the
    strip kernels (:mod:`gridfield.brushfire` runs the strips on several threads)."""
    rows, cols = occ.shape
    strips = max(1, min(strips, rows))  # no empty strip
    firsts = np.array([k * rows // strips for k in range(strips)], np.int64)
    ends = [(k + 1) * rows // strips for k in range(strips)]
    bases = np.zeros(strips, np.int64)
    for k in range(1, strips):
        bases[k] = bases[k - 1] + strip_cap(ends[k - 1] - firsts[k - 1], cols)
    last = strips - 1  # (no negative indices: this module is compiled without wraparound)
    parent = np.zeros(int(bases[last]) + strip_cap(ends[last] - firsts[last], cols) + 1, np.int32)
    lasts = np.array([label_strip(firsts[k], ends[k], occ, comp, parent, bases[k]) for k in range(strips)], np.int64)
    comp_map = np.zeros(len(parent), np.int32)
    count = merge_strips(occ, comp, parent, firsts, bases, lasts, comp_map)
    relabel_rows(0, rows, comp, comp_map)
    return count


# ----------------------------------------------------------------------------------------------
# generalized Voronoi diagram, saturation
# ----------------------------------------------------------------------------------------------
def gvd_rows(int64_t r0, int64_t r1, const int32_t[:, ::1] label, const key_t[:, ::1] distance, occ_t occ,
             uint8_t[:, ::1] gvd):
    """Rows ``r0:r1`` of the GVD: of each pair of 8-neighbouring free cells with different labels,
    mark the one farther from its obstacle; on a tie, the one with the smaller label. Each cell looks
    at its 8 neighbours, so rows can be done in any order, by any thread. ``distance`` may be any
    array that orders the cells as the distance does (the int32 steps of a chamfer metric); ``gvd``
    is ``bool``."""
    cdef int64_t rows = label.shape[0], cols = label.shape[1], r
    if rows == 0 or cols == 0 or r1 <= r0:
        return
    cdef uint8_t* mark
    with nogil:
        mark = <uint8_t*>_alloc(cols)
        for r in range(r0, r1):
            _gvd_row(r, rows, cols, &label[r, 0], &label[0, 0], rows, &distance[0, 0], &occ[0, 0], mark, &gvd[r, 0])
        free(mark)


def saturate_rows(int64_t r0, int64_t r1, f64_2d distance, double radius, double far):
    """Rows ``r0:r1``, in place: ``distance[distance >= radius] = far``."""
    cdef int64_t cols = distance.shape[1], r, c
    cdef double* drow
    if cols == 0:
        return
    with nogil:
        for r in range(r0, r1):
            drow = &distance[r, 0]
            for c in range(cols):
                if drow[c] >= radius:
                    drow[c] = far
