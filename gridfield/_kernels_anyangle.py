"""Compiled kernels behind :mod:`gridfield.anyangle` (numba, imported lazily).

Everything here works in *lattice units* of a grid: cell ``(r, c)`` is the closed square
``[c, c + 1] x [r, r + 1]`` (row 0 = lowest y), its corners are the integer points. The blocked
cells come as a uint8 array ``B`` of shape ``(rows + 2, cols + 2)`` padded with one ring (1 for a
wall border, 0 for an open one), so cell ``(r, c)`` is ``B[r + 1, c + 1]``: every cell a segment
between points of ``[0, cols] x [0, rows]`` can touch lies in the padded array. Nothing in this
module validates input; :mod:`gridfield.anyangle` does.

Free segments (the rule :func:`segment_free` implements exactly for lattice and half-integer end
points, whose cross products are exact in double precision): the segment may not meet the interior
of a blocked cell, may run along a cell edge only if a cell on one side of it is free, and may not
pass through a *pinch point* -- a corner whose two diagonally opposite cells are blocked while it
goes from one free cell to the diagonally opposite free cell (the zero-width gap of the Moving AI
no-corner-cutting rule).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy", "boundscheck": False}


@njit(**_OPTS)
def _axis_free(B, y, xa, xb, horizontal):
    """A segment on the line ``y = const`` (``horizontal``) or ``x = const`` from ``xa`` to ``xb > xa``."""
    c0 = math.floor(xa)
    c1 = math.ceil(xb) - 1
    if y == math.floor(y):  # along a grid line: a free cell on one side, no pinch at inner corners
        m = int(y)
        for c in range(c0, c1 + 1):
            if horizontal:
                if B[m, c + 1] and B[m + 1, c + 1]:
                    return False
            elif B[c + 1, m] and B[c + 1, m + 1]:
                return False
        for k in range(c0 + 1, c1 + 1):
            if horizontal:
                la, ra, lb, rb = B[m + 1, k], B[m + 1, k + 1], B[m, k], B[m, k + 1]
            else:
                la, ra, lb, rb = B[k, m + 1], B[k + 1, m + 1], B[k, m], B[k + 1, m]
            if not ((la == 0 and ra == 0) or (lb == 0 and rb == 0)):
                return False
        return True
    r = int(math.floor(y))
    for c in range(c0, c1 + 1):
        if horizontal:
            if B[r + 1, c + 1]:
                return False
        elif B[c + 1, r + 1]:
            return False
    return True


@njit(**_OPTS)
def segment_free(B, px, py, qx, qy):
    """Whether the closed segment ``p -> q`` lies in the free space (module docstring).

    A grid walk (Amanatides & Woo) over the cells whose interior the segment meets; which grid line
    it crosses next is decided by comparing cross products, so a crossing exactly through a corner is
    recognised as one and checked for a pinch.
    """
    dx = qx - px
    dy = qy - py
    if dx == 0.0 and dy == 0.0:
        return True
    if dy == 0.0:
        return _axis_free(B, py, min(px, qx), max(px, qx), True)
    if dx == 0.0:
        return _axis_free(B, px, min(py, qy), max(py, qy), False)
    sx = 1 if dx > 0 else -1
    sy = 1 if dy > 0 else -1
    adx = abs(dx)
    ady = abs(dy)
    c = int(math.floor(px)) if dx > 0 else int(math.ceil(px)) - 1
    r = int(math.floor(py)) if dy > 0 else int(math.ceil(py)) - 1
    nx = float(c + 1) if dx > 0 else float(c)
    ny = float(r + 1) if dy > 0 else float(r)
    while True:
        if B[r + 1, c + 1]:
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
            if B[r + 1, c + sx + 1] and B[r + sy + 1, c + 1]:
                return False  # through a pinch point
            c += sx
            r += sy
            nx += sx
            ny += sy


@njit(**_OPTS)
def visibility_edges(B, vx, vy, qx, qy):
    """Taut visible pairs ``i < j`` of the convex corners ``(vx, vy)``.

    ``(qx, qy)`` is the quadrant of each corner's one blocked cell (-1 or +1 per axis). A shortest
    path bending at a corner wraps round its blocked cell, so it leaves and enters it only along
    directions ``(dx, dy)`` with ``dx * dy * qx * qy <= 0`` (both edges of the cell on one side of
    the line); pairs failing that test at either end are never walked.
    """
    n = vx.size
    cap = 1 << 16
    ei = np.empty(cap, np.int32)
    ej = np.empty(cap, np.int32)
    m = 0
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
            if not segment_free(B, xi, yi, vx[j], vy[j]):
                continue
            if m == cap:
                cap *= 2
                e2 = np.empty(cap, np.int32)
                e2[:m] = ei[:m]
                ei = e2
                e2 = np.empty(cap, np.int32)
                e2[:m] = ej[:m]
                ej = e2
            ei[m] = i
            ej[m] = j
            m += 1
    return ei[:m].copy(), ej[:m].copy()


@njit(**_OPTS)
def visible_from(B, px, py, vx, vy, qx, qy):
    """Distances from the point ``p`` to every corner it sees along a taut direction (``inf`` elsewhere)."""
    n = vx.size
    out = np.empty(n)
    for j in range(n):
        dx = vx[j] - px
        dy = vy[j] - py
        if dx * dy * (qx[j] * qy[j]) > 0 or not segment_free(B, px, py, vx[j], vy[j]):
            out[j] = np.inf
        else:
            out[j] = math.sqrt(dx * dx + dy * dy)
    return out


@njit(**_OPTS)
def astar(indptr, indices, weights, vx, vy, start_d, goal_d, gx, gy):
    """A* over the corner graph from a virtual start to a virtual goal.

    ``start_d[j]`` / ``goal_d[j]``: length of the start -> corner j / corner j -> goal edge (inf: none).
    The heuristic is the straight-line distance to the goal (consistent). Returns the total length
    (inf if unreachable), the predecessor of every corner (-1: the start) and the corner from which
    the goal was entered (-1: none).
    """
    n = vx.size
    g = np.empty(n)
    g[:] = np.inf
    pred = np.full(n, -2, np.int64)
    closed = np.zeros(n, np.uint8)
    cap = 1024
    hk = np.empty(cap)
    hv = np.empty(cap, np.int64)
    size = 0
    best = np.inf
    last = -1
    for j in range(n):
        if start_d[j] < np.inf:
            g[j] = start_d[j]
            pred[j] = -1
            f = g[j] + math.sqrt((vx[j] - gx) ** 2 + (vy[j] - gy) ** 2)
            if size == cap:
                cap *= 2
                hk2 = np.empty(cap)
                hk2[:size] = hk[:size]
                hk = hk2
                hv2 = np.empty(cap, np.int64)
                hv2[:size] = hv[:size]
                hv = hv2
            # sift up
            k = size
            size += 1
            while k > 0:
                par = (k - 1) >> 1
                if hk[par] <= f:
                    break
                hk[k] = hk[par]
                hv[k] = hv[par]
                k = par
            hk[k] = f
            hv[k] = j
    while size > 0:
        f = hk[0]
        u = hv[0]
        size -= 1
        if size > 0:  # sift the last entry down from the root
            lk = hk[size]
            lv = hv[size]
            k = 0
            while True:
                ch = 2 * k + 1
                if ch >= size:
                    break
                if ch + 1 < size and hk[ch + 1] < hk[ch]:
                    ch += 1
                if hk[ch] >= lk:
                    break
                hk[k] = hk[ch]
                hv[k] = hv[ch]
                k = ch
            hk[k] = lk
            hv[k] = lv
        if f >= best:
            break
        if closed[u]:
            continue
        closed[u] = 1
        gu = g[u]
        if goal_d[u] < np.inf and gu + goal_d[u] < best:
            best = gu + goal_d[u]
            last = u
        for e in range(indptr[u], indptr[u + 1]):
            v = indices[e]
            nd = gu + weights[e]
            if nd < g[v]:
                g[v] = nd
                pred[v] = u
                fv = nd + math.sqrt((vx[v] - gx) ** 2 + (vy[v] - gy) ** 2)
                if size == cap:
                    cap *= 2
                    hk2 = np.empty(cap)
                    hk2[:size] = hk[:size]
                    hk = hk2
                    hv2 = np.empty(cap, np.int64)
                    hv2[:size] = hv[:size]
                    hv = hv2
                k = size
                size += 1
                while k > 0:
                    par = (k - 1) >> 1
                    if hk[par] <= fv:
                        break
                    hk[k] = hk[par]
                    hv[k] = hv[par]
                    k = par
                hk[k] = fv
                hv[k] = v
    return best, pred, last
