# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled voxel-grid (3-D) distance transforms behind :func:`gridfield.distance.brushfire.brushfire`
(private; imported on first use by :mod:`gridfield.distance._brushfire3d`).

Arrays are C-contiguous ``[layer, row, col]`` (``[z, y, x]``); occupancy is ``uint8``; the nearest
obstacle's indices are ``int16`` or ``int32`` (``idx_t``, one type for the three arrays of a call). The
wall border is the shell of voxels just outside the six faces: layer ``-1``/``layers`` (same row and
col), row ``-1``/``rows`` (same layer and col), col ``-1``/``cols`` (same layer and row); never an
edge or corner of the shell.

Euclidean (:func:`column_pass`, :func:`slice_pass`)
    Separable and exact (Meijster, Roerdink & Hesselink 2000; the lower envelope of parabolas as
    Felzenszwalb & Huttenlocher): the squared distance along z to the nearest obstacle of each voxel's
    column (``column_pass``, two sweeps over the layers, each a loop over a block of the ``(y, x)``
    plane), then per layer the envelope along y (blocks of ``_BLOCK`` columns gathered into contiguous
    lines) and along x (``slice_pass``). Squared distances in cells are integers (exact in int64 and in
    the float64 of the column pass). Ties: each 1-D pass keeps the smaller index, so the nearest voxel
    is, of all voxels at the least distance, the one with the smallest col, then row, then layer
    (the wall's indices -1 and n compare as numbers).
Chessboard and taxicab (:func:`chamfer`)
    The two-pass raster transform with the 13 (26-connected) or 3 (6-connected) forward neighbours and
    their mirror images, carrying the nearest obstacle; exact for both metrics. The wall enters as
    distance 1 on the boundary voxels (nearest: the shell voxel across the first face they touch, in
    the order col, row, layer).
Labels, GVD, saturation (:func:`gather_labels`, :func:`gvd_layers`, :func:`saturate_layers`)
    Per layer ranges, any thread.

Every kernel is sequential over its own range and releases the GIL;
:mod:`gridfield.distance._brushfire3d` runs the ranges on the brushfire's thread pool.
"""

from libc.math cimport INFINITY, sqrt
from libc.stdint cimport int16_t, int32_t, int64_t, uint8_t
from libc.stdlib cimport free, malloc

ctypedef fused idx_t:
    int16_t
    int32_t

#: "no site" in the integer envelopes (far above any squared distance of a grid that fits memory)
cdef int64_t _INF = (<int64_t>1) << 60
#: the chamfer's "not reached yet"
cdef int32_t _FAR = 1 << 30
#: columns per block of the envelope along y (contiguous gathers of _BLOCK values per row)
DEF _BLOCK = 16


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


cdef inline int64_t _floordiv_exact(int64_t a, int64_t b) noexcept nogil:
    # floor(a / b) for b > 0 and |a| < 2**53 (as _edt.pyx: one double division is exact enough)
    cdef double q = <double>a / <double>b
    cdef int64_t t = <int64_t>q
    return t - ((<double>t != q) & (q < 0))


cdef bint _envelope(const int64_t* f, int64_t n, int64_t* s, int64_t* t, int64_t* fs, int64_t* val,
                    int64_t* arg) noexcept nogil:
    # Lower envelope of (x - p)**2 + f[u] over the sites u = 0 .. n + 1 (position p = u - 1, f >= _INF: no
    # site) for the positions x = 0 .. n - 1: val[x] (least value), arg[x] (its position, the smaller on a
    # tie). Returns False if there is no site (val, arg untouched).
    cdef int64_t q = -1, u, fu, sq, tq, fq, w, x, d1, d2, lo, hi
    for u in range(n + 2):
        fu = f[u]
        if fu >= _INF:
            continue
        while q >= 0:
            sq = s[q]
            tq = t[q]
            fq = fs[q]
            d1 = tq - sq
            d2 = tq - u
            if d1 * d1 + fq <= d2 * d2 + fu:
                break
            q -= 1
        if q < 0:
            q = 0
            s[0] = u
            t[0] = 1
            fs[0] = fu
        else:
            sq = s[q]
            w = 1 + _floordiv_exact(u * u - sq * sq + fu - fs[q], 2 * (u - sq))
            if w <= n:
                q += 1
                s[q] = u
                t[q] = w
                fs[q] = fu
    if q < 0:
        return False
    hi = n
    while q >= 0:
        sq = s[q]
        fq = fs[q]
        lo = t[q]
        for x in range(lo, hi + 1):
            d1 = x - sq
            val[x - 1] = d1 * d1 + fq
            arg[x - 1] = sq - 1
        hi = lo - 1
        q -= 1
    return True


def column_pass(int64_t p0, int64_t p1, const uint8_t[:, ::1] occ, bint wall, double[:, ::1] f1,
                idx_t[:, ::1] vz, bint want_nearest):
    """Columns ``p0:p1`` of the ``(layers, rows * cols)`` view: ``f1[z, p]`` = squared distance along z
    to the nearest obstacle of column ``p`` (``inf`` if none), and with ``want_nearest`` ``vz[z, p]`` its
    layer (-1 / layers: the wall; the smaller layer on a tie)."""
    cdef int64_t layers = occ.shape[0], z, p, n = p1 - p0
    if layers == 0 or n <= 0:
        return
    cdef double edge = 1.0 if wall else INFINITY
    cdef double* db
    cdef int32_t* vb
    cdef double* row
    cdef double* prev
    cdef const uint8_t* o
    cdef idx_t* vrow
    cdef idx_t* vprev
    cdef double d
    with nogil:
        db = <double*>_alloc(n * sizeof(double))
        vb = <int32_t*>_alloc(n * sizeof(int32_t))
        # down: distance to the nearest obstacle at or above (smaller z)
        o = &occ[0, p0]
        row = &f1[0, p0]
        for p in range(n):
            row[p] = 0.0 if o[p] else edge
        if want_nearest:
            vrow = &vz[0, p0]
            for p in range(n):
                vrow[p] = <idx_t>(0 if o[p] else -1)
        for z in range(1, layers):
            o = &occ[z, p0]
            row = &f1[z, p0]
            prev = &f1[z - 1, p0]
            for p in range(n):
                row[p] = 0.0 if o[p] else prev[p] + 1.0
            if want_nearest:
                vrow = &vz[z, p0]
                vprev = &vz[z - 1, p0]
                for p in range(n):
                    vrow[p] = <idx_t>z if o[p] else vprev[p]
        # up: the nearest below wins only if strictly nearer; then square
        for p in range(n):
            db[p] = INFINITY
            vb[p] = <int32_t>layers
        for z in range(layers - 1, -1, -1):
            o = &occ[z, p0]
            row = &f1[z, p0]
            if z == layers - 1:
                for p in range(n):
                    db[p] = 0.0 if o[p] else edge
                    vb[p] = <int32_t>(z if o[p] else layers)
            else:
                for p in range(n):
                    db[p] = 0.0 if o[p] else db[p] + 1.0
                    vb[p] = <int32_t>z if o[p] else vb[p]
            if want_nearest:
                vrow = &vz[z, p0]
                for p in range(n):
                    if db[p] < row[p]:
                        vrow[p] = <idx_t>vb[p]
            for p in range(n):
                d = db[p] if db[p] < row[p] else row[p]
                row[p] = d * d
        free(db)
        free(vb)


def slice_pass(int64_t z0, int64_t z1, double[:, :, ::1] dist, idx_t[:, :, ::1] nl, idx_t[:, :, ::1] nr,
               idx_t[:, :, ::1] nc, bint want_nearest, bint wall, double resolution):
    """Layers ``z0:z1``, in place: from the column pass's squared distances in ``dist`` (and its layers in
    ``nl``), the envelope along y, then along x: ``dist`` becomes the Euclidean distance in world units,
    ``nl, nr, nc`` the nearest obstacle voxel (with ``want_nearest``)."""
    cdef int64_t layers = dist.shape[0], rows = dist.shape[1], cols = dist.shape[2]
    if layers == 0 or rows == 0 or cols == 0 or z1 <= z0:
        return
    cdef int64_t m = (rows if rows > cols else cols) + 2, plane = rows * cols
    cdef int64_t z, y, x, x0, nb, j, xc, yr, u
    cdef int64_t edge = 0 if wall else _INF
    cdef bint found
    cdef int64_t* f2
    cdef int32_t* ay
    cdef int32_t* vzc
    cdef int64_t* fl
    cdef int64_t* vl
    cdef int32_t* al
    cdef int64_t* s
    cdef int64_t* t
    cdef int64_t* fs
    cdef int64_t* val
    cdef int64_t* arg
    cdef int64_t* f
    cdef double* drow
    cdef double v
    with nogil:
        f2 = <int64_t*>_alloc(plane * sizeof(int64_t))
        ay = <int32_t*>_alloc((plane if want_nearest else 1) * sizeof(int32_t))
        vzc = <int32_t*>_alloc((plane if want_nearest else 1) * sizeof(int32_t))
        fl = <int64_t*>_alloc(_BLOCK * (rows + 2) * sizeof(int64_t))
        vl = <int64_t*>_alloc(_BLOCK * rows * sizeof(int64_t))
        al = <int32_t*>_alloc(_BLOCK * rows * sizeof(int32_t))
        s = <int64_t*>_alloc(m * sizeof(int64_t))
        t = <int64_t*>_alloc(m * sizeof(int64_t))
        fs = <int64_t*>_alloc(m * sizeof(int64_t))
        val = <int64_t*>_alloc(m * sizeof(int64_t))
        arg = <int64_t*>_alloc(m * sizeof(int64_t))
        f = <int64_t*>_alloc(m * sizeof(int64_t))
        for z in range(z0, z1):
            if want_nearest:
                for y in range(rows):
                    for x in range(cols):
                        vzc[y * cols + x] = <int32_t>nl[z, y, x]
            # along y, _BLOCK columns at a time
            for x0 in range(0, cols, _BLOCK):
                nb = cols - x0 if cols - x0 < _BLOCK else _BLOCK
                for j in range(nb):
                    fl[j * (rows + 2)] = edge
                    fl[j * (rows + 2) + rows + 1] = edge
                for y in range(rows):
                    drow = &dist[z, y, x0]
                    for j in range(nb):
                        v = drow[j]
                        fl[j * (rows + 2) + y + 1] = <int64_t>v if v < 1e300 else _INF
                for j in range(nb):
                    found = _envelope(&fl[j * (rows + 2)], rows, s, t, fs, val, arg)
                    if found:
                        for y in range(rows):
                            vl[j * rows + y] = val[y]
                            al[j * rows + y] = <int32_t>arg[y]
                    else:
                        for y in range(rows):
                            vl[j * rows + y] = _INF
                            al[j * rows + y] = -1
                for y in range(rows):
                    for j in range(nb):
                        f2[y * cols + x0 + j] = vl[j * rows + y]
                    if want_nearest:
                        for j in range(nb):
                            ay[y * cols + x0 + j] = al[j * rows + y]
            # along x, row by row
            f[0] = edge
            f[cols + 1] = edge
            for y in range(rows):
                drow = &dist[z, y, 0]
                for x in range(cols):
                    f[x + 1] = f2[y * cols + x]
                found = _envelope(f, cols, s, t, fs, val, arg)
                if not found:  # no obstacle at all (the caller handles that map): nothing reached
                    for x in range(cols):
                        drow[x] = INFINITY
                    if want_nearest:
                        for x in range(cols):
                            nl[z, y, x] = -1
                            nr[z, y, x] = -1
                            nc[z, y, x] = -1
                    continue
                for x in range(cols):
                    drow[x] = sqrt(<double>val[x]) * resolution
                if want_nearest:
                    for x in range(cols):
                        xc = arg[x]
                        nc[z, y, x] = <idx_t>xc
                        if xc < 0 or xc >= cols:  # the wall across the x faces
                            nr[z, y, x] = <idx_t>y
                            nl[z, y, x] = <idx_t>z
                            continue
                        yr = ay[y * cols + xc]
                        nr[z, y, x] = <idx_t>yr
                        if yr < 0 or yr >= rows:  # the wall across the y faces
                            nl[z, y, x] = <idx_t>z
                        else:
                            nl[z, y, x] = <idx_t>vzc[yr * cols + xc]
        free(f2)
        free(ay)
        free(vzc)
        free(fl)
        free(vl)
        free(al)
        free(s)
        free(t)
        free(fs)
        free(val)
        free(arg)
        free(f)


ctypedef fused flat_t:
    int32_t
    int64_t


cdef inline void _minsel(int32_t* d, flat_t* f, const int32_t* d2, const flat_t* f2, int64_t a0, int64_t a1,
                         int64_t off, int32_t add, bint nearest) noexcept nogil:
    # d[a] = min(d[a], d2[a + off] + add) for a in a0:a1, carrying f (branch-free selects)
    if nearest:
        _relax_add(d, f, d2, f2, a0, a1, off, add)
    else:
        _relax_plain(d, d2, a0, a1, off, add)


cdef inline void _relax_plain(int32_t* d, const int32_t* d2, int64_t a0, int64_t a1, int64_t off,
                              int32_t add) noexcept nogil:
    cdef int64_t a
    cdef int32_t cand
    for a in range(a0, a1):
        cand = d2[a + off] + add
        d[a] = cand if cand < d[a] else d[a]


cdef inline void _relax_add(int32_t* d, flat_t* f, const int32_t* d2, const flat_t* f2, int64_t a0, int64_t a1,
                            int64_t off, int32_t add) noexcept nogil:
    # the select as masks, so that the loop vectorizes
    cdef int64_t a
    cdef int32_t cand, cur
    cdef flat_t m
    cdef int32_t* dd = d + a0
    cdef const int32_t* ds = d2 + a0 + off
    cdef flat_t* ff = f + a0
    cdef const flat_t* fs = f2 + a0 + off
    for a in range(a1 - a0):
        cand = ds[a] + add
        cur = dd[a]
        m = -(<flat_t>(cand < cur))
        ff[a] = (fs[a] & m) | (ff[a] & ~m)
        dd[a] = cand if cand < cur else cur


cdef void _chamfer_layer(int32_t* steps, flat_t* near, bint nearest, bint chess, int64_t layers, int64_t rows,
                         int64_t cols, int64_t z, int64_t sz, int32_t* ad, flat_t* af) noexcept nogil:
    # Layer z of a pass (sz = -1 forward, +1 backward): first the neighbours in the layer before (in the
    # pass's order), which are final: the 3 x 3 minimum of that layer (separable: along x into the plane
    # buffer ad/af, then along y) or, 6-connected, the voxel itself; then the layer's own rows in the
    # pass's order, each against the row before and then sequentially along x. The same minima as the
    # raster pass over the 13 neighbours, in fewer loops.
    cdef int64_t plane = rows * cols, y, yy, x, k
    cdef int64_t zz = z + sz
    cdef int32_t* d
    cdef flat_t* f
    cdef int32_t* p
    cdef flat_t* pf
    cdef int32_t cand
    if 0 <= zz < layers:
        p = steps + zz * plane
        pf = near + zz * plane
        if chess:
            for k in range(plane):
                ad[k] = p[k]
            if nearest:
                for k in range(plane):
                    af[k] = pf[k]
            for y in range(rows):
                _minsel(ad + y * cols, af + y * cols, p + y * cols, pf + y * cols, 1, cols, -1, 0, nearest)
                _minsel(ad + y * cols, af + y * cols, p + y * cols, pf + y * cols, 0, cols - 1, 1, 0, nearest)
            for y in range(rows):
                d = steps + z * plane + y * cols
                f = near + z * plane + y * cols
                for yy in range(y - 1, y + 2):
                    if 0 <= yy < rows:
                        _minsel(d, f, ad + yy * cols, af + yy * cols, 0, cols, 0, 1, nearest)
        else:
            _minsel(steps + z * plane, near + z * plane, p, pf, 0, plane, 0, 1, nearest)
    for k in range(rows):
        y = k if sz < 0 else rows - 1 - k
        d = steps + z * plane + y * cols
        f = near + z * plane + y * cols
        yy = y + sz
        if 0 <= yy < rows:
            p = steps + z * plane + yy * cols
            pf = near + z * plane + yy * cols
            _minsel(d, f, p, pf, 0, cols, 0, 1, nearest)
            if chess:
                _minsel(d, f, p, pf, 1, cols, -1, 1, nearest)
                _minsel(d, f, p, pf, 0, cols - 1, 1, 1, nearest)
        if sz < 0:
            for x in range(1, cols):
                cand = d[x - 1] + 1
                if cand < d[x]:
                    d[x] = cand
                    if nearest:
                        f[x] = f[x - 1]
        else:
            for x in range(cols - 2, -1, -1):
                cand = d[x + 1] + 1
                if cand < d[x]:
                    d[x] = cand
                    if nearest:
                        f[x] = f[x + 1]


cdef inline void _wall_seed(int32_t* steps, flat_t* near, const uint8_t* occ, bint nearest, int64_t rows,
                            int64_t cols, int64_t z, int64_t y, int64_t x, int64_t wl, int64_t wr,
                            int64_t wc) noexcept nogil:
    cdef int64_t k = (z * rows + y) * cols + x
    if occ[k]:
        return
    steps[k] = 1
    if nearest:
        near[k] = <flat_t>(((wl + 1) * (rows + 2) + wr + 1) * (cols + 2) + wc + 1)


def chamfer(const uint8_t[:, :, ::1] occ, bint wall, bint chess, int32_t[:, :, ::1] steps, flat_t[:, :, ::1] near,
            bint want_nearest):
    """Chessboard (``chess``, 26-connected) or taxicab (6-connected) distance in voxels into ``steps``
    (0 on obstacles, ``2**30`` where nothing is reached), with the nearest obstacle voxel as a flat index
    into the grid padded by one voxel on every side in ``near`` (``want_nearest``; -1 where nothing is
    reached; :func:`decode` splits it). Two raster passes over the whole grid."""
    cdef int64_t layers = occ.shape[0], rows = occ.shape[1], cols = occ.shape[2], z, y, x, k, plane = rows * cols
    cdef int64_t pr = rows + 2, pc = cols + 2
    if layers == 0 or rows == 0 or cols == 0:
        return
    cdef int32_t* sp = &steps[0, 0, 0]
    cdef flat_t* fp = &near[0, 0, 0]
    cdef const uint8_t* op = &occ[0, 0, 0]
    cdef const uint8_t* orow
    cdef int32_t* ad
    cdef flat_t* af
    with nogil:
        for z in range(layers):
            for y in range(rows):
                k = (z * rows + y) * cols
                orow = op + k
                for x in range(cols):
                    sp[k + x] = 0 if orow[x] else _FAR
                if want_nearest:
                    for x in range(cols):
                        fp[k + x] = <flat_t>(((z + 1) * pr + y + 1) * pc + x + 1) if orow[x] else -1
        if wall:  # boundary voxels are next to the shell; where they touch several faces the col's wins, then the row's
            for y in range(rows):
                for x in range(cols):
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, 0, y, x, -1, y, x)
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, layers - 1, y, x, layers, y, x)
            for z in range(layers):
                for x in range(cols):
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, z, 0, x, z, -1, x)
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, z, rows - 1, x, z, rows, x)
                for y in range(rows):
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, z, y, 0, z, y, -1)
                    _wall_seed(sp, fp, op, want_nearest, rows, cols, z, y, cols - 1, z, y, cols)
        ad = <int32_t*>_alloc(plane * sizeof(int32_t))
        af = <flat_t*>_alloc((plane if want_nearest else 1) * sizeof(flat_t))
        for z in range(layers):
            _chamfer_layer(sp, fp, want_nearest, chess, layers, rows, cols, z, -1, ad, af)
        for z in range(layers - 1, -1, -1):
            _chamfer_layer(sp, fp, want_nearest, chess, layers, rows, cols, z, 1, ad, af)
        free(ad)
        free(af)


def decode(int64_t z0, int64_t z1, const flat_t[:, :, ::1] near, idx_t[:, :, ::1] nl, idx_t[:, :, ::1] nr,
           idx_t[:, :, ::1] nc):
    """Layers ``z0:z1``: the flat indices of :func:`chamfer` as ``(layer, row, col)`` (-1 on all three for -1)."""
    cdef int64_t rows = near.shape[1], cols = near.shape[2], pr = rows + 2, pc = cols + 2, z, y, x, f, q
    with nogil:
        for z in range(z0, z1):
            for y in range(rows):
                for x in range(cols):
                    f = near[z, y, x]
                    if f < 0:
                        nl[z, y, x] = -1
                        nr[z, y, x] = -1
                        nc[z, y, x] = -1
                        continue
                    q = f // pc
                    nc[z, y, x] = <idx_t>(f - q * pc - 1)
                    nl[z, y, x] = <idx_t>(q // pr - 1)
                    nr[z, y, x] = <idx_t>(q - (q // pr) * pr - 1)


def gather_labels(int64_t z0, int64_t z1, const idx_t[:, :, ::1] nl, const idx_t[:, :, ::1] nr,
                  const idx_t[:, :, ::1] nc, const int32_t[:, :, ::1] comp, int32_t border, int32_t none,
                  int32_t[:, :, ::1] label):
    """Layers ``z0:z1``: ``label`` = ``comp`` at the nearest voxel; ``border`` where that is the wall (outside
    the grid), ``none`` where there is no nearest voxel (all three indices -1)."""
    cdef int64_t layers = comp.shape[0], rows = comp.shape[1], cols = comp.shape[2], z, y, x, a, b, c
    with nogil:
        for z in range(z0, z1):
            for y in range(rows):
                for x in range(cols):
                    a = nl[z, y, x]
                    b = nr[z, y, x]
                    c = nc[z, y, x]
                    if 0 <= a < layers and 0 <= b < rows and 0 <= c < cols:
                        label[z, y, x] = comp[a, b, c]
                    elif a == -1 and b == -1 and c == -1:
                        label[z, y, x] = none
                    else:
                        label[z, y, x] = border


cdef inline void _gvd_dir(const int32_t* la, const double* ka, const int32_t* lb, const double* kb,
                          const uint8_t* fb, uint8_t* mark, int64_t a0, int64_t a1, int64_t off) noexcept nogil:
    # voxels a in a0:a1 against b = a + off of a neighbouring (or the same) row: a is marked if b is a
    # free voxel of another label and a is farther from its obstacle (on a tie: a has the smaller label)
    cdef int64_t a, b
    for a in range(a0, a1):
        b = a + off
        mark[a] |= (la[a] != lb[b]) & (fb[b] == 0) & ((ka[a] > kb[b]) | ((ka[a] == kb[b]) & (la[a] < lb[b])))


def gvd_layers(int64_t z0, int64_t z1, const int32_t[:, :, ::1] label, const double[:, :, ::1] key,
               const uint8_t[:, :, ::1] occ, uint8_t[:, :, ::1] gvd):
    """Layers ``z0:z1`` of the GVD: a free voxel is marked if some 26-neighbouring free voxel has another
    label and it is farther from its obstacle than that neighbour (by ``key``; on a tie: it has the
    smaller label). Each voxel reads its neighbours only, so layers go in any order, on any thread."""
    cdef int64_t layers = label.shape[0], rows = label.shape[1], cols = label.shape[2]
    cdef int64_t z, y, x, dz, dy, zz, yy
    cdef uint8_t* mark
    cdef const int32_t* la
    cdef const double* ka
    cdef const uint8_t* fa
    if rows == 0 or cols == 0 or z1 <= z0:
        return
    with nogil:
        mark = <uint8_t*>_alloc(cols)
        for z in range(z0, z1):
            for y in range(rows):
                la = &label[z, y, 0]
                ka = &key[z, y, 0]
                fa = &occ[z, y, 0]
                for x in range(cols):
                    mark[x] = 0
                for dz in range(-1, 2):
                    zz = z + dz
                    if zz < 0 or zz >= layers:
                        continue
                    for dy in range(-1, 2):
                        yy = y + dy
                        if yy < 0 or yy >= rows:
                            continue
                        if dz != 0 or dy != 0:
                            _gvd_dir(la, ka, &label[zz, yy, 0], &key[zz, yy, 0], &occ[zz, yy, 0], mark, 0, cols, 0)
                        _gvd_dir(la, ka, &label[zz, yy, 0], &key[zz, yy, 0], &occ[zz, yy, 0], mark, 1, cols, -1)
                        _gvd_dir(la, ka, &label[zz, yy, 0], &key[zz, yy, 0], &occ[zz, yy, 0], mark, 0, cols - 1, 1)
                for x in range(cols):
                    gvd[z, y, x] = mark[x] & (fa[x] == 0)
        free(mark)


def scale_steps(int64_t z0, int64_t z1, const int32_t[:, :, ::1] steps, double resolution, double[:, :, ::1] dist):
    """Layers ``z0:z1``: ``dist = steps * resolution`` (``inf`` where nothing was reached)."""
    cdef int64_t rows = steps.shape[1], cols = steps.shape[2], z, y, x
    cdef int32_t s
    with nogil:
        for z in range(z0, z1):
            for y in range(rows):
                for x in range(cols):
                    s = steps[z, y, x]
                    dist[z, y, x] = INFINITY if s >= _FAR else s * resolution


def saturate_layers(int64_t z0, int64_t z1, double[:, :, ::1] dist, double radius, double far):
    """Layers ``z0:z1``, in place: ``dist[dist >= radius] = far``."""
    cdef int64_t rows = dist.shape[1], cols = dist.shape[2], z, y, x
    with nogil:
        for z in range(z0, z1):
            for y in range(rows):
                for x in range(cols):
                    if dist[z, y, x] >= radius:
                        dist[z, y, x] = far
