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


# ----------------------------------------------------------------------------------------
# Visibility from one point with occlusion culling (exact)
# ----------------------------------------------------------------------------------------
#: Angular bins of the occlusion table (over the pseudo-angle, see :func:`_pseudo_angle`).
N_BINS = 1024


@njit(**_OPTS)
def _pseudo_angle(dx, dy):
    """A number in [0, 4) increasing with the angle of ``(dx, dy)`` (the "diamond angle")."""
    if dy >= 0:
        if dx >= 0:
            return dy / (dx + dy)
        return 1.0 - dx / (-dx + dy)
    if dx < 0:
        return 2.0 - dy / (-dx - dy)
    return 3.0 + dx / (dx - dy)


@njit(**_OPTS)
def _walk_hit(B, px, py, qx, qy):
    """:func:`segment_free` that also says where it was blocked: -1 free, ``r * (cols + 2) + c``
    (padded indices) of the first blocked cell whose interior the segment enters, or -2 when it was
    stopped otherwise (a pinch point, or a segment along a grid line)."""
    dx = qx - px
    dy = qy - py
    if dx == 0.0 or dy == 0.0:
        return -1 if segment_free(B, px, py, qx, qy) else -2
    sx = 1 if dx > 0 else -1
    sy = 1 if dy > 0 else -1
    adx = abs(dx)
    ady = abs(dy)
    c = int(math.floor(px)) if dx > 0 else int(math.ceil(px)) - 1
    r = int(math.floor(py)) if dy > 0 else int(math.ceil(py)) - 1
    nx = float(c + 1) if dx > 0 else float(c)
    ny = float(r + 1) if dy > 0 else float(r)
    w = B.shape[1]
    while True:
        if B[r + 1, c + 1]:
            return (r + 1) * w + (c + 1)
        ax = (nx - px) * sx
        ay = (ny - py) * sy
        lhs = ax * ady
        rhs = ay * adx
        if lhs < rhs:
            if ax >= adx:
                return -1
            c += sx
            nx += sx
        elif rhs < lhs:
            if ay >= ady:
                return -1
            r += sy
            ny += sy
        else:
            if ax >= adx:
                return -1
            if B[r + 1, c + sx + 1] and B[r + sy + 1, c + 1]:
                return -3 - (int(ny) * w + int(nx))  # the pinch point (lattice nx, ny)
            c += sx
            r += sy
            nx += sx
            ny += sy


@njit(**_OPTS)
def run_extents(B):
    """For every blocked cell of the padded array: the first and last padded column of its maximal
    horizontal run of blocked cells, and the first and last padded row of its vertical run."""
    R, C = B.shape
    hl = np.zeros((R, C), np.int32)
    hr = np.zeros((R, C), np.int32)
    vl = np.zeros((R, C), np.int32)
    vr = np.zeros((R, C), np.int32)
    for r in range(R):
        c = 0
        while c < C:
            if B[r, c]:
                e = c
                while e + 1 < C and B[r, e + 1]:
                    e += 1
                for t in range(c, e + 1):
                    hl[r, t] = c
                    hr[r, t] = e
                c = e + 1
            else:
                c += 1
    for c in range(C):
        r = 0
        while r < R:
            if B[r, c]:
                e = r
                while e + 1 < R and B[e + 1, c]:
                    e += 1
                for t in range(r, e + 1):
                    vl[t, c] = r
                    vr[t, c] = e
                r = e + 1
            else:
                r += 1
    return hl, hr, vl, vr


@njit(**_OPTS)
def _occlude_poly(D, part, px, py, xs, ys, npts):
    """Record a convex blocked polygon (corners ``xs, ys[:npts]``, ``p`` outside it) as seen from
    ``p``: every angular bin strictly inside its angular extent is blocked beyond its farthest
    corner (any ray strictly inside the extent enters it). Returns how many bins were ``inf``.

    An end of the extent on an axis direction (a corner level with ``p``) is exact, and the bin
    beside it counts (candidates exactly on an axis never use the bins); elsewhere a margin keeps
    the bins clear of the rounding of the pseudo-angles. ``part[b]`` = (covered from the start up to
    this fraction, beyond this squared distance; covered from this fraction to the end, beyond this).
    """
    mx = 0.0
    my = 0.0
    for k in range(npts):
        mx += xs[k]
        my += ys[k]
    ac = _pseudo_angle(mx / npts - px, my / npts - py)
    lo = 10.0
    hi = -10.0
    lo_abs = 0.0
    hi_abs = 0.0
    lo_axis = False
    hi_axis = False
    far = 0.0
    for k in range(npts):
        ex = xs[k] - px
        ey = ys[k] - py
        if ex == 0.0 and ey == 0.0:
            return 0
        a = _pseudo_angle(ex, ey)
        rel = a - ac
        wrap = 0.0
        if rel >= 2.0:
            rel -= 4.0
            wrap = -4.0
        elif rel < -2.0:
            rel += 4.0
            wrap = 4.0
        axis = ex == 0.0 or ey == 0.0
        if rel < lo:
            lo = rel
            lo_abs = a + wrap
            lo_axis = axis
        if rel > hi:
            hi = rel
            hi_abs = a + wrap
            hi_axis = axis
        far = max(far, ex * ex + ey * ey)
    nb = D.size
    scale = nb / 4.0
    b0 = int(math.floor(lo_abs * scale + 0.5)) if lo_axis else int(math.floor(lo_abs * scale + 1e-6)) + 1
    b1 = int(math.floor(hi_abs * scale + 0.5)) - 1 if hi_axis else int(math.ceil(hi_abs * scale - 1e-6)) - 2
    newly = 0
    for b in range(b0, b1 + 1):
        bb = b % nb
        if far < D[bb]:
            if D[bb] == np.inf:
                newly += 1
            D[bb] = far
    # the bins at the two ends, covered in part: a bin covered from its start by one occluder and to
    # its end by another, the two overlapping, is covered (beyond the farther of the two)
    lo_b = lo_abs * scale + (0.0 if lo_axis else 1e-6)
    hi_b = hi_abs * scale - (0.0 if hi_axis else 1e-6)
    bl = int(math.floor(lo_b))
    bh = int(math.floor(hi_b))
    if bh > bl:
        bb = bl % nb
        fr = lo_b - bl
        if fr < part[bb, 2] or (fr == part[bb, 2] and far < part[bb, 3]):
            part[bb, 2] = fr
            part[bb, 3] = far
        bb = bh % nb
        fr = hi_b - bh
        if fr > part[bb, 0] or (fr == part[bb, 0] and far < part[bb, 1]):
            part[bb, 0] = fr
            part[bb, 1] = far
        for bb in (bl % nb, bh % nb):
            if part[bb, 0] > part[bb, 2]:
                both = max(part[bb, 1], part[bb, 3])
                if both < D[bb]:
                    if D[bb] == np.inf:
                        newly += 1
                    D[bb] = both
    return newly


@njit(**_OPTS)
def _occlude_hit(D, part, px, py, B, hit, ext, xs, ys):
    """Occluders learnt from a failed walk: the maximal horizontal and vertical runs through the
    blocked cell it entered (``hit >= 0``), or the convex hull of the two cells of the pinch point it
    was stopped at (``hit <= -3``). Shapes ``p`` lies on or in are left out."""
    w = B.shape[1]
    newly = 0
    if hit >= 0:
        hl, hr, vl, vr = ext
        r = hit // w
        c = hit % w
        for t in range(2):
            if t == 0:  # padded cell (r, c) -> lattice square [c - 1, c] x [r - 1, r]
                x0, x1, y0, y1 = hl[r, c] - 1.0, hr[r, c] + 0.0, r - 1.0, r + 0.0
            else:
                x0, x1, y0, y1 = c - 1.0, c + 0.0, vl[r, c] - 1.0, vr[r, c] + 0.0
            if x0 <= px <= x1 and y0 <= py <= y1:
                continue
            xs[0], ys[0] = x0, y0
            xs[1], ys[1] = x1, y0
            xs[2], ys[2] = x1, y1
            xs[3], ys[3] = x0, y1
            newly += _occlude_poly(D, part, px, py, xs, ys, 4)
        return newly
    if hit <= -3:
        code = -3 - hit
        yq = code // w
        xq = code % w
        if xq - 1.0 <= px <= xq + 1.0 and yq - 1.0 <= py <= yq + 1.0:
            return 0
        if B[yq, xq] and B[yq + 1, xq + 1]:  # south-west and north-east cells
            xs[0], ys[0] = xq - 1.0, yq - 1.0
            xs[1], ys[1] = xq + 0.0, yq - 1.0
            xs[2], ys[2] = xq + 1.0, yq + 0.0
            xs[3], ys[3] = xq + 1.0, yq + 1.0
            xs[4], ys[4] = xq + 0.0, yq + 1.0
            xs[5], ys[5] = xq - 1.0, yq + 0.0
        else:  # north-west and south-east
            xs[0], ys[0] = xq - 1.0, yq + 1.0
            xs[1], ys[1] = xq - 1.0, yq + 0.0
            xs[2], ys[2] = xq + 0.0, yq - 1.0
            xs[3], ys[3] = xq + 1.0, yq - 1.0
            xs[4], ys[4] = xq + 1.0, yq + 0.0
            xs[5], ys[5] = xq + 0.0, yq + 1.0
        return _occlude_poly(D, part, px, py, xs, ys, 6)
    return 0


@njit(**_OPTS)
def _axis_run(B, px, py, s, horizontal):
    """How far a segment from ``p`` along a grid line (``y = py`` if ``horizontal`` else ``x = px``,
    an integer) in direction ``s`` (+-1) stays free, measured to the farthest lattice point it reaches
    (-1: none). The rule of :func:`_axis_free`, tested piece by piece."""
    rows = B.shape[0] - 2
    cols = B.shape[1] - 2
    u = px if horizontal else py
    m = int(py) if horizontal else int(px)
    top = cols if horizontal else rows
    k = int(math.floor(u)) + 1 if s > 0 else int(math.ceil(u)) - 1
    run = -1.0
    first = True
    while 0 <= k <= top:
        c = k - 1 if s > 0 else k  # the cell column (row) of the piece ending at k
        if horizontal:
            if B[m, c + 1] and B[m + 1, c + 1]:
                break
        elif B[c + 1, m] and B[c + 1, m + 1]:
            break
        if not first:  # the lattice point k - s is now inside the segment: no pinch there
            x = k - s
            if horizontal:
                la, ra, lb, rb = B[m + 1, x], B[m + 1, x + 1], B[m, x], B[m, x + 1]
            else:
                la, ra, lb, rb = B[x, m + 1], B[x + 1, m + 1], B[x, m], B[x + 1, m]
            if not ((la == 0 and ra == 0) or (lb == 0 and rb == 0)):
                break
        run = abs(k - u)
        first = False
        k += s
    return run


@njit(**_OPTS)
def _block_hidden(D, px, py, x0, y0, size, scale):
    """Whether every corner in the block ``[x0, x0 + size] x [y0, y0 + size]`` is hidden: every bin
    its angular extent touches is blocked nearer than the block. Blocks level with ``p`` (corners on
    an axis through it use the axis runs, not the bins) are never hidden."""
    x1 = x0 + size
    y1 = y0 + size
    if x0 <= px <= x1 or y0 <= py <= y1:
        return False
    ddx = max(x0 - px, 0.0, px - x1)
    ddy = max(y0 - py, 0.0, py - y1)
    dmin2 = ddx * ddx + ddy * ddy
    ac = _pseudo_angle(0.5 * (x0 + x1) - px, 0.5 * (y0 + y1) - py)
    lo = 10.0
    hi = -10.0
    for k in range(4):
        rel = _pseudo_angle((x0 if k & 1 == 0 else x1) - px, (y0 if k < 2 else y1) - py) - ac
        if rel >= 2.0:
            rel -= 4.0
        elif rel < -2.0:
            rel += 4.0
        lo = min(lo, rel)
        hi = max(hi, rel)
    nb = D.size
    b0 = int(math.floor((ac + lo) * scale)) - 1  # every bin touched, with one to spare on each side
    b1 = int(math.floor((ac + hi) * scale)) + 1
    hidden = True
    for b in range(b0, b1 + 1):
        if D[b % nb] >= dmin2:
            hidden = False
            break
    return hidden


@njit(**_OPTS)
def _visible_set(B, ext, px, py, self_q, vx, vy, qx, qy, bstart, bverts, nbx, nby, bsize, jmin, D, out_j, out_d):
    """Corners seen from ``p`` along taut directions, nearest blocks first, with occlusion culling.

    ``self_q`` is ``qx * qy`` of the corner at ``p`` (0 for a free point: every direction). Corners
    are bucketed in square blocks of ``bsize`` lattice units (``bstart``/``bverts``: CSR over the
    ``nbx * nby`` blocks). A walk that fails records what stopped it (:func:`_occlude_hit`; ``ext``
    from :func:`run_extents`) in the occlusion table ``D`` (squared distance beyond which each angular
    bin is blocked); a corner whose bin is blocked before it is skipped without a walk (its segment
    would enter a blocked cell or pass the pinch point), as is a whole block of corners hidden that
    way (:func:`_block_hidden`); and the
    search stops when every bin is blocked nearer than the next ring of blocks. Only corners
    ``j >= jmin`` are reported; with ``jmin > 0`` the corners must be numbered row by row (lattice
    ``y`` then ``x``) and ``p`` be corner ``jmin - 1``, so that directions pointing down hold none. Returns how many were written to ``out_j``/``out_d``.
    """
    nb = D.size
    scale = nb / 4.0
    for b in range(nb):
        D[b] = np.inf
    # (bins hold only candidates off the axes: those on an axis through p use the axis runs)
    if self_q != 0.0:  # the quadrants a taut edge cannot take
        for quad in range(4):
            sgn = 1.0 if quad % 2 == 0 else -1.0  # quadrants 0 and 2: dx * dy > 0
            if sgn * self_q > 0:
                for b in range(quad * nb // 4, (quad + 1) * nb // 4):
                    D[b] = -1.0
    if jmin > 0:  # corners j >= jmin lie higher or to the right on the same row (numbered row by row)
        for b in range(nb // 2, nb):
            D[b] = -1.0
    # free runs along the grid lines through p: right, up, left, down (-1: no lattice point on it)
    runs = np.full(4, -1.0)
    if py == math.floor(py):
        runs[0] = _axis_run(B, px, py, 1, True)
        if jmin == 0:
            runs[2] = _axis_run(B, px, py, -1, True)
    if px == math.floor(px):
        runs[1] = _axis_run(B, px, py, 1, False)
        if jmin == 0:
            runs[3] = _axis_run(B, px, py, -1, False)
    n_inf = 0
    for b in range(nb):
        if D[b] == np.inf:
            n_inf += 1
    bx = min(int(px // bsize), nbx - 1)
    by = min(int(py // bsize), nby - 1)
    rmax = max(bx, nbx - 1 - bx, by, nby - 1 - by)
    xs = np.empty(6)
    ys = np.empty(6)
    part = np.empty((nb, 4))
    for b in range(nb):
        part[b, 0] = -1.0
        part[b, 1] = np.inf
        part[b, 2] = 2.0
        part[b, 3] = np.inf
    m = 0
    for ring in range(rmax + 1):
        if ring >= 2 and n_inf == 0:
            near = (ring - 1) * bsize
            near2 = near * near
            worst = -1.0
            for b in range(nb):
                if D[b] > worst:
                    worst = D[b]
            for t in range(4):
                if runs[t] * runs[t] > worst and runs[t] >= 0:
                    worst = runs[t] * runs[t]
            if worst < near2:
                break
        for yy in range(by - ring, by + ring + 1):
            if yy < 0 or yy >= nby:
                continue
            step = 1 if (yy == by - ring or yy == by + ring) else 2 * ring
            if step == 0:
                step = 1
            xx = bx - ring
            while xx <= bx + ring:
                if 0 <= xx < nbx and bstart[yy * nbx + xx] < bstart[yy * nbx + xx + 1] and (
                        ring < 2 or not _block_hidden(D, px, py, xx * bsize, yy * bsize, bsize, scale)):
                    blk = yy * nbx + xx
                    for e in range(bstart[blk], bstart[blk + 1]):
                        j = bverts[e]
                        if j < jmin:
                            continue
                        dx = vx[j] - px
                        dy = vy[j] - py
                        if dx == 0.0 and dy == 0.0:
                            if jmin == 0:  # p is this corner
                                out_j[m] = j
                                out_d[m] = 0.0
                                m += 1
                            continue
                        p = dx * dy
                        if p * self_q > 0 or p * (qx[j] * qy[j]) > 0:
                            continue
                        d2 = dx * dx + dy * dy
                        if dx == 0.0 or dy == 0.0:  # on an axis through p: its free run decides
                            t = (0 if dx > 0 else 2) if dy == 0.0 else (1 if dy > 0 else 3)
                            if runs[t] >= 0 and d2 <= runs[t] * runs[t]:
                                out_j[m] = j
                                out_d[m] = math.sqrt(d2)
                                m += 1
                            continue
                        b = int(_pseudo_angle(dx, dy) * scale)
                        if b >= nb:
                            b = nb - 1
                        if d2 > D[b]:
                            continue
                        hit = _walk_hit(B, px, py, vx[j], vy[j])
                        if hit == -1:
                            out_j[m] = j
                            out_d[m] = math.sqrt(d2)
                            m += 1
                        else:
                            n_inf -= _occlude_hit(D, part, px, py, B, hit, ext, xs, ys)
                xx += step
    return m


@njit(**_OPTS)
def visibility_edges_culled(B, vx, vy, qx, qy, bstart, bverts, nbx, nby, bsize):
    """:func:`visibility_edges` with :func:`_visible_set` per corner (the same pairs, fewer walks)."""
    ext = run_extents(B)
    n = vx.size
    D = np.empty(N_BINS)
    out_j = np.empty(n, np.int64)
    out_d = np.empty(n)
    cap = 1 << 16
    ei = np.empty(cap, np.int32)
    ej = np.empty(cap, np.int32)
    m = 0
    for i in range(n):
        k = _visible_set(B, ext, vx[i], vy[i], qx[i] * qy[i], vx, vy, qx, qy, bstart, bverts, nbx, nby, bsize,
                         i + 1, D, out_j, out_d)
        if m + k > cap:
            while m + k > cap:
                cap *= 2
            e2 = np.empty(cap, np.int32)
            e2[:m] = ei[:m]
            ei = e2
            e2 = np.empty(cap, np.int32)
            e2[:m] = ej[:m]
            ej = e2
        for t in range(k):
            ei[m] = i
            ej[m] = out_j[t]
            m += 1
    return ei[:m].copy(), ej[:m].copy()


@njit(**_OPTS)
def visible_from_culled(B, ext, px, py, vx, vy, qx, qy, bstart, bverts, nbx, nby, bsize):
    """:func:`visible_from` through :func:`_visible_set` (the same distances, fewer walks); ``ext``
    from :func:`run_extents`."""
    n = vx.size
    D = np.empty(N_BINS)
    out_j = np.empty(n, np.int64)
    out_d = np.empty(n)
    k = _visible_set(B, ext, px, py, 0.0, vx, vy, qx, qy, bstart, bverts, nbx, nby, bsize, 0, D, out_j, out_d)
    res = np.empty(n)
    res[:] = np.inf
    for t in range(k):
        res[out_j[t]] = out_d[t]
    return res
