# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.exact.anyangle` (private; imported on first use): the A*
searches over the convex corners, from a virtual start to a virtual goal, on the visibility graph
(:func:`astar`) or lazily, finding each expanded corner's visible neighbours by the nearest-first search
of :mod:`gridfield.exact._occlusion` (:func:`lazy_astar`, cimported through ``_occlusion.pxd``), and
the binary heap they use (exported through ``_astar.pxd``: :mod:`gridfield.exact._polyanya` cimports it).

Lattice units and the padded blocked array ``B`` are those of :mod:`gridfield.exact._anyangle`.
Nothing in this module validates input; :mod:`gridfield.exact.anyangle` does. Cython, compiled at
install; the searches release the GIL while they run; the heap grows by doubling a C buffer.
"""

from libc.math cimport INFINITY, sqrt
from libc.stdint cimport int64_t, uint8_t
from libc.stdlib cimport free, malloc, realloc

from ._anyangle cimport blk_t, f64c_1d, i64c_1d
from ._occlusion cimport _NB, Ext, Prune, _ext, _visible_set

import numpy as np

__all__ = ["astar", "lazy_astar"]


# ----------------------------------------------------------------------------------------------
# A* over the corner graph
# ----------------------------------------------------------------------------------------------
# Heap is declared in _astar.pxd (shared with _polyanya)
cdef bint _heap_push(Heap* h, double f, int64_t j) noexcept nogil:
    """Push ``(f, j)`` on the binary min-heap (grown by doubling); False when out of memory."""
    cdef int64_t k, par, cap
    cdef double* nk
    cdef int64_t* nv
    if h.size == h.cap:
        cap = 2 * h.cap
        nk = <double*>realloc(h.k, cap * sizeof(double))
        if nk == NULL:
            return False
        h.k = nk
        nv = <int64_t*>realloc(h.v, cap * sizeof(int64_t))
        if nv == NULL:
            return False
        h.v = nv
        h.cap = cap
    k = h.size  # sift up
    h.size += 1
    while k > 0:
        par = (k - 1) >> 1
        if h.k[par] <= f:
            break
        h.k[k] = h.k[par]
        h.v[k] = h.v[par]
        k = par
    h.k[k] = f
    h.v[k] = j
    return True


cdef void _heap_pop(Heap* h) noexcept nogil:
    """Drop the root (the caller read it), sifting the last entry down from the root."""
    cdef double lk
    cdef int64_t lv, k, ch
    h.size -= 1
    if h.size > 0:
        lk = h.k[h.size]
        lv = h.v[h.size]
        k = 0
        while True:
            ch = 2 * k + 1
            if ch >= h.size:
                break
            if ch + 1 < h.size and h.k[ch + 1] < h.k[ch]:
                ch += 1
            if h.k[ch] >= lk:
                break
            h.k[k] = h.k[ch]
            h.v[k] = h.v[ch]
            k = ch
        h.k[k] = lk
        h.v[k] = lv


def astar(i64c_1d indptr, i64c_1d indices, f64c_1d weights, f64c_1d vx, f64c_1d vy, f64c_1d start_d,
          f64c_1d goal_d, double gx, double gy):
    """A* over the corner graph from a virtual start to a virtual goal.

    ``start_d[j]`` / ``goal_d[j]``: length of the start -> corner j / corner j -> goal edge (inf: none).
    The heuristic is the straight-line distance to the goal (consistent). Returns the total length
    (inf if unreachable), the predecessor of every corner (-1: the start) and the corner from which
    the goal was entered (-1: none).
    """
    cdef int64_t n = vx.shape[0], j, u, v, e
    cdef double best = INFINITY, f, gu, nd, tx, ty
    cdef int64_t last = -1
    cdef bint ok = True
    g_arr = np.full(n, np.inf)
    pred_arr = np.full(n, -2, np.int64)
    closed_arr = np.zeros(n, np.uint8)
    cdef double[::1] g = g_arr
    cdef int64_t[::1] pred = pred_arr
    cdef uint8_t[::1] closed = closed_arr
    cdef Heap h
    h.size = 0
    h.cap = 1024
    h.k = <double*>malloc(h.cap * sizeof(double))
    h.v = <int64_t*>malloc(h.cap * sizeof(int64_t))
    try:
        if h.k == NULL or h.v == NULL:
            raise MemoryError("astar: no memory for the heap")
        with nogil:
            for j in range(n):
                if start_d[j] < INFINITY:
                    g[j] = start_d[j]
                    pred[j] = -1
                    tx = vx[j] - gx
                    ty = vy[j] - gy
                    f = g[j] + sqrt(tx * tx + ty * ty)
                    if not _heap_push(&h, f, j):
                        ok = False
                        break
            while ok and h.size > 0:
                f = h.k[0]
                u = h.v[0]
                _heap_pop(&h)
                if f >= best:
                    break
                if closed[u]:
                    continue
                closed[u] = 1
                gu = g[u]
                if goal_d[u] < INFINITY and gu + goal_d[u] < best:
                    best = gu + goal_d[u]
                    last = u
                for e in range(indptr[u], indptr[u + 1]):
                    v = indices[e]
                    nd = gu + weights[e]
                    if nd < g[v]:
                        g[v] = nd
                        pred[v] = u
                        tx = vx[v] - gx
                        ty = vy[v] - gy
                        if not _heap_push(&h, nd + sqrt(tx * tx + ty * ty), v):
                            ok = False
                            break
        if not ok:
            raise MemoryError("astar: no memory for the heap")
    finally:
        free(h.k)
        free(h.v)
    return best, pred_arr, last


# ----------------------------------------------------------------------------------------------
# Lazy A*: the corners' visible neighbours computed when a corner is expanded (no per-map graph)
# ----------------------------------------------------------------------------------------------
def lazy_astar(blk_t B, tuple ext, f64c_1d vx, f64c_1d vy, f64c_1d qx, f64c_1d qy, i64c_1d bstart, i64c_1d bverts,
               int64_t nbx, int64_t nby, double bsize, double sx, double sy, f64c_1d start_d, f64c_1d goal_d,
               double gx, double gy):
    """A* over the convex corners from the point ``s`` to the point ``g`` without a graph.

    ``start_d[j]`` / ``goal_d[j]``: length of the segment start -> corner j / corner j -> goal (inf:
    not visible along a taut direction; :func:`visible_from_culled`). Expanding a corner ``u`` runs
    the nearest-first visibility search of :func:`_visible_set` from it, restricted to

    - taut directions at ``u`` (the quadrant rule of :func:`visibility_edges`) and at the corner seen;
    - the *taut turn* from ``u``'s parent ``p``: the path ``p -> u -> v`` must bend round ``u``'s
      blocked cell, ``cross(u - p, v - u)`` of the same sign as ``cross(u - p, c)`` (``c`` the
      direction of that cell from ``u``) or 0. Otherwise the wedge inside the turn is free near
      ``u`` and cutting it shortens the path strictly, so no shortest path (and no optimal ``g`` of
      ``v``) uses the turn; with ties any optimal parent's turn may be pruned for that reason;
    - corners not closed, that the edge would improve (``g[u] + |uv| < g[v]``) and whose ``f`` stays
      below the best goal length found.

    The heuristic is the straight-line distance to the goal (consistent), so the first time the
    popped ``f`` reaches the best goal length found, that length is optimal. Returns the length (inf:
    unreachable), the predecessor of every corner (-1: the start, -2: none), the corner from which
    the goal was entered (-1: none) and how many corners were expanded.
    """
    cdef int64_t R = B.shape[0], W = B.shape[1], n = vx.shape[0], j, u, v, k, t, pu, expanded = 0
    cdef Ext ex = _ext(ext, R, W)
    cdef double best = INFINITY, f, gu, nd, tx, ty, d1x, d1y, sgn
    cdef int64_t last = -1
    cdef bint ok = True
    g_arr = np.full(n, np.inf)
    pred_arr = np.full(n, -2, np.int64)
    closed_arr = np.zeros(n, np.uint8)
    if n == 0:
        return best, pred_arr, last, expanded
    cdef double[::1] g = g_arr
    cdef int64_t[::1] pred = pred_arr
    cdef uint8_t[::1] closed = closed_arr
    cdef Prune pr
    cdef Heap h
    h.size = 0
    h.cap = 1024
    h.k = <double*>malloc(h.cap * sizeof(double))
    h.v = <int64_t*>malloc(h.cap * sizeof(int64_t))
    cdef double* D = <double*>malloc(_NB * sizeof(double))
    cdef double* part = <double*>malloc(4 * _NB * sizeof(double))
    cdef int64_t* out_j = <int64_t*>malloc(n * sizeof(int64_t))
    cdef double* out_d = <double*>malloc(n * sizeof(double))
    pr.closed = &closed[0]
    pr.g = &g[0]
    pr.gx = gx
    pr.gy = gy
    try:
        if h.k == NULL or h.v == NULL or D == NULL or part == NULL or out_j == NULL or out_d == NULL:
            raise MemoryError("lazy_astar: no memory")
        with nogil:
            for j in range(n):
                if start_d[j] < INFINITY:
                    g[j] = start_d[j]
                    pred[j] = -1
                    tx = vx[j] - gx
                    ty = vy[j] - gy
                    if not _heap_push(&h, g[j] + sqrt(tx * tx + ty * ty), j):
                        ok = False
                        break
            while ok and h.size > 0:
                f = h.k[0]
                u = h.v[0]
                _heap_pop(&h)
                if f >= best:
                    break
                if closed[u]:
                    continue
                closed[u] = 1
                expanded += 1
                gu = g[u]
                if goal_d[u] < INFINITY and gu + goal_d[u] < best:
                    best = gu + goal_d[u]
                    last = u
                pu = pred[u]
                if pu >= 0:
                    d1x = vx[u] - vx[pu]
                    d1y = vy[u] - vy[pu]
                else:
                    d1x = vx[u] - sx
                    d1y = vy[u] - sy
                # the side of the turn that wraps round u's blocked cell (direction (qx, qy)); 0 when
                # u is the start itself (no parent direction: every taut direction)
                sgn = d1x * qy[u] - d1y * qx[u]
                if sgn > 0:
                    pr.hx = d1x
                    pr.hy = d1y
                elif sgn < 0:
                    pr.hx = -d1x
                    pr.hy = -d1y
                else:
                    pr.hx = 0.0
                    pr.hy = 0.0
                pr.gu = gu
                pr.best = best
                k = _visible_set(&B[0, 0], R, W, &ex, vx[u], vy[u], qx[u] * qy[u], &vx[0], &vy[0], &qx[0], &qy[0],
                                 &bstart[0], &bverts[0], nbx, nby, bsize, 0, D, _NB, part, out_j, out_d, &pr)
                for t in range(k):
                    v = out_j[t]
                    nd = gu + out_d[t]
                    if nd < g[v]:
                        g[v] = nd
                        pred[v] = u
                        tx = vx[v] - gx
                        ty = vy[v] - gy
                        if not _heap_push(&h, nd + sqrt(tx * tx + ty * ty), v):
                            ok = False
                            break
        if not ok:
            raise MemoryError("lazy_astar: no memory for the heap")
    finally:
        free(h.k)
        free(h.v)
        free(D)
        free(part)
        free(out_j)
        free(out_d)
    return best, pred_arr, last, expanded
