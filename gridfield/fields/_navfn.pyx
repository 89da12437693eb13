# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.fields.navfn` (the NavFn navigation function and its gradient path)
and :class:`gridfield.fields.costmap.Costmap`'s point queries.

The arithmetic follows ROS 2 Nav2's ``nav2_navfn_planner`` (``navfn.cpp``, after Brock and
Konolige's planar-wave interpolation), written anew here: float32 potentials, the same priority
blocks and their capacity, the same order of updates, so that the potentials agree to the bit with
NavFn's on the same cost array. Arrays are flat, indexed ``row * nx + col`` (row 0 = lowest y, as
the costmap's), ``nx`` columns; the cost array is NavFn's (``COST_NEUTRAL + COST_FACTOR * cost``,
254 = blocked, its outer ring blocked). Nothing here validates input: :mod:`gridfield.fields.navfn` does.
"""

from libc.math cimport NAN, hypotf, isfinite, round as c_round
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free as c_free, malloc

import numpy as np

cdef float POT_HIGH = 1.0e10
cdef int COST_OBS = 254
cdef int COST_NEUTRAL = 50
cdef int BUF = 10000  # PRIORITYBUFSIZE: a block holds at most this many cells (more are dropped, as NavFn does)
cdef double INVSQRT2 = 0.707106781


cdef struct Blocks:
    int* cur
    int* nxt
    int* over
    int ncur
    int nnxt
    int nover
    float threshold


cdef inline void _push(int* buf, int* count, int n, int ns, uint8_t* pending, const uint8_t* cost) noexcept nogil:
    if n >= 0 and n < ns and not pending[n] and cost[n] < COST_OBS and count[0] < BUF:
        buf[count[0]] = n
        count[0] += 1
        pending[n] = 1


cdef inline void _push_in(int* buf, int* count, int n, uint8_t* pending, const uint8_t* cost) noexcept nogil:
    # _push for a neighbour of an updated cell: updated cells are inside the blocked ring, so n is in range
    if not pending[n] and cost[n] < COST_OBS and count[0] < BUF:
        buf[count[0]] = n
        count[0] += 1
        pending[n] = 1


cdef inline void _update(int n, int nx, int ns, float* pot, const uint8_t* cost, uint8_t* pending,
                         Blocks* b, const float* edge) noexcept nogil:
    cdef float l = pot[n - 1], r = pot[n + 1], u = pot[n - nx], d = pot[n + nx]
    cdef float lo_x = l if l < r else r
    cdef float lo_y = u if u < d else d
    cdef float hf, diff, base, p, v, ratio, le, re, ue, de
    if cost[n] >= COST_OBS:
        return
    hf = <float>cost[n]
    diff = lo_x - lo_y
    base = lo_y
    if diff < 0:
        diff = -diff
        base = lo_x
    if diff >= hf:
        p = base + hf  # one neighbour only
    else:
        ratio = diff / hf
        v = <float>(-0.2301 * ratio * ratio + 0.5307 * ratio + 0.7040)  # quadratic fit of the planar wave
        p = base + hf * v
    if p < pot[n]:
        le = edge[cost[n - 1]]  # (float)(INVSQRT2 * (float)cost), tabulated
        re = edge[cost[n + 1]]
        ue = edge[cost[n - nx]]
        de = edge[cost[n + nx]]
        pot[n] = p
        if p < b.threshold:
            if l > p + le:
                _push_in(b.nxt, &b.nnxt, n - 1, pending, cost)
            if r > p + re:
                _push_in(b.nxt, &b.nnxt, n + 1, pending, cost)
            if u > p + ue:
                _push_in(b.nxt, &b.nnxt, n - nx, pending, cost)
            if d > p + de:
                _push_in(b.nxt, &b.nnxt, n + nx, pending, cost)
        else:
            if l > p + le:
                _push_in(b.over, &b.nover, n - 1, pending, cost)
            if r > p + re:
                _push_in(b.over, &b.nover, n + 1, pending, cost)
            if u > p + ue:
                _push_in(b.over, &b.nover, n - nx, pending, cost)
            if d > p + de:
                _push_in(b.over, &b.nover, n + nx, pending, cost)


def navfn_costs(const uint8_t[:, ::1] cost, bint allow_unknown, int64_t clear_row, int64_t clear_col):
    """NavFn's cost array of costmap costs (``setCostmap`` after ``clearRobotCell``, then ``setupNavFn``'s
    blocked ring): ``50 + (int)(0.8 * c)`` below 253, 253 for unknown (255) with ``allow_unknown``, else 254."""
    cdef int64_t rows = cost.shape[0], cols = cost.shape[1], r, c
    cdef int v
    out = np.empty((rows, cols), dtype=np.uint8)
    cdef uint8_t[:, ::1] o = out
    with nogil:
        for r in range(rows):
            for c in range(cols):
                v = cost[r, c]
                if r == clear_row and c == clear_col:
                    v = 0
                if v < 253:
                    v = <int>(COST_NEUTRAL + 0.8 * v)
                    o[r, c] = <uint8_t>(v if v < COST_OBS else COST_OBS - 1)
                elif v == 255 and allow_unknown:
                    o[r, c] = COST_OBS - 1
                else:
                    o[r, c] = COST_OBS
        for c in range(cols):
            o[0, c] = COST_OBS
            o[rows - 1, c] = COST_OBS
        for r in range(rows):
            o[r, 0] = COST_OBS
            o[r, cols - 1] = COST_OBS
    return out


def propagate(const uint8_t[::1] cost, int nx, int ny, int source, int target, bint stop_at_target,
              int cycles):
    """NavFn's Dijkstra propagation (``propNavFnDijkstra``) from the cell ``source`` (potential 0).

    Parameters
    ----------
    cost : uint8, shape (nx * ny,)
        NavFn's cost array (outer ring 254).
    source, target : int
        Flat indices: the propagation starts at ``source``; with ``stop_at_target`` it stops after
        the first cycle that gives ``target`` a potential.
    cycles : int
        Cycle limit (NavFn: ``max(nx * ny / 20, nx + ny)``).

    Returns
    -------
    (ndarray of float32, int, bool)
        The potentials (1e10 where unassigned), the cycles run, whether it ended before the limit.
    """
    cdef int ns = nx * ny
    pot_arr = np.full(ns, POT_HIGH, dtype=np.float32)
    cdef float[::1] potv = pot_arr
    cdef float* pot = &potv[0]
    cdef const uint8_t* c = &cost[0]
    cdef uint8_t* pending = <uint8_t*>malloc(ns if ns > 0 else 1)
    cdef int* b1 = <int*>malloc(BUF * sizeof(int))
    cdef int* b2 = <int*>malloc(BUF * sizeof(int))
    cdef int* b3 = <int*>malloc(BUF * sizeof(int))
    cdef int* tmp
    cdef Blocks b
    cdef float edge[256]
    cdef int cycle = 0, i, k
    if pending == NULL or b1 == NULL or b2 == NULL or b3 == NULL:
        c_free(pending); c_free(b1); c_free(b2); c_free(b3)
        raise MemoryError("navfn: cannot allocate the propagation buffers")
    with nogil:
        for i in range(256):
            edge[i] = <float>(INVSQRT2 * <float>i)
        for i in range(ns):
            pending[i] = 0
        b.cur = b1
        b.nxt = b2
        b.over = b3
        b.ncur = 0
        b.nnxt = 0
        b.nover = 0
        b.threshold = <float>COST_OBS
        pot[source] = 0.0
        _push(b.cur, &b.ncur, source + 1, ns, pending, c)
        _push(b.cur, &b.ncur, source - 1, ns, pending, c)
        _push(b.cur, &b.ncur, source - nx, ns, pending, c)
        _push(b.cur, &b.ncur, source + nx, ns, pending, c)
        while cycle < cycles:
            if b.ncur == 0 and b.nnxt == 0:
                break
            for i in range(b.ncur):
                pending[b.cur[i]] = 0
            for i in range(b.ncur):
                _update(b.cur[i], nx, ns, pot, c, pending, &b, edge)
            b.ncur = b.nnxt
            b.nnxt = 0
            tmp = b.cur
            b.cur = b.nxt
            b.nxt = tmp
            if b.ncur == 0:
                b.threshold += 2 * COST_NEUTRAL  # priInc
                b.ncur = b.nover
                b.nover = 0
                tmp = b.cur
                b.cur = b.over
                b.over = tmp
            if stop_at_target and pot[target] < POT_HIGH:
                break
            cycle += 1
    c_free(pending)
    c_free(b1)
    c_free(b2)
    c_free(b3)
    return pot_arr, cycle, cycle < cycles


cdef inline float _grad(const float* pot, int n, int nx, int ns, float* gy) noexcept nogil:
    """NavFn's ``gradCell``: the normalized gradient at cell ``n`` (x returned, y in gy[0]); 0, 0 when flat."""
    cdef float cv, dx = 0.0, dy = 0.0, norm
    gy[0] = 0.0
    if n < nx or n > ns - nx:
        return 0.0
    cv = pot[n]
    if cv >= POT_HIGH:
        if pot[n - 1] < POT_HIGH:
            dx = -COST_OBS
        elif pot[n + 1] < POT_HIGH:
            dx = COST_OBS
        if pot[n - nx] < POT_HIGH:
            dy = -COST_OBS
        elif pot[n + nx] < POT_HIGH:
            dy = COST_OBS
    else:
        if pot[n - 1] < POT_HIGH:
            dx += pot[n - 1] - cv
        if pot[n + 1] < POT_HIGH:
            dx += cv - pot[n + 1]
        if pot[n - nx] < POT_HIGH:
            dy += pot[n - nx] - cv
        if pot[n + nx] < POT_HIGH:
            dy += cv - pot[n + nx]
    norm = hypotf(dx, dy)
    if norm > 0:
        norm = <float>(1.0 / norm)
        gy[0] = norm * dy
        return norm * dx
    return 0.0


cdef inline int _trunc_int(float v) noexcept nogil:
    # C's float -> int conversion; out of range gives INT_MIN as x86 does (NavFn's `int minp = potarr[...]`)
    if v >= 2147483648.0 or v < -2147483648.0 or v != v:
        return -2147483647 - 1
    return <int>v


def gradient_path(const float[::1] pot, int nx, int ny, int from_x, int from_y, int to_x, int to_y, int max_steps,
                  float step=0.5):
    """NavFn's ``calcPath``: half-cell steps down the bilinearly interpolated normalized gradient.

    Parameters
    ----------
    pot : float32, shape (nx * ny,)
        Potentials of :func:`propagate` (0 at ``(to_x, to_y)``).
    from_x, from_y : int
        Cell (column, row) the path starts from.
    to_x, to_y : int
        The cell of potential 0: the path's last point.
    max_steps : int
        Step limit (Nav2: ``max(nx, ny) * max_cycles_factor``, 4).

    Returns
    -------
    (ndarray of float32, shape (k, 2), int)
        The points ``(x, y)`` in cells (a cell's index at its centre), and a status: 0 reached,
        1 out of bounds, 2 no path (high potential), 3 zero gradient, 4 out of steps. Only status 0
        keeps the points (NavFn returns no path otherwise).
    """
    cdef int ns = nx * ny
    out = np.zeros((max(max_steps, 1), 2), dtype=np.float32)
    cdef float[:, ::1] o = out
    cdef const float* p = &pot[0]
    cdef int stc = from_y * nx + from_x
    cdef float dx = 0.0, dy = 0.0, x1, x2, y1, y2, gx, gy, ss
    cdef float g00x, g01x, g10x, g11x, g00y, g01y, g10y, g11y, tmp
    cdef int npath = 0, i, nearest, stcnx, stcpx, minc, minp, sti, k, status = 4
    cdef bint osc
    with nogil:
        for i in range(max_steps):
            nearest = stc + <int>c_round(dx) + <int>(nx * c_round(dy))
            if nearest > ns - 1:
                nearest = ns - 1
            if nearest < 0:
                nearest = 0
            if p[nearest] < COST_NEUTRAL:
                o[npath, 0] = <float>to_x
                o[npath, 1] = <float>to_y
                npath += 1
                status = 0
                break
            if stc < nx or stc > ns - nx:
                status = 1
                break
            o[npath, 0] = stc % nx + dx
            o[npath, 1] = stc // nx + dy
            npath += 1
            osc = npath > 2 and o[npath - 1, 0] == o[npath - 3, 0] and o[npath - 1, 1] == o[npath - 3, 1]
            stcnx = stc + nx
            stcpx = stc - nx
            if (p[stc] >= POT_HIGH or p[stc + 1] >= POT_HIGH or p[stc - 1] >= POT_HIGH or p[stcnx] >= POT_HIGH
                    or p[stcnx + 1] >= POT_HIGH or p[stcnx - 1] >= POT_HIGH or p[stcpx] >= POT_HIGH
                    or p[stcpx + 1] >= POT_HIGH or p[stcpx - 1] >= POT_HIGH or osc):
                # next to unassigned cells (or oscillating): step to the lowest of the 8 neighbours
                minc = stc
                minp = _trunc_int(p[stc])
                for k in range(8):
                    if k < 3:
                        sti = stcpx - 1 + k
                    elif k == 3:
                        sti = stc - 1
                    elif k == 4:
                        sti = stc + 1
                    else:
                        sti = stcnx - 1 + (k - 5)
                    if p[sti] < <float>minp:
                        minp = _trunc_int(p[sti])
                        minc = sti
                stc = minc
                dx = 0.0
                dy = 0.0
                if p[stc] >= POT_HIGH:
                    status = 2
                    break
            else:
                g00x = _grad(p, stc, nx, ns, &g00y)
                g01x = _grad(p, stc + 1, nx, ns, &g01y)
                g10x = _grad(p, stcnx, nx, ns, &g10y)
                g11x = _grad(p, stcnx + 1, nx, ns, &g11y)
                x1 = <float>((1.0 - dx) * g00x + dx * g01x)
                x2 = <float>((1.0 - dx) * g10x + dx * g11x)
                gx = <float>((1.0 - dy) * x1 + dy * x2)
                y1 = <float>((1.0 - dx) * g00y + dx * g01y)
                y2 = <float>((1.0 - dx) * g10y + dx * g11y)
                gy = <float>((1.0 - dy) * y1 + dy * y2)
                if gx == 0.0 and gy == 0.0:
                    status = 3
                    break
                ss = step / hypotf(gx, gy)
                dx += gx * ss
                dy += gy * ss
                if dx > 1.0:
                    stc += 1
                    dx -= 1.0
                if dx < -1.0:
                    stc -= 1
                    dx += 1.0
                if dy > 1.0:
                    stc += nx
                    dy -= 1.0
                if dy < -1.0:
                    stc -= nx
                    dy += 1.0
    return out[:npath].copy(), status


# ----------------------------------------------------------------------------------------------
# Costmap queries (gridfield.fields.costmap.Costmap): many points, one pass each
# ----------------------------------------------------------------------------------------------

cdef inline double _floor(double t) noexcept nogil:
    """floor(t) for finite |t| < 2**62 without a libm call (the baseline x86-64 has no rounding instruction)."""
    cdef double i = <double><int64_t>t
    return i - 1.0 if i > t else i


cdef inline int64_t _cell(double v, double origin, double res, double inv) noexcept nogil:
    """gridfield.core.grid._cell_index for one value: the cell of the boundaries origin + i * res as computed in
    floating point (a first guess from the reciprocal ``inv``, then corrected as _cell_index corrects)."""
    cdef double t = (v - origin) * inv
    cdef double i
    if t < -1.0:
        return -1
    if t > 4.0e18:
        return <int64_t>4.0e18
    i = _floor(t)
    if v >= origin + (i + 1) * res:
        i += 1
    if v < origin + i * res:
        i -= 1
    if i < -1.0:
        return -1
    if i > 4.0e18:
        return <int64_t>4.0e18
    return <int64_t>i


cdef inline bint _corners(double x, double y, double x0, double y0, double res, int64_t rows, int64_t cols,
                          int64_t* r0, int64_t* r1, int64_t* c0, int64_t* c1, double* tx, double* ty) noexcept nogil:
    """The four cell centres round (x, y) and the bilinear weights (clamped at the outer centres);
    False when the point is outside the grid."""
    cdef int64_t r, c
    cdef double fx, fy
    if not (isfinite(x) and isfinite(y)):
        return False
    cdef double inv = 1.0 / res
    r = _cell(y, y0, res, inv)
    c = _cell(x, x0, res, inv)
    if r < 0 or r >= rows or c < 0 or c >= cols:
        return False
    fx = (x - x0) * inv - 0.5
    fy = (y - y0) * inv - 0.5
    if fx < 0:
        fx = 0
    if fx > cols - 1:
        fx = cols - 1
    if fy < 0:
        fy = 0
    if fy > rows - 1:
        fy = rows - 1
    c0[0] = <int64_t>fx  # fx, fy >= 0: truncation is floor
    r0[0] = <int64_t>fy
    if c0[0] > cols - 2:
        c0[0] = cols - 2 if cols >= 2 else 0
    if r0[0] > rows - 2:
        r0[0] = rows - 2 if rows >= 2 else 0
    c1[0] = c0[0] + 1 if c0[0] + 1 < cols else cols - 1
    r1[0] = r0[0] + 1 if r0[0] + 1 < rows else rows - 1
    tx[0] = fx - c0[0]
    ty[0] = fy - r0[0]
    return True


def query_cost(const uint8_t[:, ::1] cost, const double[:, ::1] pts, double x0, double y0, double res):
    """The cost of the cell holding each point; 255 outside."""
    cdef int64_t n = pts.shape[0], rows = cost.shape[0], cols = cost.shape[1], i, r, c
    cdef double inv = 1.0 / res
    out = np.empty(n, dtype=np.uint8)
    cdef uint8_t[::1] o = out
    with nogil:
        for i in range(n):
            o[i] = 255
            if isfinite(pts[i, 0]) and isfinite(pts[i, 1]):
                r = _cell(pts[i, 1], y0, res, inv)
                c = _cell(pts[i, 0], x0, res, inv)
                if 0 <= r < rows and 0 <= c < cols:
                    o[i] = cost[r, c]
    return out


def query_bilinear(const double[:, ::1] a, const double[:, ::1] b, const double[:, ::1] pts, double x0, double y0,
                   double res, bint two):
    """Bilinear interpolation of ``a`` (and of ``b`` when ``two``) between the cell centres; nan outside.
    Returns shape (N,) or, with ``two``, (N, 2)."""
    cdef int64_t n = pts.shape[0], rows = a.shape[0], cols = a.shape[1], i, r0, r1, c0, c1
    cdef double tx, ty
    out = np.empty((n, 2 if two else 1))
    cdef double[:, ::1] o = out
    with nogil:
        for i in range(n):
            if _corners(pts[i, 0], pts[i, 1], x0, y0, res, rows, cols, &r0, &r1, &c0, &c1, &tx, &ty):
                o[i, 0] = ((a[r0, c0] * (1 - tx) + a[r0, c1] * tx) * (1 - ty)
                           + (a[r1, c0] * (1 - tx) + a[r1, c1] * tx) * ty)
                if two:
                    o[i, 1] = ((b[r0, c0] * (1 - tx) + b[r0, c1] * tx) * (1 - ty)
                               + (b[r1, c0] * (1 - tx) + b[r1, c1] * tx) * ty)
            else:
                o[i, 0] = NAN
                if two:
                    o[i, 1] = NAN
    return out if two else out[:, 0]


def query_nearest(const int32_t[:, ::1] nr, const int32_t[:, ::1] nc, const double[:, ::1] pts, double x0, double y0,
                  double res):
    """Of the nearest obstacle cells of the four centres round each point, the centre nearest the point."""
    cdef int64_t n = pts.shape[0], rows = nr.shape[0], cols = nr.shape[1], i, k, r0, r1, c0, c1, rr, cc
    cdef double tx, ty, best, ox, oy, d2
    out = np.full((n, 2), NAN)
    cdef double[:, ::1] o = out
    with nogil:
        for i in range(n):
            if not _corners(pts[i, 0], pts[i, 1], x0, y0, res, rows, cols, &r0, &r1, &c0, &c1, &tx, &ty):
                continue
            best = 1.0e308
            for k in range(4):
                rr = r0 if k < 2 else r1
                cc = c0 if k % 2 == 0 else c1
                if nr[rr, cc] < 0:
                    continue
                ox = x0 + (nc[rr, cc] + 0.5) * res
                oy = y0 + (nr[rr, cc] + 0.5) * res
                d2 = (ox - pts[i, 0]) * (ox - pts[i, 0]) + (oy - pts[i, 1]) * (oy - pts[i, 1])
                if d2 < best:
                    best = d2
                    o[i, 0] = ox
                    o[i, 1] = oy
    return out
