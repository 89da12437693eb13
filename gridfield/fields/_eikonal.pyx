# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.fields.navfield` (Cython, compiled at install; imported lazily).

The fast marching method (Sethian 1996; Tsitsiklis 1995) over the free cells of a grid, in *cell
units* (a step between orthogonal neighbours has length 1): a first-order upwind solution of the
eikonal equation ``|grad T| = cost`` on the 4-neighbour stencil and on the 45-degree-rotated
stencil of the diagonal neighbours (spacing ``sqrt 2``), the smaller of the two (the multi-stencil
scheme of Hassouna & Farag, IEEE PAMI 29(9), 2007). A diagonal neighbour is used only when both
cells beside the diagonal are free (the move rule of the wavefronts: no front through a corner the
robot cannot pass). :func:`march` keeps the front in a binary heap indexed by cell (decrease-key in
place: the exact order, the reference); :func:`march_buckets` in an untidy bucket queue (what
:mod:`gridfield.fields.navfield` uses). Also :func:`upwind` (the gradient arrays) and :func:`ascend`
(steepest ascent onto a skeleton).

Both marches start from *fixed sources*: cells with given values that are never changed (the goal cell and
its neighbours at their exact Euclidean distance, or a skeleton's values). Every other cell gets a
value strictly above the smallest of its accepted neighbours, so that discrete steepest descent
from any reached cell ends at a source. Cells never reached keep ``inf``. With ``stop`` >= 0 the
march ends once every cell up to the value of cell ``stop`` plus ``margin`` is accepted; the others
are set to ``inf``.

Nothing here validates input; :mod:`gridfield.fields.navfield` does. Masks are ``uint8`` (or ``bool``),
values ``float64``, indices ``int64``.
"""

from libc.math cimport INFINITY, sqrt
from libc.stdint cimport int64_t, uint8_t
from libc.stdint cimport int32_t
from libc.stdlib cimport free as c_free, malloc, realloc

import numpy as np

ctypedef const uint8_t[:, :] mask_t
ctypedef const double[:, :] val_t

cdef double SQRT2 = 1.4142135623730951


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


# ----------------------------------------------------------------------------------------------
# an indexed binary min-heap of cells keyed by u[cell]
# ----------------------------------------------------------------------------------------------
cdef inline void _sift_up(int64_t* heap, int64_t* pos, const double* u, int64_t i) noexcept nogil:
    cdef int64_t v = heap[i], p
    cdef double key = u[v]
    while i > 0:
        p = (i - 1) >> 1
        if u[heap[p]] <= key:
            break
        heap[i] = heap[p]
        pos[heap[i]] = i
        i = p
    heap[i] = v
    pos[v] = i


cdef inline void _sift_down(int64_t* heap, int64_t* pos, const double* u, int64_t n, int64_t i) noexcept nogil:
    cdef int64_t v = heap[i], c
    cdef double key = u[v]
    while True:
        c = 2 * i + 1
        if c >= n:
            break
        if c + 1 < n and u[heap[c + 1]] < u[heap[c]]:
            c += 1
        if u[heap[c]] >= key:
            break
        heap[i] = heap[c]
        pos[heap[i]] = i
        i = c
    heap[i] = v
    pos[v] = i


cdef inline void _push_or_lower(int64_t* heap, int64_t* pos, double* u, int64_t* n, int64_t v, double val) noexcept nogil:
    """Insert cell ``v`` with ``val``, or lower its key to ``val`` (never raise it)."""
    if pos[v] < 0:
        u[v] = val
        heap[n[0]] = v
        pos[v] = n[0]
        n[0] += 1
        _sift_up(heap, pos, u, pos[v])
    elif val < u[v]:
        u[v] = val
        _sift_up(heap, pos, u, pos[v])


cdef inline int64_t _pop(int64_t* heap, int64_t* pos, const double* u, int64_t* n) noexcept nogil:
    cdef int64_t top = heap[0]
    n[0] -= 1
    pos[top] = -2  # accepted
    if n[0] > 0:
        heap[0] = heap[n[0]]
        pos[heap[0]] = 0
        _sift_down(heap, pos, u, n[0], 0)
    return top


cdef uint8_t* _pad_mask(mask_t m, int64_t w) noexcept nogil:
    """Flat copy of ``m`` padded with a ring of zeros (malloc'd), padded width ``w``."""
    cdef int64_t rows = m.shape[0], cols = m.shape[1], r, c, base
    cdef int64_t n = (rows + 2) * w
    cdef uint8_t* f = <uint8_t*>_alloc(n)
    for r in range(n):
        f[r] = 0
    for r in range(rows):
        base = (r + 1) * w + 1
        for c in range(cols):
            if m[r, c]:
                f[base + c] = 1
    return f


cdef inline double _solve2(double a, double b, double f) noexcept nogil:
    """The upwind update from the two axis minima ``a``, ``b`` (inf when absent) with cost ``f`` per unit."""
    cdef double t, d
    if a > b:
        t = a
        a = b
        b = t
    if a == INFINITY:
        return INFINITY
    if b - a >= f:
        return a + f
    d = a - b
    return 0.5 * (a + b + sqrt(2.0 * f * f - d * d))


cdef inline double _known(const double* u, const int64_t* pos, const uint8_t* free_, int64_t v) noexcept nogil:
    """``u[v]`` if the cell is free and accepted (or a fixed source already accepted), else inf."""
    if free_[v] and pos[v] == -2:
        return u[v]
    return INFINITY


cdef inline double _update4(const double* u, const int64_t* pos, const uint8_t* free_, int64_t v, int64_t w,
                            double f) noexcept nogil:
    """The 4-neighbour stencil's update of cell ``v``."""
    cdef double a, b, t
    a = _known(u, pos, free_, v - 1)
    t = _known(u, pos, free_, v + 1)
    if t < a:
        a = t
    b = _known(u, pos, free_, v - w)
    t = _known(u, pos, free_, v + w)
    if t < b:
        b = t
    return _solve2(a, b, f)


cdef inline double _update8(const double* u, const int64_t* pos, const uint8_t* free_, int64_t v, int64_t w,
                            double f) noexcept nogil:
    """The rotated stencil's update: the diagonals (+1,+1)/(-1,-1) and (+1,-1)/(-1,+1), spacing
    sqrt 2, each usable only when both cells beside it are free."""
    cdef double a = INFINITY, b = INFINITY, t
    if free_[v + w] and free_[v + 1]:
        a = _known(u, pos, free_, v + w + 1)
    if free_[v - w] and free_[v - 1]:
        t = _known(u, pos, free_, v - w - 1)
        if t < a:
            a = t
    if free_[v + w] and free_[v - 1]:
        b = _known(u, pos, free_, v + w - 1)
    if free_[v - w] and free_[v + 1]:
        t = _known(u, pos, free_, v - w + 1)
        if t < b:
            b = t
    return _solve2(a, b, f * SQRT2)


def march(mask_t free, val_t cost, const int64_t[:] src_r, const int64_t[:] src_c, const double[:] src_v,
          bint diag, int64_t stop_r, int64_t stop_c, double margin):
    """Fast marching from fixed sources over the free cells (cell units).

    ``cost``: the slowness per cell (``1 / speed``, >= some positive number), or an empty array for
    cost 1 everywhere. ``diag``: use the rotated stencil too. ``stop_r``/``stop_c``: the cell whose
    acceptance (plus ``margin``) ends the march, or -1. Returns ``(T, accepted cells)``.
    """
    cdef int64_t rows = free.shape[0], cols = free.shape[1]
    cdef int64_t w = cols + 2
    cdef int64_t n = (rows + 2) * w
    cdef int64_t i, r, c, v, nb, k, hn = 0, count = 0
    cdef bint uniform = cost.shape[0] == 0
    cdef double f, val, limit = INFINITY
    cdef int64_t stop_v = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
    cdef int64_t nsrc = src_r.shape[0]
    cdef int64_t offs[4]
    out = np.empty((rows, cols))
    cdef double[:, ::1] o = out
    cdef uint8_t* fr
    cdef uint8_t* fixed
    cdef double* u
    cdef double* cst
    cdef int64_t* heap
    cdef int64_t* pos
    offs[0] = 1
    offs[1] = -1
    offs[2] = w
    offs[3] = -w
    with nogil:
        fr = _pad_mask(free, w)
        fixed = <uint8_t*>_alloc(n)
        u = <double*>_alloc(n * sizeof(double))
        cst = <double*>_alloc((0 if uniform else n) * sizeof(double))
        heap = <int64_t*>_alloc(n * sizeof(int64_t))
        pos = <int64_t*>_alloc(n * sizeof(int64_t))
        for i in range(n):
            u[i] = INFINITY
            pos[i] = -1
            fixed[i] = 0
        if not uniform:
            for r in range(rows):
                for c in range(cols):
                    cst[(r + 1) * w + c + 1] = cost[r, c]
        for k in range(nsrc):
            v = (src_r[k] + 1) * w + src_c[k] + 1
            if fr[v]:
                _push_or_lower(heap, pos, u, &hn, v, src_v[k])
                fixed[v] = 1
        while hn > 0:
            if u[heap[0]] > limit:
                break
            v = _pop(heap, pos, u, &hn)
            count += 1
            if v == stop_v:
                limit = u[v] + margin
            # the neighbours whose stencils hold the accepted cell: each recomputes that stencil only
            # (its other stencil's inputs did not change), and keeps the smaller value
            for k in range(8 if diag else 4):
                if k < 4:
                    nb = v + offs[k]
                elif k == 4:
                    nb = v + w + 1
                elif k == 5:
                    nb = v + w - 1
                elif k == 6:
                    nb = v - w + 1
                else:
                    nb = v - w - 1
                if not fr[nb] or pos[nb] == -2 or fixed[nb]:
                    continue
                f = 1.0 if uniform else cst[nb]
                if k < 4:
                    val = _update4(u, pos, fr, nb, w, f)
                else:
                    val = _update8(u, pos, fr, nb, w, f)
                if val < INFINITY:
                    _push_or_lower(heap, pos, u, &hn, nb, val)
        for r in range(rows):
            for c in range(cols):
                v = (r + 1) * w + c + 1
                o[r, c] = u[v] if pos[v] == -2 else INFINITY
        c_free(fr)
        c_free(fixed)
        c_free(u)
        c_free(cst)
        c_free(heap)
        c_free(pos)
    return out, count


# ----------------------------------------------------------------------------------------------
# fast marching with an untidy bucket queue (Yatziv, Bartesaghi & Sapiro, J. Comput. Phys. 212, 2006)
# ----------------------------------------------------------------------------------------------
cdef inline double _astar_key(double val, double r, double c, double sr, double sc, double hw) noexcept nogil:
    """The A* key of a cell at row ``r``, column ``c`` (padded) with value ``val``: ``val`` plus ``hw`` times
    its Euclidean distance in cells to the stop cell ``(sr, sc)``."""
    cdef double dr = r - sr, dc = c - sc
    return val + hw * sqrt(dr * dr + dc * dc)


cdef inline bint _bpush(int32_t** data, int64_t* size, int64_t* cap, int64_t b, int32_t v) noexcept nogil:
    cdef int64_t nc
    cdef int32_t* p
    if size[b] == cap[b]:
        nc = cap[b] * 2 if cap[b] > 0 else 64
        p = <int32_t*>realloc(data[b], nc * sizeof(int32_t))
        if p == NULL:
            return False
        data[b] = p
        cap[b] = nc
    data[b][size[b]] = v
    size[b] += 1
    return True


def march_buckets(mask_t free, val_t cost, const int64_t[:] src_r, const int64_t[:] src_c, const double[:] src_v,
                  bint diag, int64_t stop_r, int64_t stop_c, double margin, double delta, double max_cost,
                  double hweight=0.0, int64_t[:] box=None, double reopen=INFINITY):
    """:func:`march` with the priority queue replaced by buckets of width ``delta`` (cells), each
    a first-in first-out list: O(1) per cell instead of a heap's O(log n). Cells of one bucket are
    accepted in arrival order, so values may differ from the exact march by about ``delta``; every
    cell still gets a value strictly above an accepted neighbour's (the upwind update), so descent
    still ends at a source. The sources must be sorted by value; ``max_cost`` bounds ``cost``.
    Returns ``(T, accepted cells)``; raises MemoryError when a bucket cannot grow.

    ``hweight`` > 0 with a stop cell: the A*-ordered truncated march (as NavFn's A* mode): the
    buckets are keyed by ``T + hweight * h`` with ``h`` the Euclidean distance (cells) to the stop
    cell, and the march ends once every cell of key up to ``T(stop) + margin`` is accepted. A cell
    is still given the upwind update from its accepted neighbours, so it stays strictly above one
    of them (descent still ends at a source). A neighbour whose value it needed may be accepted after
    it (the heuristic is not a bound for the 2-neighbour update); the cell is then lowered and
    accepted again when its value drops by more than ``reopen`` cells (label correcting; inf:
    never), so that the values approach the full march's. ``box``
    (int64, length 4), when given, receives the accepted cells' bounding box ``r0, r1, c0, c1``
    (inclusive; ``r0 > r1`` when none).

    One call of :meth:`Marcher.run` on a fresh :class:`Marcher` (which a caller marching many times
    on one map keeps instead).
    """
    m = Marcher(free, cost)
    out, count, bx = m.run(src_r, src_c, src_v, diag, stop_r, stop_c, margin, delta, max_cost, hweight, reopen)
    if box is not None and box.shape[0] >= 4:
        box[0] = bx[0]
        box[1] = bx[1]
        box[2] = bx[2]
        box[3] = bx[3]
    return out, count


# the state bits of a cell of a Marcher: free, a fixed source, accepted
cdef enum:
    S_FREE = 1
    S_FIXED = 2
    S_DONE = 4


cdef class Marcher:
    """The bucket-queue march of :func:`march_buckets` on one free mask and slowness, kept for many
    marches (the queries of one map): the padded mask and slowness are copied once, the work arrays
    and buckets are allocated once and only the cells a march touched are reset after it (no
    map-sized allocation or initialisation per march). Not for concurrent use (the caller locks).

    ``free``: the free mask (``uint8``); ``cost``: the slowness (as :func:`march_buckets`; empty for 1
    everywhere). Memory: about 30 bytes per cell.
    """
    cdef int64_t rows, cols, w, n, nbk_alloc, ntouched
    cdef bint uniform
    cdef uint8_t* st
    cdef double* cst
    cdef double* u
    cdef double* kv
    cdef int32_t* touched
    cdef int32_t** data
    cdef int64_t* size
    cdef int64_t* cap

    def __cinit__(self, mask_t free, val_t cost):
        cdef int64_t rows = free.shape[0], cols = free.shape[1], r, c, i, w = cols + 2
        cdef int64_t n = (rows + 2) * w
        self.rows = rows
        self.cols = cols
        self.w = w
        self.n = n
        self.uniform = cost.shape[0] == 0
        self.nbk_alloc = 0
        self.ntouched = 0
        self.data = NULL
        self.size = NULL
        self.cap = NULL
        self.st = <uint8_t*>_alloc(n)
        self.u = <double*>_alloc(n * sizeof(double))
        self.kv = <double*>_alloc(n * sizeof(double))
        self.touched = <int32_t*>_alloc(n * sizeof(int32_t))
        self.cst = <double*>_alloc((0 if self.uniform else n) * sizeof(double))
        if self.st == NULL or self.u == NULL or self.kv == NULL or self.touched == NULL or self.cst == NULL:
            raise MemoryError("Marcher: out of memory")
        with nogil:
            for i in range(n):
                self.st[i] = 0
                self.u[i] = INFINITY
                self.kv[i] = INFINITY
            for r in range(rows):
                for c in range(cols):
                    if free[r, c]:
                        self.st[(r + 1) * w + c + 1] = S_FREE
            if not self.uniform:
                for r in range(rows):
                    for c in range(cols):
                        self.cst[(r + 1) * w + c + 1] = cost[r, c]

    def __dealloc__(self):
        cdef int64_t i
        if self.data != NULL:
            for i in range(self.nbk_alloc):
                c_free(self.data[i])
        c_free(self.data)
        c_free(self.size)
        c_free(self.cap)
        c_free(self.st)
        c_free(self.u)
        c_free(self.kv)
        c_free(self.touched)
        c_free(self.cst)

    cdef bint _buckets(self, int64_t nbk) noexcept:
        """At least ``nbk`` empty buckets (grown, never shrunk)."""
        cdef int64_t i
        cdef int32_t** d
        cdef int64_t* s
        cdef int64_t* cp
        if nbk <= self.nbk_alloc:
            return True
        d = <int32_t**>realloc(self.data, nbk * sizeof(int32_t*))
        if d == NULL:
            return False
        self.data = d
        s = <int64_t*>realloc(self.size, nbk * sizeof(int64_t))
        if s == NULL:
            return False
        self.size = s
        cp = <int64_t*>realloc(self.cap, nbk * sizeof(int64_t))
        if cp == NULL:
            return False
        self.cap = cp
        for i in range(self.nbk_alloc, nbk):
            self.data[i] = NULL
            self.size[i] = 0
            self.cap[i] = 0
        self.nbk_alloc = nbk
        return True

    def run(self, const int64_t[:] src_r, const int64_t[:] src_c, const double[:] src_v, bint diag,
            int64_t stop_r, int64_t stop_c, double margin, double delta, double max_cost, double hweight=0.0,
            double reopen=INFINITY, double scale=1.0, bint gradient=False, double[:, ::1] into=None,
            double[:, ::1] into_gx=None, double[:, ::1] into_gy=None):
        """One march (:func:`march_buckets`'s arguments). Returns ``(T, accepted cells, box)``, ``T``
        multiplied by ``scale``; with ``gradient``, ``(T, accepted cells, box, gx, gy)``: the upwind
        differences of ``T`` (:func:`upwind` with ``diagonal`` and the ``free`` mask, divided by
        ``scale`` when it is not 1), zero off the accepted cells. ``box`` (a tuple) as
        :func:`march_buckets`'s. ``into``, ``into_gx``, ``into_gy`` (C-contiguous, the mask's shape),
        when given: the arrays ``T``, ``gx``, ``gy`` are written to (wholly) and returned instead of
        new ones."""
        cdef int64_t rows = self.rows, cols = self.cols, w = self.w
        cdef int64_t i, r, c, v, nb, k, count = 0, live = 0, cur, bk, sp = 0, slot, nt = 0
        cdef bint uniform = self.uniform, ok = True
        cdef double f, val, limit = INFINITY, inv = 1.0 / delta
        cdef int64_t stop_v = (stop_r + 1) * w + stop_c + 1 if stop_r >= 0 else -1
        cdef int64_t nsrc = src_r.shape[0]
        cdef bint astar = hweight > 0.0 and stop_r >= 0
        cdef bint reacc = astar and reopen < INFINITY
        cdef double hw = hweight if astar else 0.0, key, sr = <double>(stop_r + 1), sc = <double>(stop_c + 1)
        cdef int64_t nbk = <int64_t>((max_cost + hw) * SQRT2 * inv) + 4
        cdef int64_t br0 = rows, br1 = -1, bc0 = cols, bc1 = -1, vr, vc, nk = 8 if diag else 4
        cdef uint8_t skip = S_FREE | S_FIXED | (0 if reacc else S_DONE), s
        cdef int64_t offs[8]
        cdef int64_t orow[8]
        cdef int64_t ocol[8]
        cdef uint8_t* st = self.st
        cdef double* u = self.u
        cdef double* kv = self.kv
        cdef double* cst = self.cst
        cdef int32_t* touched = self.touched
        cdef int32_t** data
        cdef int64_t* size
        cdef int64_t* cap
        if not self._buckets(nbk):
            raise MemoryError("march_buckets: out of memory for the bucket queue")
        data = self.data
        size = self.size
        cap = self.cap
        orow[:] = [0, 0, 1, -1, 1, 1, -1, -1]
        ocol[:] = [1, -1, 0, 0, 1, -1, 1, -1]
        for k in range(8):
            offs[k] = orow[k] * w + ocol[k]
        # the output arrays' shapes, before the march changes any state
        if (into is not None and (into.shape[0] != rows or into.shape[1] != cols)) or \
                (into_gx is not None and (into_gx.shape[0] != rows or into_gx.shape[1] != cols)) or \
                (into_gy is not None and (into_gy.shape[0] != rows or into_gy.shape[1] != cols)):
            raise ValueError("Marcher.run: an output array has another shape than the mask")
        out = np.empty((rows, cols)) if into is None else into.base
        cdef double[:, ::1] o = out if into is None else into
        with nogil:
            for k in range(nsrc):  # every source is fixed from the start (at its smallest given value)
                v = (src_r[k] + 1) * w + src_c[k] + 1
                if (st[v] & S_FREE) and src_v[k] < u[v]:
                    if u[v] == INFINITY:
                        touched[nt] = <int32_t>v
                        nt += 1
                    u[v] = src_v[k]
                    st[v] |= S_FIXED
            cur = <int64_t>(src_v[0] * inv) if nsrc > 0 else 0
            while ok:
                # the sources due by this bucket join the queue
                while sp < nsrc:
                    v = (src_r[sp] + 1) * w + src_c[sp] + 1
                    key = _astar_key(src_v[sp], <double>(v // w), <double>(v % w), sr, sc, hw) if astar else src_v[sp]
                    if <int64_t>(key * inv) > cur:
                        break
                    if (st[v] & S_FREE) and not (st[v] & S_DONE) and src_v[sp] == u[v]:
                        ok = _bpush(data, size, cap, cur % nbk, <int32_t>v) and ok
                        live += 1
                    sp += 1
                if live == 0:
                    if sp >= nsrc:
                        break
                    v = (src_r[sp] + 1) * w + src_c[sp] + 1
                    key = _astar_key(src_v[sp], <double>(v // w), <double>(v % w), sr, sc, hw) if astar else src_v[sp]
                    cur = <int64_t>(key * inv)
                    continue
                if cur * delta > limit:
                    break
                slot = cur % nbk
                i = 0
                while i < size[slot] and ok:
                    v = data[slot][i]
                    i += 1
                    live -= 1
                    if st[v] & S_DONE:
                        continue
                    st[v] |= S_DONE
                    kv[v] = u[v]
                    count += 1
                    vr = v // w
                    vc = v - vr * w
                    if vr - 1 < br0:
                        br0 = vr - 1
                    if vr - 1 > br1:
                        br1 = vr - 1
                    if vc - 1 < bc0:
                        bc0 = vc - 1
                    if vc - 1 > bc1:
                        bc1 = vc - 1
                    if v == stop_v and u[v] + margin < limit:
                        limit = u[v] + margin
                    for k in range(nk):
                        nb = v + offs[k]
                        s = st[nb]
                        if (s & skip) != S_FREE:  # not free, fixed, or (without re-acceptance) accepted
                            continue
                        f = 1.0 if uniform else cst[nb]
                        if k < 4:
                            val = _update4b(kv, nb, w, f)
                        else:
                            val = _update8s(kv, st, nb, w, f)
                        if s & S_DONE:
                            # A* order: a cell accepted before a neighbour its update needed is lowered
                            # and accepted again (label correcting), so its dependents are redone too
                            if val >= u[nb] - reopen:
                                continue
                            st[nb] = s & ~S_DONE
                        if val < u[nb]:
                            if u[nb] == INFINITY:
                                touched[nt] = <int32_t>nb
                                nt += 1
                            u[nb] = val
                            key = _astar_key(val, <double>(vr + orow[k]), <double>(vc + ocol[k]), sr, sc, hw) if astar else val
                            bk = <int64_t>(key * inv)
                            if bk < cur:
                                bk = cur
                            ok = _bpush(data, size, cap, bk % nbk, <int32_t>nb)
                            live += 1
                size[slot] = 0
                cur += 1
            for i in range(nbk):
                size[i] = 0
            for r in range(rows):
                for c in range(cols):
                    o[r, c] = INFINITY
            for i in range(nt):
                v = touched[i]
                if st[v] & S_DONE:
                    o[v // w - 1, v % w - 1] = u[v] * scale
        if gradient and ok:
            if into_gx is None or into_gy is None:
                gx = np.zeros((rows, cols))
                gy = np.zeros((rows, cols))
                _upwind_done(u, st, w, br0, br1, bc0, bc1, scale, gx, gy)
            else:
                gx = into_gx.base
                gy = into_gy.base
                with nogil:
                    for r in range(rows):
                        for c in range(cols):
                            into_gx[r, c] = 0.0
                            into_gy[r, c] = 0.0
                _upwind_done(u, st, w, br0, br1, bc0, bc1, scale, into_gx, into_gy)
        with nogil:
            for i in range(nt):  # back to the clean state for the next march
                v = touched[i]
                u[v] = INFINITY
                kv[v] = INFINITY
                st[v] &= S_FREE
        if not ok:
            raise MemoryError("march_buckets: out of memory for the bucket queue")
        if gradient:
            return out, count, (br0, br1, bc0, bc1), gx, gy
        return out, count, (br0, br1, bc0, bc1)


cdef inline bint _upwind_axes(double v, double xl, double xr, double yd, double yu, double* x,
                              double* y) noexcept nogil:
    """The upwind rule of :func:`upwind` at one cell of value ``v`` along the axes: the difference towards
    the lower of its two neighbours (``xl``/``xr`` left/right, ``yd``/``yu`` below/above; the left/lower
    one on a tie), 0 where neither is lower. True when neither axis has a lower neighbour (then
    :func:`_upwind_diag` decides)."""
    x[0] = 0.0
    y[0] = 0.0
    if xl <= xr:
        if xl < v:
            x[0] = v - xl
    elif xr < v:
        x[0] = xr - v
    if yd <= yu:
        if yd < v:
            y[0] = v - yd
    elif yu < v:
        y[0] = yu - v
    return x[0] == 0.0 and y[0] == 0.0


cdef inline void _upwind_diag(double v, double dmm, double dmp, double dpm, double dpp, double* x,
                              double* y) noexcept nogil:
    """The upwind rule of :func:`upwind` at a cell with no lower 4-neighbour: the difference towards the
    lowest diagonal neighbour ``d[dr][dc]`` (``dmm`` = row -1, column -1, ..., the first one on a tie;
    ``inf`` for one that may not be used), ``-(v - d) (dc, dr) / 2``; nothing when none is lower."""
    cdef double best = v
    cdef int64_t bdr = 0, bdc = 0
    if dmm < best:
        best, bdr, bdc = dmm, -1, -1
    if dmp < best:
        best, bdr, bdc = dmp, -1, 1
    if dpm < best:
        best, bdr, bdc = dpm, 1, -1
    if dpp < best:
        best, bdr, bdc = dpp, 1, 1
    if bdr != 0:
        x[0] = -0.5 * (v - best) * bdc
        y[0] = -0.5 * (v - best) * bdr


cdef inline double _settled(const double* u, const uint8_t* st, int64_t p) noexcept nogil:
    """``u[p]`` if the cell is accepted, else inf (what the march's ``T`` holds)."""
    return u[p] if st[p] & S_DONE else INFINITY


cdef void _upwind_done(const double* u, const uint8_t* st, int64_t w, int64_t r0, int64_t r1, int64_t c0, int64_t c1,
                       double scale, double[:, ::1] ox, double[:, ::1] oy) noexcept:
    """:func:`upwind` (``diagonal``, the ``free`` mask) of ``T`` (``u * scale`` on the accepted cells) on the padded arrays of a
    :class:`Marcher` over the accepted cells of rows ``r0..r1``, columns ``c0..c1`` (unpadded), the
    differences divided by ``scale`` when it is not 1 (the order of operations of scaling ``T``, then
    differencing, then dividing). The ring of the padding plays the grid's edge (not accepted, not free)."""
    cdef int64_t r, c, p
    cdef double v, x, y
    cdef double d[4]
    cdef int64_t k, dr, dc
    with nogil:
        for r in range(r0, r1 + 1):
            for c in range(c0, c1 + 1):
                p = (r + 1) * w + c + 1
                if not (st[p] & S_DONE):
                    continue
                v = u[p] * scale
                if _upwind_axes(v, _settled(u, st, p - 1) * scale, _settled(u, st, p + 1) * scale,
                                _settled(u, st, p - w) * scale, _settled(u, st, p + w) * scale, &x, &y):
                    k = 0
                    for dr in range(-1, 2, 2):  # a diagonal whose two side cells are free (the march's rule)
                        for dc in range(-1, 2, 2):
                            d[k] = (_settled(u, st, p + dr * w + dc) * scale
                                    if (st[p + dr * w] & S_FREE) and (st[p + dc] & S_FREE) else INFINITY)
                            k += 1
                    _upwind_diag(v, d[0], d[1], d[2], d[3], &x, &y)
                if scale != 1.0:
                    x = x / scale
                    y = y / scale
                ox[r, c] = x
                oy[r, c] = y


cdef inline double _update4b(const double* kv, int64_t v, int64_t w, double f) noexcept nogil:
    """:func:`_update4` on the array of accepted values (``inf`` where not accepted)."""
    cdef double a = kv[v - 1], b = kv[v - w], t
    t = kv[v + 1]
    if t < a:
        a = t
    t = kv[v + w]
    if t < b:
        b = t
    return _solve2(a, b, f)


cdef inline double _update8s(const double* kv, const uint8_t* st, int64_t v, int64_t w, double f) noexcept nogil:
    """:func:`_update8`'s rotated stencil on the array of accepted values (``inf`` where not
    accepted), the free mask read from the state bits of a :class:`Marcher`."""
    cdef double a = INFINITY, b = INFINITY, t
    cdef bint up = st[v + w] & S_FREE, down = st[v - w] & S_FREE, right = st[v + 1] & S_FREE, left = st[v - 1] & S_FREE
    if up and right:
        a = kv[v + w + 1]
    if down and left:
        t = kv[v - w - 1]
        if t < a:
            a = t
    if up and left:
        b = kv[v + w - 1]
    if down and right:
        t = kv[v - w + 1]
        if t < b:
            b = t
    return _solve2(a, b, f * SQRT2)


def upwind(val_t t, bint diagonal=False, mask_t free=None):
    """Upwind differences of ``t`` per cell along x (columns) and y (rows): towards the lower
    neighbour (the left/lower one on a tie), 0 where no neighbour is lower and on non-finite cells;
    non-finite neighbours are never used (:func:`gridfield.fields.navigation.upwind_gradient`'s rule).
    With ``diagonal``, a cell with no lower 4-neighbour takes the difference towards its lowest
    diagonal neighbour whose two side cells are finite (the march's rotated stencil can leave a
    cell whose only lower neighbour is diagonal). ``free`` (the shape of ``t``), when given: the two
    side cells of a diagonal need only be free there (the march's rule), not finite: the rim of a
    truncated march, where a free side cell may not be settled yet."""
    cdef int64_t rows = t.shape[0], cols = t.shape[1], r, c, dr, dc, k
    cdef double v, x, y
    cdef double d[4]
    cdef bint usable
    gx = np.zeros((rows, cols))
    gy = np.zeros((rows, cols))
    cdef double[:, ::1] ox = gx
    cdef double[:, ::1] oy = gy
    cdef bint byfree = free is not None
    cdef const uint8_t[:, :] fm = free if byfree else np.zeros((1, 1), np.uint8)
    with nogil:
        for r in range(rows):
            for c in range(cols):
                v = t[r, c]
                if not (v < INFINITY):
                    continue
                if _upwind_axes(v, t[r, c - 1] if c > 0 else INFINITY, t[r, c + 1] if c + 1 < cols else INFINITY,
                                t[r - 1, c] if r > 0 else INFINITY, t[r + 1, c] if r + 1 < rows else INFINITY,
                                &x, &y) and diagonal:
                    k = 0
                    for dr in range(-1, 2, 2):  # the diagonals whose two side cells are usable
                        for dc in range(-1, 2, 2):
                            d[k] = INFINITY
                            if 0 <= r + dr < rows and 0 <= c + dc < cols:
                                if byfree:
                                    usable = fm[r + dr, c] != 0 and fm[r, c + dc] != 0
                                else:
                                    usable = t[r + dr, c] < INFINITY and t[r, c + dc] < INFINITY
                                if usable:
                                    d[k] = t[r + dr, c + dc]
                            k += 1
                    _upwind_diag(v, d[0], d[1], d[2], d[3], &x, &y)
                ox[r, c] = x
                oy[r, c] = y
    return gx, gy


def ascend(val_t dist, mask_t free, mask_t target, int64_t r0, int64_t c0):
    """Steepest ascent of ``dist`` over the free 8-neighbours (no corner cutting) from ``(r0, c0)``
    until a cell of ``target`` or a cell with no higher neighbour; the visited cells, shape (K, 2)."""
    cdef int64_t rows = free.shape[0], cols = free.shape[1]
    cdef int64_t r = r0, c = c0, k, nr, nc, br, bc, count = 0
    cdef double best, d
    cdef int64_t dr[8]
    cdef int64_t dc[8]
    dr[:] = [0, 0, 1, -1, 1, 1, -1, -1]
    dc[:] = [1, -1, 0, 0, 1, -1, 1, -1]
    out = np.empty((rows * cols if rows * cols < 1 << 20 else 1 << 20, 2), np.int64)
    cdef int64_t[:, ::1] o = out
    cdef int64_t cap = o.shape[0]
    with nogil:
        while count < cap:
            o[count, 0] = r
            o[count, 1] = c
            count += 1
            if target[r, c]:
                break
            best = dist[r, c]
            br = -1
            bc = -1
            for k in range(8):
                nr = r + dr[k]
                nc = c + dc[k]
                if nr < 0 or nr >= rows or nc < 0 or nc >= cols or not free[nr, nc]:
                    continue
                if k >= 4 and not (free[r + dr[k], c] and free[r, c + dc[k]]):
                    continue
                d = dist[nr, nc]
                if d > best:
                    best = d
                    br = nr
                    bc = nc
            if br < 0:
                break
            r = br
            c = bc
    return out[:count].copy()
