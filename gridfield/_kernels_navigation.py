"""Compiled kernels behind :mod:`gridfield.navigation` (numba, imported lazily).

Everything here works in *cell units* on plain arrays indexed ``[row, col]`` (row 0 = lowest y):
a step between orthogonal neighbours has length 1, a diagonal step ``diag`` (``sqrt(2)`` for octile
costs, 1 for unit costs). Grids are copied once into a flat array padded with a ring of blocked
cells, so that the inner loops need no bounds checks. Nothing in this module validates input; the
public functions in :mod:`gridfield.navigation` do.

Move rule (Moving AI, no corner cutting): a diagonal step ``(dr, dc)`` from ``(r, c)`` is allowed only
when both ``(r + dr, c)`` and ``(r, c + dc)`` are free. The rule is symmetric, so the graph is
undirected and a wavefront from the goal gives the distance *to* the goal.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy", "boundscheck": False}


@njit(**_OPTS)
def _pad_free(free):
    """Flat uint8 copy of ``free`` with a blocked ring; returns it and the padded width."""
    rows, cols = free.shape
    w = cols + 2
    f = np.zeros((rows + 2) * w, np.uint8)
    for r in range(rows):
        base = (r + 1) * w + 1
        for c in range(cols):
            if free[r, c]:
                f[base + c] = 1
    return f, w


@njit(**_OPTS)
def _unpad(a, rows, cols, scale):
    w = cols + 2
    out = np.empty((rows, cols))
    for r in range(rows):
        base = (r + 1) * w + 1
        for c in range(cols):
            out[r, c] = a[base + c] * scale
    return out


@njit(**_OPTS)
def wavefront_uniform(free, goal_r, goal_c, connectivity, diag, stop_r, stop_c, scale):
    """Exact shortest-path distance to the goal cell with orthogonal steps 1 and diagonal steps ``diag``.

    Dijkstra with a bucket queue keyed by ``floor(distance)`` (Dial's algorithm with the bucket width
    equal to the shortest edge, 1). Every relaxation from bucket ``k`` lands in bucket ``k + 1`` or
    ``k + 2`` (``diag < 2``), so all cells of bucket ``k`` are final when it is reached and may be
    settled in any order: three rotating buckets replace the heap. ``diag`` must lie in ``[1, 2)``.

    ``stop_r >= 0`` ends the search once cell ``(stop_r, stop_c)`` is settled (values larger than its
    distance are then upper bounds, or ``inf``). Unreachable and blocked cells are ``inf``. The result
    is multiplied by ``scale`` (the resolution).
    """
    rows, cols = free.shape
    f, w = _pad_free(free)
    n = f.size
    dist = np.empty(n)
    dist[:] = np.inf
    stop = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
    g = (goal_r + 1) * w + goal_c + 1
    cap = 1024
    b0 = np.empty(cap, np.int32)  # bucket k (being settled)
    b1 = np.empty(cap, np.int32)  # bucket k + 1
    b2 = np.empty(cap, np.int32)  # bucket k + 2
    n0 = 0
    n1 = 0
    n2 = 0
    if f[g]:
        dist[g] = 0.0
        b0[0] = g
        n0 = 1
    eight = connectivity == 8
    k = 0
    done = False
    while n0 + n1 + n2 > 0 and not done:
        # room for every push the n0 cells of this bucket can make
        if n1 + 8 * n0 > b1.shape[0]:
            t = np.empty(2 * (n1 + 8 * n0), np.int32)
            t[:n1] = b1[:n1]
            b1 = t
        if n2 + 4 * n0 > b2.shape[0]:
            t = np.empty(2 * (n2 + 4 * n0), np.int32)
            t[:n2] = b2[:n2]
            b2 = t
        lo = float(k)
        hi2 = lo + 2.0
        for i in range(n0):
            u = b0[i]
            du = dist[u]
            if du < lo:  # stale: improved into an earlier bucket and settled there
                continue
            if u == stop:
                done = True
                break
            fr = f[u + 1]
            fl = f[u - 1]
            fu = f[u + w]
            fd = f[u - w]
            nd = du + 1.0  # in [k + 1, k + 2)
            for v, ok in ((u + 1, fr), (u - 1, fl), (u + w, fu), (u - w, fd)):
                if ok:
                    old = dist[v]
                    if nd < old:
                        dist[v] = nd
                        if old >= hi2:  # not yet in bucket k + 1
                            b1[n1] = v
                            n1 += 1
            if eight:
                nd = du + diag
                if nd < hi2:
                    for v, ok in ((u + w + 1, fr & fu), (u + w - 1, fl & fu), (u - w + 1, fr & fd),
                                  (u - w - 1, fl & fd)):
                        if ok and f[v]:
                            old = dist[v]
                            if nd < old:
                                dist[v] = nd
                                if old >= hi2:
                                    b1[n1] = v
                                    n1 += 1
                else:
                    for v, ok in ((u + w + 1, fr & fu), (u + w - 1, fl & fu), (u - w + 1, fr & fd),
                                  (u - w - 1, fl & fd)):
                        if ok and f[v]:
                            old = dist[v]
                            if nd < old:
                                dist[v] = nd
                                # a finite old value is < k + 3, i.e. already in bucket k + 2
                                if old == np.inf:
                                    b2[n2] = v
                                    n2 += 1
        t = b0
        b0 = b1
        b1 = b2
        b2 = t
        n0 = n1
        n1 = n2
        n2 = 0
        k += 1
    return _unpad(dist, rows, cols, scale)


@njit(**_OPTS)
def wavefront_weighted(free, cost, goal_r, goal_c, connectivity, diag, stop_r, stop_c, scale):
    """Exact shortest-path distance with cell costs: a step from ``u`` to ``v`` costs
    ``length * (cost[u] + cost[v]) / 2`` (length 1 or ``diag``). Requires ``cost >= 1`` on free cells,
    so that every edge costs at least 1 and a ring of ``floor(diag * max(cost)) + 2`` buckets of
    width 1 is an exact priority queue (Dial's algorithm).
    """
    rows, cols = free.shape
    f, w = _pad_free(free)
    n = f.size
    cp = np.ones(n)
    cmax = 1.0
    for r in range(rows):
        base = (r + 1) * w + 1
        for c in range(cols):
            if free[r, c]:
                cp[base + c] = cost[r, c]
                if cost[r, c] > cmax:
                    cmax = cost[r, c]
    nb = int(math.floor(diag * cmax)) + 2
    dist = np.empty(n)
    dist[:] = np.inf
    stop = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
    cap = 1024
    buckets = np.empty((nb, cap), np.int32)
    size = np.zeros(nb, np.int64)
    g = (goal_r + 1) * w + goal_c + 1
    pending = 0
    if f[g]:
        dist[g] = 0.0
        buckets[0, 0] = g
        size[0] = 1
        pending = 1
    eight = connectivity == 8
    half_d = 0.5 * diag
    k = 0
    while pending > 0:
        b = k % nb
        m = size[b]
        # room for every push of this bucket in the fullest other bucket
        need = int(size.max()) + 8 * m
        if need > buckets.shape[1]:
            t = np.empty((nb, 2 * need), np.int32)
            t[:, : buckets.shape[1]] = buckets
            buckets = t
        lo = float(k)
        stop_now = False
        for i in range(m):
            u = buckets[b, i]
            du = dist[u]
            if du < lo:
                continue
            if u == stop:
                stop_now = True
                break
            cu = cp[u]
            fr = f[u + 1]
            fl = f[u - 1]
            fu = f[u + w]
            fd = f[u - w]
            for v, ok in ((u + 1, fr), (u - 1, fl), (u + w, fu), (u - w, fd)):
                if ok:
                    nd = du + 0.5 * (cu + cp[v])
                    old = dist[v]
                    if nd < old:
                        dist[v] = nd
                        ib = int(nd)
                        if old == np.inf or int(old) != ib:
                            bb = ib % nb
                            buckets[bb, size[bb]] = v
                            size[bb] += 1
                            pending += 1
            if eight:
                for v, ok in ((u + w + 1, fr & fu), (u + w - 1, fl & fu), (u - w + 1, fr & fd),
                              (u - w - 1, fl & fd)):
                    if ok and f[v]:
                        nd = du + half_d * (cu + cp[v])
                        old = dist[v]
                        if nd < old:
                            dist[v] = nd
                            ib = int(nd)
                            if old == np.inf or int(old) != ib:
                                bb = ib % nb
                                buckets[bb, size[bb]] = v
                                size[bb] += 1
                                pending += 1
        if stop_now:
            break
        pending -= m
        size[b] = 0
        k += 1
    return _unpad(dist, rows, cols, scale)


@njit(**_OPTS)
def descend(value, free, cost, start_r, start_c, connectivity, diag, mode, scale):
    """Cells ``(row, col)`` from the start cell down to a cell of value 0 on ``value``.

    ``mode`` 0 (shortest-path fields): step to the allowed neighbour ``v`` minimizing
    ``value[v] + cost(u, v)`` among those with ``value[v] < value[u]`` -- on an exact Dijkstra field
    this is a shortest-path parent, so the chain's cost equals ``value[start]``.
    ``mode`` 1 (harmonic fields): steepest descent, maximizing ``(value[u] - value[v]) / length``.
    ``cost`` is an empty array for unit cell costs; step costs are multiplied by ``scale`` (the
    resolution, when ``value`` is in world units). Returns the chain and a flag: 1 reached a zero,
    0 stopped where no neighbour is lower (a numerical local minimum).
    """
    rows, cols = value.shape
    weighted = cost.shape[0] > 0
    out = np.empty((64, 2), np.int64)
    m = 0
    r = start_r
    c = start_c
    reached = 0
    limit = rows * cols + 1
    while m < limit:
        if m == out.shape[0]:
            t = np.empty((2 * m, 2), np.int64)
            t[:m] = out
            out = t
        out[m, 0] = r
        out[m, 1] = c
        m += 1
        vu = value[r, c]
        if vu == 0.0:
            reached = 1
            break
        best = np.inf
        br = -1
        bc = -1
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                if dr == 0 and dc == 0:
                    continue
                isdiag = dr != 0 and dc != 0
                if isdiag and connectivity == 4:
                    continue
                rr = r + dr
                cc = c + dc
                if rr < 0 or rr >= rows or cc < 0 or cc >= cols or not free[rr, cc]:
                    continue
                if isdiag and not (free[r + dr, c] and free[r, c + dc]):
                    continue
                vv = value[rr, cc]
                if not vv < vu:
                    continue
                length = diag if isdiag else 1.0
                if mode == 0:
                    step = scale * length * (0.5 * (cost[r, c] + cost[rr, cc]) if weighted else 1.0)
                    key = vv + step
                else:
                    key = -(vu - vv) / length
                if key < best:
                    best = key
                    br = rr
                    bc = cc
        if br < 0:
            break
        r = br
        c = bc
    return out[:m].copy(), reached


@njit(**_OPTS)
def chain_points(cells, sx, sy, gx, gy, reached, x0, y0, res, diag):
    """World points of a descent: the start ``(sx, sy)``, the centres of ``cells``, and the goal
    ``(gx, gy)`` when ``reached``, with a point equal to the one before it dropped. Also returns the
    chain's length between cell centres (orthogonal step ``res``, diagonal ``diag * res``)."""
    m = cells.shape[0]
    pts = np.empty((m + 2, 2))
    pts[0, 0] = sx
    pts[0, 1] = sy
    n = 1
    length = 0.0
    for k in range(m):
        x = x0 + (cells[k, 1] + 0.5) * res
        y = y0 + (cells[k, 0] + 0.5) * res
        if k > 0:
            if cells[k, 0] != cells[k - 1, 0] and cells[k, 1] != cells[k - 1, 1]:
                length += diag * res
            else:
                length += res
        if x != pts[n - 1, 0] or y != pts[n - 1, 1]:
            pts[n, 0] = x
            pts[n, 1] = y
            n += 1
    if reached and (gx != pts[n - 1, 0] or gy != pts[n - 1, 1]):
        pts[n, 0] = gx
        pts[n, 1] = gy
        n += 1
    return pts[:n].copy(), length


@njit(**_OPTS)
def _bilinear(a, valid, x, y):
    """Bilinear interpolation at ``(x, y)`` (cell units, centres at half-integers) over valid samples
    only (weights renormalized); NaN when no corner is valid."""
    rows, cols = a.shape
    fx = x - 0.5
    fy = y - 0.5
    j0 = int(math.floor(fx))
    i0 = int(math.floor(fy))
    tx = fx - j0
    ty = fy - i0
    acc = 0.0
    wsum = 0.0
    for di in range(2):
        for dj in range(2):
            i = i0 + di
            j = j0 + dj
            if i < 0 or i >= rows or j < 0 or j >= cols or not valid[i, j]:
                continue
            wt = (tx if dj else 1.0 - tx) * (ty if di else 1.0 - ty)
            if wt <= 0.0:
                continue
            acc += wt * a[i, j]
            wsum += wt
    if wsum <= 0.0:
        return np.nan
    return acc / wsum


@njit(**_OPTS)
def follow_interpolated(value, gx, gy, free, x0, y0, goal_x, goal_y, step, tolerance, max_iterations, diag):
    """Follow ``-grad`` of a distance-like field (fast marching) with normalized steps.

    Positions are in cell units. A continuous step of length ``step`` along the bilinearly
    interpolated negative gradient is taken when it lands in a free cell reachable under the move
    rule and lowers the interpolated value; otherwise the follower moves to the centre of the
    lowest allowed neighbour cell (which always exists on a fast-marching field, whose values
    strictly increase away from the goal). Returns ``(points, status, iterations)`` with status
    0 reached, 1 stalled (no lower neighbour), 2 out of iterations.
    """
    rows, cols = value.shape
    valid = np.empty((rows, cols), np.bool_)
    for i in range(rows):
        for j in range(cols):
            valid[i, j] = free[i, j] and np.isfinite(value[i, j])
    gr = int(math.floor(goal_y))
    gc = int(math.floor(goal_x))
    pts = np.empty((256, 2))
    m = 0
    x = x0
    y = y0
    status = 2
    it = 0
    pts[0, 0] = x
    pts[0, 1] = y
    m = 1
    while it < max_iterations:
        r = int(math.floor(y))
        c = int(math.floor(x))
        if (r == gr and c == gc) or math.hypot(x - goal_x, y - goal_y) <= tolerance:
            status = 0
            break
        it += 1
        vx = _bilinear(gx, valid, x, y)
        vy = _bilinear(gy, valid, x, y)
        here = _bilinear(value, valid, x, y)
        moved = False
        nrm = math.hypot(vx, vy)
        if nrm > 0.0 and np.isfinite(nrm) and np.isfinite(here):
            nx = x - step * vx / nrm
            ny = y - step * vy / nrm
            nr = int(math.floor(ny))
            nc = int(math.floor(nx))
            ok = 0 <= nr < rows and 0 <= nc < cols and valid[nr, nc]
            if ok and nr != r and nc != c:  # crossed a cell corner: both orthogonal cells must be free
                ok = free[nr, c] and free[r, nc]
            if ok:
                there = _bilinear(value, valid, nx, ny)
                if there < here:
                    x = nx
                    y = ny
                    moved = True
        if not moved:
            vu = value[r, c]
            best = vu
            br = -1
            bc = -1
            for dr in range(-1, 2):
                for dc in range(-1, 2):
                    if dr == 0 and dc == 0:
                        continue
                    rr = r + dr
                    cc = c + dc
                    if rr < 0 or rr >= rows or cc < 0 or cc >= cols or not valid[rr, cc]:
                        continue
                    if dr != 0 and dc != 0 and not (free[r + dr, c] and free[r, c + dc]):
                        continue
                    if value[rr, cc] < best:
                        best = value[rr, cc]
                        br = rr
                        bc = cc
            if br < 0:
                status = 1
                break
            x = bc + 0.5
            y = br + 0.5
        if m == pts.shape[0]:
            t = np.empty((2 * m, 2))
            t[:m] = pts[:m]
            pts = t
        pts[m, 0] = x
        pts[m, 1] = y
        m += 1
    return pts[:m].copy(), status, it


@njit(**_OPTS)
def mic0_factor(left, down, right, up, omega):
    """Pivots ``d`` of the modified incomplete Cholesky factorization ``A ~ L D^-1 L^T`` of the
    5-point Dirichlet Laplacian (diagonal 4, ``-1`` between neighbouring unknowns) on unknowns in
    row-major order. ``left/down/right/up[i]`` is the index of that neighbour among the unknowns, or -1.
    ``omega`` in ``[0, 1)`` blends IC(0) (0) and MIC(0) (-> 1). A pivot that would fall below 1e-3
    falls back to the IC(0) value, which for this M-matrix is at least 2.
    """
    n = left.shape[0]
    d = np.empty(n)
    for i in range(n):
        v = 4.0
        v0 = 4.0
        j = left[i]
        if j >= 0:
            v0 -= 1.0 / d[j]
            v -= (1.0 + (omega if up[j] >= 0 else 0.0)) / d[j]
        j = down[i]
        if j >= 0:
            v0 -= 1.0 / d[j]
            v -= (1.0 + (omega if right[j] >= 0 else 0.0)) / d[j]
        d[i] = v if v > 1e-3 else v0
    return d


@njit(**_OPTS)
def mic0_apply(left, down, right, up, d, r):
    """Solve ``(L D^-1 L^T) z = r`` for the factorization of :func:`mic0_factor`."""
    n = left.shape[0]
    y = np.empty(n)
    for i in range(n):
        v = r[i]
        j = left[i]
        if j >= 0:
            v += y[j] / d[j]
        j = down[i]
        if j >= 0:
            v += y[j] / d[j]
        y[i] = v
    for i in range(n - 1, -1, -1):
        v = y[i]
        j = right[i]
        if j >= 0:
            v += y[j]
        j = up[i]
        if j >= 0:
            v += y[j]
        y[i] = v / d[i]
    return y


@njit(**_OPTS)
def _laplace_matvec(left, down, right, up, x, out):
    n = left.shape[0]
    for i in range(n):
        v = 4.0 * x[i]
        j = left[i]
        if j >= 0:
            v -= x[j]
        j = right[i]
        if j >= 0:
            v -= x[j]
        j = down[i]
        if j >= 0:
            v -= x[j]
        j = up[i]
        if j >= 0:
            v -= x[j]
        out[i] = v


@njit(**_OPTS)
def pcg_laplace(left, down, right, up, b, omega, rtol, maxiter):
    """Conjugate gradients on the 5-point Dirichlet Laplacian (see :func:`mic0_factor`) preconditioned by
    MIC(0). Stops when ``|r| <= rtol * |b|``. Returns ``(x, iterations, relative residual)``."""
    n = left.shape[0]
    d = mic0_factor(left, down, right, up, omega)
    x = mic0_apply(left, down, right, up, d, b)  # the preconditioner's guess
    r = np.empty(n)
    ap = np.empty(n)
    _laplace_matvec(left, down, right, up, x, ap)
    bb = 0.0
    rr = 0.0
    for i in range(n):
        r[i] = b[i] - ap[i]
        bb += b[i] * b[i]
        rr += r[i] * r[i]
    bnorm = math.sqrt(bb)
    if bnorm == 0.0:
        return np.zeros(n), 0, 0.0
    z = mic0_apply(left, down, right, up, d, r)
    p = z.copy()
    rz = 0.0
    for i in range(n):
        rz += r[i] * z[i]
    it = 0
    while math.sqrt(rr) > rtol * bnorm and it < maxiter:
        it += 1
        _laplace_matvec(left, down, right, up, p, ap)
        pap = 0.0
        for i in range(n):
            pap += p[i] * ap[i]
        if pap <= 0.0:
            break
        alpha = rz / pap
        rr = 0.0
        for i in range(n):
            x[i] += alpha * p[i]
            r[i] -= alpha * ap[i]
            rr += r[i] * r[i]
        z = mic0_apply(left, down, right, up, d, r)
        rz_new = 0.0
        for i in range(n):
            rz_new += r[i] * z[i]
        beta = rz_new / rz
        rz = rz_new
        for i in range(n):
            p[i] = z[i] + beta * p[i]
    return x, it, math.sqrt(rr) / bnorm


@njit(**_OPTS)
def clearance_along(occupied, rows_idx, cols_idx, wall, budget):
    """Smallest Euclidean distance (in cells) from the centres of the given cells to the centre of an
    obstacle cell -- with ``wall``, the ring of cells just outside the grid counts as obstacle, as in
    :func:`gridfield.brushfire.brushfire`. Searches Chebyshev rings around each cell, only out to the
    best distance found so far. Returns ``inf`` when there is no obstacle, and -1 when more than
    ``budget`` cells would have to be examined (the caller then uses a distance transform).
    """
    rows, cols = occupied.shape
    best = np.inf
    work = 0
    kmax = max(rows, cols) + 1
    for i in range(rows_idx.shape[0]):
        r = rows_idx[i]
        c = cols_idx[i]
        k = 1
        while k < best and k <= kmax:
            for t in range(-k, k + 1):
                for side in range(4):
                    if side == 0:
                        rr = r - k
                        cc = c + t
                    elif side == 1:
                        rr = r + k
                        cc = c + t
                    elif side == 2:
                        if t == -k or t == k:
                            continue
                        rr = r + t
                        cc = c - k
                    else:
                        if t == -k or t == k:
                            continue
                        rr = r + t
                        cc = c + k
                    if 0 <= rr < rows and 0 <= cc < cols:
                        hit = occupied[rr, cc]
                    else:
                        hit = wall and -1 <= rr <= rows and -1 <= cc <= cols
                    if hit:
                        d = math.sqrt(float((rr - r) * (rr - r) + (cc - c) * (cc - c)))
                        if d < best:
                            best = d
            work += 8 * k
            if work > budget:
                return -1.0
            k += 1
        if best == np.inf:  # the rings covered the whole grid (and the wall ring): no obstacle at all
            return best
    return best
