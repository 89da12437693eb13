# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.exact.anyangle` (private; imported on first use): the segment
walk and the exhaustive visibility of the convex corners. The nearest-first visibility with occlusion
culling is :mod:`gridfield.exact._occlusion`, the A* searches over the corners (on the graph, and lazy)
:mod:`gridfield.exact._astar`; they cimport the walk and the edge list from here (``_anyangle.pxd``).

Everything here works in *lattice units* of a grid: cell ``(r, c)`` is the closed square
``[c, c + 1] x [r, r + 1]`` (row 0 = lowest y), its corners are the integer points. The blocked
cells come as a uint8 array ``B`` of shape ``(rows + 2, cols + 2)`` padded with one ring (1 for a
wall border, 0 for an open one), so cell ``(r, c)`` is ``B[r + 1, c + 1]``: every cell a segment
between points of ``[0, cols] x [0, rows]`` can touch lies in the padded array. Nothing in this
module validates input; :mod:`gridfield.exact.anyangle` does.

Free segments (the rule :func:`segment_free` implements exactly for lattice and half-integer end
points, whose cross products are exact in double precision): the segment may not meet the interior
of a blocked cell, may run along a cell edge only if a cell on one side of it is free, and may not
pass through a *pinch point* -- a corner whose two diagonally opposite cells are blocked while it
goes from one free cell to the diagonally opposite free cell (the zero-width gap of the Moving AI
no-corner-cutting rule).

Cython, compiled at install; every kernel releases the GIL while it runs. The C helpers take raw
pointers: ``B`` is C-contiguous, indexed ``B[r * W + c]`` with ``W = cols + 2``, and every index is
one of a padded cell the segment touches (bounds checks off). Integer ``//`` and ``%`` appear on
non-negative operands only. The edge lists grow by doubling a C buffer.
"""

from libc.math cimport INFINITY, ceil, floor, sqrt
from libc.stdlib cimport free, malloc, realloc
from libc.string cimport memcpy

import numpy as np

__all__ = ["segment_free", "visibility_edges", "visible_from"]


cdef bint _axis_free(const uint8_t* B, int64_t W, double y, double xa, double xb, bint horizontal) noexcept nogil:
    """A segment on the line ``y = const`` (``horizontal``) or ``x = const`` from ``xa`` to ``xb > xa``."""
    cdef int64_t c0 = <int64_t>floor(xa), c1 = <int64_t>ceil(xb) - 1, m, c, k, r
    cdef uint8_t la, ra, lb, rb
    if y == floor(y):  # along a grid line: a free cell on one side, no pinch at inner corners
        m = <int64_t>y
        for c in range(c0, c1 + 1):
            if horizontal:
                if B[m * W + c + 1] and B[(m + 1) * W + c + 1]:
                    return False
            elif B[(c + 1) * W + m] and B[(c + 1) * W + m + 1]:
                return False
        for k in range(c0 + 1, c1 + 1):
            if horizontal:
                la = B[(m + 1) * W + k]
                ra = B[(m + 1) * W + k + 1]
                lb = B[m * W + k]
                rb = B[m * W + k + 1]
            else:
                la = B[k * W + m + 1]
                ra = B[(k + 1) * W + m + 1]
                lb = B[k * W + m]
                rb = B[(k + 1) * W + m]
            if not ((la == 0 and ra == 0) or (lb == 0 and rb == 0)):
                return False
        return True
    r = <int64_t>floor(y)
    for c in range(c0, c1 + 1):
        if horizontal:
            if B[(r + 1) * W + c + 1]:
                return False
        elif B[(c + 1) * W + r + 1]:
            return False
    return True


cdef bint _segment_free(const uint8_t* B, int64_t W, double px, double py, double qx, double qy) noexcept nogil:
    cdef double dx = qx - px, dy = qy - py, adx, ady, nx, ny, ax, ay, lhs, rhs
    cdef int64_t sx, sy, c, r
    if dx == 0.0 and dy == 0.0:
        return True
    if dy == 0.0:
        return _axis_free(B, W, py, _dmin(px, qx), _dmax(px, qx), True)
    if dx == 0.0:
        return _axis_free(B, W, px, _dmin(py, qy), _dmax(py, qy), False)
    sx = 1 if dx > 0 else -1
    sy = 1 if dy > 0 else -1
    adx = -dx if dx < 0 else dx
    ady = -dy if dy < 0 else dy
    c = <int64_t>floor(px) if dx > 0 else <int64_t>ceil(px) - 1
    r = <int64_t>floor(py) if dy > 0 else <int64_t>ceil(py) - 1
    nx = <double>(c + 1) if dx > 0 else <double>c
    ny = <double>(r + 1) if dy > 0 else <double>r
    while True:
        if B[(r + 1) * W + c + 1]:
            return False
        ax = (nx - px) * sx
        ay = (ny - py) * sy
        lhs = ax * ady  # t_x * |dx| * |dy|
        rhs = ay * adx  # t_y * |dx| * |dy|
        if lhs < rhs:
            if ax >= adx:
                return True
            c += sx
            nx += sx
        elif rhs < lhs:
            if ay >= ady:
                return True
            r += sy
            ny += sy
        else:
            if ax >= adx:
                return True
            if B[(r + 1) * W + c + sx + 1] and B[(r + sy + 1) * W + c + 1]:
                return False  # through a pinch point
            c += sx
            r += sy
            nx += sx
            ny += sy


def segment_free(blk_t B, double px, double py, double qx, double qy):
    """Whether the closed segment ``p -> q`` lies in the free space (module docstring).

    A grid walk (Amanatides & Woo) over the cells whose interior the segment meets; which grid line
    it crosses next is decided by comparing cross products, so a crossing exactly through a corner is
    recognised as one and checked for a pinch.
    """
    cdef bint ok
    with nogil:
        ok = _segment_free(&B[0, 0], B.shape[1], px, py, qx, qy)
    return ok


# ----------------------------------------------------------------------------------------------
# growable edge list
# ----------------------------------------------------------------------------------------------
# Edges is declared in _anyangle.pxd (shared with _occlusion)
cdef bint _edges_init(Edges* e) noexcept nogil:
    e.m = 0
    e.cap = 1 << 16
    e.ei = <int32_t*>malloc(e.cap * sizeof(int32_t))
    e.ej = <int32_t*>malloc(e.cap * sizeof(int32_t))
    return e.ei != NULL and e.ej != NULL


cdef bint _edges_reserve(Edges* e, int64_t need) noexcept nogil:
    """Room for ``need`` edges in all (the capacity doubles)."""
    cdef int64_t cap = e.cap
    cdef int32_t* p
    if need <= cap:
        return True
    while need > cap:
        cap *= 2
    p = <int32_t*>realloc(e.ei, cap * sizeof(int32_t))
    if p == NULL:
        return False
    e.ei = p
    p = <int32_t*>realloc(e.ej, cap * sizeof(int32_t))
    if p == NULL:
        return False
    e.ej = p
    e.cap = cap
    return True


cdef object _edges_out(Edges* e):
    """The edges as two int32 arrays; frees the buffers."""
    ei = np.empty(e.m, np.int32)
    ej = np.empty(e.m, np.int32)
    cdef int32_t[::1] oi = ei, oj = ej
    if e.m:
        memcpy(&oi[0], e.ei, e.m * sizeof(int32_t))
        memcpy(&oj[0], e.ej, e.m * sizeof(int32_t))
    free(e.ei)
    free(e.ej)
    e.ei = NULL
    e.ej = NULL
    return ei, ej


def visibility_edges(blk_t B, f64c_1d vx, f64c_1d vy, f64c_1d qx, f64c_1d qy):
    """Taut visible pairs ``i < j`` of the convex corners ``(vx, vy)``.

    ``(qx, qy)`` is the quadrant of each corner's one blocked cell (-1 or +1 per axis). A shortest
    path bending at a corner wraps round its blocked cell, so it leaves and enters it only along
    directions ``(dx, dy)`` with ``dx * dy * qx * qy <= 0`` (both edges of the cell on one side of
    the line); pairs failing that test at either end are never walked.
    """
    cdef int64_t n = vx.shape[0], i, j, W = B.shape[1]
    cdef double xi, yi, si, dx, dy, p
    cdef Edges e
    cdef bint ok
    cdef const uint8_t* b = &B[0, 0]
    if not _edges_init(&e):
        free(e.ei)
        free(e.ej)
        raise MemoryError("visibility_edges: no memory for the edge list")
    with nogil:
        ok = True
        for i in range(n):
            xi = vx[i]
            yi = vy[i]
            si = qx[i] * qy[i]
            for j in range(i + 1, n):
                dx = vx[j] - xi
                dy = vy[j] - yi
                p = dx * dy
                if p * si > 0 or p * (qx[j] * qy[j]) > 0:
                    continue
                if not _segment_free(b, W, xi, yi, vx[j], vy[j]):
                    continue
                if not _edges_reserve(&e, e.m + 1):
                    ok = False
                    break
                e.ei[e.m] = <int32_t>i
                e.ej[e.m] = <int32_t>j
                e.m += 1
            if not ok:
                break
    out = _edges_out(&e)
    if not ok:
        raise MemoryError("visibility_edges: no memory for the edge list")
    return out


def visible_from(blk_t B, double px, double py, f64c_1d vx, f64c_1d vy, f64c_1d qx, f64c_1d qy):
    """Distances from the point ``p`` to every corner it sees along a taut direction (``inf`` elsewhere)."""
    cdef int64_t n = vx.shape[0], j, W = B.shape[1]
    cdef double dx, dy
    out = np.empty(n)
    cdef double[::1] o = out
    cdef const uint8_t* b = &B[0, 0]
    with nogil:
        for j in range(n):
            dx = vx[j] - px
            dy = vy[j] - py
            if dx * dy * (qx[j] * qy[j]) > 0 or not _segment_free(b, W, px, py, vx[j], vy[j]):
                o[j] = INFINITY
            else:
                o[j] = sqrt(dx * dx + dy * dy)
    return out
