# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :class:`gridfield.distance.incremental.IncrementalBrushfire` (private; imported on first use).

Everything works on a rectangular *window* ``rows r0:r1, cols c0:c1`` of the full-grid arrays, with
global cell indices. The Euclidean transform of a window (:func:`window_edt`) is the transform of
:mod:`gridfield.distance._edt` (same column rule, the very same compiled lower envelope
``_edt_1d``, cimported from it) restricted to the sites inside the window, so it picks the nearest
site by the same rule: the smallest squared distance, then the smallest column, then the smallest
row. The full transform picks exactly that one too (checked against brute force in the tests), which
is what lets a window result be merged cell by cell into a full-grid one (:func:`lower_merge`,
:func:`raise_apply`). :func:`khatib_window` runs the row function of the full potential kernel
(``gridfield/_potential_rows.h``) on the window's columns, so its values are bit-identical to a full
build.

Conventions: ``nr``/``nc`` are the nearest obstacle cells (int32, ``(-1, -1)`` = none); wall-border
cells are row ``-1``/``rows`` or column ``-1``/``cols``; squared distances are in cells (int64);
occupancy, marks and the GVD are ``uint8`` (``bool`` arrays are accepted); cell lists are int64;
2-D arrays are C-contiguous. Nothing here validates input: :mod:`gridfield.distance.incremental` does.

Cython, compiled at install; every kernel releases the GIL. Bounds checks are off: every index is a
window cell, a neighbour guarded by the grid bounds, or a queue slot bounded by the cells queued.
Integer ``//`` and ``%`` appear only on non-negative operands (raster indices), so C division is
Python's.
"""

from libc.math cimport INFINITY, ceil, sqrt
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free, malloc
from libc.string cimport memset

import numpy as np

from ._edt cimport _edt_1d
from ._edt import BIG

cdef extern from "_potential_rows.h" nogil:
    void gf_khatib_row(int64_t r, int64_t c0, int64_t c1, const uint8_t* occ, const int32_t* nr, const int32_t* nc,
                       double x0, double y0, double res, double goal_x, double goal_y, double zeta, double d_star,
                       double ds2, int conic, int metric, double eta, double q_star, double inv_q, int ipow,
                       double sat, double far, double* U, double* GX, double* GY)

__all__ = ["NONE_D2", "first_cells", "gather_rows", "gvd_window", "insert_in_place", "khatib_window",
           "labels_window", "lower_merge", "max_distance2", "orphan_box", "raise_apply", "raise_check",
           "remove_in_place", "remove_rest_in_place", "ring_reached", "set_cells", "window_edt"]

#: Squared distance meaning "no site" (larger than any squared distance on a grid).
NONE_D2 = np.int64(1) << np.int64(62)
cdef int64_t _NONE_D2 = (<int64_t>1) << 62
cdef int64_t _BIG = (<int64_t>1) << 30

ctypedef const uint8_t[:, ::1] u8c_2d
ctypedef uint8_t[:, ::1] u8_2d
ctypedef const int32_t[:, ::1] i32c_2d
ctypedef int32_t[:, ::1] i32_2d
ctypedef const int64_t[:, ::1] i64c_2d
ctypedef int64_t[:, ::1] i64_2d
ctypedef double[:, ::1] f64_2d
ctypedef const int64_t[:] cells_t  # cell lists (any stride)


cdef inline int64_t _min(int64_t a, int64_t b) noexcept nogil:
    return a if a < b else b


cdef inline int64_t _max(int64_t a, int64_t b) noexcept nogil:
    return a if a > b else b


cdef inline int64_t _old_d2(int64_t r, int64_t c, int64_t a, int64_t b) noexcept nogil:
    if a == -1 and b == -1:
        return _NONE_D2
    return (r - a) * (r - a) + (c - b) * (c - b)


cdef inline bint _less(int64_t d2, int64_t col, int64_t row, int64_t e2, int64_t ecol, int64_t erow) noexcept nogil:
    # (d2, col, row) < (e2, ecol, erow) lexicographically: the tie rule of the full transform
    if d2 != e2:
        return d2 < e2
    if col != ecol:
        return col < ecol
    return row < erow


def window_edt(u8c_2d sites, int64_t r0, int64_t r1, int64_t c0, int64_t c1, bint wt, bint wb, bint wl, bint wr,
               int64_t inf, i64_2d vr, int64_t[::1] g, int64_t[::1] rowv, int64_t[::1] s, int64_t[::1] t,
               int64_t[::1] val, int64_t[::1] arg, i32_2d wnr, i32_2d wnc, i64_2d wd2):
    """Euclidean transform of the sites (``sites[r, c] != 0``) inside the window: for each window cell,
    ``wnr``/``wnc`` (global cell of the nearest site) and ``wd2`` (its squared distance;
    :data:`NONE_D2` and ``(-1, -1)`` when the window holds no site). ``wt``/``wb``/``wl``/``wr``:
    whether the wall rows ``-1``/``rows`` or columns ``-1``/``cols`` count as sites (only when the
    window reaches that edge). Window-shaped outputs and scratch ``vr``; 1-D scratch of at least
    ``c1 - c0 + 2`` elements. ``inf``: larger than any row distance on the grid."""
    cdef int64_t rows = sites.shape[0], n = c1 - c0, h = r1 - r0, i, j, r, b, v, d, a
    cdef int64_t top = -1 if wt else -_BIG
    cdef int64_t bottom = rows if wb else _BIG
    cdef const uint8_t* srow
    cdef int64_t* vrow
    cdef int64_t* prev
    cdef int64_t* below
    if h <= 0 or n <= 0:
        return
    with nogil:
        # column pass: nearest site row in each column (ties: the smaller row), swept row by row (the
        # arrays are row-major): down, the nearest site at or above; up, the one below if strictly nearer
        for i in range(h):
            r = r0 + i
            srow = &sites[r, c0]
            vrow = &vr[i, 0]
            if i == 0:
                for j in range(n):
                    vrow[j] = r if srow[j] else top
            else:
                prev = &vr[i - 1, 0]
                for j in range(n):
                    vrow[j] = r if srow[j] else prev[j]
        below = &g[0]  # scratch: the nearest site at or below, per column (g is reused by the row pass)
        for j in range(n):
            below[j] = bottom
        for i in range(h - 1, -1, -1):
            r = r0 + i
            srow = &sites[r, c0]
            vrow = &vr[i, 0]
            for j in range(n):
                if srow[j]:
                    below[j] = r
                b = below[j]
                if (b - r) < (r - vrow[j]):
                    vrow[j] = b
        for i in range(h):  # row pass: lower envelope (the full transform's)
            r = r0 + i
            g[0] = 0 if wl else inf
            g[n + 1] = 0 if wr else inf
            rowv[0] = r
            rowv[n + 1] = r
            vrow = &vr[i, 0]
            for j in range(n):
                v = vrow[j]
                rowv[j + 1] = v
                d = r - v if r >= v else v - r
                g[j + 1] = d if d < inf else inf
            if _edt_1d(&g[0], n, inf, &s[0], &t[0], &val[0], &arg[0]):
                for j in range(n):
                    a = arg[j]
                    wnr[i, j] = <int32_t>rowv[a]
                    wnc[i, j] = <int32_t>(c0 + a - 1)
                    wd2[i, j] = val[j]
            else:
                for j in range(n):
                    wnr[i, j] = -1
                    wnc[i, j] = -1
                    wd2[i, j] = _NONE_D2


def ring_reached(int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t rows, int64_t cols, i64c_2d wd2,
                 i32c_2d nr, i32c_2d nc, uint8_t[::1] out):
    """For each side of the window that is not a grid edge (``out[0..3]``: rows ``r0``, ``r1 - 1``,
    columns ``c0``, ``c1 - 1``), whether some cell of that side may be reached by the change: its
    window distance ``sqrt(wd2)`` is at most its current distance (from ``nr``/``nc``) plus
    ``sqrt(2)``. A cell whose nearest obstacle the change alters (one it adds, or one it removes)
    is joined to the changed cells by an 8-connected path of cells meeting that bound (the lattice
    cells nearest to the straight segment), so when no side is reached no such cell lies outside."""
    cdef double slack = sqrt(2.0) + 1e-9
    cdef int64_t h = r1 - r0, w = c1 - c0, k, m, n, i, j, d2, o2, r, c
    with nogil:
        for k in range(4):
            out[k] = 0
        for k in range(4):
            if (k == 0 and r0 == 0) or (k == 1 and r1 == rows) or (k == 2 and c0 == 0) or (k == 3 and c1 == cols):
                continue
            n = w if k < 2 else h
            for m in range(n):
                if k == 0:
                    i = 0
                    j = m
                elif k == 1:
                    i = h - 1
                    j = m
                elif k == 2:
                    i = m
                    j = 0
                else:
                    i = m
                    j = w - 1
                d2 = wd2[i, j]
                if d2 == _NONE_D2:
                    continue
                r = r0 + i
                c = c0 + j
                o2 = _old_d2(r, c, nr[r, c], nc[r, c])
                if o2 == _NONE_D2 or sqrt(<double>d2) <= sqrt(<double>o2) + slack:
                    out[k] = 1
                    break


def lower_merge(int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_2d wnr, i32c_2d wnc, i64c_2d wd2, i32_2d nr,
                i32_2d nc, f64_2d distance, double res, int64_t[::1] box):
    """Insertion: every window cell whose window nearest site beats its current nearest obstacle
    (by the full transform's rule) takes it. ``box`` (int64[4]) grows to the bounding box
    ``r0, r1, c0, c1`` of the cells changed; returns their number."""
    cdef int64_t count = 0, i, j, r, c, d2, a, b
    with nogil:
        for i in range(r1 - r0):
            r = r0 + i
            for j in range(c1 - c0):
                c = c0 + j
                d2 = wd2[i, j]
                if d2 == _NONE_D2:
                    continue
                a = nr[r, c]
                b = nc[r, c]
                if not _less(d2, wnc[i, j], wnr[i, j], _old_d2(r, c, a, b), b, a):
                    continue
                nr[r, c] = wnr[i, j]
                nc[r, c] = wnc[i, j]
                distance[r, c] = sqrt(<double>d2) * res
                count += 1
                box[0] = _min(box[0], r)
                box[1] = _max(box[1], r + 1)
                box[2] = _min(box[2], c)
                box[3] = _max(box[3], c + 1)
    return count


def orphan_box(int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t rows, int64_t cols, i32c_2d nr, i32c_2d nc,
               u8c_2d mark, int64_t[::1] box):
    """Removal: bounding box (``box``, int64[4]) of the window cells whose nearest obstacle is a
    removed cell (``mark`` set there); returns their number and the largest squared distance to it."""
    cdef int64_t count = 0, far2 = 0, r, c, a, b
    with nogil:
        for r in range(r0, r1):
            for c in range(c0, c1):
                a = nr[r, c]
                b = nc[r, c]
                if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                    continue
                count += 1
                far2 = _max(far2, _old_d2(r, c, a, b))
                box[0] = _min(box[0], r)
                box[1] = _max(box[1], r + 1)
                box[2] = _min(box[2], c)
                box[3] = _max(box[3], c + 1)
    return count, far2


def raise_check(int64_t b0, int64_t b1, int64_t e0, int64_t e1, int64_t r0, int64_t r1, int64_t c0, int64_t c1,
                int64_t rows, int64_t cols, i32c_2d nr, i32c_2d nc, u8c_2d mark, i64c_2d wd2):
    """Removal: whether the window ``r0:r1, c0:c1`` (``wd2`` its transform of all obstacles) gives
    every orphan in the box ``b0:b1, e0:e1`` its exact nearest obstacle, i.e. one strictly nearer than
    any cell outside the window. Returns -1 if so, else the largest window distance (in cells, rounded
    up) among the orphans that failed (``-2`` when an orphan found no obstacle in the window)."""
    cdef int64_t worst = -1, r, c, a, b, out, d2
    with nogil:
        for r in range(b0, b1):
            for c in range(e0, e1):
                a = nr[r, c]
                b = nc[r, c]
                if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                    continue
                out = _BIG
                if r0 > 0:
                    out = _min(out, r - r0 + 1)
                if r1 < rows:
                    out = _min(out, r1 - r)
                if c0 > 0:
                    out = _min(out, c - c0 + 1)
                if c1 < cols:
                    out = _min(out, c1 - c)
                d2 = wd2[r - r0, c - c0]
                if d2 == _NONE_D2:
                    if out < _BIG:  # no obstacle in the window, but maybe outside: widen the window
                        worst = -2
                        break
                    continue
                if d2 >= out * out:
                    worst = _max(worst, <int64_t>ceil(sqrt(<double>d2)))
            if worst == -2:
                break
    return worst


def raise_apply(int64_t b0, int64_t b1, int64_t e0, int64_t e1, int64_t r0, int64_t c0, int64_t rows, int64_t cols,
                i32_2d nr, i32_2d nc, u8c_2d mark, i32c_2d wnr, i32c_2d wnc, i64c_2d wd2, f64_2d distance, double res):
    """Removal: the orphans in the box ``b0:b1, e0:e1`` take their window nearest obstacle."""
    cdef int64_t r, c, a, b, d2
    with nogil:
        for r in range(b0, b1):
            for c in range(e0, e1):
                a = nr[r, c]
                b = nc[r, c]
                if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                    continue
                d2 = wd2[r - r0, c - c0]
                if d2 == _NONE_D2:
                    nr[r, c] = -1
                    nc[r, c] = -1
                    distance[r, c] = INFINITY
                else:
                    nr[r, c] = wnr[r - r0, c - c0]
                    nc[r, c] = wnc[r - r0, c - c0]
                    distance[r, c] = sqrt(<double>d2) * res


def max_distance2(int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_2d nr, i32c_2d nc):
    """Largest current squared distance (cells) over the window; :data:`NONE_D2` if some cell has none."""
    cdef int64_t m = 0, r, c
    with nogil:
        for r in range(r0, r1):
            for c in range(c0, c1):
                m = _max(m, _old_d2(r, c, nr[r, c], nc[r, c]))
    return m


def set_cells(cells_t cr, cells_t cc, u8_2d arr, int value):
    """``arr[cr[k], cc[k]] = value`` for every k."""
    cdef Py_ssize_t k
    cdef uint8_t v = <uint8_t>value
    with nogil:
        for k in range(cr.shape[0]):
            arr[cr[k], cc[k]] = v


# ----------------------------------------------------------------------------------------------
# labels and GVD on a window
# ----------------------------------------------------------------------------------------------
cdef void _labels(int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_2d nr, i32c_2d nc, i32c_2d ids,
                  int32_t border_label, i32_2d label) noexcept nogil:
    cdef int64_t rows = nr.shape[0], cols = nr.shape[1], r, c, a, b
    for r in range(r0, r1):
        for c in range(c0, c1):
            a = nr[r, c]
            b = nc[r, c]
            if a == -1 and b == -1:
                label[r, c] = 0
            elif a < 0 or a >= rows or b < 0 or b >= cols:
                label[r, c] = border_label
            else:
                label[r, c] = ids[a, b]


def labels_window(int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_2d nr, i32c_2d nc, i32c_2d ids,
                  int32_t border_label, i32_2d label):
    """``label`` = ``ids`` at the nearest obstacle (``border_label`` for a wall cell, 0 for none)."""
    with nogil:
        _labels(r0, r1, c0, c1, nr, nc, ids, border_label, label)


def gvd_window(int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_2d label, const double[:, ::1] key, u8c_2d occ,
               u8_2d gvd):
    """The GVD rule of :func:`gridfield.distance._brushfire.label_gvd_rows` on the window cells: a free
    cell is marked if some 8-neighbouring free cell has another label and it is farther from its
    obstacle (on a tie: it has the smaller label)."""
    cdef int64_t rows = label.shape[0], cols = label.shape[1], r, c, dr, dc, rr, cc
    cdef bint mk
    cdef int32_t la, lb
    cdef double da, db
    with nogil:
        for r in range(r0, r1):
            for c in range(c0, c1):
                mk = False
                if not occ[r, c]:
                    la = label[r, c]
                    da = key[r, c]
                    for dr in range(-1, 2):
                        rr = r + dr
                        if rr < 0 or rr >= rows:
                            continue
                        for dc in range(-1, 2):
                            cc = c + dc
                            if cc < 0 or cc >= cols or (dr == 0 and dc == 0) or occ[rr, cc]:
                                continue
                            lb = label[rr, cc]
                            db = key[rr, cc]
                            if la != lb and (da > db or (da == db and la < lb)):
                                mk = True
                gvd[r, c] = mk


def gather_rows(int64_t r0, int64_t r1, i32c_2d nr, i32c_2d nc, i32c_2d comp, int32_t border_label, i32_2d label):
    """Rows ``r0:r1`` of ``label`` = ``comp`` at the nearest obstacle (all columns)."""
    with nogil:
        _labels(r0, r1, 0, nr.shape[1], nr, nc, comp, border_label, label)


# ----------------------------------------------------------------------------------------------
# potential window (the fused Khatib kernel of gridfield.fields.potential, on a window, same arithmetic)
# ----------------------------------------------------------------------------------------------
def khatib_window(int64_t r0, int64_t r1, int64_t c0, int64_t c1, u8c_2d occ, i32c_2d nr, i32c_2d nc, double x0,
                  double y0, double res, double goal_x, double goal_y, double zeta, double d_star, bint conic,
                  int metric, double eta, double q_star, int ipow, double sat, double far, f64_2d U, f64_2d GX,
                  f64_2d GY):
    """Cells ``r0:r1, c0:c1`` of :func:`gridfield.fields._potential._khatib_kernel`: the same row
    function on the window's columns (so the values are bit-identical to a full build)."""
    cdef double ds2 = d_star * d_star
    cdef double inv_q = 1.0 / q_star
    cdef int64_t r
    if r1 <= r0 or c1 <= c0:
        return
    with nogil:
        for r in range(r0, r1):
            gf_khatib_row(r, c0, c1, &occ[r, 0], &nr[r, 0], &nc[r, 0], x0, y0, res, goal_x, goal_y, zeta, d_star,
                          ds2, conic, metric, eta, q_star, inv_q, ipow, sat, far, &U[r, 0], &GX[r, 0], &GY[r, 0])


# ----------------------------------------------------------------------------------------------
# component numbers kept in place (maps without world ids), when a change renumbers nothing
# ----------------------------------------------------------------------------------------------
def first_cells(i32c_2d comp, int64_t[::1] first):
    """``first[k]``: raster index ``r * cols + c`` of the first cell of component ``k`` (``first`` holds
    -1 on entry for ``k >= 1``)."""
    cdef int64_t rows = comp.shape[0], cols = comp.shape[1], r, c, k
    with nogil:
        for r in range(rows):
            for c in range(cols):
                k = comp[r, c]
                if k > 0 and first[k] < 0:
                    first[k] = r * cols + c


cdef int _DR[8]
cdef int _DC[8]
_DR[:] = [-1, -1, -1, 0, 1, 1, 1, 0]
_DC[:] = [-1, 0, 1, 1, 1, 0, -1, -1]


cdef inline int _iabs(int a) noexcept nogil:
    return a if a >= 0 else -a


cdef int _ring_parts(u8c_2d occ, u8c_2d mark, int64_t r, int64_t c) noexcept nogil:
    """Number of 8-connected groups formed by the obstacle cells (``occ`` or ``mark``) among the 8
    neighbours of ``(r, c)``, connected through those neighbours only."""
    cdef int64_t rows = occ.shape[0], cols = occ.shape[1], rr, cc
    cdef bint on[8]
    cdef int parent[8]
    cdef int i, j, a, b, n = 0
    for i in range(8):
        parent[i] = i
        rr = r + _DR[i]
        cc = c + _DC[i]
        on[i] = 0 <= rr < rows and 0 <= cc < cols and (occ[rr, cc] or mark[rr, cc])
    for i in range(8):
        if not on[i]:
            continue
        for j in range(i + 1, 8):
            if on[j] and _iabs(_DR[i] - _DR[j]) <= 1 and _iabs(_DC[i] - _DC[j]) <= 1:
                a = i
                while parent[a] != a:
                    a = parent[a]
                b = j
                while parent[b] != b:
                    b = parent[b]
                if a != b:
                    parent[a if a > b else b] = a if a < b else b
    for i in range(8):
        if on[i] and parent[i] == i:
            n += 1
    return n


cdef bint _remove_in_place(cells_t fr, cells_t fc, u8c_2d occ, u8_2d mark, i32_2d comp, int64_t[::1] first,
                           int64_t max_passes) noexcept nogil:
    cdef int64_t rows = occ.shape[0], cols = occ.shape[1], total = rows * cols, left = fr.shape[0]
    cdef int64_t p, k, r, c, t, idx, j, rr, cc
    cdef bint progress
    for p in range(max_passes):
        progress = False
        for k in range(fr.shape[0]):
            r = fr[k]
            c = fc[k]
            if not mark[r, c]:  # already taken out
                continue
            t = comp[r, c]
            if _ring_parts(occ, mark, r, c) != 1:  # would split the component (for now), or it vanishes
                continue
            idx = r * cols + c
            j = first[t]
            if j == idx:  # the next cell of the component in raster order becomes its first
                j = idx + 1
                while j < total:
                    rr = j // cols
                    cc = j - rr * cols
                    if comp[rr, cc] == t:
                        break
                    j += 1
                if j >= first[t + 1]:
                    return False
            mark[r, c] = 0
            comp[r, c] = 0
            first[t] = j
            left -= 1
            progress = True
        if left == 0:
            return True
        if not progress:
            return False
    return False


def remove_in_place(cells_t fr, cells_t fc, u8c_2d occ, u8_2d mark, i32_2d comp, int64_t[::1] first,
                    int64_t max_passes):
    """Take the cells ``fr, fc`` (marked in ``mark``, already free in ``occ``) out of their components
    one by one, each only while provably no component splits or vanishes (its obstacle neighbours are
    connected around it) and the components keep their order by first cell (so their numbers stay).
    Cells that cannot go yet are retried after the others, for up to ``max_passes`` passes (peeling a
    removed blob from its edge). Returns False when that cannot be shown for every cell (the caller
    then renumbers everything)."""
    cdef bint ok
    with nogil:
        ok = _remove_in_place(fr, fc, occ, mark, comp, first, max_passes)
    return ok


cdef bint _remove_rest(cells_t fr, cells_t fc, u8_2d mark, i32_2d comp, int64_t[::1] first, int64_t r0, int64_t r1,
                       int64_t c0, int64_t c1, uint8_t* seen, uint8_t* visit, int64_t* qr,
                       int64_t* qc) noexcept nogil:
    cdef int64_t rows = comp.shape[0], cols = comp.shape[1], total = rows * cols, h = r1 - r0, w = c1 - c0
    cdef int64_t k, m, r, c, t, sr, sc, want, a, b, dr, dc, aa, bb, head, tail, met, j
    for k in range(fr.shape[0]):
        r = fr[k]
        c = fc[k]
        if not mark[r, c]:
            continue
        t = comp[r, c]
        # the cells of t next to the stuck cells, and one to start from
        sr = -1
        sc = -1
        want = 0
        for m in range(fr.shape[0]):
            a = fr[m]
            b = fc[m]
            if not mark[a, b] or comp[a, b] != t:
                continue
            for dr in range(-1, 2):
                for dc in range(-1, 2):
                    aa = a + dr
                    bb = b + dc
                    if 0 <= aa < rows and 0 <= bb < cols and comp[aa, bb] == t and not mark[aa, bb]:
                        if aa < r0 or aa >= r1 or bb < c0 or bb >= c1:
                            return False
                        if not seen[(aa - r0) * w + bb - c0]:
                            seen[(aa - r0) * w + bb - c0] = 1  # counted once (reset below)
                            want += 1
                            sr = aa
                            sc = bb
        if want == 0:  # the component would vanish
            return False
        # flood the component's other cells in the window from one contact; count the contacts met
        memset(visit, 0, <size_t>(h * w))
        qr[0] = sr
        qc[0] = sc
        visit[(sr - r0) * w + sc - c0] = 1
        head = 0
        tail = 1
        met = 0
        while head < tail:
            a = qr[head]
            b = qc[head]
            head += 1
            if seen[(a - r0) * w + b - c0]:
                met += 1
            for dr in range(-1, 2):
                for dc in range(-1, 2):
                    aa = a + dr
                    bb = b + dc
                    if (r0 <= aa < r1 and c0 <= bb < c1 and not visit[(aa - r0) * w + bb - c0] and comp[aa, bb] == t
                            and not mark[aa, bb]):
                        visit[(aa - r0) * w + bb - c0] = 1
                        qr[tail] = aa
                        qc[tail] = bb
                        tail += 1
        if met != want:
            return False
        memset(seen, 0, <size_t>(h * w))
        # all fine for t: take its stuck cells out, and move its first cell on if it was one of them
        for m in range(fr.shape[0]):
            a = fr[m]
            b = fc[m]
            if mark[a, b] and comp[a, b] == t:
                mark[a, b] = 0
                comp[a, b] = 0
        j = first[t]
        if comp[j // cols, j - (j // cols) * cols] != t:
            while j < total:
                a = j // cols
                if comp[a, j - a * cols] == t:
                    break
                j += 1
            if j >= first[t + 1]:
                return False
            first[t] = j
    return True


def remove_rest_in_place(cells_t fr, cells_t fc, u8_2d mark, i32_2d comp, int64_t[::1] first, int64_t r0,
                         int64_t r1, int64_t c0, int64_t c1):
    """After :func:`remove_in_place` got stuck: take out the cells still marked (``fr, fc``) all at
    once if, for every component they belong to, the component's cells next to them stay connected
    to each other without them, through that component's cells inside the window ``r0:r1, c0:c1``
    (a flood fill there). Then every remaining part of the component touches one of those cells, so
    none is cut off. Returns False when that is not shown (a split, a vanished component, or a
    connection only outside the window)."""
    cdef int64_t size = (r1 - r0) * (c1 - c0)
    cdef size_t n = <size_t>(size if size > 0 else 1)
    cdef uint8_t* seen = <uint8_t*>malloc(n)
    cdef uint8_t* visit = <uint8_t*>malloc(n)
    cdef int64_t* qr = <int64_t*>malloc(n * sizeof(int64_t))
    cdef int64_t* qc = <int64_t*>malloc(n * sizeof(int64_t))
    cdef bint ok
    try:
        if seen == NULL or visit == NULL or qr == NULL or qc == NULL:
            raise MemoryError("remove_rest_in_place: no memory for the window")
        memset(seen, 0, n)
        with nogil:
            ok = _remove_rest(fr, fc, mark, comp, first, r0, r1, c0, c1, seen, visit, qr, qc)
    finally:
        free(seen)
        free(visit)
        free(qr)
        free(qc)
    return ok


cdef bint _insert_in_place(cells_t nr_, cells_t nc_, u8_2d mark, i32_2d comp, int64_t[::1] first, int64_t[::1] qr,
                           int64_t[::1] qc) noexcept nogil:
    cdef int64_t rows = comp.shape[0], cols = comp.shape[1], n = nr_.shape[0], tail = 0, head = 0
    cdef int64_t k, r, c, dr, dc, rr, cc, t, v, idx
    for k in range(n):
        r = nr_[k]
        c = nc_[k]
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols and comp[rr, cc] > 0 and mark[r, c] == 1:
                    mark[r, c] = 2
                    qr[tail] = r
                    qc[tail] = c
                    tail += 1
    while head < tail:
        r = qr[head]
        c = qc[head]
        head += 1
        t = 0
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols:
                    v = comp[rr, cc]
                    if v > 0:
                        if t == 0:
                            t = v
                        elif v != t:  # two components merge
                            return False
        comp[r, c] = <int32_t>t
        idx = r * cols + c
        if idx < first[t]:
            if idx < first[t - 1]:
                return False
            first[t] = idx
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols and mark[rr, cc] == 1:
                    mark[rr, cc] = 2
                    qr[tail] = rr
                    qc[tail] = cc
                    tail += 1
    return tail == n  # cells left over form components of their own


def insert_in_place(cells_t nr_, cells_t nc_, u8_2d mark, i32_2d comp, int64_t[::1] first, int64_t[::1] qr,
                    int64_t[::1] qc):
    """Give the new obstacle cells ``nr_, nc_`` (``mark == 1``, ``comp == 0``) the number of the one
    component they join, spreading from the cells next to existing obstacles, while provably no two
    components merge, no new one appears and the order by first cell stays. Returns False as soon as
    that cannot be shown."""
    cdef bint ok
    with nogil:
        ok = _insert_in_place(nr_, nc_, mark, comp, first, qr, qc)
    return ok
