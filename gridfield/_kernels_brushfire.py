"""Numba kernels behind :func:`gridfield.brushfire.brushfire` (private; imported on first use).

Chessboard and taxicab (:func:`chamfer_steps`, :func:`chamfer_nearest`)
    The classic two-pass raster transform with a 3x3 mask (Rosenfeld & Pfaltz 1966), exact for both
    metrics. Each row is done in two stages: the neighbours in the previous row (a branch-free loop
    the compiler vectorizes), then the left (right) neighbour (a scan). The nearest obstacle cell is
    carried along: the neighbour that gives a cell its final value has a nearest obstacle at exactly
    that distance, so the carried cell is an exact nearest obstacle. Sequential over rows.

Euclidean (:func:`column_pass`, :func:`edt_row_pass`)
    Separable: for every cell the nearest obstacle row in its column, then per row the lower envelope
    of the parabolas ``(x - i)**2 + g_i**2`` (Meijster, Roerdink & Hesselink 2000), whose winning
    column gives the exact nearest obstacle cell. Parallel over column blocks / row blocks.

Components (:func:`label_components`)
    8-connected, two-pass union-find; components are numbered in raster order of their first cell
    (row 0 first), the numbering of ``scipy.ndimage.label``. Sequential (run beside a chamfer pass).

Then :func:`label_pass`, :func:`gvd_pass` and :func:`saturate_pass` (parallel over row blocks).

Conventions: arrays are C-contiguous ``[row, col]``; occupancy is passed as ``uint8``; the wall
border is the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols`` (never its corners).
Sequential kernels are ``nogil`` so that two of them can run side by side in Python threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: Sentinel row for "no obstacle above/below" (far beyond any real grid).
BIG = 1 << 30

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}


@njit(**_OPTS)
def _chunks(n, nthreads):  # pragma: no cover - compiled
    """Number of work chunks for ``n`` independent lines (a few per thread, for balance)."""
    return max(1, min(n, 4 * nthreads))


# ----------------------------------------------------------------------------------------------
# chessboard / taxicab: two-pass raster transform
# ----------------------------------------------------------------------------------------------
@njit(**_OPTS)
def chamfer_steps(occ, wall, conn8, steps, distance, resolution, write_distance):  # pragma: no cover
    """Chessboard (``conn8``) or taxicab steps; also ``distance = steps * resolution`` if asked."""
    rows, cols = occ.shape
    inf = np.int64(rows + cols + 4)
    edge = np.int64(0) if wall else inf
    p = np.empty(cols + 2, np.int32)  # the neighbouring row, padded (padding never wins)
    p[0] = inf
    p[cols + 1] = inf
    t = np.empty(cols, np.int32)
    for r in range(rows):  # forward: up-left, up, up-right, left
        orow = occ[r]
        srow = steps[r]
        if r == 0:
            for c in range(cols):
                p[c + 1] = edge
        else:
            prev = steps[r - 1]
            for c in range(cols):
                p[c + 1] = prev[c]
        if conn8:
            for c in range(cols):
                a = min(min(np.int64(p[c]), np.int64(p[c + 1])), np.int64(p[c + 2])) + 1
                t[c] = a - a * np.int64(orow[c])
        else:
            for c in range(cols):
                a = np.int64(p[c + 1]) + 1
                t[c] = a - a * np.int64(orow[c])
        left = edge
        for c in range(cols):
            a = min(np.int64(t[c]), left + 1)
            srow[c] = a
            left = a
    for r in range(rows - 1, -1, -1):  # backward: down-right, down, down-left, right
        srow = steps[r]
        if r == rows - 1:
            for c in range(cols):
                p[c + 1] = edge
        else:
            nxt = steps[r + 1]
            for c in range(cols):
                p[c + 1] = nxt[c]
        if conn8:
            for c in range(cols):
                a = min(min(np.int64(p[c]), np.int64(p[c + 1])), np.int64(p[c + 2])) + 1
                t[c] = min(a, np.int64(srow[c]))
        else:
            for c in range(cols):
                t[c] = min(np.int64(p[c + 1]) + 1, np.int64(srow[c]))
        right = edge
        c = np.uint64(cols)  # unsigned index: no negative-index wraparound checks in the scan
        while c > 0:
            c -= np.uint64(1)
            a = min(np.int64(t[c]), right + 1)
            srow[c] = a
            right = a
        if write_distance:
            drow = distance[r]
            for c in range(cols):
                drow[c] = srow[c] * resolution


@njit(**_OPTS)
def chamfer_nearest(occ, wall, conn8, steps, nrow, ncol, distance, resolution, write_distance):  # pragma: no cover
    """:func:`chamfer_steps` carrying the nearest obstacle cell ``(nrow, ncol)`` along (branch-free
    selects: ``x += (y - x) * m`` with ``m`` in {0, 1})."""
    rows, cols = occ.shape
    inf = np.int64(rows + cols + 4)
    edge = np.int64(0) if wall else inf
    p = np.empty(cols + 2, np.int32)
    pr = np.zeros(cols + 2, np.int32)
    pc = np.zeros(cols + 2, np.int32)
    p[0] = inf
    p[cols + 1] = inf
    t = np.empty(cols, np.int32)
    tr = np.empty(cols, np.int32)
    tc = np.empty(cols, np.int32)
    for r in range(rows):  # forward
        orow = occ[r]
        srow = steps[r]
        rrow = nrow[r]
        crow = ncol[r]
        if r == 0:
            for c in range(cols):
                p[c + 1] = edge
                pr[c + 1] = -1
                pc[c + 1] = c
        else:
            prev = steps[r - 1]
            prevr = nrow[r - 1]
            prevc = ncol[r - 1]
            for c in range(cols):
                p[c + 1] = prev[c]
                pr[c + 1] = prevr[c]
                pc[c + 1] = prevc[c]
        for c in range(cols):
            a = np.int64(p[c + 1])
            ar = np.int64(pr[c + 1])
            ac = np.int64(pc[c + 1])
            if conn8:
                b = np.int64(p[c])
                m = np.int64(b < a)
                a += (b - a) * m
                ar += (np.int64(pr[c]) - ar) * m
                ac += (np.int64(pc[c]) - ac) * m
                b = np.int64(p[c + 2])
                m = np.int64(b < a)
                a += (b - a) * m
                ar += (np.int64(pr[c + 2]) - ar) * m
                ac += (np.int64(pc[c + 2]) - ac) * m
            a += 1
            o = np.int64(orow[c])
            t[c] = a - a * o
            tr[c] = ar + (r - ar) * o
            tc[c] = ac + (c - ac) * o
        left = edge
        lr = np.int64(r)
        lc = np.int64(-1)
        for c in range(cols):
            a = np.int64(t[c])
            b = left + 1
            m = np.int64(b < a)
            a += (b - a) * m
            lr = tr[c] + (lr - tr[c]) * m
            lc = tc[c] + (lc - tc[c]) * m
            srow[c] = a
            rrow[c] = lr
            crow[c] = lc
            left = a
    for r in range(rows - 1, -1, -1):  # backward
        srow = steps[r]
        rrow = nrow[r]
        crow = ncol[r]
        if r == rows - 1:
            for c in range(cols):
                p[c + 1] = edge
                pr[c + 1] = rows
                pc[c + 1] = c
        else:
            nxt = steps[r + 1]
            nxtr = nrow[r + 1]
            nxtc = ncol[r + 1]
            for c in range(cols):
                p[c + 1] = nxt[c]
                pr[c + 1] = nxtr[c]
                pc[c + 1] = nxtc[c]
        for c in range(cols):
            a = np.int64(p[c + 1])
            ar = np.int64(pr[c + 1])
            ac = np.int64(pc[c + 1])
            if conn8:
                b = np.int64(p[c])
                m = np.int64(b < a)
                a += (b - a) * m
                ar += (np.int64(pr[c]) - ar) * m
                ac += (np.int64(pc[c]) - ac) * m
                b = np.int64(p[c + 2])
                m = np.int64(b < a)
                a += (b - a) * m
                ar += (np.int64(pr[c + 2]) - ar) * m
                ac += (np.int64(pc[c + 2]) - ac) * m
            a += 1
            cur = np.int64(srow[c])
            m = np.int64(a < cur)
            t[c] = cur + (a - cur) * m
            tr[c] = rrow[c] + (ar - rrow[c]) * m
            tc[c] = crow[c] + (ac - crow[c]) * m
        right = edge
        rr = np.int64(r)
        rc = np.int64(cols)
        c = np.uint64(cols)
        while c > 0:
            c -= np.uint64(1)
            a = np.int64(t[c])
            b = right + 1
            m = np.int64(b < a)
            a += (b - a) * m
            rr = tr[c] + (rr - tr[c]) * m
            rc = tc[c] + (rc - tc[c]) * m
            srow[c] = a
            rrow[c] = rr
            crow[c] = rc
            right = a
        if write_distance:
            drow = distance[r]
            for c in range(cols):
                drow[c] = srow[c] * resolution


# ----------------------------------------------------------------------------------------------
# Euclidean: separable lower-envelope transform
# ----------------------------------------------------------------------------------------------
@njit(cache=True, nogil=True, inline="always")
def _down_segment(orow, prev, vrow, r):  # pragma: no cover - compiled
    # nearest obstacle at or above: r on an obstacle, else the one of the row above (branch-free)
    for c in range(orow.shape[0]):
        p = np.int64(prev[c])
        vrow[c] = p + (r - p) * np.int64(orow[c])


@njit(cache=True, nogil=True, inline="always")
def _up_segment(below, vrow, r):  # pragma: no cover - compiled
    # The row below holds its final nearest row b. If b lies below r, it is also r's nearest obstacle
    # below (r is free, or b == r); keep the one above (a) unless b is strictly nearer.
    for c in range(vrow.shape[0]):
        a = np.int64(vrow[c])
        b = np.int64(below[c])
        s = np.int64((b - r) < (r - a))
        vrow[c] = a + (b - a) * s


@njit(**_OPTS)
def column_block(occ, wall, vr, c0, c1):  # pragma: no cover - compiled
    """:func:`column_pass` on the columns ``c0:c1``."""
    rows = occ.shape[0]
    top = -1 if wall else -BIG
    bottom = rows if wall else BIG
    for c in range(c0, c1):
        vr[0, c] = 0 if occ[0, c] else top
    for r in range(1, rows):
        _down_segment(occ[r, c0:c1], vr[r - 1, c0:c1], vr[r, c0:c1], r)
    last = rows - 1
    for c in range(c0, c1):
        if bottom - last < last - vr[last, c]:
            vr[last, c] = bottom
    for r in range(rows - 2, -1, -1):
        _up_segment(vr[r + 1, c0:c1], vr[r, c0:c1], r)


@njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def column_pass(occ, wall, vr, nthreads):  # pragma: no cover - compiled
    """``vr[r, c]`` = row of the obstacle nearest to ``(r, c)`` in column ``c`` (ties: the one above).

    Wall border: rows ``-1`` and ``rows`` count as obstacles. No obstacle in the column: ``+-BIG``.
    Each thread owns a contiguous block of columns.
    """
    cols = occ.shape[1]
    nblocks = max(1, min(cols // 64, nthreads))
    for k in prange(nblocks):
        column_block(occ, wall, vr, k * cols // nblocks, (k + 1) * cols // nblocks)


@njit(**_OPTS)
def edt_1d(g, n, inf, s, t, val, arg):  # pragma: no cover - compiled
    """Lower envelope of ``f_i(x) = (x - i)**2 + g[i]**2`` over the sites ``i`` in ``0..n+1`` with
    ``g[i] < inf``, for ``x`` in ``1..n``: ``val[x - 1]`` (squared distance) and ``arg[x - 1]``
    (winning site). Returns False if there is no site."""
    q = -1
    for u in range(n + 2):
        gu = g[u]
        if gu >= inf:
            continue
        fu = gu * gu
        while q >= 0:
            sq = s[q]
            tq = t[q]
            gs = g[sq]
            if (tq - sq) * (tq - sq) + gs * gs <= (tq - u) * (tq - u) + fu:
                break
            q -= 1
        if q < 0:
            q = 0
            s[0] = u
            t[0] = 1
        else:
            sq = s[q]
            gs = g[sq]
            # first x where u is strictly nearer than s[q] (floor division of an integer ratio)
            w = 1 + (u * u - sq * sq + fu - gs * gs) // (2 * (u - sq))
            if w <= n:
                q += 1
                s[q] = u
                t[q] = w
    if q < 0:
        return False
    for x in range(n, 0, -1):
        sq = s[q]
        gs = g[sq]
        val[x - 1] = (x - sq) * (x - sq) + gs * gs
        arg[x - 1] = sq
        if x == t[q]:
            q -= 1
    return True


@njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def edt_row_pass(vr, wall, resolution, distance, nearest_row, nearest_col, want_nearest,
                 comp, comp_map, use_map, want_label, label, border_label, nthreads):  # pragma: no cover
    """Row pass of the Euclidean transform: ``distance`` and optionally nearest obstacle and label.

    ``vr`` holds the column pass result; it may be the very array ``nearest_row`` (each row is copied
    to a buffer before it is overwritten). Labels: see :func:`label_pass`.
    """
    rows, cols = vr.shape
    n = cols
    inf = np.int64(rows + cols + 4)
    nchunks = _chunks(rows, nthreads)
    for k in prange(nchunks):
        r0 = k * rows // nchunks
        r1 = (k + 1) * rows // nchunks
        g = np.empty(n + 2, np.int64)
        rowv = np.empty(n + 2, np.int64)
        s = np.empty(n + 2, np.int64)
        t = np.empty(n + 2, np.int64)
        val = np.empty(n, np.int64)
        arg = np.empty(n, np.int64)
        for r in range(r0, r1):
            g[0] = 0 if wall else inf
            g[n + 1] = 0 if wall else inf
            rowv[0] = r
            rowv[n + 1] = r
            for c in range(n):
                v = np.int64(vr[r, c])
                rowv[c + 1] = v
                d = abs(r - v)
                g[c + 1] = min(d, inf)
            edt_1d(g, n, inf, s, t, val, arg)
            for c in range(n):
                distance[r, c] = np.sqrt(np.float64(val[c])) * resolution
            if want_nearest:
                for c in range(n):
                    a = arg[c]
                    nearest_row[r, c] = rowv[a]
                    nearest_col[r, c] = a - 1
            if want_label:
                for c in range(n):
                    a = arg[c]
                    nr = rowv[a]
                    nc = a - 1
                    if nr < 0 or nr >= rows or nc < 0 or nc >= cols:
                        label[r, c] = border_label
                    elif use_map:
                        label[r, c] = comp_map[comp[nr, nc]]
                    else:
                        label[r, c] = comp[nr, nc]


# ----------------------------------------------------------------------------------------------
# connected components (8-connected) of the obstacle cells
# ----------------------------------------------------------------------------------------------
@njit(cache=True, nogil=True, inline="always")
def _find(parent, x):  # pragma: no cover - compiled
    root = x
    while parent[root] != root:
        root = parent[root]
    while parent[x] != root:
        nxt = parent[x]
        parent[x] = root
        x = nxt
    return root


@njit(cache=True, nogil=True, inline="always")
def _union(parent, a, b):  # pragma: no cover - compiled
    ra = _find(parent, a)
    rb = _find(parent, b)
    if ra < rb:
        parent[rb] = ra
    elif rb < ra:
        parent[ra] = rb


@njit(**_OPTS)
def label_components(occ, comp):  # pragma: no cover - compiled
    """Provisional 8-connected labels in ``comp`` (0 on free cells); returns ``(comp_map, count)``.

    ``comp_map[comp[r, c]]`` is the final label, numbered 1.. in raster order of each component's
    first cell (row 0 first). The root of every union-find set is its smallest provisional label.
    """
    rows, cols = occ.shape
    # provisional labels are only created at cells with no labelled neighbour before them: no two
    # are 8-adjacent, so there are at most ceil(rows/2) * ceil(cols/2) of them
    cap = ((rows + 1) // 2) * ((cols + 1) // 2) + 2
    parent = np.empty(cap, np.int32)
    parent[0] = 0
    nxt = 1
    for r in range(rows):
        orow = occ[r]
        crow = comp[r]
        if r == 0:
            left = 0
            for c in range(cols):
                if not orow[c]:
                    crow[c] = 0
                    left = 0
                    continue
                if left == 0:
                    parent[nxt] = nxt
                    left = nxt
                    nxt += 1
                crow[c] = left
            continue
        up = comp[r - 1]
        for c in range(cols):
            if not orow[c]:
                crow[c] = 0
                continue
            u = up[c]
            if u:
                crow[c] = u
                continue
            ur = up[c + 1] if c + 1 < cols else 0
            ul = up[c - 1] if c > 0 else 0
            lf = crow[c - 1] if c > 0 else 0
            if ur:
                if ul:
                    _union(parent, ur, ul)
                elif lf:
                    _union(parent, ur, lf)
                crow[c] = ur
            elif ul:
                crow[c] = ul
            elif lf:
                crow[c] = lf
            else:
                parent[nxt] = nxt
                crow[c] = nxt
                nxt += 1
    comp_map = np.empty(nxt, np.int32)
    comp_map[0] = 0
    count = 0
    for i in range(1, nxt):
        p = parent[i]
        if p == i:
            count += 1
            comp_map[i] = count
        else:
            comp_map[i] = comp_map[_find(parent, p)]
    return comp_map, count


# ----------------------------------------------------------------------------------------------
# labels of the nearest obstacles, generalized Voronoi diagram, saturation
# ----------------------------------------------------------------------------------------------
@njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def label_pass(nearest_row, nearest_col, comp, comp_map, use_map, border_label, label, nthreads):  # pragma: no cover
    """``label = comp_map[comp[nr, nc]]`` (or ``comp[nr, nc]`` without ``use_map``); ``border_label``
    where the nearest obstacle is the wall (outside the grid)."""
    rows, cols = label.shape
    nchunks = _chunks(rows, nthreads)
    for k in prange(nchunks):
        for r in range(k * rows // nchunks, (k + 1) * rows // nchunks):
            for c in range(cols):
                nr = nearest_row[r, c]
                nc = nearest_col[r, c]
                if nr < 0 or nr >= rows or nc < 0 or nc >= cols:
                    label[r, c] = border_label
                elif use_map:
                    label[r, c] = comp_map[comp[nr, nc]]
                else:
                    label[r, c] = comp[nr, nc]


@njit(cache=True, nogil=True, inline="always")
def _gvd_dir(la, da, lb, db, fb, mark, a0, a1, off, later):  # pragma: no cover - compiled
    # cells a in a0:a1 against b = a + off of a neighbouring (or the same) row
    if later:
        for c in range(a0, a1):
            b = c + off
            mark[c] |= (la[c] != lb[b]) & (fb[b] == 0) & (da[c] >= db[b])
    else:
        for c in range(a0, a1):
            b = c + off
            mark[c] |= (la[c] != lb[b]) & (fb[b] == 0) & (da[c] > db[b])


@njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def gvd_pass(label, distance, occ, gvd, nthreads):  # pragma: no cover - compiled
    """Mark free cells next to a free cell of another label: of each such 8-neighbour pair the farther
    cell, on ties the one first in raster order. Each cell looks at its 8 neighbours, so every row is
    written by one thread only."""
    rows, cols = label.shape
    nchunks = _chunks(rows, nthreads)
    for k in prange(nchunks):
        mark = np.empty(cols, np.bool_)
        for r in range(k * rows // nchunks, (k + 1) * rows // nchunks):
            la = label[r]
            da = distance[r]
            fa = occ[r]
            mark[:] = False
            for dr in range(-1, 2):
                rr = r + dr
                if rr < 0 or rr >= rows:
                    continue
                lb = label[rr]
                db = distance[rr]
                fb = occ[rr]
                # neighbour b = (r + dr, c + dc) comes later in raster order iff dr > 0 or dc > 0 on
                # the same row; on a tie the earlier cell of the pair is marked
                if dr != 0:
                    _gvd_dir(la, da, lb, db, fb, mark, 0, cols, 0, dr > 0)
                _gvd_dir(la, da, lb, db, fb, mark, 1, cols, -1, dr > 0)
                _gvd_dir(la, da, lb, db, fb, mark, 0, cols - 1, 1, dr >= 0)
            grow = gvd[r]
            for c in range(cols):
                grow[c] = mark[c] & (fa[c] == 0)


@njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def saturate_pass(distance, radius, far, nthreads):  # pragma: no cover - compiled
    """In place: ``distance[distance >= radius] = far``."""
    rows, cols = distance.shape
    nchunks = _chunks(rows, nthreads)
    for k in prange(nchunks):
        for r in range(k * rows // nchunks, (k + 1) * rows // nchunks):
            for c in range(cols):
                if distance[r, c] >= radius:
                    distance[r, c] = far
