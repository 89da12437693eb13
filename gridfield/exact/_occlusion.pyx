# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels behind :mod:`gridfield.exact.anyangle` (private; imported on first use): the
visibility of the convex corners from a point by a nearest-first search with occlusion culling
(exact: the same pairs and distances as the exhaustive walks of :mod:`gridfield.exact._anyangle`).
Its search from one point, ``_visible_set``, is exported through ``_occlusion.pxd`` to the lazy A* of
:mod:`gridfield.exact._astar`, which runs it from each corner it expands.

Lattice units, the padded blocked array ``B`` and the free-segment rule are those of
:mod:`gridfield.exact._anyangle`, whose segment walk and edge list are cimported from it
(``_anyangle.pxd``). Nothing in this module validates input; :mod:`gridfield.exact.anyangle` does.

Cython, compiled at install; every kernel releases the GIL while it runs. The C helpers take raw
pointers (``B[r * W + c]`` with ``W = cols + 2``, bounds checks off). Integer ``//`` and ``%`` appear
on non-negative operands only, except for the angular bins, which wrap through :func:`_wrap`
(Python's modulo); float floor division is Python's (:func:`_floordiv`).
"""

from libc.math cimport INFINITY, ceil, copysign, floor, fmod, sqrt
from libc.stdlib cimport free, malloc

from ._anyangle cimport (
    Edges,
    _dmax,
    _dmin,
    _edges_init,
    _edges_out,
    _edges_reserve,
    _segment_free,
    blk_t,
    f64c_1d,
    i64c_1d,
)

import numpy as np

__all__ = ["N_BINS", "run_extents", "visibility_edges_culled", "visible_from_culled"]

#: Angular bins of the occlusion table (over the pseudo-angle, see :func:`_pseudo_angle`).
N_BINS = _NB

ctypedef const int32_t[:, ::1] ext_t


# Ext and Prune are declared in _occlusion.pxd (shared with _astar)
cdef inline int64_t _wrap(int64_t b, int64_t n) noexcept nogil:
    """``b % n`` with Python's sign rule (``n > 0``)."""
    cdef int64_t m = b % n
    return m + n if m < 0 else m


cdef inline double _floordiv(double a, double b) noexcept nogil:
    """Python's float ``a // b`` (CPython's algorithm, so the result is the same to the bit)."""
    cdef double mod = fmod(a, b), div, fl
    div = (a - mod) / b
    if mod != 0.0:
        if (b < 0) != (mod < 0):
            div -= 1.0
    if div != 0.0:
        fl = floor(div)
        if div - fl > 0.5:
            fl += 1.0
    else:
        fl = copysign(0.0, a / b)
    return fl


# ----------------------------------------------------------------------------------------
# Visibility from one point with occlusion culling (exact)
# ----------------------------------------------------------------------------------------
cdef inline double _pseudo_angle(double dx, double dy) noexcept nogil:
    """A number in [0, 4) increasing with the angle of ``(dx, dy)`` (the "diamond angle")."""
    if dy >= 0:
        if dx >= 0:
            return dy / (dx + dy)
        return 1.0 - dx / (-dx + dy)
    if dx < 0:
        return 2.0 - dy / (-dx - dy)
    return 3.0 + dx / (dx - dy)


cdef int64_t _walk_hit(const uint8_t* B, int64_t W, double px, double py, double qx, double qy) noexcept nogil:
    """:func:`segment_free` that also says where it was blocked: -1 free, ``r * (cols + 2) + c``
    (padded indices) of the first blocked cell whose interior the segment enters, or -2 when it was
    stopped otherwise (a segment along a grid line); ``-3 - (y * W + x)`` for a pinch point ``(x, y)``."""
    cdef double dx = qx - px, dy = qy - py, adx, ady, nx, ny, ax, ay, lhs, rhs
    cdef int64_t sx, sy, c, r
    if dx == 0.0 or dy == 0.0:
        return -1 if _segment_free(B, W, px, py, qx, qy) else -2
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
            return (r + 1) * W + (c + 1)
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
            if B[(r + 1) * W + c + sx + 1] and B[(r + sy + 1) * W + c + 1]:
                return -3 - (<int64_t>ny * W + <int64_t>nx)  # the pinch point (lattice nx, ny)
            c += sx
            r += sy
            nx += sx
            ny += sy


def run_extents(blk_t B):
    """For every blocked cell of the padded array: the first and last padded column of its maximal
    horizontal run of blocked cells, and the first and last padded row of its vertical run."""
    cdef int64_t R = B.shape[0], C = B.shape[1], r, c, e, t
    hl_a = np.zeros((R, C), np.int32)
    hr_a = np.zeros((R, C), np.int32)
    vl_a = np.zeros((R, C), np.int32)
    vr_a = np.zeros((R, C), np.int32)
    cdef int32_t[:, ::1] hl = hl_a, hr = hr_a, vl = vl_a, vr = vr_a
    with nogil:
        for r in range(R):
            c = 0
            while c < C:
                if B[r, c]:
                    e = c
                    while e + 1 < C and B[r, e + 1]:
                        e += 1
                    for t in range(c, e + 1):
                        hl[r, t] = <int32_t>c
                        hr[r, t] = <int32_t>e
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
                        vl[t, c] = <int32_t>r
                        vr[t, c] = <int32_t>e
                    r = e + 1
                else:
                    r += 1
    return hl_a, hr_a, vl_a, vr_a


cdef int64_t _occlude_poly(double* D, int64_t nb, double* part, double px, double py, const double* xs,
                           const double* ys, int64_t npts) noexcept nogil:
    """Record a convex blocked polygon (corners ``xs, ys[:npts]``, ``p`` outside it) as seen from
    ``p``: every angular bin strictly inside its angular extent is blocked beyond its farthest
    corner (any ray strictly inside the extent enters it). Returns how many bins were ``inf``.

    An end of the extent on an axis direction (a corner level with ``p``) is exact, and the bin
    beside it counts (candidates exactly on an axis never use the bins); elsewhere a margin keeps
    the bins clear of the rounding of the pseudo-angles. ``part[4 * b:]`` = (covered from the start up
    to this fraction, beyond this squared distance; covered from this fraction to the end, beyond this).
    """
    cdef double mx = 0.0, my = 0.0, ac, lo = 10.0, hi = -10.0, lo_abs = 0.0, hi_abs = 0.0, far = 0.0
    cdef double ex, ey, a, rel, wrap, scale, lo_b, hi_b, fr, both
    cdef bint lo_axis = False, hi_axis = False, axis
    cdef int64_t k, b0, b1, b, bb, newly = 0, bl, bh, side
    for k in range(npts):
        mx += xs[k]
        my += ys[k]
    ac = _pseudo_angle(mx / npts - px, my / npts - py)
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
        far = _dmax(far, ex * ex + ey * ey)
    scale = nb / 4.0
    b0 = <int64_t>floor(lo_abs * scale + 0.5) if lo_axis else <int64_t>floor(lo_abs * scale + 1e-6) + 1
    b1 = <int64_t>floor(hi_abs * scale + 0.5) - 1 if hi_axis else <int64_t>ceil(hi_abs * scale - 1e-6) - 2
    for b in range(b0, b1 + 1):
        bb = _wrap(b, nb)
        if far < D[bb]:
            if D[bb] == INFINITY:
                newly += 1
            D[bb] = far
    # the bins at the two ends, covered in part: a bin covered from its start by one occluder and to
    # its end by another, the two overlapping, is covered (beyond the farther of the two)
    lo_b = lo_abs * scale + (0.0 if lo_axis else 1e-6)
    hi_b = hi_abs * scale - (0.0 if hi_axis else 1e-6)
    bl = <int64_t>floor(lo_b)
    bh = <int64_t>floor(hi_b)
    if bh > bl:
        bb = _wrap(bl, nb)
        fr = lo_b - bl
        if fr < part[4 * bb + 2] or (fr == part[4 * bb + 2] and far < part[4 * bb + 3]):
            part[4 * bb + 2] = fr
            part[4 * bb + 3] = far
        bb = _wrap(bh, nb)
        fr = hi_b - bh
        if fr > part[4 * bb] or (fr == part[4 * bb] and far < part[4 * bb + 1]):
            part[4 * bb] = fr
            part[4 * bb + 1] = far
        for side in range(2):
            bb = _wrap(bl if side == 0 else bh, nb)
            if part[4 * bb] > part[4 * bb + 2]:
                both = _dmax(part[4 * bb + 1], part[4 * bb + 3])
                if both < D[bb]:
                    if D[bb] == INFINITY:
                        newly += 1
                    D[bb] = both
    return newly


cdef int64_t _occlude_hit(double* D, int64_t nb, double* part, double px, double py, const uint8_t* B, int64_t W,
                          int64_t hit, const Ext* ext, double* xs, double* ys) noexcept nogil:
    """Occluders learnt from a failed walk: the maximal horizontal and vertical runs through the
    blocked cell it entered (``hit >= 0``), or the convex hull of the two cells of the pinch point it
    was stopped at (``hit <= -3``). Shapes ``p`` lies on or in are left out."""
    cdef int64_t newly = 0, r, c, t, code, yq, xq
    cdef double x0, x1, y0, y1, fx, fy
    if hit >= 0:
        r = hit // W
        c = hit % W
        for t in range(2):
            if t == 0:  # padded cell (r, c) -> lattice square [c - 1, c] x [r - 1, r]
                x0 = ext.hl[r * W + c] - 1.0
                x1 = ext.hr[r * W + c] + 0.0
                y0 = r - 1.0
                y1 = r + 0.0
            else:
                x0 = c - 1.0
                x1 = c + 0.0
                y0 = ext.vl[r * W + c] - 1.0
                y1 = ext.vr[r * W + c] + 0.0
            if x0 <= px <= x1 and y0 <= py <= y1:
                continue
            xs[0] = x0
            ys[0] = y0
            xs[1] = x1
            ys[1] = y0
            xs[2] = x1
            ys[2] = y1
            xs[3] = x0
            ys[3] = y1
            newly += _occlude_poly(D, nb, part, px, py, xs, ys, 4)
        return newly
    if hit <= -3:
        code = -3 - hit
        yq = code // W
        xq = code % W
        fx = <double>xq
        fy = <double>yq
        if fx - 1.0 <= px <= fx + 1.0 and fy - 1.0 <= py <= fy + 1.0:
            return 0
        if B[yq * W + xq] and B[(yq + 1) * W + xq + 1]:  # south-west and north-east cells
            xs[0] = fx - 1.0
            ys[0] = fy - 1.0
            xs[1] = fx + 0.0
            ys[1] = fy - 1.0
            xs[2] = fx + 1.0
            ys[2] = fy + 0.0
            xs[3] = fx + 1.0
            ys[3] = fy + 1.0
            xs[4] = fx + 0.0
            ys[4] = fy + 1.0
            xs[5] = fx - 1.0
            ys[5] = fy + 0.0
        else:  # north-west and south-east
            xs[0] = fx - 1.0
            ys[0] = fy + 1.0
            xs[1] = fx - 1.0
            ys[1] = fy + 0.0
            xs[2] = fx + 0.0
            ys[2] = fy - 1.0
            xs[3] = fx + 1.0
            ys[3] = fy - 1.0
            xs[4] = fx + 1.0
            ys[4] = fy + 0.0
            xs[5] = fx + 0.0
            ys[5] = fy + 1.0
        return _occlude_poly(D, nb, part, px, py, xs, ys, 6)
    return 0


cdef double _axis_run(const uint8_t* B, int64_t R, int64_t W, double px, double py, int64_t s,
                      bint horizontal) noexcept nogil:
    """How far a segment from ``p`` along a grid line (``y = py`` if ``horizontal`` else ``x = px``,
    an integer) in direction ``s`` (+-1) stays free, measured to the farthest lattice point it reaches
    (-1: none). The rule of :func:`_axis_free`, tested piece by piece."""
    cdef int64_t rows = R - 2, cols = W - 2, m, top, k, c, x
    cdef double u = px if horizontal else py, run = -1.0, d
    cdef bint first = True
    cdef uint8_t la, ra, lb, rb
    m = <int64_t>py if horizontal else <int64_t>px
    top = cols if horizontal else rows
    k = <int64_t>floor(u) + 1 if s > 0 else <int64_t>ceil(u) - 1
    while 0 <= k <= top:
        c = k - 1 if s > 0 else k  # the cell column (row) of the piece ending at k
        if horizontal:
            if B[m * W + c + 1] and B[(m + 1) * W + c + 1]:
                break
        elif B[(c + 1) * W + m] and B[(c + 1) * W + m + 1]:
            break
        if not first:  # the lattice point k - s is now inside the segment: no pinch there
            x = k - s
            if horizontal:
                la = B[(m + 1) * W + x]
                ra = B[(m + 1) * W + x + 1]
                lb = B[m * W + x]
                rb = B[m * W + x + 1]
            else:
                la = B[x * W + m + 1]
                ra = B[(x + 1) * W + m + 1]
                lb = B[x * W + m]
                rb = B[(x + 1) * W + m]
            if not ((la == 0 and ra == 0) or (lb == 0 and rb == 0)):
                break
        d = k - u
        run = -d if d < 0 else d
        first = False
        k += s
    return run


cdef bint _block_hidden(const double* D, int64_t nb, double px, double py, double x0, double y0, double size,
                        double scale) noexcept nogil:
    """Whether every corner in the block ``[x0, x0 + size] x [y0, y0 + size]`` is hidden: every bin
    its angular extent touches is blocked nearer than the block. Blocks level with ``p`` (corners on
    an axis through it use the axis runs, not the bins) are never hidden."""
    cdef double x1 = x0 + size, y1 = y0 + size, ddx, ddy, dmin2, ac, lo = 10.0, hi = -10.0, rel
    cdef int64_t k, b0, b1, b
    if x0 <= px <= x1 or y0 <= py <= y1:
        return False
    ddx = _dmax(_dmax(x0 - px, 0.0), px - x1)
    ddy = _dmax(_dmax(y0 - py, 0.0), py - y1)
    dmin2 = ddx * ddx + ddy * ddy
    ac = _pseudo_angle(0.5 * (x0 + x1) - px, 0.5 * (y0 + y1) - py)
    for k in range(4):
        rel = _pseudo_angle((x0 if (k & 1) == 0 else x1) - px, (y0 if k < 2 else y1) - py) - ac
        if rel >= 2.0:
            rel -= 4.0
        elif rel < -2.0:
            rel += 4.0
        lo = _dmin(lo, rel)
        hi = _dmax(hi, rel)
    b0 = <int64_t>floor((ac + lo) * scale) - 1  # every bin touched, with one to spare on each side
    b1 = <int64_t>floor((ac + hi) * scale) + 1
    for b in range(b0, b1 + 1):
        if D[_wrap(b, nb)] >= dmin2:
            return False
    return True


cdef inline void _pseudo_dir(double a, double* dx, double* dy) noexcept nogil:
    """A direction whose :func:`_pseudo_angle` is ``a`` (in [0, 4])."""
    if a < 1.0:
        dx[0] = 1.0 - a
        dy[0] = a
    elif a < 2.0:
        dx[0] = 1.0 - a
        dy[0] = 2.0 - a
    elif a < 3.0:
        dx[0] = a - 3.0
        dy[0] = 2.0 - a
    else:
        dx[0] = a - 3.0
        dy[0] = a - 4.0


cdef void _half_plane_bins(double* D, int64_t nb, double scale, double hx, double hy) noexcept nogil:
    """Block every bin ``b`` whose neighbours ``b - 1 .. b + 1`` lie strictly outside the half-plane
    ``hx * dy - hy * dx >= 0``: both ends of that three-bin arc (less than 180 degrees) are outside,
    so every direction of it is, and the one bin of margin covers the rounding of a candidate's bin."""
    cdef int64_t b
    cdef double ax, ay, bx, by
    for b in range(nb):
        if D[b] < 0:
            continue
        _pseudo_dir(_wrap(b - 1, nb) / scale, &ax, &ay)
        _pseudo_dir(_wrap(b + 2, nb) / scale, &bx, &by)
        if hx * ay - hy * ax < 0 and hx * by - hy * bx < 0:
            D[b] = -1.0


cdef inline bint _improves(const Prune* pr, int64_t j, double d2, const double* vx, const double* vy) noexcept nogil:
    """Whether the edge to the visible corner ``j`` (squared length ``d2``) is worth reporting: ``j``
    open, ``gu + d < g[j]`` and ``gu + d + |j - goal| < best``."""
    cdef double nd, tx, ty
    if pr.closed[j]:
        return False
    nd = pr.gu + sqrt(d2)
    if nd >= pr.g[j]:
        return False
    tx = vx[j] - pr.gx
    ty = vy[j] - pr.gy
    return nd + sqrt(tx * tx + ty * ty) < pr.best


cdef int64_t _visible_set(const uint8_t* B, int64_t R, int64_t W, const Ext* ext, double px, double py,
                          double self_q, const double* vx, const double* vy, const double* qx, const double* qy,
                          const int64_t* bstart, const int64_t* bverts, int64_t nbx, int64_t nby, double bsize,
                          int64_t jmin, double* D, int64_t nb, double* part, int64_t* out_j,
                          double* out_d, const Prune* pr) noexcept nogil:
    """Corners seen from ``p`` along taut directions, nearest blocks first, with occlusion culling.

    ``self_q`` is ``qx * qy`` of the corner at ``p`` (0 for a free point: every direction). Corners
    are bucketed in square blocks of ``bsize`` lattice units (``bstart``/``bverts``: CSR over the
    ``nbx * nby`` blocks). A walk that fails records what stopped it (:func:`_occlude_hit`; ``ext``
    from :func:`run_extents`) in the occlusion table ``D`` (squared distance beyond which each angular
    bin is blocked); a corner whose bin is blocked before it is skipped without a walk (its segment
    would enter a blocked cell or pass the pinch point), as is a whole block of corners hidden that
    way (:func:`_block_hidden`); and the search stops when every bin is blocked nearer than the next
    ring of blocks. Only corners ``j >= jmin`` are reported; with ``jmin > 0`` the corners must be
    numbered row by row (lattice ``y`` then ``x``) and ``p`` be corner ``jmin - 1``, so that
    directions pointing down hold none. Returns how many were written to ``out_j``/``out_d``.
    ``part``: scratch of ``4 * nb`` doubles. ``pr`` (NULL: none): the lazy search's filters
    (:class:`Prune`): corners outside its half-plane are neither walked nor reported (the bins wholly
    outside it, with one bin of margin each side, are blocked from the start); the others are walked
    as usual (their failed walks feed the occlusion table) but reported only if :func:`_improves`.
    """
    cdef double scale = nb / 4.0, sgn, near, near2, worst, dx, dy, p, d2, nd, tx, ty
    cdef double runs[4]
    cdef double xs[6]
    cdef double ys[6]
    cdef int64_t b, quad, n_inf = 0, bx, by, rmax, m = 0, ring, t, yy, xx, step, blk, e, j, hit
    for b in range(nb):
        D[b] = INFINITY
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
    for t in range(4):
        runs[t] = -1.0
    if py == floor(py):
        runs[0] = _axis_run(B, R, W, px, py, 1, True)
        if jmin == 0:
            runs[2] = _axis_run(B, R, W, px, py, -1, True)
    if px == floor(px):
        runs[1] = _axis_run(B, R, W, px, py, 1, False)
        if jmin == 0:
            runs[3] = _axis_run(B, R, W, px, py, -1, False)
    if pr != NULL and (pr.hx != 0.0 or pr.hy != 0.0):
        _half_plane_bins(D, nb, scale, pr.hx, pr.hy)
        if pr.hy > 0:  # right: (1, 0) gives -hy
            runs[0] = -1.0
        if pr.hx < 0:  # up: (0, 1) gives hx
            runs[1] = -1.0
        if pr.hy < 0:  # left
            runs[2] = -1.0
        if pr.hx > 0:  # down
            runs[3] = -1.0
    for b in range(nb):
        if D[b] == INFINITY:
            n_inf += 1
    bx = <int64_t>_floordiv(px, bsize)
    bx = bx if bx < nbx - 1 else nbx - 1
    by = <int64_t>_floordiv(py, bsize)
    by = by if by < nby - 1 else nby - 1
    rmax = bx
    if nbx - 1 - bx > rmax:
        rmax = nbx - 1 - bx
    if by > rmax:
        rmax = by
    if nby - 1 - by > rmax:
        rmax = nby - 1 - by
    for b in range(nb):
        part[4 * b] = -1.0
        part[4 * b + 1] = INFINITY
        part[4 * b + 2] = 2.0
        part[4 * b + 3] = INFINITY
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
                        ring < 2 or not _block_hidden(D, nb, px, py, xx * bsize, yy * bsize, bsize, scale)):
                    blk = yy * nbx + xx
                    for e in range(bstart[blk], bstart[blk + 1]):
                        j = bverts[e]
                        if j < jmin:
                            continue
                        dx = vx[j] - px
                        dy = vy[j] - py
                        if dx == 0.0 and dy == 0.0:
                            if jmin == 0 and pr == NULL:  # p is this corner
                                out_j[m] = j
                                out_d[m] = 0.0
                                m += 1
                            continue
                        p = dx * dy
                        if p * self_q > 0 or p * (qx[j] * qy[j]) > 0:
                            continue
                        d2 = dx * dx + dy * dy
                        if pr != NULL and pr.hx * dy - pr.hy * dx < 0:
                            continue
                        if dx == 0.0 or dy == 0.0:  # on an axis through p: its free run decides
                            if dy == 0.0:
                                t = 0 if dx > 0 else 2
                            else:
                                t = 1 if dy > 0 else 3
                            if runs[t] >= 0 and d2 <= runs[t] * runs[t] and (pr == NULL or _improves(pr, j, d2, vx, vy)):
                                out_j[m] = j
                                out_d[m] = sqrt(d2)
                                m += 1
                            continue
                        b = <int64_t>(_pseudo_angle(dx, dy) * scale)
                        if b >= nb:
                            b = nb - 1
                        if d2 > D[b]:
                            continue
                        hit = _walk_hit(B, W, px, py, vx[j], vy[j])
                        if hit == -1:
                            if pr != NULL and not _improves(pr, j, d2, vx, vy):
                                continue  # walked all the same: a failed walk feeds the occlusion table
                            out_j[m] = j
                            out_d[m] = sqrt(d2)
                            m += 1
                        else:
                            n_inf -= _occlude_hit(D, nb, part, px, py, B, W, hit, ext, xs, ys)
                xx += step
    return m


cdef Ext _ext(tuple ext, int64_t R, int64_t W):
    cdef ext_t hl = ext[0], hr = ext[1], vl = ext[2], vr = ext[3]
    if (hl.shape[0] != R or hl.shape[1] != W or hr.shape[0] != R or hr.shape[1] != W or vl.shape[0] != R
            or vl.shape[1] != W or vr.shape[0] != R or vr.shape[1] != W):
        raise ValueError("run extents of another shape than the padded array")
    cdef Ext e
    e.hl = &hl[0, 0]
    e.hr = &hr[0, 0]
    e.vl = &vl[0, 0]
    e.vr = &vr[0, 0]
    return e


def visibility_edges_culled(blk_t B, f64c_1d vx, f64c_1d vy, f64c_1d qx, f64c_1d qy, i64c_1d bstart, i64c_1d bverts,
                            int64_t nbx, int64_t nby, double bsize):
    """:func:`visibility_edges` with the nearest-first search with occlusion culling per corner (the
    same pairs, fewer walks)."""
    ext_arrays = run_extents(B)  # kept alive while the pointers are used
    cdef int64_t R = B.shape[0], W = B.shape[1], n = vx.shape[0], i, k, t
    cdef Ext ext = _ext(ext_arrays, R, W)
    cdef Edges e
    cdef bint ok = True
    cdef double* D = <double*>malloc(_NB * sizeof(double))
    cdef double* part = <double*>malloc(4 * _NB * sizeof(double))
    cdef int64_t* out_j = <int64_t*>malloc((n if n > 0 else 1) * sizeof(int64_t))
    cdef double* out_d = <double*>malloc((n if n > 0 else 1) * sizeof(double))
    cdef const uint8_t* b = &B[0, 0]
    cdef const double* pvx = &vx[0] if n else NULL
    cdef const double* pvy = &vy[0] if n else NULL
    cdef const double* pqx = &qx[0] if n else NULL
    cdef const double* pqy = &qy[0] if n else NULL
    cdef const int64_t* pbs = &bstart[0]
    cdef const int64_t* pbv = &bverts[0] if bverts.shape[0] else NULL
    try:
        if not _edges_init(&e) or D == NULL or part == NULL or out_j == NULL or out_d == NULL:
            ok = False
        else:
            with nogil:
                for i in range(n):
                    k = _visible_set(b, R, W, &ext, pvx[i], pvy[i], pqx[i] * pqy[i], pvx, pvy, pqx, pqy, pbs, pbv,
                                     nbx, nby, bsize, i + 1, D, _NB, part, out_j, out_d, NULL)
                    if not _edges_reserve(&e, e.m + k):
                        ok = False
                        break
                    for t in range(k):
                        e.ei[e.m] = <int32_t>i
                        e.ej[e.m] = <int32_t>out_j[t]
                        e.m += 1
        out = _edges_out(&e)
    finally:
        free(D)
        free(part)
        free(out_j)
        free(out_d)
    if not ok:
        raise MemoryError("visibility_edges_culled: no memory")
    return out


def visible_from_culled(blk_t B, tuple ext, double px, double py, f64c_1d vx, f64c_1d vy, f64c_1d qx, f64c_1d qy,
                        i64c_1d bstart, i64c_1d bverts, int64_t nbx, int64_t nby, double bsize):
    """:func:`visible_from` through the nearest-first search with occlusion culling (the same
    distances, fewer walks); ``ext`` from :func:`run_extents`."""
    cdef int64_t R = B.shape[0], W = B.shape[1], n = vx.shape[0], k, t
    cdef Ext e = _ext(ext, R, W)
    res = np.full(n, np.inf)
    if n == 0:
        return res
    cdef double[::1] o = res
    cdef double* D = <double*>malloc(_NB * sizeof(double))
    cdef double* part = <double*>malloc(4 * _NB * sizeof(double))
    cdef int64_t* out_j = <int64_t*>malloc(n * sizeof(int64_t))
    cdef double* out_d = <double*>malloc(n * sizeof(double))
    try:
        if D == NULL or part == NULL or out_j == NULL or out_d == NULL:
            raise MemoryError("visible_from_culled: no memory")
        with nogil:
            k = _visible_set(&B[0, 0], R, W, &e, px, py, 0.0, &vx[0], &vy[0], &qx[0], &qy[0], &bstart[0],
                             &bverts[0], nbx, nby, bsize, 0, D, _NB, part, out_j, out_d, NULL)
            for t in range(k):
                o[out_j[t]] = out_d[t]
    finally:
        free(D)
        free(part)
        free(out_j)
        free(out_d)
    return res
