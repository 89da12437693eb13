"""Compiled kernels of the grid follower: field sampling and exact segment-vs-cell walks.

Only kernels live here (scalar point samplers shared by :func:`gridfield.follow.follow` and
:func:`gridfield.follow.follow_many`, and their many-point loops); the follower's logic is in
:mod:`gridfield.follow`. Arrays follow the grid conventions: ``occ[row, col]`` with row 0 at the
lowest y, cell ``(j, i)`` covering ``[x0 + i*res, x0 + (i+1)*res)``.
"""

import math

import numba

from .grid import _scalar_index

__all__ = [
    "_bilinear2",
    "_blocked_many",
    "_cell_blocked",
    "_cell_index",
    "_cell_values",
    "_force_at",
    "_force_many",
    "_nearest2",
    "_segment_blocked",
    "entry_point",
]


@numba.njit(cache=True, nogil=True)
def _bilinear2(a, b, occ, x0, y0, res, x, y):  # pragma: no cover - numba
    """Bilinear interpolation of two arrays among the free corner cells (renormalized), clamped."""
    rows, cols = occ.shape
    u = (x - x0) / res - 0.5
    v = (y - y0) / res - 0.5
    if not (u >= 0.0):  # also NaN
        u = 0.0
    if u > cols - 1.0:
        u = cols - 1.0
    if not (v >= 0.0):
        v = 0.0
    if v > rows - 1.0:
        v = rows - 1.0
    i0 = int(u)
    j0 = int(v)
    i1 = min(i0 + 1, cols - 1)
    j1 = min(j0 + 1, rows - 1)
    fu = u - i0
    fv = v - j0
    sa = 0.0
    sb = 0.0
    sw = 0.0
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
        return sa / sw, sb / sw
    # every corner with weight is occupied: the nearest free corner, if any, else 0
    best = 4.0
    ra = 0.0
    rb = 0.0
    for jj in (j0, j1):
        for ii in (i0, i1):
            if not occ[jj, ii]:
                dd = (ii - u) * (ii - u) + (jj - v) * (jj - v)
                if dd < best:
                    best = dd
                    ra = a[jj, ii]
                    rb = b[jj, ii]
    return ra, rb


@numba.njit(cache=True, nogil=True)
def _nearest2(a, b, occ, x0, y0, res, x, y):  # pragma: no cover - numba
    """Values of two arrays in the cell containing the point (clamped to the grid); 0 on obstacles."""
    rows, cols = occ.shape
    if not (math.isfinite(x) and math.isfinite(y)):
        return 0.0, 0.0
    i = min(max(_cell_index(x, x0, res), 0), cols - 1)
    j = min(max(_cell_index(y, y0, res), 0), rows - 1)
    if occ[j, i]:
        return 0.0, 0.0
    return a[j, i], b[j, i]


@numba.njit(cache=True, nogil=True)
def _force_at(gx, gy, occ, x0, y0, res, nearest, x, y):  # pragma: no cover - numba
    if nearest:
        vx, vy = _nearest2(gx, gy, occ, x0, y0, res, x, y)
    else:
        vx, vy = _bilinear2(gx, gy, occ, x0, y0, res, x, y)
    return -vx, -vy


@numba.njit(cache=True, nogil=True)
def _force_many(gx, gy, occ, x0, y0, res, nearest, xs, ys, fx, fy):  # pragma: no cover - numba
    for k in range(xs.shape[0]):
        fx[k], fy[k] = _force_at(gx, gy, occ, x0, y0, res, nearest, xs[k], ys[k])


#: World coordinate -> cell index, the rule of :meth:`gridfield.grid.Grid.world_to_cell` (the very
#: function behind :meth:`gridfield.grid.Grid.cell_of`, compiled).
_cell_index = numba.njit(cache=True, nogil=True)(_scalar_index)


@numba.njit(cache=True, nogil=True)
def _cell_values(a, x0, y0, res, xs, ys, out, inside):  # pragma: no cover - numba
    """``a`` at the cells containing the points, clamped to the grid; whether each point is inside."""
    rows, cols = a.shape
    for k in range(xs.shape[0]):
        i = _cell_index(xs[k], x0, res)
        j = _cell_index(ys[k], y0, res)
        inside[k] = 0 <= i < cols and 0 <= j < rows
        out[k] = a[min(max(j, 0), rows - 1), min(max(i, 0), cols - 1)]


@numba.njit(cache=True, nogil=True)
def _cell_blocked(occ, wall, i, j):  # pragma: no cover - numba
    rows, cols = occ.shape
    if i < 0 or j < 0 or i >= cols or j >= rows:
        return wall
    return occ[j, i]


@numba.njit(cache=True, nogil=True)
def _segment_blocked(occ, x0, y0, res, wall, xa, ya, xb, yb):  # pragma: no cover - numba
    """Whether the segment crosses (or touches at a corner) an occupied cell, or a wall outside the grid.

    An exact cell walk (Amanatides & Woo): every cell whose interior the segment crosses is checked;
    where the segment passes exactly through a cell corner, both side cells are checked too.
    """
    if not (math.isfinite(xa) and math.isfinite(ya) and math.isfinite(xb) and math.isfinite(yb)):
        return True
    rows, cols = occ.shape
    u0 = (xa - x0) / res
    v0 = (ya - y0) / res
    u1 = (xb - x0) / res
    v1 = (yb - y0) / res
    # cells by the grid's own rule (GridMap.is_free agrees); the walk's crossings use u, v
    i = _cell_index(xa, x0, res)
    j = _cell_index(ya, y0, res)
    ie = _cell_index(xb, x0, res)
    je = _cell_index(yb, y0, res)
    out_a = i < 0 or j < 0 or i >= cols or j >= rows
    out_b = ie < 0 or je < 0 or ie >= cols or je >= rows
    if wall and (out_a or out_b):
        return True
    if out_a or out_b:  # open border: only the part inside the grid can be blocked (Liang-Barsky clip)
        du = u1 - u0
        dv = v1 - v0
        t0 = 0.0
        t1 = 1.0
        for k in range(4):
            if k == 0:
                p, q = -du, u0
            elif k == 1:
                p, q = du, cols - u0
            elif k == 2:
                p, q = -dv, v0
            else:
                p, q = dv, rows - v0
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
            u0, v0 = ua, va
            i = min(max(math.floor(ua), 0), cols - 1)
            j = min(max(math.floor(va), 0), rows - 1)
        if out_b:
            u1, v1 = ub, vb
            ie = min(max(math.floor(ub), 0), cols - 1)
            je = min(max(math.floor(vb), 0), rows - 1)
    if _cell_blocked(occ, wall, i, j):
        return True
    du = u1 - u0
    dv = v1 - v0
    si = 1 if du > 0 else -1
    sj = 1 if dv > 0 else -1
    inf = math.inf
    if du > 0:
        tmx = (i + 1 - u0) / du
        tdx = 1.0 / du
    elif du < 0:
        tmx = (u0 - i) / -du
        tdx = -1.0 / du
    else:
        tmx = inf
        tdx = inf
    if dv > 0:
        tmy = (j + 1 - v0) / dv
        tdy = 1.0 / dv
    elif dv < 0:
        tmy = (v0 - j) / -dv
        tdy = -1.0 / dv
    else:
        tmy = inf
        tdy = inf
    n = abs(ie - i) + abs(je - j)
    for _ in range(n + 2):
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
            if _cell_blocked(occ, wall, i + si, j) or _cell_blocked(occ, wall, i, j + sj):
                return True
            i += si
            j += sj
            tmx += tdx
            tmy += tdy
        if _cell_blocked(occ, wall, i, j):
            return True
    return False


@numba.njit(cache=True, nogil=True)
def _blocked_many(occ, x0, y0, res, wall, xa, ya, xb, yb, out):  # pragma: no cover - numba
    for k in range(xa.shape[0]):
        out[k] = _segment_blocked(occ, x0, y0, res, wall, xa[k], ya[k], xb[k], yb[k])


def entry_point(dispatcher, *args):
    """The compiled entry point of a numba function for these argument types.

    Calling it skips the dispatcher's per-call type resolution (about half the cost of a call with
    three array arguments); falls back to the dispatcher if numba's internals differ.
    """
    dispatcher(*args)
    try:
        sig = tuple(numba.typeof(a) for a in args)
        return dispatcher.overloads[sig].entry_point
    except (AttributeError, KeyError, TypeError, ValueError):  # pragma: no cover - numba internals
        return dispatcher
