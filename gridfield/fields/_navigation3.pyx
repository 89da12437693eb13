# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels of the voxel (3-D) navigation: :mod:`gridfield.fields.navigation3d` and
:mod:`gridfield.following.follow3d` (Cython, compiled at install; imported lazily).

Arrays are indexed ``[a0, a1, a2]`` (``[layer, row, col]`` = ``[z, y, x]`` for a voxel grid); a
point in *cell units* is ``(q0, q1, q2)`` with ``q_a = (coordinate_a - origin_a) / resolution`` in
the same axis order, so voxel ``i`` spans ``[i, i + 1)`` on each axis and its centre is ``i + 0.5``.
Nothing here validates input; the Python modules do.

Move rule (Moving AI 3-D, Brewer & Sturtevant 2018): a move between two voxels of the
26-neighbourhood is allowed only when every voxel of their bounding box is free (both ends, the two
side voxels of a 2-axis diagonal, all eight voxels of the 2x2x2 block of a 3-axis diagonal). That is
exactly the set of voxels whose *closed* cube the straight segment between the two centres touches,
so the discrete moves and the exact segment test (:func:`segment_clear`) agree. The rule is
symmetric: a wavefront from the goal gives the distance *to* the goal.

Options ready for an (x, y, theta) planner: per-axis ``spacing`` (a move costs
``sqrt(sum (spacing_a d_a)^2)``), a periodic axis 0 (index ``-1`` is ``n0 - 1``), and a per-voxel
slowness (a move costs its length times the mean slowness of its two ends).
"""

from libc.math cimport INFINITY, floor, sqrt
from libc.stdint cimport int32_t, int64_t, uint8_t, uint32_t
from libc.stdlib cimport free as c_free, malloc, realloc

import numpy as np

ctypedef const uint8_t[:, :, :] mask3_t
ctypedef const double[:, :, :] val3_t


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


# ----------------------------------------------------------------------------------------------
# the 26-neighbourhood: position j = 9 (dz + 1) + 3 (dy + 1) + (dx + 1); the bounding-box masks
# ----------------------------------------------------------------------------------------------
cdef uint32_t _REQ[27]
cdef int _DZ[27]
cdef int _DY[27]
cdef int _DX[27]


cdef void _init_moves() noexcept:
    cdef int j, a, b, c, ea, eb, ec
    cdef uint32_t m
    for j in range(27):
        a = j // 9 - 1
        b = (j // 3) % 3 - 1
        c = j % 3 - 1
        _DZ[j] = a
        _DY[j] = b
        _DX[j] = c
        m = 0
        for ea in range(2):
            for eb in range(2):
                for ec in range(2):
                    m |= (<uint32_t>1) << (9 * (ea * a + 1) + 3 * (eb * b + 1) + (ec * c + 1))
        _REQ[j] = m


_init_moves()


# ----------------------------------------------------------------------------------------------
# an indexed binary min-heap (keys inline, positions per voxel: decrease-key, no stale entries)
# ----------------------------------------------------------------------------------------------
cdef struct Heap:
    double* key
    int32_t* item
    int32_t* pos  # per voxel: -1 never queued, -2 settled, else its index in the heap
    int64_t n
    int64_t cap


cdef inline void _sift_up(Heap* h, int64_t i) noexcept nogil:
    cdef double k = h.key[i]
    cdef int32_t v = h.item[i]
    cdef int64_t p
    while i > 0:
        p = (i - 1) >> 1
        if h.key[p] <= k:
            break
        h.key[i] = h.key[p]
        h.item[i] = h.item[p]
        h.pos[h.item[i]] = <int32_t>i
        i = p
    h.key[i] = k
    h.item[i] = v
    h.pos[v] = <int32_t>i


cdef inline void _sift_down(Heap* h, int64_t i) noexcept nogil:
    cdef double k = h.key[i]
    cdef int32_t v = h.item[i]
    cdef int64_t c, n = h.n
    while True:
        c = 2 * i + 1
        if c >= n:
            break
        if c + 1 < n and h.key[c + 1] < h.key[c]:
            c += 1
        if h.key[c] >= k:
            break
        h.key[i] = h.key[c]
        h.item[i] = h.item[c]
        h.pos[h.item[i]] = <int32_t>i
        i = c
    h.key[i] = k
    h.item[i] = v
    h.pos[v] = <int32_t>i


cdef inline bint _push(Heap* h, int32_t v, double k) noexcept nogil:
    """Queue ``v`` with key ``k`` or lower its key; False when out of memory."""
    cdef int64_t i = h.pos[v], nc
    cdef double* tk
    cdef int32_t* ti
    if i >= 0:
        h.key[i] = k
        _sift_up(h, i)
        return True
    if h.n == h.cap:
        nc = 2 * h.cap
        tk = <double*>realloc(h.key, nc * sizeof(double))
        if tk == NULL:
            return False
        h.key = tk
        ti = <int32_t*>realloc(h.item, nc * sizeof(int32_t))
        if ti == NULL:
            return False
        h.item = ti
        h.cap = nc
    h.key[h.n] = k
    h.item[h.n] = v
    h.n += 1
    _sift_up(h, h.n - 1)
    return True


cdef inline int32_t _pop(Heap* h) noexcept nogil:
    cdef int32_t v = h.item[0]
    h.n -= 1
    if h.n > 0:
        h.key[0] = h.key[h.n]
        h.item[0] = h.item[h.n]
        _sift_down(h, 0)
    h.pos[v] = -2
    return v


# ----------------------------------------------------------------------------------------------
# the wavefront
# ----------------------------------------------------------------------------------------------
#: The circular bucket queue is used while the largest move cost is at most this many times the
#: smallest (costs 1 .. sqrt 3 with a bounded slowness); beyond, the binary heap.
cdef int64_t MAX_BUCKETS = 64


cdef inline void _offsets(int64_t* off, int64_t u, bint periodic, int64_t n0, int64_t plane,
                          int64_t C) noexcept nogil:
    """The 27 neighbour offsets of ``u`` (periodic axis 0: the wrap at the first and last layer)."""
    cdef int64_t k = u // plane, o
    cdef int j
    for j in range(27):
        o = _DZ[j] * plane
        if k == 0 and _DZ[j] < 0:
            o = (n0 - 1) * plane
        elif k == n0 - 1 and _DZ[j] > 0:
            o = -(n0 - 1) * plane
        off[j] = o + _DY[j] * C + _DX[j]


cdef inline uint32_t _free_mask(const uint8_t* f, int64_t u, const int64_t* off) noexcept nogil:
    cdef uint32_t mask = 0
    cdef int j
    for j in range(27):
        mask |= (<uint32_t>(f[u + off[j]] & 1)) << j
    return mask


cdef bint _buckets(uint8_t* f, double* dist, const double* slow, int64_t* off, const double* length,
                   int64_t g, int64_t stop, double margin, double width, int64_t nb, bint periodic,
                   int64_t n0, int64_t plane, int64_t C) noexcept nogil:
    """Dijkstra with a circular bucket queue (Dial): bucket ``b`` holds voxels of value in
    ``[b width, (b + 1) width)``, ``width`` the smallest move cost, so a bucket's voxels are final when
    it is reached and need no ordering; ``nb`` buckets are live at most. Settled voxels get bit 2 of
    ``f``. Returns True when out of memory."""
    cdef int32_t** slot = <int32_t**>_alloc(nb * sizeof(int32_t*))
    cdef int64_t* size = <int64_t*>_alloc(nb * sizeof(int64_t))
    cdef int64_t* cap = <int64_t*>_alloc(nb * sizeof(int64_t))
    cdef int64_t i, j, s, b, kb = 0, queued = 1, u, v, bo, bn, sz
    cdef int32_t* cur
    cdef int32_t* t
    cdef double du, nd, old, limit = INFINITY, su = 1.0, inv = 1.0 / width
    cdef uint32_t mask
    cdef bint oom = False
    for i in range(nb):
        cap[i] = 1024
        size[i] = 0
        slot[i] = <int32_t*>_alloc(cap[i] * sizeof(int32_t))
    dist[g] = 0.0
    slot[0][0] = <int32_t>g
    size[0] = 1
    while queued > 0 and not oom:
        if kb * width > limit:
            break
        s = kb & (nb - 1)
        cur = slot[s]
        sz = size[s]
        for i in range(sz):
            u = cur[i]
            if f[u] & 2:
                continue
            f[u] |= 2
            du = dist[u]
            if u == stop:
                limit = du + margin
            if periodic:
                _offsets(off, u, periodic, n0, plane, C)
            mask = _free_mask(f, u, off)
            if slow != NULL:
                su = slow[u]
            for j in range(27):
                if j == 13 or (mask & _REQ[j]) != _REQ[j]:
                    continue
                v = u + off[j]
                if slow != NULL:
                    nd = du + length[j] * 0.5 * (su + slow[v])
                else:
                    nd = du + length[j]
                old = dist[v]  # a settled voxel is never improved: its value is below du + width
                if nd < old:
                    dist[v] = nd
                    bn = <int64_t>(nd * inv)
                    if bn <= kb:
                        bn = kb + 1
                    if old != INFINITY:
                        bo = <int64_t>(old * inv)
                        if bo <= kb:
                            bo = kb + 1
                        if bo == bn:
                            continue
                    b = bn & (nb - 1)
                    if size[b] == cap[b]:
                        t = <int32_t*>realloc(slot[b], 2 * cap[b] * sizeof(int32_t))
                        if t == NULL:
                            oom = True
                            break
                        slot[b] = t
                        cap[b] *= 2
                    slot[b][size[b]] = <int32_t>v
                    size[b] += 1
                    queued += 1
            if oom:
                break
        queued -= sz
        size[s] = 0
        kb += 1
    for i in range(nb):
        c_free(slot[i])
    c_free(slot)
    c_free(size)
    c_free(cap)
    return oom


cdef bint _heap_search(uint8_t* f, double* dist, const double* slow, int64_t* off, const double* length,
                       int64_t g, int64_t stop, double margin, bint periodic, int64_t n0, int64_t plane,
                       int64_t C, Heap* h) noexcept nogil:
    """Dijkstra with the indexed binary heap ``h`` (any positive costs). Settled voxels get bit 2 of
    ``f``. Returns True when out of memory."""
    cdef int64_t u, v
    cdef int j
    cdef double du, nd, limit = INFINITY, su = 1.0
    cdef uint32_t mask
    dist[g] = 0.0
    if not _push(h, <int32_t>g, 0.0):
        return True
    while h.n > 0:
        if h.key[0] > limit:
            break
        u = _pop(h)
        f[u] |= 2
        du = dist[u]
        if u == stop:
            limit = du + margin
        if periodic:
            _offsets(off, u, periodic, n0, plane, C)
        mask = _free_mask(f, u, off)
        if slow != NULL:
            su = slow[u]
        for j in range(27):
            if j == 13 or (mask & _REQ[j]) != _REQ[j]:
                continue
            v = u + off[j]
            if f[v] & 2:
                continue
            if slow != NULL:
                nd = du + length[j] * 0.5 * (su + slow[v])
            else:
                nd = du + length[j]
            if nd < dist[v]:
                dist[v] = nd
                if not _push(h, <int32_t>v, nd):
                    return True
    return False


def wavefront3(mask3_t free, int64_t g0, int64_t g1, int64_t g2, double s0, double s1, double s2,
               bint periodic, val3_t slowness, int64_t t0, int64_t t1, int64_t t2, double margin):
    """Dijkstra from voxel ``(g0, g1, g2)`` over the 26-neighbourhood under the bounding-box rule.

    Parameters (all in array order): ``free`` (uint8 mask), the goal voxel, the spacings ``s0, s1, s2``
    (a move ``d`` costs ``sqrt(sum (s_a d_a)^2)``, in the unit of the result), ``periodic`` (axis 0
    wraps), ``slowness`` (shape of ``free``, or ``(0, 0, 0)`` for none: a move costs its length times
    the mean slowness of its ends), the stop voxel (``t0 < 0``: none; else the search ends once every
    voxel of value up to the stop voxel's plus ``margin`` is settled).

    Returns the float64 values, shape of ``free``: ``inf`` on blocked, unreached and (with a stop voxel)
    unsettled voxels. Raises MemoryError when the heap cannot grow.
    """
    cdef int64_t n0 = free.shape[0], n1 = free.shape[1], n2 = free.shape[2]
    cdef int64_t p0 = 0 if periodic else 1
    cdef int64_t L = n0 + 2 * p0, R = n1 + 2, C = n2 + 2, plane = R * C, n = L * plane
    cdef int64_t i, j, k, r, c, u, base, stop = -1
    cdef int64_t off[27]
    cdef double length[27]
    cdef uint8_t* f
    cdef double* dist
    cdef double* slow = NULL
    cdef bint use_slow = slowness.shape[0] != 0, oom = False
    cdef double lmin, lmax, smin, smax, width
    cdef int64_t nb
    cdef Heap h
    out = np.empty((n0, n1, n2))
    cdef double[:, :, ::1] o3 = out
    if n >= (<int64_t>1 << 31) - 1:
        raise MemoryError("the voxel grid is too large for the wavefront's 32-bit voxel indices")
    with nogil:
        f = <uint8_t*>_alloc(n)
        dist = <double*>_alloc(n * sizeof(double))
        h.pos = NULL
        h.key = NULL
        h.item = NULL
        if use_slow:
            slow = <double*>_alloc(n * sizeof(double))
        for i in range(n):
            f[i] = 0
            dist[i] = INFINITY
        for k in range(n0):
            for r in range(n1):
                base = (k + p0) * plane + (r + 1) * C + 1
                for c in range(n2):
                    if free[k, r, c]:
                        f[base + c] = 1
                    if use_slow:
                        slow[base + c] = slowness[k, r, c]
        for j in range(27):
            length[j] = sqrt((s0 * _DZ[j]) ** 2 + (s1 * _DY[j]) ** 2 + (s2 * _DX[j]) ** 2)
            off[j] = _DZ[j] * plane + _DY[j] * C + _DX[j]
        if t0 >= 0:
            stop = (t0 + p0) * plane + (t1 + 1) * C + t2 + 1
        u = (g0 + p0) * plane + (g1 + 1) * C + g2 + 1
        lmin = INFINITY
        lmax = 0.0
        for j in range(27):
            if j != 13:
                lmin = min(lmin, length[j])
                lmax = max(lmax, length[j])
        smin = smax = 1.0
        if use_slow:
            smin = INFINITY
            smax = 0.0
            for i in range(n):
                if f[i]:
                    smin = min(smin, slow[i])
                    smax = max(smax, slow[i])
        width = lmin * smin
        nb = <int64_t>(lmax * smax / width) + 2 if width > 0 else 1 << 30
        if nb <= MAX_BUCKETS:
            k = 1
            while k < nb:
                k *= 2
            nb = k  # a power of two: the ring's index is a mask
        if f[u] and nb <= MAX_BUCKETS:
            oom = _buckets(f, dist, slow, off, length, u, stop, margin, width, nb, periodic, n0, plane, C)
        elif f[u]:
            h.pos = <int32_t*>_alloc(n * sizeof(int32_t))
            h.cap = 4096
            h.n = 0
            h.key = <double*>_alloc(h.cap * sizeof(double))
            h.item = <int32_t*>_alloc(h.cap * sizeof(int32_t))
            for i in range(n):
                h.pos[i] = -1
            oom = _heap_search(f, dist, slow, off, length, u, stop, margin, periodic, n0, plane, C, &h)
        if not oom:
            for k in range(n0):
                for r in range(n1):
                    base = (k + p0) * plane + (r + 1) * C + 1
                    for c in range(n2):
                        o3[k, r, c] = dist[base + c] if f[base + c] & 2 else INFINITY
        c_free(f)
        c_free(dist)
        if h.pos != NULL:
            c_free(h.pos)
            c_free(h.key)
            c_free(h.item)
        if slow != NULL:
            c_free(slow)
    if oom:
        raise MemoryError("out of memory in the voxel wavefront's queue")
    return out


# ----------------------------------------------------------------------------------------------
# moves and the discrete descent
# ----------------------------------------------------------------------------------------------
cdef inline bint _voxel_free(mask3_t free, int64_t k, int64_t r, int64_t c, bint periodic) noexcept nogil:
    cdef int64_t n0 = free.shape[0]
    if periodic:
        k = (k % n0 + n0) % n0
    elif k < 0 or k >= n0:
        return False
    if r < 0 or r >= free.shape[1] or c < 0 or c >= free.shape[2]:
        return False
    return free[k, r, c] != 0


cdef inline bint _move_ok(mask3_t free, int64_t k, int64_t r, int64_t c, int a, int b, int d,
                          bint periodic) noexcept nogil:
    """Whether the move ``(a, b, d)`` from ``(k, r, c)`` keeps its bounding box in free voxels."""
    cdef int ea, eb, ed
    for ea in range(2):
        for eb in range(2):
            for ed in range(2):
                if not _voxel_free(free, k + ea * a, r + eb * b, c + ed * d, periodic):
                    return False
    return True


def move_allowed(mask3_t free, int64_t k, int64_t r, int64_t c, int a, int b, int d, bint periodic=False):
    """Python access to the move rule (tests, callers that check one move)."""
    return _move_ok(free, k, r, c, a, b, d, periodic)


def descend3(val3_t value, mask3_t free, int64_t k, int64_t r, int64_t c, bint periodic=False,
             bint parent=False, double s0=1.0, double s1=1.0, double s2=1.0, val3_t slowness=None):
    """Discrete descent from voxel ``(k, r, c)``: repeatedly to the allowed neighbour of the lowest value
    (strictly lower than the current one; ties to the first in the order ``dz, dy, dx = -1..1``). With
    ``parent``, to the allowed lower neighbour minimizing value + move cost (spacings ``s0, s1, s2`` and
    the ``slowness`` of the wavefront, ``None`` or ``(0, 0, 0)`` for none): a shortest-path parent, so the
    chain costs the start's value.

    Returns ``(cells, reached)``: the int64 ``(n, 3)`` chain from the start voxel (included) to where it
    ended, and whether that voxel has value 0 (the goal of a wavefront).
    """
    cdef int64_t n0 = value.shape[0], cap = 256, m = 1, bk, br, bc, nk, nr, nc
    cdef int j
    cdef double best, here, w, key, bkey
    cdef double length[27]
    cdef bint use_slow = slowness is not None and slowness.shape[0] != 0
    if slowness is None:
        slowness = np.zeros((0, 0, 0))
    for j in range(27):
        length[j] = sqrt((s0 * _DZ[j]) ** 2 + (s1 * _DY[j]) ** 2 + (s2 * _DX[j]) ** 2)
    cdef int64_t* buf = <int64_t*>_alloc(3 * cap * sizeof(int64_t))
    cdef int64_t* t
    cdef bint oom = False
    with nogil:
        buf[0] = k
        buf[1] = r
        buf[2] = c
        here = value[k, r, c]
        while here > 0.0:
            best = here
            bkey = INFINITY
            bk = -1
            for j in range(27):
                if j == 13:
                    continue
                nk = k + _DZ[j]
                nr = r + _DY[j]
                nc = c + _DX[j]
                if periodic:
                    nk = (nk % n0 + n0) % n0
                elif nk < 0 or nk >= n0:
                    continue
                if nr < 0 or nr >= value.shape[1] or nc < 0 or nc >= value.shape[2]:
                    continue
                w = value[nk, nr, nc]
                if not (w < here):
                    continue
                if parent:
                    key = w + length[j] * (0.5 * (slowness[k, r, c] + slowness[nk, nr, nc]) if use_slow else 1.0)
                else:
                    key = w
                if key < bkey and _move_ok(free, k, r, c, _DZ[j], _DY[j], _DX[j], periodic):
                    bkey = key
                    best = w
                    bk = nk
                    br = nr
                    bc = nc
            if bk < 0:
                break
            if m == cap:
                t = <int64_t*>realloc(buf, 6 * cap * sizeof(int64_t))
                if t == NULL:
                    oom = True
                    break
                buf = t
                cap *= 2
            k = bk
            r = br
            c = bc
            buf[3 * m] = k
            buf[3 * m + 1] = r
            buf[3 * m + 2] = c
            m += 1
            here = best
    if oom:
        c_free(buf)
        raise MemoryError("out of memory in the voxel descent")
    cells = np.empty((m, 3), np.int64)
    cdef int64_t[:, ::1] cv = cells
    for j in range(m):
        cv[j, 0] = buf[3 * j]
        cv[j, 1] = buf[3 * j + 1]
        cv[j, 2] = buf[3 * j + 2]
    c_free(buf)
    return cells, here == 0.0


# ----------------------------------------------------------------------------------------------
# the exact segment test
# ----------------------------------------------------------------------------------------------
cdef inline bint _touches(double* p, double* d, int64_t i0, int64_t i1, int64_t i2) noexcept nogil:
    """Whether the segment ``p + t d``, ``t in [0, 1]``, meets the closed cube of voxel ``(i0, i1, i2)``."""
    cdef double lo = 0.0, hi = 1.0, a, b, tmp
    cdef int64_t idx[3]
    cdef int ax
    idx[0] = i0
    idx[1] = i1
    idx[2] = i2
    for ax in range(3):
        if d[ax] == 0.0:
            if p[ax] < idx[ax] or p[ax] > idx[ax] + 1:
                return False
        else:
            a = (idx[ax] - p[ax]) / d[ax]
            b = (idx[ax] + 1 - p[ax]) / d[ax]
            if a > b:
                tmp = a
                a = b
                b = tmp
            if a > lo:
                lo = a
            if b < hi:
                hi = b
            if lo > hi:
                return False
    return True


cdef bint _clear(mask3_t free, double* p, double* q) noexcept nogil:
    """Whether the closed segment ``p -> q`` (cell units, array order) touches only free voxels of the
    grid (a voxel outside the grid counts as blocked): the voxels an Amanatides-Woo walk visits, and
    the blocked ones among their 26 neighbours tested for contact with the segment."""
    cdef double d[3]
    cdef double tmax[3]
    cdef double tdel[3]
    cdef int64_t cur[3]
    cdef int64_t step[3]
    cdef int64_t n[3]
    cdef int ax, a, b, c, best
    cdef int64_t k, r, cc, guard
    n[0] = free.shape[0]
    n[1] = free.shape[1]
    n[2] = free.shape[2]
    for ax in range(3):
        d[ax] = q[ax] - p[ax]
        cur[ax] = <int64_t>floor(p[ax])
        if d[ax] > 0:
            step[ax] = 1
            tdel[ax] = 1.0 / d[ax]
            tmax[ax] = (cur[ax] + 1 - p[ax]) / d[ax]
        elif d[ax] < 0:
            step[ax] = -1
            tdel[ax] = -1.0 / d[ax]
            tmax[ax] = (cur[ax] - p[ax]) / d[ax]
        else:
            step[ax] = 0
            tdel[ax] = INFINITY
            tmax[ax] = INFINITY
    guard = 0
    while True:
        for a in range(-1, 2):
            for b in range(-1, 2):
                for c in range(-1, 2):
                    k = cur[0] + a
                    r = cur[1] + b
                    cc = cur[2] + c
                    if 0 <= k < n[0] and 0 <= r < n[1] and 0 <= cc < n[2] and free[k, r, cc]:
                        continue
                    if _touches(p, d, k, r, cc):
                        return False
        best = 0
        if tmax[1] < tmax[best]:
            best = 1
        if tmax[2] < tmax[best]:
            best = 2
        if tmax[best] > 1.0:
            return True
        cur[best] += step[best]
        tmax[best] += tdel[best]
        guard += 1
        if guard > 3 * (n[0] + n[1] + n[2]) + 16:  # cannot happen for a segment inside the grid
            return False


def segment_clear(mask3_t free, double a0, double a1, double a2, double b0, double b1, double b2):
    """Whether the segment from ``(a0, a1, a2)`` to ``(b0, b1, b2)`` (cell units, array order) touches
    only free voxels of the grid (closed cubes: grazing a blocked voxel's face, edge or corner counts)."""
    cdef double p[3]
    cdef double q[3]
    p[0] = a0
    p[1] = a1
    p[2] = a2
    q[0] = b0
    q[1] = b1
    q[2] = b2
    cdef bint ok
    with nogil:
        ok = _clear(free, p, q)
    return ok


def path_clear(mask3_t free, const double[:, :] pts):
    """Index of the first segment of the polyline ``pts`` (cell units, array order) that touches a blocked
    voxel, or -1 when every segment is clear."""
    cdef int64_t i, m = pts.shape[0]
    cdef double p[3]
    cdef double q[3]
    cdef int64_t bad = -1
    with nogil:
        for i in range(m - 1):
            p[0] = pts[i, 0]
            p[1] = pts[i, 1]
            p[2] = pts[i, 2]
            q[0] = pts[i + 1, 0]
            q[1] = pts[i + 1, 1]
            q[2] = pts[i + 1, 2]
            if not _clear(free, p, q):
                bad = i
                break
    return bad


def shortcut(mask3_t free, const double[:, :] pts):
    """String pulling over a polyline's own vertices (cell units, array order) whose segments are clear:
    from each kept vertex, the farthest later vertex reached by a clear segment (extended one vertex at
    a time). Returns the int64 indices of the kept vertices (first and last included)."""
    cdef int64_t m = pts.shape[0], i = 0, j, nk = 1
    cdef double p[3]
    cdef double q[3]
    keep = np.empty(max(m, 1), np.int64)
    cdef int64_t[::1] kv = keep
    kv[0] = 0
    if m < 2:
        return keep[:m]
    with nogil:
        while i < m - 1:
            j = i + 1
            p[0] = pts[i, 0]
            p[1] = pts[i, 1]
            p[2] = pts[i, 2]
            while j + 1 < m:
                q[0] = pts[j + 1, 0]
                q[1] = pts[j + 1, 1]
                q[2] = pts[j + 1, 2]
                if not _clear(free, p, q):
                    break
                j += 1
            kv[nk] = j
            nk += 1
            i = j
    return keep[:nk]


# ----------------------------------------------------------------------------------------------
# the follower
# ----------------------------------------------------------------------------------------------
cdef inline bint _sample(val3_t U, val3_t g0, val3_t g1, val3_t g2, mask3_t free, double* q,
                         double* u, double* grad) noexcept nogil:
    """Trilinear interpolation of ``U`` and the gradient at ``q`` over the up to 8 surrounding voxel
    centres that are free with a finite ``U`` (weights renormalized); False when none is."""
    cdef double f[3]
    cdef int64_t i[3]
    cdef int ax, a, b, c
    cdef int64_t k, r, cc
    cdef double w, wsum = 0.0, su = 0.0, s0 = 0.0, s1 = 0.0, s2 = 0.0
    for ax in range(3):
        i[ax] = <int64_t>floor(q[ax] - 0.5)
        f[ax] = q[ax] - 0.5 - i[ax]
    for a in range(2):
        k = i[0] + a
        if k < 0 or k >= U.shape[0]:
            continue
        for b in range(2):
            r = i[1] + b
            if r < 0 or r >= U.shape[1]:
                continue
            for c in range(2):
                cc = i[2] + c
                if cc < 0 or cc >= U.shape[2] or not free[k, r, cc] or not (U[k, r, cc] < INFINITY):
                    continue
                w = (f[0] if a else 1.0 - f[0]) * (f[1] if b else 1.0 - f[1]) * (f[2] if c else 1.0 - f[2])
                if w <= 0.0:
                    continue
                wsum += w
                su += w * U[k, r, cc]
                s0 += w * g0[k, r, cc]
                s1 += w * g1[k, r, cc]
                s2 += w * g2[k, r, cc]
    if wsum <= 0.0:
        return False
    u[0] = su / wsum
    grad[0] = s0 / wsum
    grad[1] = s1 / wsum
    grad[2] = s2 / wsum
    return True


cdef inline bint _put(double** buf, int64_t* m, int64_t* cap, double a, double b, double c) noexcept nogil:
    cdef double* t
    if m[0] == cap[0]:
        t = <double*>realloc(buf[0], 6 * cap[0] * sizeof(double))
        if t == NULL:
            return False
        buf[0] = t
        cap[0] *= 2
    buf[0][3 * m[0]] = a
    buf[0][3 * m[0] + 1] = b
    buf[0][3 * m[0] + 2] = c
    m[0] += 1
    return True


def follow3(val3_t U, val3_t g0, val3_t g1, val3_t g2, mask3_t free, double q0, double q1, double q2,
            double e0, double e1, double e2, double step, int64_t max_iterations, bint finish):
    """Gradient descent on a voxel field from ``q`` to the goal ``e`` (cell units, array order; the
    gradient arrays in array order too, per cell unit).

    Each step moves ``step`` cells along the trilinearly interpolated ``-grad``; it is taken when its
    segment touches only free voxels (:func:`segment_clear`) and the interpolated ``U`` decreases.
    Otherwise the discrete descent takes over (to the current voxel's centre, then from neighbour to
    lowest allowed neighbour, :func:`descend3`'s rule) until it is below the level where the step
    failed, and the continuous steps resume. The run ends in the goal's voxel (the goal appended),
    at a voxel without a lower allowed neighbour (a local minimum), or after ``max_iterations`` steps;
    with ``finish`` the discrete descent then completes the path (a complete field's descent ends at the
    goal).

    Returns ``(points, status, iterations, discrete)``: the ``(n, 3)`` cell-unit points (start first),
    status 0 reached / 1 local minimum / 2 max iterations, the steps taken and how many were discrete.
    """
    cdef int64_t cap = 1024, m = 0, it = 0, nd = 0, gk, gr, gc, k, r, c, bk, br, bc, nk, nr, nc
    cdef double* buf = <double*>_alloc(3 * cap * sizeof(double))
    cdef double q[3]
    cdef double t[3]
    cdef double grad[3]
    cdef double u, ut, norm, level, best, w
    cdef int status = 2, j
    cdef bint oom = False, ok
    cdef int64_t n0 = U.shape[0], n1 = U.shape[1], n2 = U.shape[2]
    q[0] = q0
    q[1] = q1
    q[2] = q2
    gk = <int64_t>floor(e0)
    gr = <int64_t>floor(e1)
    gc = <int64_t>floor(e2)
    with nogil:
        oom = not _put(&buf, &m, &cap, q0, q1, q2)
        while not oom:
            k = <int64_t>floor(q[0])
            r = <int64_t>floor(q[1])
            c = <int64_t>floor(q[2])
            if k == gk and r == gr and c == gc:
                oom = not _put(&buf, &m, &cap, e0, e1, e2)
                status = 0
                break
            if it >= max_iterations:
                if not finish:
                    status = 2
                    break
            ok = False
            if it < max_iterations and _sample(U, g0, g1, g2, free, q, &u, grad):
                norm = sqrt(grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2])
                if norm > 0.0:
                    for j in range(3):
                        t[j] = q[j] - step * grad[j] / norm
                    if _sample(U, g0, g1, g2, free, t, &ut, grad) and ut < u and _clear(free, q, t):
                        ok = True
            if ok:
                q[0] = t[0]
                q[1] = t[1]
                q[2] = t[2]
                oom = not _put(&buf, &m, &cap, q[0], q[1], q[2])
                it += 1
                continue
            # the discrete descent, down to below the level where the continuous step failed
            if not _sample(U, g0, g1, g2, free, q, &level, grad):
                level = U[k, r, c]
            if level > U[k, r, c]:
                level = U[k, r, c]
            if q[0] != k + 0.5 or q[1] != r + 0.5 or q[2] != c + 0.5:
                q[0] = k + 0.5
                q[1] = r + 0.5
                q[2] = c + 0.5
                oom = not _put(&buf, &m, &cap, q[0], q[1], q[2])
            status = 1
            while not oom:
                best = U[k, r, c]
                bk = -1
                for j in range(27):
                    if j == 13:
                        continue
                    nk = k + _DZ[j]
                    nr = r + _DY[j]
                    nc = c + _DX[j]
                    if nk < 0 or nk >= n0 or nr < 0 or nr >= n1 or nc < 0 or nc >= n2:
                        continue
                    w = U[nk, nr, nc]
                    if w < best and _move_ok(free, k, r, c, _DZ[j], _DY[j], _DX[j], False):
                        best = w
                        bk = nk
                        br = nr
                        bc = nc
                if bk < 0:
                    break
                k = bk
                r = br
                c = bc
                q[0] = k + 0.5
                q[1] = r + 0.5
                q[2] = c + 0.5
                oom = not _put(&buf, &m, &cap, q[0], q[1], q[2])
                it += 1
                nd += 1
                if (k == gk and r == gr and c == gc) or best < level:
                    status = 2
                    break
            if status == 1:  # no lower allowed neighbour outside the goal's voxel
                break
    if oom:
        c_free(buf)
        raise MemoryError("out of memory in the voxel follower")
    pts = np.empty((m, 3))
    cdef double[:, ::1] pv = pts
    for k in range(m):
        pv[k, 0] = buf[3 * k]
        pv[k, 1] = buf[3 * k + 1]
        pv[k, 2] = buf[3 * k + 2]
    c_free(buf)
    return pts, status, it, nd
