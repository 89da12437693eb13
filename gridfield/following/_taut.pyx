# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.following.taut` (Cython, compiled at install; imported lazily).

The walk of the cells a segment crosses, its exact supercover (:func:`crossed_clearance`), and the
string pulling over a path's vertices that checks every new segment with it (:func:`taut`), for the
potential planner's taut post-pass. Points are in *cell units* (column, row: ``(x - x0) / resolution``);
masks ``uint8`` (or ``bool``), clearances ``float64``. Nothing here validates input;
:mod:`gridfield.following.taut` does.
"""

from libc.math cimport INFINITY, ceil, fabs, floor
from libc.stdint cimport int64_t, uint8_t
from libc.stdlib cimport free as c_free, llabs, malloc

import numpy as np

ctypedef const uint8_t[:, :] mask_t
ctypedef const double[:, :] val_t


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


# ----------------------------------------------------------------------------------------------
# taut paths: line of sight over the cells a segment crosses (gridfield.following.taut)
# ----------------------------------------------------------------------------------------------
cdef struct Need:
    # the clearance a crossed cell needs: need[(r - r0) * w + (c - c0)] inside the box, ``base`` outside
    const double* need
    int64_t r0, c0, h, w
    double base


cdef inline double _need(const Need* nd, int64_t r, int64_t c) noexcept nogil:
    if nd.need == NULL or r < nd.r0 or c < nd.c0 or r >= nd.r0 + nd.h or c >= nd.c0 + nd.w:
        return nd.base
    return nd.need[(r - nd.r0) * nd.w + (c - nd.c0)]


cdef inline bint _cell_ok(mask_t occ, val_t clear, int64_t r, int64_t c, const Need* nd) noexcept nogil:
    """A free cell of the grid whose clearance is at least its need (outside the grid: not ok)."""
    if r < 0 or c < 0 or r >= occ.shape[0] or c >= occ.shape[1]:
        return False
    return occ[r, c] == 0 and clear[r, c] >= _need(nd, r, c)


cdef inline bint _cell_blocked(mask_t occ, int64_t r, int64_t c) noexcept nogil:
    if r < 0 or c < 0 or r >= occ.shape[0] or c >= occ.shape[1]:
        return True
    return occ[r, c] != 0


cdef double _walk(double u0, double v0, double u1, double v1, mask_t occ, val_t clear, const Need* nd) noexcept nogil:
    """Walk the cells the segment (u0, v0)-(u1, v1) (cell units: column, row) crosses, its exact
    supercover. Returns the smallest clearance of the crossed cells, or -1 as soon as one is
    blocked, outside the grid or below its need (``nd``). A segment that passes exactly through a
    grid vertex does not enter the two cells beside it (it touches them at a point), unless both are
    blocked (a pinch: no way through; "exactly": the cross product of the segment and the vertex is 0 in
    floating point, as it is for cell centres and other short binary fractions); within 1e-9 of a
    vertex (not exactly on it) it is taken to enter both."""
    cdef int64_t c = <int64_t>floor(u0), r = <int64_t>floor(v0)
    cdef int64_t ce = <int64_t>floor(u1), re = <int64_t>floor(v1)
    cdef double du = u1 - u0, dv = v1 - v0
    cdef int64_t sc = 1 if du > 0 else -1, sr = 1 if dv > 0 else -1
    cdef double tdu = INFINITY, tdv = INFINITY, tmu = INFINITY, tmv = INFINITY
    cdef double low = INFINITY
    cdef int64_t guard = 0, limit
    if not _cell_ok(occ, clear, r, c, nd):
        return -1.0
    low = clear[r, c]
    if du != 0.0:
        tdu = 1.0 / fabs(du)
        tmu = ((c + 1 - u0) if du > 0 else (u0 - c)) * tdu
    if dv != 0.0:
        tdv = 1.0 / fabs(dv)
        tmv = ((r + 1 - v0) if dv > 0 else (v0 - r)) * tdv
    limit = llabs(ce - c) + llabs(re - r) + 4
    while (c != ce or r != re) and guard < limit:
        guard += 1
        if c == ce:
            r += sr
            tmv += tdv
        elif r == re:
            c += sc
            tmu += tdu
        elif tmu < tmv - 1e-9:
            c += sc
            tmu += tdu
        elif tmv < tmu - 1e-9:
            r += sr
            tmv += tdv
        else:  # at (or within 1e-9 of) a vertex: exactly through it when the cross product is 0
            if (c + (sc > 0) - u0) * dv - (r + (sr > 0) - v0) * du == 0.0:
                if _cell_blocked(occ, r, c + sc) and _cell_blocked(occ, r + sr, c):
                    return -1.0
            else:
                if not _cell_ok(occ, clear, r, c + sc, nd) or not _cell_ok(occ, clear, r + sr, c, nd):
                    return -1.0
                low = min(low, min(clear[r, c + sc], clear[r + sr, c]))
            c += sc
            r += sr
            tmu += tdu
            tmv += tdv
        if not _cell_ok(occ, clear, r, c, nd):
            return -1.0
        low = min(low, clear[r, c])
    if c != ce or r != re:  # rounding ran the walk past its end: refuse
        return -1.0
    return low


def crossed_clearance(const double[:, :] pts, mask_t occ, val_t clear):
    """The smallest ``clear`` of the cells the polyline ``pts`` (cell units: column, row) crosses
    (:func:`_walk`'s rule); -1 when it crosses a blocked cell or leaves the grid."""
    cdef Py_ssize_t i, n = pts.shape[0]
    cdef double low = INFINITY, w
    cdef Need nd
    nd.need = NULL
    nd.base = -INFINITY
    if n == 0:
        return INFINITY
    with nogil:
        if n == 1:
            if _cell_ok(occ, clear, <int64_t>floor(pts[0, 1]), <int64_t>floor(pts[0, 0]), &nd):
                low = clear[<int64_t>floor(pts[0, 1]), <int64_t>floor(pts[0, 0])]
            else:
                low = -1.0
        for i in range(n - 1):
            w = _walk(pts[i, 0], pts[i, 1], pts[i + 1, 0], pts[i + 1, 1], occ, clear, &nd)
            if w < 0:
                low = -1.0
                break
            low = min(low, w)
    return low


cdef inline bint _sees(const double[:, :] pts, int64_t i, int64_t j, mask_t occ, val_t clear,
                       const Need* nd) noexcept nogil:
    return _walk(pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1], occ, clear, nd) >= 0.0


cdef int64_t _pull(const double[:, :] pts, int64_t* idx, int64_t n, mask_t occ, val_t clear,
                   const Need* nd) noexcept nogil:
    """One greedy pass over the vertices ``pts[idx[:n]]``, in place; returns how many are kept."""
    cdef int64_t i = 0, lo, hi, mid, k = 1
    while i < n - 1:
        lo = i + 1
        hi = n  # first position known not to be seen (n: none known)
        mid = i + 2
        while mid < n:
            if _sees(pts, idx[i], idx[mid], occ, clear, nd):
                lo = mid
                mid = i + 2 * (mid - i)
            else:
                hi = mid
                break
        if hi == n and lo < n - 1:
            if _sees(pts, idx[i], idx[n - 1], occ, clear, nd):
                lo = n - 1
            else:
                hi = n - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _sees(pts, idx[i], idx[mid], occ, clear, nd):
                lo = mid
            else:
                hi = mid
        idx[k] = idx[lo]  # k <= lo: nothing still needed is overwritten
        k += 1
        i = lo
    return k


def taut(const double[:, :] pts, mask_t occ, val_t clear, double band, double radius, int passes=1):
    """Indices of the vertices of ``pts`` (cell units: column, row) that a greedy string pulling
    keeps: from each kept vertex ``i`` the farthest later vertex ``j`` found (galloping, then
    bisection) whose segment from ``i`` crosses only free cells whose ``clear`` is at least their
    need (:func:`_walk`); ``i + 1`` always (the path's own segment). The first and last vertex are
    kept; the pass runs again over the kept vertices, up to ``passes`` times, while it drops one. A cell's need is ``min(band, the smallest clear of the cells of the vertices of pts within
    radius cells of it)``, ``band`` for a cell farther than ``radius`` from every vertex (``band <= 0``:
    0, any free cell)."""
    cdef int64_t n = pts.shape[0], i = 0, k = 1, m, p
    cdef int64_t[::1] out = np.empty(max(n, 1), np.int64)
    cdef int64_t rmin, rmax, cmin, cmax, rr, cc, r, c, R, dr, dc
    cdef double d, rad2 = radius * radius
    cdef double* need = NULL
    cdef Need nd
    if n == 0:
        return np.empty(0, np.int64)
    nd.need = NULL
    nd.base = band if band > 0 else 0.0
    nd.r0 = nd.c0 = nd.h = nd.w = 0
    with nogil:
        if band > 0 and radius > 0:
            # the need of the cells within ``radius`` of a vertex: stamped from every vertex
            R = <int64_t>ceil(radius)
            rmin = rmax = <int64_t>floor(pts[0, 1])
            cmin = cmax = <int64_t>floor(pts[0, 0])
            for i in range(1, n):
                r = <int64_t>floor(pts[i, 1])
                c = <int64_t>floor(pts[i, 0])
                rmin = min(rmin, r)
                rmax = max(rmax, r)
                cmin = min(cmin, c)
                cmax = max(cmax, c)
            nd.r0, nd.c0 = rmin - R, cmin - R
            nd.h, nd.w = rmax - rmin + 2 * R + 1, cmax - cmin + 2 * R + 1
            need = <double*>_alloc(nd.h * nd.w * sizeof(double))
            if need != NULL:
                for i in range(nd.h * nd.w):
                    need[i] = INFINITY
                for i in range(n):
                    r = <int64_t>floor(pts[i, 1])
                    c = <int64_t>floor(pts[i, 0])
                    if r < 0 or c < 0 or r >= occ.shape[0] or c >= occ.shape[1]:
                        continue
                    d = min(clear[r, c], band)
                    for dr in range(-R, R + 1):
                        for dc in range(-R, R + 1):
                            if dr * dr + dc * dc > rad2:
                                continue
                            rr = (r + dr - nd.r0) * nd.w + (c + dc - nd.c0)
                            if d < need[rr]:
                                need[rr] = d
                for i in range(nd.h * nd.w):
                    if need[i] > band:
                        need[i] = band
                nd.need = need
            else:
                nd.base = 0.0  # no memory for the tube: the plain rule of the smallest clearance
                for i in range(n):
                    r = <int64_t>floor(pts[i, 1])
                    c = <int64_t>floor(pts[i, 0])
                    if 0 <= r < occ.shape[0] and 0 <= c < occ.shape[1]:
                        nd.base = min(band, clear[r, c]) if i == 0 else min(nd.base, clear[r, c])
        m = n
        for i in range(n):
            out[i] = i
        for p in range(passes):
            k = _pull(pts, &out[0], m, occ, clear, &nd)
            if k == m:
                break
            m = k
        if need != NULL:
            c_free(need)
    return np.asarray(out[:m]).copy()
