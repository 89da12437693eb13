# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind the voxel-grid :class:`~gridfield.distance.incremental.IncrementalBrushfire`
(:mod:`gridfield.distance._incremental3d`; private, imported on first use).

The 3-D counterpart of :mod:`gridfield.distance._incremental`: everything works on a box *window*
``layers z0:z1, rows r0:r1, cols c0:c1`` of the full-grid ``[layer, row, col]`` arrays, with global
cell indices. :func:`window_edt3` is the exact Euclidean transform of the sites inside the window,
separable in three passes (Meijster et al. 2000; Felzenszwalb & Huttenlocher 2012 for the lower
envelope of sampled parabolas): the nearest site layer along each layer line, then per row line the
lower envelope over the rows, then per column line over the columns. Every pass keeps the smallest
index on a tie, so the site it picks is the smallest by ``(squared distance, col, row, layer)`` (the
tie rule of the full 3-D transform), which is what lets a window result be merged cell by cell into
a full-grid one (:func:`lower_merge3`, :func:`raise_apply3`): proved below at the envelope and
checked against brute force in ``tests/test_incremental3d.py``.

Conventions: ``nl``/``nr``/``nc`` are the nearest obstacle cells (int32, ``(-1, -1, -1)`` = none);
wall-border cells are layer ``-1``/``layers``, row ``-1``/``rows`` or column ``-1``/``cols`` (one
coordinate outside the grid, the others the cell's own); squared distances are in cells (int64);
occupancy and marks are ``uint8``; cell lists are int64; 3-D arrays are C-contiguous. Nothing here
validates input: :mod:`gridfield.distance._incremental3d` does.

Why the passes give the tie rule: pass 1 keeps, per ``(row, col)`` line, the nearest site layer
(ties: the lower). Pass 2 minimises ``(r - r')**2 + f1(r')`` over the rows ``r'`` of a ``(layer, col)``
line, ties to the smallest ``r'``; the rows reaching the minimum are exactly those holding a site at
the minimal distance within column ``c'``, so the smallest of them and, within it, the lower layer
are the rule's choice within column ``c'``. Pass 3 then takes the smallest column among the minima.

Cython, compiled at install; every kernel releases the GIL. Bounds checks are off: every index is a
window cell or a neighbour guarded by the grid bounds.
"""

from libc.math cimport INFINITY, ceil, sqrt
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free, malloc

import numpy as np

__all__ = ["NONE_D2", "distance3", "labels_window3", "lower_merge3", "max_distance2_3", "orphan_box3", "raise_apply3",
           "raise_check3", "ring_reached3", "set_cells3", "window_edt3"]

#: Squared distance meaning "no site" (larger than any squared distance on a grid).
NONE_D2 = np.int64(1) << np.int64(62)
cdef int64_t _NONE_D2 = (<int64_t>1) << 62
cdef int64_t _BIG = (<int64_t>1) << 30  # sentinel layer for "no site in this layer line"
cdef int64_t _HALF = (<int64_t>1) << 29  # beyond any real layer

ctypedef const uint8_t[:, :, ::1] u8c_3d
ctypedef uint8_t[:, :, ::1] u8_3d
ctypedef const int32_t[:, :, ::1] i32c_3d
ctypedef int32_t[:, :, ::1] i32_3d
ctypedef const int64_t[:, :, ::1] i64c_3d
ctypedef int64_t[:, :, ::1] i64_3d
ctypedef double[:, :, ::1] f64_3d
ctypedef const int64_t[:] cells_t  # cell lists (any stride)


cdef inline int64_t _min(int64_t a, int64_t b) noexcept nogil:
    return a if a < b else b


cdef inline int64_t _max(int64_t a, int64_t b) noexcept nogil:
    return a if a > b else b


cdef inline int64_t _floordiv(int64_t a, int64_t b) noexcept nogil:
    # floor(a / b) for b > 0 (C division truncates towards zero)
    cdef int64_t q = a / b
    if q * b > a:
        q -= 1
    return q


cdef inline int64_t _old_d2(int64_t z, int64_t r, int64_t c, int64_t a, int64_t b, int64_t e) noexcept nogil:
    if a == -1 and b == -1 and e == -1:
        return _NONE_D2
    return (z - a) * (z - a) + (r - b) * (r - b) + (c - e) * (c - e)


cdef inline bint _less(int64_t d2, int64_t col, int64_t row, int64_t lay, int64_t e2, int64_t ecol, int64_t erow,
                       int64_t elay) noexcept nogil:
    # (d2, col, row, layer) < (e2, ecol, erow, elayer) lexicographically: the tie rule of the full transform
    if d2 != e2:
        return d2 < e2
    if col != ecol:
        return col < ecol
    if row != erow:
        return row < erow
    return lay < elay


cdef bint _envelope(const int64_t* f, int64_t n, int64_t* s, int64_t* t, int64_t* fs, int64_t* val,
                    int64_t* arg) noexcept nogil:
    """Lower envelope of the parabolas ``(x - u)**2 + f[u]`` over the positions ``u = 0 .. n + 1``
    (``f[u] >= NONE_D2``: no site), for ``x = 1 .. n``: ``val[x - 1]`` the least value, ``arg[x - 1]``
    the smallest ``u`` reaching it. Positions 0 and ``n + 1`` are the sentinels (walls) beside the
    line. Returns False when no position holds a site.

    The stack holds site ``s[q]`` and the first ``x`` it wins, ``t[q]`` (strictly increasing). A new
    site ``u`` pops the top while it is strictly below the top at the top's first ``x``; else it is
    pushed from the first ``x`` where it is *strictly* below the top, so ties keep the smaller site."""
    cdef int64_t q = -1, u, fu, sq, tq, fq, w, x, d1, d2, lo, hi
    for u in range(n + 2):
        fu = f[u]
        if fu >= _NONE_D2:
            continue
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
            # first x where u is strictly below s[q]: 2x(u - sq) > u**2 - sq**2 + fu - fq
            w = 1 + _floordiv(u * u - sq * sq + fu - fs[q], 2 * (u - sq))
            if w <= n:
                q += 1
                s[q] = u
                t[q] = w
                fs[q] = fu
    if q < 0:
        return False
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


cdef int _edt3(u8c_3d sites, int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, bint wz0,
               bint wz1, bint wr0, bint wr1, bint wc0, bint wc1, i32_3d wnl, i32_3d wnr, i32_3d wnc,
               i64_3d wd2) noexcept nogil:
    cdef int64_t layers = sites.shape[0], rows = sites.shape[1], cols = sites.shape[2]
    cdef int64_t D = z1 - z0, H = r1 - r0, W = c1 - c0, L = _max(D, _max(H, W)) + 2
    cdef int64_t i, j, k, z, r, a, b, d, v
    cdef int64_t top = -1 if wz0 else -_BIG
    cdef int64_t bottom = layers if wz1 else _BIG
    cdef int64_t* f = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int64_t* s = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int64_t* t = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int64_t* fs = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int64_t* val = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int64_t* arg = <int64_t*>malloc(L * sizeof(int64_t))
    cdef int32_t* la = <int32_t*>malloc(L * sizeof(int32_t))
    cdef int32_t* ro = <int32_t*>malloc(L * sizeof(int32_t))
    cdef int32_t* below = <int32_t*>malloc(H * W * sizeof(int32_t) + 4)
    cdef const uint8_t* srow
    cdef int32_t* vrow
    cdef int32_t* prev
    if f == NULL or s == NULL or t == NULL or fs == NULL or val == NULL or arg == NULL or la == NULL or ro == NULL \
            or below == NULL:
        free(f); free(s); free(t); free(fs); free(val); free(arg); free(la); free(ro); free(below)
        return -1
    # pass 1, along the layers: wnl = layer of the nearest site in the (row, col) line (ties: the lower),
    # +-BIG for none; swept plane by plane (row-major): up, the nearest at or below; down, the one above
    # if strictly nearer
    for i in range(D):
        z = z0 + i
        for j in range(H):
            srow = &sites[z, r0 + j, c0]
            vrow = &wnl[i, j, 0]
            if i == 0:
                for k in range(W):
                    vrow[k] = <int32_t>(z if srow[k] else top)
            else:
                prev = &wnl[i - 1, j, 0]
                for k in range(W):
                    vrow[k] = <int32_t>(z if srow[k] else prev[k])
    for j in range(H * W):
        below[j] = <int32_t>bottom
    for i in range(D - 1, -1, -1):
        z = z0 + i
        for j in range(H):
            srow = &sites[z, r0 + j, c0]
            vrow = &wnl[i, j, 0]
            prev = &below[j * W]
            for k in range(W):
                if srow[k]:
                    prev[k] = <int32_t>z
                b = prev[k]
                if (b - z) < (z - vrow[k]):
                    vrow[k] = <int32_t>b
    # pass 2, along the rows of each (layer, col) line: wd2 = partial squared distance, wnr its row,
    # wnl its layer (the sentinel rows -1 / rows: the wall, at the cell's own layer)
    for i in range(D):
        z = z0 + i
        for k in range(W):
            f[0] = 0 if wr0 else _NONE_D2
            f[H + 1] = 0 if wr1 else _NONE_D2
            la[0] = <int32_t>z
            la[H + 1] = <int32_t>z
            for j in range(H):
                v = wnl[i, j, k]
                la[j + 1] = <int32_t>v
                if v >= _HALF or v <= -_HALF:  # no site in the layer line
                    f[j + 1] = _NONE_D2
                else:
                    d = z - v
                    f[j + 1] = d * d
            if _envelope(f, H, s, t, fs, val, arg):
                for j in range(H):
                    a = arg[j]
                    wd2[i, j, k] = val[j]
                    wnr[i, j, k] = <int32_t>(r0 + a - 1)
                    wnl[i, j, k] = la[a]
            else:
                for j in range(H):
                    wd2[i, j, k] = _NONE_D2
    # pass 3, along the columns of each (layer, row) line
    for i in range(D):
        z = z0 + i
        for j in range(H):
            r = r0 + j
            f[0] = 0 if wc0 else _NONE_D2
            f[W + 1] = 0 if wc1 else _NONE_D2
            la[0] = <int32_t>z
            la[W + 1] = <int32_t>z
            ro[0] = <int32_t>r
            ro[W + 1] = <int32_t>r
            for k in range(W):
                f[k + 1] = wd2[i, j, k]
                la[k + 1] = wnl[i, j, k]
                ro[k + 1] = wnr[i, j, k]
            if _envelope(f, W, s, t, fs, val, arg):
                for k in range(W):
                    a = arg[k]
                    wd2[i, j, k] = val[k]
                    wnc[i, j, k] = <int32_t>(c0 + a - 1)
                    wnr[i, j, k] = ro[a]
                    wnl[i, j, k] = la[a]
            else:
                for k in range(W):
                    wd2[i, j, k] = _NONE_D2
                    wnl[i, j, k] = -1
                    wnr[i, j, k] = -1
                    wnc[i, j, k] = -1
    free(f); free(s); free(t); free(fs); free(val); free(arg); free(la); free(ro); free(below)
    return 0


def window_edt3(u8c_3d sites, int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, bint wz0,
                bint wz1, bint wr0, bint wr1, bint wc0, bint wc1, i32_3d wnl, i32_3d wnr, i32_3d wnc, i64_3d wd2):
    """Euclidean transform of the sites (``sites[z, r, c] != 0``) inside the window: for each window
    cell, ``wnl``/``wnr``/``wnc`` (global cell of the nearest site, the smallest by ``(squared
    distance, col, row, layer)``) and ``wd2`` (its squared distance; :data:`NONE_D2` and
    ``(-1, -1, -1)`` when the window holds no site). ``wz0``/``wz1``/``wr0``/``wr1``/``wc0``/``wc1``:
    whether the wall layers ``-1``/``layers``, rows ``-1``/``rows`` or columns ``-1``/``cols`` count
    as sites (only meaningful when the window reaches that face). Window-shaped outputs."""
    cdef int ok
    if z1 <= z0 or r1 <= r0 or c1 <= c0:
        return
    with nogil:
        ok = _edt3(sites, z0, z1, r0, r1, c0, c1, wz0, wz1, wr0, wr1, wc0, wc1, wnl, wnr, wnc, wd2)
    if ok != 0:
        raise MemoryError("window_edt3: no memory for the scratch lines")


def ring_reached3(int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t layers,
                  int64_t rows, int64_t cols, i64c_3d wd2, i32c_3d nl, i32c_3d nr, i32c_3d nc, uint8_t[::1] out):
    """For each face of the window that is not a grid face (``out[0..5]``: layers ``z0``, ``z1 - 1``,
    rows ``r0``, ``r1 - 1``, columns ``c0``, ``c1 - 1``), whether some cell of that face may be reached
    by the change: its window distance ``sqrt(wd2)`` is at most its current distance plus ``sqrt(3)``.
    A cell whose nearest obstacle the change alters is joined to the changed cells by a 26-connected
    chain of cells meeting that bound (the lattice cells nearest to the straight segment: each within
    ``sqrt(3) / 2`` of it), so when no face is reached no such cell lies outside."""
    cdef double slack = sqrt(3.0) + 1e-9
    cdef int64_t D = z1 - z0, H = r1 - r0, W = c1 - c0, f, i, j, k, d2, o2, z, r, c
    cdef int64_t lo0, hi0, lo1, hi1, lo2, hi2
    with nogil:
        for f in range(6):
            out[f] = 0
        for f in range(6):
            if (f == 0 and z0 == 0) or (f == 1 and z1 == layers) or (f == 2 and r0 == 0) or (f == 3 and r1 == rows) \
                    or (f == 4 and c0 == 0) or (f == 5 and c1 == cols):
                continue
            lo0, hi0, lo1, hi1, lo2, hi2 = 0, D, 0, H, 0, W
            if f == 0:
                hi0 = 1
            elif f == 1:
                lo0 = D - 1
            elif f == 2:
                hi1 = 1
            elif f == 3:
                lo1 = H - 1
            elif f == 4:
                hi2 = 1
            else:
                lo2 = W - 1
            for i in range(lo0, hi0):
                for j in range(lo1, hi1):
                    for k in range(lo2, hi2):
                        d2 = wd2[i, j, k]
                        if d2 == _NONE_D2:
                            continue
                        z = z0 + i
                        r = r0 + j
                        c = c0 + k
                        o2 = _old_d2(z, r, c, nl[z, r, c], nr[z, r, c], nc[z, r, c])
                        if o2 == _NONE_D2 or sqrt(<double>d2) <= sqrt(<double>o2) + slack:
                            out[f] = 1
                            break
                    if out[f]:
                        break
                if out[f]:
                    break


def lower_merge3(int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_3d wnl, i32c_3d wnr,
                 i32c_3d wnc, i64c_3d wd2, i32_3d nl, i32_3d nr, i32_3d nc, f64_3d distance, double res,
                 int64_t[::1] box):
    """Insertion: every window cell whose window nearest site beats its current nearest obstacle (by
    the full transform's rule) takes it. ``box`` (int64[6]) grows to the bounding box ``z0, z1, r0,
    r1, c0, c1`` of the cells changed; returns their number."""
    cdef int64_t count = 0, i, j, k, z, r, c, d2, a, b, e
    with nogil:
        for i in range(z1 - z0):
            z = z0 + i
            for j in range(r1 - r0):
                r = r0 + j
                for k in range(c1 - c0):
                    c = c0 + k
                    d2 = wd2[i, j, k]
                    if d2 == _NONE_D2:
                        continue
                    a = nl[z, r, c]
                    b = nr[z, r, c]
                    e = nc[z, r, c]
                    if not _less(d2, wnc[i, j, k], wnr[i, j, k], wnl[i, j, k], _old_d2(z, r, c, a, b, e), e, b, a):
                        continue
                    nl[z, r, c] = wnl[i, j, k]
                    nr[z, r, c] = wnr[i, j, k]
                    nc[z, r, c] = wnc[i, j, k]
                    distance[z, r, c] = sqrt(<double>d2) * res
                    count += 1
                    box[0] = _min(box[0], z)
                    box[1] = _max(box[1], z + 1)
                    box[2] = _min(box[2], r)
                    box[3] = _max(box[3], r + 1)
                    box[4] = _min(box[4], c)
                    box[5] = _max(box[5], c + 1)
    return count


cdef inline bint _orphan(int64_t layers, int64_t rows, int64_t cols, int64_t a, int64_t b, int64_t e,
                         u8c_3d mark) noexcept nogil:
    # whether the nearest obstacle (a, b, e) is a grid cell that is marked (removed)
    return 0 <= a < layers and 0 <= b < rows and 0 <= e < cols and mark[a, b, e] != 0


def orphan_box3(int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t layers, int64_t rows,
                int64_t cols, i32c_3d nl, i32c_3d nr, i32c_3d nc, u8c_3d mark, int64_t[::1] box):
    """Removal: bounding box (``box``, int64[6]) of the window cells whose nearest obstacle is a
    removed cell (``mark`` set there); returns their number and the largest squared distance to it."""
    cdef int64_t count = 0, far2 = 0, z, r, c, a, b, e
    with nogil:
        for z in range(z0, z1):
            for r in range(r0, r1):
                for c in range(c0, c1):
                    a = nl[z, r, c]
                    b = nr[z, r, c]
                    e = nc[z, r, c]
                    if not _orphan(layers, rows, cols, a, b, e, mark):
                        continue
                    count += 1
                    far2 = _max(far2, _old_d2(z, r, c, a, b, e))
                    box[0] = _min(box[0], z)
                    box[1] = _max(box[1], z + 1)
                    box[2] = _min(box[2], r)
                    box[3] = _max(box[3], r + 1)
                    box[4] = _min(box[4], c)
                    box[5] = _max(box[5], c + 1)
    return count, far2


def raise_check3(int64_t b0, int64_t b1, int64_t b2, int64_t b3, int64_t b4, int64_t b5, int64_t z0, int64_t z1,
                 int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t layers, int64_t rows, int64_t cols,
                 i32c_3d nl, i32c_3d nr, i32c_3d nc, u8c_3d mark, i64c_3d wd2):
    """Removal: whether the window ``z0:z1, r0:r1, c0:c1`` (``wd2`` its transform of all obstacles)
    gives every orphan in the box ``b0:b1, b2:b3, b4:b5`` its exact nearest obstacle, i.e. one
    strictly nearer than any cell outside the window (at least as far as the nearest window face
    that is not a grid face). Returns -1 if so, else the largest window distance (in cells, rounded
    up) among the orphans that failed (``-2`` when an orphan found no obstacle in the window)."""
    cdef int64_t worst = -1, z, r, c, out, d2
    with nogil:
        worst = _check(b0, b1, b2, b3, b4, b5, z0, z1, r0, r1, c0, c1, layers, rows, cols, nl, nr, nc, mark, wd2)
    return worst


cdef int64_t _check(int64_t b0, int64_t b1, int64_t b2, int64_t b3, int64_t b4, int64_t b5, int64_t z0, int64_t z1,
                    int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t layers, int64_t rows, int64_t cols,
                    i32c_3d nl, i32c_3d nr, i32c_3d nc, u8c_3d mark, i64c_3d wd2) noexcept nogil:
    cdef int64_t worst = -1, z, r, c, out, d2
    if True:
        for z in range(b0, b1):
            for r in range(b2, b3):
                for c in range(b4, b5):
                    if not _orphan(layers, rows, cols, nl[z, r, c], nr[z, r, c], nc[z, r, c], mark):
                        continue
                    out = _BIG
                    if z0 > 0:
                        out = _min(out, z - z0 + 1)
                    if z1 < layers:
                        out = _min(out, z1 - z)
                    if r0 > 0:
                        out = _min(out, r - r0 + 1)
                    if r1 < rows:
                        out = _min(out, r1 - r)
                    if c0 > 0:
                        out = _min(out, c - c0 + 1)
                    if c1 < cols:
                        out = _min(out, c1 - c)
                    d2 = wd2[z - z0, r - r0, c - c0]
                    if d2 == _NONE_D2:
                        if out < _BIG:  # no obstacle in the window, but maybe outside: widen the window
                            return -2
                        continue
                    if d2 >= out * out:
                        worst = _max(worst, <int64_t>ceil(sqrt(<double>d2)))
    return worst


def raise_apply3(int64_t b0, int64_t b1, int64_t b2, int64_t b3, int64_t b4, int64_t b5, int64_t z0, int64_t r0,
                 int64_t c0, int64_t layers, int64_t rows, int64_t cols, i32_3d nl, i32_3d nr, i32_3d nc, u8c_3d mark,
                 i32c_3d wnl, i32c_3d wnr, i32c_3d wnc, i64c_3d wd2, f64_3d distance, double res):
    """Removal: the orphans in the box ``b0:b1, b2:b3, b4:b5`` take their window nearest obstacle
    (the window starting at ``z0, r0, c0``)."""
    cdef int64_t z, r, c, d2, i, j, k
    with nogil:
        for z in range(b0, b1):
            for r in range(b2, b3):
                for c in range(b4, b5):
                    if not _orphan(layers, rows, cols, nl[z, r, c], nr[z, r, c], nc[z, r, c], mark):
                        continue
                    i = z - z0
                    j = r - r0
                    k = c - c0
                    d2 = wd2[i, j, k]
                    if d2 == _NONE_D2:
                        nl[z, r, c] = -1
                        nr[z, r, c] = -1
                        nc[z, r, c] = -1
                        distance[z, r, c] = INFINITY
                    else:
                        nl[z, r, c] = wnl[i, j, k]
                        nr[z, r, c] = wnr[i, j, k]
                        nc[z, r, c] = wnc[i, j, k]
                        distance[z, r, c] = sqrt(<double>d2) * res


def max_distance2_3(int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_3d nl, i32c_3d nr,
                    i32c_3d nc):
    """Largest current squared distance (cells) over the window; :data:`NONE_D2` if some cell has none."""
    cdef int64_t m = 0, z, r, c
    with nogil:
        for z in range(z0, z1):
            for r in range(r0, r1):
                for c in range(c0, c1):
                    m = _max(m, _old_d2(z, r, c, nl[z, r, c], nr[z, r, c], nc[z, r, c]))
    return m


def set_cells3(cells_t cz, cells_t cr, cells_t cc, u8_3d arr, int value):
    """``arr[cz[k], cr[k], cc[k]] = value`` for every k."""
    cdef Py_ssize_t k
    cdef uint8_t v = <uint8_t>value
    with nogil:
        for k in range(cz.shape[0]):
            arr[cz[k], cr[k], cc[k]] = v


def distance3(int64_t z0, int64_t z1, i64c_3d d2, double res, f64_3d distance):
    """Layers ``z0:z1`` of ``distance`` = ``sqrt(d2) * res`` (``inf`` for :data:`NONE_D2`), the arithmetic
    of :func:`lower_merge3` (a full-grid ``d2``)."""
    cdef int64_t z, r, c, v
    with nogil:
        for z in range(z0, z1):
            for r in range(d2.shape[1]):
                for c in range(d2.shape[2]):
                    v = d2[z, r, c]
                    distance[z, r, c] = INFINITY if v == _NONE_D2 else sqrt(<double>v) * res


def labels_window3(int64_t z0, int64_t z1, int64_t r0, int64_t r1, int64_t c0, int64_t c1, i32c_3d nl, i32c_3d nr,
                   i32c_3d nc, i32c_3d ids, int32_t border_label, i32_3d label):
    """``label`` = ``ids`` at the nearest obstacle (``border_label`` for a wall cell, 0 for none)."""
    cdef int64_t layers = nl.shape[0], rows = nl.shape[1], cols = nl.shape[2], z, r, c, a, b, e
    with nogil:
        for z in range(z0, z1):
            for r in range(r0, r1):
                for c in range(c0, c1):
                    a = nl[z, r, c]
                    b = nr[z, r, c]
                    e = nc[z, r, c]
                    if a == -1 and b == -1 and e == -1:
                        label[z, r, c] = 0
                    elif a < 0 or a >= layers or b < 0 or b >= rows or e < 0 or e >= cols:
                        label[z, r, c] = border_label
                    else:
                        label[z, r, c] = ids[a, b, e]
