# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :func:`gridfield.distance.brushfire.brushfire` that every metric shares
(private; imported on first use). The transforms themselves are :mod:`gridfield.distance._chamfer`
(chessboard and taxicab) and :mod:`gridfield.distance._edt` (Euclidean).

Memory (:func:`empty`, :func:`pool_limit`, :func:`pool_bytes`)
    The grid-sized output arrays, on blocks that earlier results gave back (see below).

Components (:func:`label_strip`, :func:`merge_strips`, :func:`relabel_rows`)
    8-connected, two-pass union-find on horizontal strips, joined across the strip boundaries;
    components are numbered in raster order of their first cell (row 0 first), the numbering of
    ``scipy.ndimage.label``. Strips are independent.

Labels and GVD (:func:`label_gvd_rows`, :func:`gvd_rows`), saturation (:func:`saturate_rows`)
    Independent over rows. The label of a cell is the one of its nearest obstacle cell
    (``_gather_labels32`` of ``_brushfire.pxd``, inline here and in the Euclidean row pass of
    :mod:`gridfield.distance._edt`).

Every kernel is sequential and releases the GIL; the ones taking a range of rows (``r0, r1``) are
run by :mod:`gridfield.distance.brushfire` on several threads that take chunks of the range as they
become free, and the sequential ones run beside each other.

Conventions: arrays are C-contiguous ``[row, col]``; occupancy is passed as ``uint8``; the wall
border is the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols`` (never its corners).

Cython, compiled at install (see "Building the kernels" in ``benchmarks/README.md``): the hot loops
run on raw row pointers; indices are guarded as in the reference code, so bounds checks are off.
"""


from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free


cdef extern from "_brushfire_rows.h" nogil:
    void* gf_map(size_t n)
    void gf_unmap(void* p, size_t n)

from cython.view cimport array as cvarray

import numpy as np

ctypedef fused key_t:
    int32_t
    double


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
    strip kernels (:mod:`gridfield.distance.brushfire` runs the strips on several threads)."""
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
# labels and the generalized Voronoi diagram, saturation
# ----------------------------------------------------------------------------------------------
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
    """Rows ``r0:r1``: ``label`` (see :func:`_gather_labels32`) and, if ``want_gvd``, the GVD (see
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
