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
symmetric: a wavefront from the goal gives the distance *to* the goal. The segment test, the string
pulling and the follower are :mod:`gridfield.fields._voxelpath`; the move rule is inline in ``_voxel.pxd``.

Options ready for an (x, y, theta) planner: per-axis ``spacing`` (a move costs
``sqrt(sum (spacing_a d_a)^2)``), a periodic axis 0 (index ``-1`` is ``n0 - 1``), and a per-voxel
slowness (a move costs its length times the mean slowness of its two ends).
"""

from libc.math cimport INFINITY, floor, sqrt
from libc.stdint cimport int32_t, int64_t, uint8_t, uint32_t
from libc.stdlib cimport free as c_free, malloc, qsort, realloc

import numpy as np

from ._voxel cimport _move_ok, mask3_t, val3_t


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


cdef inline uint32_t _free_mask(const uint8_t* f, int64_t u, const int64_t* off, uint32_t* unsettled) noexcept nogil:
    """The free neighbours of ``u`` as bits (position j), and in ``unsettled`` those not settled yet (bit 2
    of ``f`` clear), so that a settled neighbour's value is never read."""
    cdef uint32_t mask = 0, todo = 0, b
    cdef int j
    for j in range(27):
        b = f[u + off[j]]
        mask |= (b & 1) << j
        todo |= ((b ^ 2) >> 1 & b & 1) << j
    unsettled[0] = todo
    return mask


#: A bucket of at least this many voxels is sorted by index before it is settled (its voxels, and the
#: neighbours they relax, are then visited in memory order: fewer cache misses on large grids).
cdef int64_t SORT_BUCKET = 2048
cdef bint _sort_buckets = True


def set_bucket_sort(bint on):
    """Switch the bucket sort on or off (benchmarks: its effect side by side)."""
    global _sort_buckets
    _sort_buckets = on


cdef int _cmp_int32(const void* a, const void* b) noexcept nogil:
    cdef int32_t x = (<const int32_t*>a)[0], y = (<const int32_t*>b)[0]
    return (x > y) - (x < y)


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
    cdef uint32_t mask, todo
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
        if _sort_buckets and sz >= SORT_BUCKET:
            qsort(cur, sz, sizeof(int32_t), _cmp_int32)
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
            mask = _free_mask(f, u, off, &todo)
            if slow != NULL:
                su = slow[u]
            for j in range(27):
                if not (todo >> j) & 1 or (mask & _REQ[j]) != _REQ[j]:
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
    cdef uint32_t mask, todo
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
        mask = _free_mask(f, u, off, &todo)
        if slow != NULL:
            su = slow[u]
        for j in range(27):
            if not (todo >> j) & 1 or (mask & _REQ[j]) != _REQ[j]:
                continue
            v = u + off[j]
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
