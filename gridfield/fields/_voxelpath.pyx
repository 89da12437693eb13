# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled kernels of the voxel paths: the exact segment test, string pulling and the follower of
:mod:`gridfield.following.follow3d` (called through :mod:`gridfield.fields.navigation3d`; Cython,
compiled at install; imported lazily).

Points are in *cell units* in array order (``q_a = (coordinate_a - origin_a) / resolution``, axis 0 =
z), voxel ``i`` spans ``[i, i + 1)``. A segment is clear when it touches the **closed** cube of no
blocked voxel and of no voxel outside the grid: the voxels an Amanatides-Woo walk visits, and the
blocked ones among their 26 neighbours tested for contact (every touched cube shares a point with a
visited one). The discrete moves of the follower's fallback use the bounding-box rule of
:mod:`gridfield.fields._navigation3` (inline in ``_voxel.pxd``), whose moves are exactly the clear
segments between neighbouring centres. Nothing here validates input.
"""

from libc.math cimport INFINITY, floor, sqrt
from libc.stdint cimport int64_t, uint8_t
from libc.stdlib cimport free as c_free, malloc, realloc

import numpy as np

from ._voxel cimport _move_ok, mask3_t, val3_t


cdef inline void* _alloc(size_t n) noexcept nogil:
    return malloc(n if n > 0 else 1)


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
    cdef int status = 2, j, dz, dy, dx
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
                    dz = j // 9 - 1
                    dy = (j // 3) % 3 - 1
                    dx = j % 3 - 1
                    nk = k + dz
                    nr = r + dy
                    nc = c + dx
                    if nk < 0 or nk >= n0 or nr < 0 or nr >= n1 or nc < 0 or nc >= n2:
                        continue
                    w = U[nk, nr, nc]
                    if w < best and _move_ok(free, k, r, c, dz, dy, dx, False):
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
