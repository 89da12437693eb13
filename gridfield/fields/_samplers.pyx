# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels of the grid follower: field sampling and exact segment-vs-cell walks.

Only kernels live here (scalar point samplers shared by :func:`gridfield.following.follower.follow` and
:func:`gridfield.following.follower.follow_many`, and their many-point loops); the follower's logic is in
:mod:`gridfield.follow`. Arrays follow the grid conventions: ``occ[row, col]`` with row 0 at the
lowest y, cell ``(j, i)`` covering ``[x0 + i*res, x0 + (i+1)*res)``.

Cython, compiled at install (see "Building the kernels" in ``benchmarks/README.md``). Arrays are
C-contiguous; ``occ`` is a ``bool`` (or ``uint8``) array, the fields ``float64``. Indices are
clamped or checked before every access, so bounds checks are off.
"""

from libc.math cimport floor, isfinite, INFINITY

__all__ = [
    "_blocked_many",
    "_cell_blocked",
    "_cell_index",
    "_cell_values",
    "_force_many",
    "_segment_blocked",
    "ForceSampler",
    "SegmentTest",
    "ValueSampler",
]

ctypedef const unsigned char[:, ::1] occ_t
ctypedef const double[:, ::1] arr_t


cdef inline Py_ssize_t _imin(Py_ssize_t a, Py_ssize_t b) noexcept nogil:
    return a if a < b else b


cdef inline Py_ssize_t _imax(Py_ssize_t a, Py_ssize_t b) noexcept nogil:
    return a if a > b else b


cdef inline long long _cidx(double v, double origin, double res) noexcept nogil:
    # the rule of gridfield.core.coords.scalar_index (Grid.world_to_cell), in the same IEEE double arithmetic
    cdef long long i = <long long>floor((v - origin) / res)
    if v >= origin + <double>(i + 1) * res:
        i += 1
    if v < origin + <double>i * res:
        i -= 1
    return i


cdef inline void _c_bilinear2(arr_t a, arr_t b, occ_t occ, double x0, double y0, double res, double x, double y,
                              double* ra, double* rb) noexcept nogil:
    cdef Py_ssize_t rows = occ.shape[0], cols = occ.shape[1]
    cdef double u = (x - x0) / res - 0.5
    cdef double v = (y - y0) / res - 0.5
    if not (u >= 0.0):  # also NaN
        u = 0.0
    if u > cols - 1.0:
        u = cols - 1.0
    if not (v >= 0.0):
        v = 0.0
    if v > rows - 1.0:
        v = rows - 1.0
    cdef Py_ssize_t i0 = <Py_ssize_t>u
    cdef Py_ssize_t j0 = <Py_ssize_t>v
    cdef Py_ssize_t i1 = _imin(i0 + 1, cols - 1)
    cdef Py_ssize_t j1 = _imin(j0 + 1, rows - 1)
    cdef double fu = u - i0
    cdef double fv = v - j0
    cdef double sa = 0.0, sb = 0.0, sw = 0.0, w
    w = (1.0 - fu) * (1.0 - fv)
    if w > 0.0 and not occ[j0, i0]:
        sa += w * a[j0, i0]
        sb += w * b[j0, i0]
        sw += w
    w = fu * (1.0 - fv)
    if w > 0.0 and not occ[j0, i1]:
        sa += w * a[j0, i1]
        sb += w * b[j0, i1]
        sw += w
    w = (1.0 - fu) * fv
    if w > 0.0 and not occ[j1, i0]:
        sa += w * a[j1, i0]
        sb += w * b[j1, i0]
        sw += w
    w = fu * fv
    if w > 0.0 and not occ[j1, i1]:
        sa += w * a[j1, i1]
        sb += w * b[j1, i1]
        sw += w
    if sw > 0.0:
        ra[0] = sa / sw
        rb[0] = sb / sw
        return
    # every corner with weight is occupied: the nearest free corner, if any, else 0
    cdef double best = 4.0, dd
    cdef Py_ssize_t jj, ii, p, q
    ra[0] = 0.0
    rb[0] = 0.0
    for p in range(2):
        jj = j0 if p == 0 else j1
        for q in range(2):
            ii = i0 if q == 0 else i1
            if not occ[jj, ii]:
                dd = (ii - u) * (ii - u) + (jj - v) * (jj - v)
                if dd < best:
                    best = dd
                    ra[0] = a[jj, ii]
                    rb[0] = b[jj, ii]


cdef inline void _c_nearest2(arr_t a, arr_t b, occ_t occ, double x0, double y0, double res, double x, double y,
                             double* ra, double* rb) noexcept nogil:
    cdef Py_ssize_t rows = occ.shape[0], cols = occ.shape[1]
    ra[0] = 0.0
    rb[0] = 0.0
    if not (isfinite(x) and isfinite(y)):
        return
    cdef Py_ssize_t i = <Py_ssize_t>_imin(_imax(<Py_ssize_t>_cidx(x, x0, res), 0), cols - 1)
    cdef Py_ssize_t j = <Py_ssize_t>_imin(_imax(<Py_ssize_t>_cidx(y, y0, res), 0), rows - 1)
    if occ[j, i]:
        return
    ra[0] = a[j, i]
    rb[0] = b[j, i]


cdef inline void _c_force(arr_t gx, arr_t gy, occ_t occ, double x0, double y0, double res, bint nearest,
                          double x, double y, double* fx, double* fy) noexcept nogil:
    cdef double vx, vy
    if nearest:
        _c_nearest2(gx, gy, occ, x0, y0, res, x, y, &vx, &vy)
    else:
        _c_bilinear2(gx, gy, occ, x0, y0, res, x, y, &vx, &vy)
    fx[0] = -vx
    fy[0] = -vy


def _force_many(arr_t gx, arr_t gy, occ_t occ, double x0, double y0, double res, bint nearest,
                const double[::1] xs, const double[::1] ys, double[::1] fx, double[::1] fy):
    """``-(grad_x, grad_y)`` at many points (``nearest`` cell, else bilinear), into ``fx``, ``fy``."""
    cdef Py_ssize_t k
    with nogil:
        for k in range(xs.shape[0]):
            _c_force(gx, gy, occ, x0, y0, res, nearest, xs[k], ys[k], &fx[k], &fy[k])


def _cell_index(double v, double origin, double res):
    """World coordinate -> cell index, the rule of :meth:`gridfield.core.grid.Grid.world_to_cell` (the very
    rule of :func:`gridfield.core.coords.scalar_index`, compiled)."""
    return _cidx(v, origin, res)


def _cell_values(arr_t a, double x0, double y0, double res, const double[::1] xs, const double[::1] ys,
                 double[::1] out, unsigned char[::1] inside):
    """``a`` at the cells containing the points, clamped to the grid; whether each point is inside."""
    cdef Py_ssize_t rows = a.shape[0], cols = a.shape[1], k
    cdef long long i, j
    with nogil:
        for k in range(xs.shape[0]):
            i = _cidx(xs[k], x0, res)
            j = _cidx(ys[k], y0, res)
            inside[k] = 0 <= i < cols and 0 <= j < rows
            out[k] = a[_imin(_imax(<Py_ssize_t>j, 0), rows - 1), _imin(_imax(<Py_ssize_t>i, 0), cols - 1)]


cdef inline bint _c_cell_blocked(occ_t occ, bint wall, long long i, long long j) noexcept nogil:
    if i < 0 or j < 0 or i >= occ.shape[1] or j >= occ.shape[0]:
        return wall
    return occ[j, i] != 0


def _cell_blocked(occ_t occ, bint wall, long long i, long long j):
    """Whether cell ``(j, i)`` is occupied; outside the grid: ``wall``."""
    return _c_cell_blocked(occ, wall, i, j)


cdef inline long long _lclamp(double v, long long hi) noexcept nogil:
    cdef long long f = <long long>floor(v)
    if f < 0:
        f = 0
    if f > hi:
        f = hi
    return f


cdef bint _c_segment_blocked(occ_t occ, double x0, double y0, double res, bint wall, double xa, double ya,
                             double xb, double yb) noexcept nogil:
    if not (isfinite(xa) and isfinite(ya) and isfinite(xb) and isfinite(yb)):
        return True
    cdef long long rows = occ.shape[0], cols = occ.shape[1]
    cdef double u0 = (xa - x0) / res
    cdef double v0 = (ya - y0) / res
    cdef double u1 = (xb - x0) / res
    cdef double v1 = (yb - y0) / res
    # cells by the grid's own rule (GridMap.is_free agrees); the walk's crossings use u, v
    cdef long long i = _cidx(xa, x0, res)
    cdef long long j = _cidx(ya, y0, res)
    cdef long long ie = _cidx(xb, x0, res)
    cdef long long je = _cidx(yb, y0, res)
    cdef bint out_a = i < 0 or j < 0 or i >= cols or j >= rows
    cdef bint out_b = ie < 0 or je < 0 or ie >= cols or je >= rows
    cdef double du, dv, t0, t1, p, q, ua, va, ub, vb
    cdef int k
    if wall and (out_a or out_b):
        return True
    if out_a or out_b:  # open border: only the part inside the grid can be blocked (Liang-Barsky clip)
        du = u1 - u0
        dv = v1 - v0
        t0 = 0.0
        t1 = 1.0
        for k in range(4):
            if k == 0:
                p = -du
                q = u0
            elif k == 1:
                p = du
                q = cols - u0
            elif k == 2:
                p = -dv
                q = v0
            else:
                p = dv
                q = rows - v0
            if p == 0.0:
                if q < 0.0:
                    return False
            elif p < 0.0:
                t0 = max(t0, q / p)
            else:
                t1 = min(t1, q / p)
        if t0 > t1:
            return False
        ua = u0 + t0 * du
        va = v0 + t0 * dv
        ub = u0 + t1 * du
        vb = v0 + t1 * dv
        if out_a:
            u0 = ua
            v0 = va
            i = _lclamp(ua, cols - 1)
            j = _lclamp(va, rows - 1)
        if out_b:
            u1 = ub
            v1 = vb
            ie = _lclamp(ub, cols - 1)
            je = _lclamp(vb, rows - 1)
    if _c_cell_blocked(occ, wall, i, j):
        return True
    du = u1 - u0
    dv = v1 - v0
    cdef long long si = 1 if du > 0 else -1
    cdef long long sj = 1 if dv > 0 else -1
    cdef double tmx, tdx, tmy, tdy
    if du > 0:
        tmx = (i + 1 - u0) / du
        tdx = 1.0 / du
    elif du < 0:
        tmx = (u0 - i) / -du
        tdx = -1.0 / du
    else:
        tmx = INFINITY
        tdx = INFINITY
    if dv > 0:
        tmy = (j + 1 - v0) / dv
        tdy = 1.0 / dv
    elif dv < 0:
        tmy = (v0 - j) / -dv
        tdy = -1.0 / dv
    else:
        tmy = INFINITY
        tdy = INFINITY
    cdef long long n = (ie - i if ie >= i else i - ie) + (je - j if je >= j else j - je), s
    for s in range(n + 2):
        if i == ie and j == je:
            return False
        if tmx > 1.0 and tmy > 1.0:
            return False
        if tmx < tmy:
            i += si
            tmx += tdx
        elif tmy < tmx:
            j += sj
            tmy += tdy
        else:  # through a corner: the two side cells touch the segment
            if _c_cell_blocked(occ, wall, i + si, j) or _c_cell_blocked(occ, wall, i, j + sj):
                return True
            i += si
            j += sj
            tmx += tdx
            tmy += tdy
        if _c_cell_blocked(occ, wall, i, j):
            return True
    return False


def _segment_blocked(occ_t occ, double x0, double y0, double res, bint wall, double xa, double ya, double xb,
                     double yb):
    """Whether the segment crosses (or touches at a corner) an occupied cell, or a wall outside the grid.

    An exact cell walk (Amanatides & Woo): every cell whose interior the segment crosses is checked;
    where the segment passes exactly through a cell corner, both side cells are checked too.
    """
    return _c_segment_blocked(occ, x0, y0, res, wall, xa, ya, xb, yb)


def _blocked_many(occ_t occ, double x0, double y0, double res, bint wall, const double[::1] xa,
                  const double[::1] ya, const double[::1] xb, const double[::1] yb, unsigned char[::1] out):
    """:func:`_segment_blocked` for many segments, into ``out`` (``bool``)."""
    cdef Py_ssize_t k
    with nogil:
        for k in range(xa.shape[0]):
            out[k] = _c_segment_blocked(occ, x0, y0, res, wall, xa[k], ya[k], xb[k], yb[k])


# ----------------------------------------------------------------------------------------------
# typed scalar samplers: the arrays' buffers are bound once, each call passes only the point(s)
# ----------------------------------------------------------------------------------------------
cdef class _OnGrid:
    """The grid a bound sampler reads: its occupancy (kept alive by the sampler) and its frame."""
    cdef occ_t occ
    cdef double x0, y0, res

    def __init__(self, occ_t occ, double x0, double y0, double res):
        self.occ = occ
        self.x0 = x0
        self.y0 = y0
        self.res = res


cdef class ForceSampler(_OnGrid):
    """``sampler(p) -> (fx, fy)``: the force ``-(grad_x, grad_y)`` at the world point ``p``, sampled in
    the nearest cell or bilinearly among the free corner cells (:func:`_force_many`'s arithmetic, one point).

    The arrays are bound at creation (kept alive by the sampler); a call converts only ``p[0]`` and
    ``p[1]``.
    """
    cdef arr_t gx, gy
    cdef bint nearest

    def __init__(self, arr_t gx, arr_t gy, occ_t occ, double x0, double y0, double res, bint nearest):
        if gx.shape[0] != occ.shape[0] or gx.shape[1] != occ.shape[1] or gy.shape[0] != occ.shape[0] \
                or gy.shape[1] != occ.shape[1]:
            raise ValueError("the gradient arrays and the occupancy must have one shape")
        _OnGrid.__init__(self, occ, x0, y0, res)
        self.gx = gx
        self.gy = gy
        self.nearest = nearest

    def __call__(self, p):
        cdef double fx, fy
        _c_force(self.gx, self.gy, self.occ, self.x0, self.y0, self.res, self.nearest, p[0], p[1], &fx, &fy)
        return fx, fy


cdef class ValueSampler(_OnGrid):
    """``sampler(p) -> float``: one array's value at the world point ``p``, in the nearest cell
    (``nearest``) or bilinearly among the free corner cells (the arithmetic of :class:`ForceSampler`)."""
    cdef arr_t a
    cdef bint nearest

    def __init__(self, arr_t a, occ_t occ, double x0, double y0, double res, bint nearest):
        if a.shape[0] != occ.shape[0] or a.shape[1] != occ.shape[1]:
            raise ValueError("the array and the occupancy must have one shape")
        _OnGrid.__init__(self, occ, x0, y0, res)
        self.a = a
        self.nearest = nearest

    def __call__(self, p):
        cdef double va, vb
        if self.nearest:
            _c_nearest2(self.a, self.a, self.occ, self.x0, self.y0, self.res, p[0], p[1], &va, &vb)
        else:
            _c_bilinear2(self.a, self.a, self.occ, self.x0, self.y0, self.res, p[0], p[1], &va, &vb)
        return va


cdef class SegmentTest(_OnGrid):
    """``test(p, q) -> bool``: whether the segment ``p -> q`` crosses an occupied cell (or leaves a
    walled grid), walked exactly (:func:`_segment_blocked`)."""
    cdef bint wall

    def __init__(self, occ_t occ, double x0, double y0, double res, bint wall):
        _OnGrid.__init__(self, occ, x0, y0, res)
        self.wall = wall

    def __call__(self, p, q):
        return _c_segment_blocked(self.occ, self.x0, self.y0, self.res, self.wall, p[0], p[1], q[0], q[1])
