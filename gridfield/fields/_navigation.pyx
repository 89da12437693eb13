# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.fields.navigation` (Cython, compiled at install; imported lazily).

Everything here works in *cell units* on plain arrays indexed ``[row, col]`` (row 0 = lowest y):
a step between orthogonal neighbours has length 1, a diagonal step ``diag`` (``sqrt(2)`` for octile
costs, 1 for unit costs). Grids are copied once into a flat array padded with a ring of blocked
cells, so that the inner loops need no bounds checks. Nothing in this module validates input; the
public functions in :mod:`gridfield.fields.navigation` do. Input arrays may have any strides (``bool``
or ``uint8`` masks, ``float64`` values, ``int64`` index arrays); indices are guarded, so bounds
checks are off.

Move rule (Moving AI, no corner cutting): a diagonal step ``(dr, dc)`` from ``(r, c)`` is allowed only
when both ``(r + dr, c)`` and ``(r, c + dc)`` are free, or when the map's extra diagonals allow it
(``xdiag``: :attr:`gridfield.core.grid.GridMap.diagonals`, the diagonals a disc robot fits along though a
side cell is blocked in its configuration space; bit 0 of ``xdiag[r, c]`` joins ``(r, c)`` and
``(r + 1, c + 1)``, bit 1 joins ``(r, c + 1)`` and ``(r + 1, c)``; an empty ``(0, 0)`` array for none,
and then the kernels run exactly as without it). The rule is symmetric, so the graph is undirected and
a wavefront from the goal gives the distance *to* the goal.

The harmonic field's linear solver (MIC(0)-preconditioned conjugate gradients on the Laplacian) is
:mod:`gridfield.fields._laplace`.
"""


from libc.math cimport INFINITY, NAN, floor, hypot, isfinite, sqrt
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free as c_free, malloc, realloc

import numpy as np

ctypedef const uint8_t[:, :] mask_t
ctypedef const double[:, :] val_t
ctypedef const int64_t[:] idx_t

cdef uint8_t[:, ::1] _NO_DIAGONALS = np.zeros((0, 0), np.uint8)  # no extra diagonal (the default)


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


cdef uint8_t* _pad_free(mask_t free_, int64_t* width) noexcept nogil:
    """Flat uint8 copy of ``free`` with a blocked ring (malloc'd; the caller frees it); its padded width."""
    cdef int64_t rows = free_.shape[0], cols = free_.shape[1], r, c, base
    cdef int64_t w = cols + 2
    cdef int64_t n = (rows + 2) * w
    cdef uint8_t* f = <uint8_t*>_alloc(n)
    for r in range(n):
        f[r] = 0
    for r in range(rows):
        base = (r + 1) * w + 1
        for c in range(cols):
            if free_[r, c]:
                f[base + c] = 1
    width[0] = w
    return f


cdef uint8_t* _pad_diag(mask_t xdiag, int64_t rows, int64_t cols, int64_t w) noexcept nogil:
    """The extra diagonals ``xdiag`` (blocks of 2x2 cells) as a flat per-cell mask of the padded layout
    (malloc'd; the caller frees it), or NULL when there are none: bit 0 allows the step to ``u + w + 1``,
    bit 1 to ``u + w - 1``, bit 2 to ``u - w + 1``, bit 3 to ``u - w - 1``."""
    cdef int64_t n = (rows + 2) * w, i, j, u
    cdef uint8_t* x
    cdef uint8_t b
    if xdiag.shape[0] == 0 or xdiag.shape[0] != rows - 1 or xdiag.shape[1] != cols - 1:
        return NULL
    x = <uint8_t*>_alloc(n)
    for i in range(n):
        x[i] = 0
    for i in range(rows - 1):
        for j in range(cols - 1):
            b = xdiag[i, j]
            if b:
                u = (i + 1) * w + j + 1  # cell (i, j)
                if b & 1:  # (i, j) <-> (i + 1, j + 1)
                    x[u] |= 1
                    x[u + w + 1] |= 8
                if b & 2:  # (i, j + 1) <-> (i + 1, j)
                    x[u + 1] |= 2
                    x[u + w] |= 4
    return x


cdef inline bint _xdiag_ok(mask_t xdiag, int64_t r, int64_t c, int64_t dr, int64_t dc) noexcept nogil:
    """Whether the extra diagonals allow the diagonal step ``(dr, dc)`` from ``(r, c)`` (both cells inside)."""
    if xdiag.shape[0] == 0:
        return False
    return (xdiag[r if dr > 0 else r - 1, c if dc > 0 else c - 1] >> (0 if dr == dc else 1)) & 1


cdef object _unpad(const double* a, int64_t rows, int64_t cols, double scale):
    out = np.empty((rows, cols))
    cdef double[:, ::1] o = out
    cdef int64_t w = cols + 2, r, c, base
    with nogil:
        for r in range(rows):
            base = (r + 1) * w + 1
            for c in range(cols):
                o[r, c] = a[base + c] * scale
    return out


cdef inline bint _grow(int32_t** buf, int64_t* cap, int64_t need) noexcept nogil:
    """Make ``buf`` hold at least ``need`` entries (doubling); False if out of memory."""
    cdef int64_t n
    cdef int32_t* t
    if need <= cap[0]:
        return True
    n = 2 * need
    t = <int32_t*>realloc(buf[0], n * sizeof(int32_t))
    if t == NULL:
        return False
    buf[0] = t
    cap[0] = n
    return True


cdef inline void _relax_uniform(double* dist, int64_t v, double nd, double hi2, int32_t* b1, int64_t* n1) noexcept nogil:
    cdef double old = dist[v]
    if nd < old:
        dist[v] = nd
        if old >= hi2:  # not yet in bucket k + 1
            b1[n1[0]] = <int32_t>v
            n1[0] += 1


cdef inline void _relax_far(double* dist, int64_t v, double nd, int32_t* b2, int64_t* n2) noexcept nogil:
    cdef double old = dist[v]
    if nd < old:
        dist[v] = nd
        # a finite old value is < k + 3, i.e. already in bucket k + 2
        if old == INFINITY:
            b2[n2[0]] = <int32_t>v
            n2[0] += 1


def wavefront_uniform(mask_t free, int64_t goal_r, int64_t goal_c, int64_t connectivity, double diag,
                      int64_t stop_r, int64_t stop_c, double scale, mask_t xdiag=None):
    """Exact shortest-path distance to the goal cell with orthogonal steps 1 and diagonal steps ``diag``.

    Dijkstra with a bucket queue keyed by ``floor(distance)`` (Dial's algorithm with the bucket width
    equal to the shortest edge, 1). Every relaxation from bucket ``k`` lands in bucket ``k + 1`` or
    ``k + 2`` (``diag < 2``), so all cells of bucket ``k`` are final when it is reached and may be
    settled in any order: three rotating buckets replace the heap. ``diag`` must lie in ``[1, 2)``.

    ``stop_r >= 0`` ends the search once cell ``(stop_r, stop_c)`` is settled (values larger than its
    distance are then upper bounds, or ``inf``). Unreachable and blocked cells are ``inf``. The result
    is multiplied by ``scale`` (the resolution).
    """
    cdef int64_t rows = free.shape[0], cols = free.shape[1], w, n, i, u, stop, g, k
    cdef uint8_t* f
    cdef double* dist
    cdef int32_t* b0
    cdef int32_t* b1
    cdef int32_t* b2
    cdef int32_t* tb
    cdef int64_t c0 = 1024, c1 = 1024, c2 = 1024, ct, n0 = 0, n1 = 0, n2 = 0
    cdef bint eight = connectivity == 8, done = False, oom = False
    cdef double du, nd, lo, hi2
    cdef uint8_t fr, fl, fu, fd, xb = 0
    cdef uint8_t* x = NULL
    if xdiag is None:
        xdiag = _NO_DIAGONALS
    with nogil:
        f = _pad_free(free, &w)
        if eight:
            x = _pad_diag(xdiag, rows, cols, w)
        n = (rows + 2) * w
        dist = <double*>_alloc(n * sizeof(double))
        for i in range(n):
            dist[i] = INFINITY
        stop = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
        g = (goal_r + 1) * w + goal_c + 1
        b0 = <int32_t*>_alloc(c0 * sizeof(int32_t))  # bucket k (being settled)
        b1 = <int32_t*>_alloc(c1 * sizeof(int32_t))  # bucket k + 1
        b2 = <int32_t*>_alloc(c2 * sizeof(int32_t))  # bucket k + 2
        if f[g]:
            dist[g] = 0.0
            b0[0] = <int32_t>g
            n0 = 1
        k = 0
        while n0 + n1 + n2 > 0 and not done:
            # room for every push the n0 cells of this bucket can make
            if not (_grow(&b1, &c1, n1 + 8 * n0) and _grow(&b2, &c2, n2 + 4 * n0)):
                oom = True
                break
            lo = <double>k
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
                if x != NULL:
                    xb = x[u]
                nd = du + 1.0  # in [k + 1, k + 2)
                if fr:
                    _relax_uniform(dist, u + 1, nd, hi2, b1, &n1)
                if fl:
                    _relax_uniform(dist, u - 1, nd, hi2, b1, &n1)
                if fu:
                    _relax_uniform(dist, u + w, nd, hi2, b1, &n1)
                if fd:
                    _relax_uniform(dist, u - w, nd, hi2, b1, &n1)
                if eight:
                    nd = du + diag
                    if nd < hi2:
                        if (fr & fu | (xb & 1)) and f[u + w + 1]:
                            _relax_uniform(dist, u + w + 1, nd, hi2, b1, &n1)
                        if (fl & fu | (xb & 2)) and f[u + w - 1]:
                            _relax_uniform(dist, u + w - 1, nd, hi2, b1, &n1)
                        if (fr & fd | (xb & 4)) and f[u - w + 1]:
                            _relax_uniform(dist, u - w + 1, nd, hi2, b1, &n1)
                        if (fl & fd | (xb & 8)) and f[u - w - 1]:
                            _relax_uniform(dist, u - w - 1, nd, hi2, b1, &n1)
                    else:
                        if (fr & fu | (xb & 1)) and f[u + w + 1]:
                            _relax_far(dist, u + w + 1, nd, b2, &n2)
                        if (fl & fu | (xb & 2)) and f[u + w - 1]:
                            _relax_far(dist, u + w - 1, nd, b2, &n2)
                        if (fr & fd | (xb & 4)) and f[u - w + 1]:
                            _relax_far(dist, u - w + 1, nd, b2, &n2)
                        if (fl & fd | (xb & 8)) and f[u - w - 1]:
                            _relax_far(dist, u - w - 1, nd, b2, &n2)
            tb = b0
            ct = c0
            b0 = b1
            c0 = c1
            b1 = b2
            c1 = c2
            b2 = tb
            c2 = ct
            n0 = n1
            n1 = n2
            n2 = 0
            k += 1
        c_free(f)
        c_free(x)
        c_free(b0)
        c_free(b1)
        c_free(b2)
    if oom:
        c_free(dist)
        raise MemoryError("wavefront_uniform: out of memory for the bucket queue")
    try:
        return _unpad(dist, rows, cols, scale)
    finally:
        c_free(dist)


cdef inline void _relax_weighted(double* dist, int64_t v, double nd, int32_t* buckets, int64_t cap, int64_t* size,
                                 int64_t nb, int64_t* pending) noexcept nogil:
    cdef double old = dist[v]
    cdef int64_t ib, bb
    if nd < old:
        dist[v] = nd
        ib = <int64_t>nd
        if old == INFINITY or <int64_t>old != ib:
            bb = ib % nb
            buckets[bb * cap + size[bb]] = <int32_t>v
            size[bb] += 1
            pending[0] += 1


def wavefront_weighted(mask_t free, val_t cost, int64_t goal_r, int64_t goal_c, int64_t connectivity, double diag,
                       int64_t stop_r, int64_t stop_c, double scale, mask_t xdiag=None):
    """Exact shortest-path distance with cell costs: a step from ``u`` to ``v`` costs
    ``length * (cost[u] + cost[v]) / 2`` (length 1 or ``diag``). Requires ``cost >= 1`` on free cells,
    so that every edge costs at least 1 and a ring of ``floor(diag * max(cost)) + 2`` buckets of
    width 1 is an exact priority queue (Dial's algorithm).
    """
    cdef int64_t rows = free.shape[0], cols = free.shape[1], w, n, r, c, base, i, nb, stop, g, k, b, m, need
    cdef int64_t smax, u, v, j, cap = 1024, ncap, pending = 0
    cdef uint8_t* f
    cdef double* cp
    cdef double* dist
    cdef double cmax = 1.0, cu, du, nd, lo, half_d = 0.5 * diag
    cdef int32_t* buckets
    cdef int32_t* t
    cdef int64_t* size
    cdef bint eight = connectivity == 8, stop_now, oom = False
    cdef uint8_t fr, fl, fu, fd, xb = 0
    cdef uint8_t* x = NULL
    if xdiag is None:
        xdiag = _NO_DIAGONALS
    with nogil:
        f = _pad_free(free, &w)
        if eight:
            x = _pad_diag(xdiag, rows, cols, w)
        n = (rows + 2) * w
        cp = <double*>_alloc(n * sizeof(double))
        for i in range(n):
            cp[i] = 1.0
        for r in range(rows):
            base = (r + 1) * w + 1
            for c in range(cols):
                if free[r, c]:
                    cp[base + c] = cost[r, c]
                    if cost[r, c] > cmax:
                        cmax = cost[r, c]
        nb = <int64_t>floor(diag * cmax) + 2
        dist = <double*>_alloc(n * sizeof(double))
        for i in range(n):
            dist[i] = INFINITY
        stop = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
        buckets = <int32_t*>_alloc(nb * cap * sizeof(int32_t))
        size = <int64_t*>_alloc(nb * sizeof(int64_t))
        for i in range(nb):
            size[i] = 0
        g = (goal_r + 1) * w + goal_c + 1
        if f[g]:
            dist[g] = 0.0
            buckets[0] = <int32_t>g
            size[0] = 1
            pending = 1
        k = 0
        while pending > 0:
            b = k % nb
            m = size[b]
            # room for every push of this bucket in the fullest other bucket
            smax = 0
            for i in range(nb):
                if size[i] > smax:
                    smax = size[i]
            need = smax + 8 * m
            if need > cap:
                ncap = 2 * need
                t = <int32_t*>malloc(nb * ncap * sizeof(int32_t))
                if t == NULL:
                    oom = True
                    break
                for i in range(nb):
                    for j in range(size[i]):
                        t[i * ncap + j] = buckets[i * cap + j]
                c_free(buckets)
                buckets = t
                cap = ncap
            lo = <double>k
            stop_now = False
            for i in range(m):
                u = buckets[b * cap + i]
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
                if x != NULL:
                    xb = x[u]
                if fr:
                    _relax_weighted(dist, u + 1, du + 0.5 * (cu + cp[u + 1]), buckets, cap, size, nb, &pending)
                if fl:
                    _relax_weighted(dist, u - 1, du + 0.5 * (cu + cp[u - 1]), buckets, cap, size, nb, &pending)
                if fu:
                    _relax_weighted(dist, u + w, du + 0.5 * (cu + cp[u + w]), buckets, cap, size, nb, &pending)
                if fd:
                    _relax_weighted(dist, u - w, du + 0.5 * (cu + cp[u - w]), buckets, cap, size, nb, &pending)
                if eight:
                    v = u + w + 1
                    if (fr & fu | (xb & 1)) and f[v]:
                        _relax_weighted(dist, v, du + half_d * (cu + cp[v]), buckets, cap, size, nb, &pending)
                    v = u + w - 1
                    if (fl & fu | (xb & 2)) and f[v]:
                        _relax_weighted(dist, v, du + half_d * (cu + cp[v]), buckets, cap, size, nb, &pending)
                    v = u - w + 1
                    if (fr & fd | (xb & 4)) and f[v]:
                        _relax_weighted(dist, v, du + half_d * (cu + cp[v]), buckets, cap, size, nb, &pending)
                    v = u - w - 1
                    if (fl & fd | (xb & 8)) and f[v]:
                        _relax_weighted(dist, v, du + half_d * (cu + cp[v]), buckets, cap, size, nb, &pending)
            if stop_now:
                break
            pending -= m
            size[b] = 0
            k += 1
        c_free(f)
        c_free(x)
        c_free(cp)
        c_free(buckets)
        c_free(size)
    if oom:
        c_free(dist)
        raise MemoryError("wavefront_weighted: out of memory for the bucket queue")
    try:
        return _unpad(dist, rows, cols, scale)
    finally:
        c_free(dist)


def descend(val_t value, mask_t free, val_t cost, int64_t start_r, int64_t start_c, int64_t connectivity,
            double diag, int64_t mode, double scale, mask_t xdiag=None):
    """Cells ``(row, col)`` from the start cell down to a cell of value 0 on ``value``.

    ``mode`` 0 (shortest-path fields): step to the allowed neighbour ``v`` minimizing
    ``value[v] + cost(u, v)`` among those with ``value[v] < value[u]`` -- on an exact Dijkstra field
    this is a shortest-path parent, so the chain's cost equals ``value[start]``.
    ``mode`` 1 (harmonic fields): steepest descent, maximizing ``(value[u] - value[v]) / length``.
    ``cost`` is an empty array for unit cell costs; step costs are multiplied by ``scale`` (the
    resolution, when ``value`` is in world units). Returns the chain and a flag: 1 reached a zero,
    0 stopped where no neighbour is lower (a numerical local minimum).
    """
    cdef int64_t rows = value.shape[0], cols = value.shape[1], m = 0, r = start_r, c = start_c, reached = 0
    cdef int64_t limit = rows * cols + 1, cap = 64, br, bc, dr, dc, rr, cc
    cdef bint weighted = cost.shape[0] > 0, isdiag, oom = False
    cdef double vu, vv, best, length, step, key
    cdef int64_t* out = <int64_t*>_alloc(2 * cap * sizeof(int64_t))
    cdef int64_t* t
    if xdiag is None:
        xdiag = _NO_DIAGONALS
    with nogil:
        while m < limit:
            if m == cap:
                t = <int64_t*>realloc(out, 4 * cap * sizeof(int64_t))
                if t == NULL:
                    oom = True
                    break
                out = t
                cap *= 2
            out[2 * m] = r
            out[2 * m + 1] = c
            m += 1
            vu = value[r, c]
            if vu == 0.0:
                reached = 1
                break
            best = INFINITY
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
                    if isdiag and not (free[r + dr, c] and free[r, c + dc]) and not _xdiag_ok(xdiag, r, c, dr, dc):
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
    if oom:
        c_free(out)
        raise MemoryError("descend: out of memory")
    res = np.empty((m, 2), np.int64)
    cdef int64_t[:, ::1] rv = res
    cdef int64_t i
    for i in range(m):
        rv[i, 0] = out[2 * i]
        rv[i, 1] = out[2 * i + 1]
    c_free(out)
    return res, reached


def chain_points(const int64_t[:, :] cells, double sx, double sy, double gx, double gy, bint reached, double x0,
                 double y0, double res, double diag):
    """World points of a descent: the start ``(sx, sy)``, the centres of ``cells``, and the goal
    ``(gx, gy)`` when ``reached``, with a point equal to the one before it dropped. Also returns the
    chain's length between cell centres (orthogonal step ``res``, diagonal ``diag * res``)."""
    cdef int64_t m = cells.shape[0], n = 1, k
    pts = np.empty((m + 2, 2))
    cdef double[:, ::1] p = pts
    cdef double length = 0.0, x, y
    p[0, 0] = sx
    p[0, 1] = sy
    for k in range(m):
        x = x0 + (cells[k, 1] + 0.5) * res
        y = y0 + (cells[k, 0] + 0.5) * res
        if k > 0:
            if cells[k, 0] != cells[k - 1, 0] and cells[k, 1] != cells[k - 1, 1]:
                length += diag * res
            else:
                length += res
        if x != p[n - 1, 0] or y != p[n - 1, 1]:
            p[n, 0] = x
            p[n, 1] = y
            n += 1
    if reached and (gx != p[n - 1, 0] or gy != p[n - 1, 1]):
        p[n, 0] = gx
        p[n, 1] = gy
        n += 1
    return pts[:n].copy(), length


cdef double _bilinear_c(val_t a, const uint8_t[:, ::1] valid, double x, double y) noexcept nogil:
    cdef int64_t rows = a.shape[0], cols = a.shape[1], di, dj, i, j
    cdef double fx = x - 0.5, fy = y - 0.5
    cdef int64_t j0 = <int64_t>floor(fx)
    cdef int64_t i0 = <int64_t>floor(fy)
    cdef double tx = fx - j0, ty = fy - i0, acc = 0.0, wsum = 0.0, wt
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
        return NAN
    return acc / wsum


def _bilinear(val_t a, const uint8_t[:, ::1] valid, double x, double y):
    """Bilinear interpolation at ``(x, y)`` (cell units, centres at half-integers) over valid samples
    only (weights renormalized); NaN when no corner is valid."""
    return _bilinear_c(a, valid, x, y)


def follow_interpolated(val_t value, val_t gx, val_t gy, mask_t free, double x0, double y0, double goal_x,
                        double goal_y, double step, double tolerance, int64_t max_iterations, double diag):
    """Follow ``-grad`` of a distance-like field (fast marching) with normalized steps.

    Positions are in cell units. A continuous step of length ``step`` along the bilinearly
    interpolated negative gradient is taken when it lands in a free cell reachable under the move
    rule and lowers the interpolated value; otherwise the follower moves to the centre of the
    lowest allowed neighbour cell (which always exists on a fast-marching field, whose values
    strictly increase away from the goal). Returns ``(points, status, iterations)`` with status
    0 reached, 1 stalled (no lower neighbour), 2 out of iterations.
    """
    cdef int64_t rows = value.shape[0], cols = value.shape[1], i, j
    validarr = np.empty((rows, cols), np.uint8)
    cdef uint8_t[:, ::1] valid = validarr
    for i in range(rows):
        for j in range(cols):
            valid[i, j] = free[i, j] and isfinite(value[i, j])
    cdef int64_t gr = <int64_t>floor(goal_y), gc = <int64_t>floor(goal_x)
    cdef int64_t cap = 256, m = 1, status = 2, it = 0, r, c, nr, nc, br, bc, dr, dc, rr, cc
    cdef double* pts = <double*>_alloc(2 * cap * sizeof(double))
    cdef double* t
    cdef double x = x0, y = y0, vx, vy, here, nrm, nx, ny, there, vu, best
    cdef bint moved, ok, oom = False
    pts[0] = x
    pts[1] = y
    with nogil:
        while it < max_iterations:
            r = <int64_t>floor(y)
            c = <int64_t>floor(x)
            if (r == gr and c == gc) or hypot(x - goal_x, y - goal_y) <= tolerance:
                status = 0
                break
            it += 1
            vx = _bilinear_c(gx, valid, x, y)
            vy = _bilinear_c(gy, valid, x, y)
            here = _bilinear_c(value, valid, x, y)
            moved = False
            nrm = hypot(vx, vy)
            if nrm > 0.0 and isfinite(nrm) and isfinite(here):
                nx = x - step * vx / nrm
                ny = y - step * vy / nrm
                nr = <int64_t>floor(ny)
                nc = <int64_t>floor(nx)
                ok = 0 <= nr < rows and 0 <= nc < cols and valid[nr, nc]
                if ok and nr != r and nc != c:  # crossed a cell corner: both orthogonal cells must be free
                    ok = free[nr, c] and free[r, nc]
                if ok:
                    there = _bilinear_c(value, valid, nx, ny)
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
            if m == cap:
                t = <double*>realloc(pts, 4 * cap * sizeof(double))
                if t == NULL:
                    oom = True
                    break
                pts = t
                cap *= 2
            pts[2 * m] = x
            pts[2 * m + 1] = y
            m += 1
    if oom:
        c_free(pts)
        raise MemoryError("follow_interpolated: out of memory")
    res = np.empty((m, 2))
    cdef double[:, ::1] rv = res
    for i in range(m):
        rv[i, 0] = pts[2 * i]
        rv[i, 1] = pts[2 * i + 1]
    c_free(pts)
    return res, status, it


def clearance_along(mask_t occupied, idx_t rows_idx, idx_t cols_idx, bint wall, int64_t budget):
    """Smallest Euclidean distance (in cells) from the centres of the given cells to the centre of an
    obstacle cell -- with ``wall``, the ring of cells just outside the grid counts as obstacle, as in
    :func:`gridfield.distance.brushfire.brushfire`. Searches Chebyshev rings around each cell, only out to the
    best distance found so far. Returns ``inf`` when there is no obstacle, and -1 when more than
    ``budget`` cells would have to be examined (the caller then uses a distance transform).
    """
    cdef double best
    with nogil:
        best = _clearance(occupied, rows_idx, cols_idx, wall, budget)
    return best


cdef double _clearance(mask_t occupied, idx_t rows_idx, idx_t cols_idx, bint wall, int64_t budget) noexcept nogil:
    cdef int64_t rows = occupied.shape[0], cols = occupied.shape[1], work = 0, i, r, c, k, t, side, rr, cc
    cdef int64_t kmax = (rows if rows > cols else cols) + 1
    cdef double best = INFINITY, d
    cdef bint hit
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
                        hit = occupied[rr, cc] != 0
                    else:
                        hit = wall and -1 <= rr <= rows and -1 <= cc <= cols
                    if hit:
                        d = sqrt(<double>((rr - r) * (rr - r) + (cc - c) * (cc - c)))
                        if d < best:
                            best = d
            work += 8 * k
            if work > budget:
                return -1.0
            k += 1
        if best == INFINITY:  # the rings covered the whole grid (and the wall ring): no obstacle at all
            return best
    return best
