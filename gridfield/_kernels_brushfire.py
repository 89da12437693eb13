"""Numba kernels behind :func:`gridfield.brushfire.brushfire` (private; imported on first use).

Chessboard and taxicab (:func:`chamfer_steps`, :func:`chamfer_nearest`)
    The classic two-pass raster transform with a 3x3 mask (Rosenfeld & Pfaltz 1966), exact for both
    metrics. Each row is done in two stages: the neighbours in the previous row (a branch-free loop
    the compiler vectorizes), then the left (right) neighbour (a scan, run as 4 interleaved chains).
    The nearest obstacle cell is carried along: the neighbour that gives a cell its final value has a
    nearest obstacle at exactly that distance, so the carried cell is an exact nearest obstacle.
    Sequential over the rows.

Euclidean (:func:`column_block`, :func:`edt_rows`)
    Separable: for every cell the nearest obstacle row in its column, then per row the lower envelope
    of the parabolas ``(x - i)**2 + g_i**2`` (Meijster, Roerdink & Hesselink 2000), whose winning
    column gives the exact nearest obstacle cell. Columns, then rows, are independent.

Components (:func:`label_strip`, :func:`merge_strips`, :func:`relabel_rows`)
    8-connected, two-pass union-find on horizontal strips, joined across the strip boundaries;
    components are numbered in raster order of their first cell (row 0 first), the numbering of
    ``scipy.ndimage.label``. Strips are independent.

Then :func:`decode_rows` (nearest cell and label of the chamfer path), :func:`gvd_rows` and
:func:`saturate_rows`, again independent over rows.

Every kernel is sequential and releases the GIL (``nogil``); the ones taking a range of rows or
columns (``r0, r1`` / ``c0, c1``) are run by :mod:`gridfield.brushfire` on several threads that take
chunks of the range as they become free, and the sequential ones run beside each other.

Conventions: arrays are C-contiguous ``[row, col]``; occupancy is passed as ``uint8``; the wall
border is the ring of cells at rows ``-1``/``rows`` and columns ``-1``/``cols`` (never its corners).
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Sentinel row for "no obstacle above/below" (far beyond any real grid).
BIG = 1 << 30

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}


# ----------------------------------------------------------------------------------------------
# chessboard / taxicab: two-pass raster transform
# ----------------------------------------------------------------------------------------------
# The scans s[c] = min(t[c], s[c -+ 1] + 1) are latency bound (one compare-select chain per row): they
# run as 4 interleaved chains over 4 segments of the row, then the carry of each segment's end is
# pushed into the next segment for as long as it improves it (a few cells at most in practice).
_NOINFO = np.int64(1 << 30)  # initial carry of the inner segments: never wins


@njit(cache=True, nogil=True, inline="always")
def _scan_right(t, s, cols, edge):  # pragma: no cover - compiled
    """Left-to-right scan ``s[c] = min(t[c], s[c - 1] + 1)``, ``s[-1] = edge``."""
    n = max(0, cols // 4 - 17)  # segment length (not a multiple of the page size)
    l0 = np.int64(edge)
    l1 = _NOINFO
    l2 = _NOINFO
    l3 = _NOINFO
    for j in range(n):
        a = min(np.int64(t[j]), l0 + 1)
        s[j] = a
        l0 = a
        a = min(np.int64(t[n + j]), l1 + 1)
        s[n + j] = a
        l1 = a
        a = min(np.int64(t[2 * n + j]), l2 + 1)
        s[2 * n + j] = a
        l2 = a
        a = min(np.int64(t[3 * n + j]), l3 + 1)
        s[3 * n + j] = a
        l3 = a
    if n == 0:
        l3 = np.int64(edge)
    for c in range(4 * n, cols):
        a = min(np.int64(t[c]), l3 + 1)
        s[c] = a
        l3 = a
    for k in range(1, 4):
        c = k * n
        end = cols if k == 3 else c + n
        if c == 0:
            continue
        v = np.int64(s[c - 1]) + 1
        while c < end and v < s[c]:
            s[c] = v
            v += 1
            c += 1


@njit(cache=True, nogil=True, inline="always")
def _scan_left(t, s, cols, edge):  # pragma: no cover - compiled
    """Right-to-left scan ``s[c] = min(t[c], s[c + 1] + 1)``, ``s[cols] = edge`` (x = cols - 1 - c)."""
    n = max(0, cols // 4 - 17)
    top = cols - 1
    l0 = np.int64(edge)
    l1 = _NOINFO
    l2 = _NOINFO
    l3 = _NOINFO
    for j in range(n):
        c = np.uint64(top - j)  # unsigned indices: no negative-index wraparound checks
        a = min(np.int64(t[c]), l0 + 1)
        s[c] = a
        l0 = a
        c = np.uint64(top - n - j)
        a = min(np.int64(t[c]), l1 + 1)
        s[c] = a
        l1 = a
        c = np.uint64(top - 2 * n - j)
        a = min(np.int64(t[c]), l2 + 1)
        s[c] = a
        l2 = a
        c = np.uint64(top - 3 * n - j)
        a = min(np.int64(t[c]), l3 + 1)
        s[c] = a
        l3 = a
    if n == 0:
        l3 = np.int64(edge)
    for x in range(4 * n, cols):
        c = np.uint64(top - x)
        a = min(np.int64(t[c]), l3 + 1)
        s[c] = a
        l3 = a
    for k in range(1, 4):
        x = k * n
        end = cols if k == 3 else x + n
        if x == 0:
            continue
        v = np.int64(s[np.uint64(top - x + 1)]) + 1
        while x < end and v < s[np.uint64(top - x)]:
            s[np.uint64(top - x)] = v
            v += 1
            x += 1


@njit(cache=True, nogil=True, inline="always")
def _scan_right_idx(t, ti, s, si, cols, edge, edge_i):  # pragma: no cover - compiled
    """:func:`_scan_right` carrying the nearest-cell index ``si`` of the winner."""
    n = max(0, cols // 4 - 17)
    l0 = np.int64(edge)
    l1 = _NOINFO
    l2 = _NOINFO
    l3 = _NOINFO
    i0 = np.int64(edge_i)
    i1 = np.int64(0)
    i2 = np.int64(0)
    i3 = np.int64(0)
    for j in range(n):
        c = j
        a = np.int64(t[c])
        m = np.int64(l0 + 1 < a)
        a += (l0 + 1 - a) * m
        i0 = ti[c] + (i0 - ti[c]) * m
        s[c] = a
        si[c] = i0
        l0 = a
        c = n + j
        a = np.int64(t[c])
        m = np.int64(l1 + 1 < a)
        a += (l1 + 1 - a) * m
        i1 = ti[c] + (i1 - ti[c]) * m
        s[c] = a
        si[c] = i1
        l1 = a
        c = 2 * n + j
        a = np.int64(t[c])
        m = np.int64(l2 + 1 < a)
        a += (l2 + 1 - a) * m
        i2 = ti[c] + (i2 - ti[c]) * m
        s[c] = a
        si[c] = i2
        l2 = a
        c = 3 * n + j
        a = np.int64(t[c])
        m = np.int64(l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = a
        si[c] = i3
        l3 = a
    if n == 0:
        l3 = np.int64(edge)
        i3 = np.int64(edge_i)
    for c in range(4 * n, cols):
        a = np.int64(t[c])
        m = np.int64(l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = a
        si[c] = i3
        l3 = a
    for k in range(1, 4):
        c = k * n
        end = cols if k == 3 else c + n
        if c == 0:
            continue
        v = np.int64(s[c - 1]) + 1
        vi = si[c - 1]
        while c < end and v < s[c]:
            s[c] = v
            si[c] = vi
            v += 1
            c += 1


@njit(cache=True, nogil=True, inline="always")
def _scan_left_idx(t, ti, s, si, cols, edge, edge_i):  # pragma: no cover - compiled
    """:func:`_scan_left` carrying the nearest-cell index ``si`` of the winner."""
    n = max(0, cols // 4 - 17)
    top = cols - 1
    l0 = np.int64(edge)
    l1 = _NOINFO
    l2 = _NOINFO
    l3 = _NOINFO
    i0 = np.int64(edge_i)
    i1 = np.int64(0)
    i2 = np.int64(0)
    i3 = np.int64(0)
    for j in range(n):
        c = np.uint64(top - j)
        a = np.int64(t[c])
        m = np.int64(l0 + 1 < a)
        a += (l0 + 1 - a) * m
        i0 = ti[c] + (i0 - ti[c]) * m
        s[c] = a
        si[c] = i0
        l0 = a
        c = np.uint64(top - n - j)
        a = np.int64(t[c])
        m = np.int64(l1 + 1 < a)
        a += (l1 + 1 - a) * m
        i1 = ti[c] + (i1 - ti[c]) * m
        s[c] = a
        si[c] = i1
        l1 = a
        c = np.uint64(top - 2 * n - j)
        a = np.int64(t[c])
        m = np.int64(l2 + 1 < a)
        a += (l2 + 1 - a) * m
        i2 = ti[c] + (i2 - ti[c]) * m
        s[c] = a
        si[c] = i2
        l2 = a
        c = np.uint64(top - 3 * n - j)
        a = np.int64(t[c])
        m = np.int64(l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = a
        si[c] = i3
        l3 = a
    if n == 0:
        l3 = np.int64(edge)
        i3 = np.int64(edge_i)
    for x in range(4 * n, cols):
        c = np.uint64(top - x)
        a = np.int64(t[c])
        m = np.int64(l3 + 1 < a)
        a += (l3 + 1 - a) * m
        i3 = ti[c] + (i3 - ti[c]) * m
        s[c] = a
        si[c] = i3
        l3 = a
    for k in range(1, 4):
        x = k * n
        end = cols if k == 3 else x + n
        if x == 0:
            continue
        c = np.uint64(top - x + 1)
        v = np.int64(s[c]) + 1
        vi = si[c]
        while x < end and v < s[np.uint64(top - x)]:
            c = np.uint64(top - x)
            s[c] = v
            si[c] = vi
            v += 1
            x += 1


@njit(**_OPTS)
def chamfer_steps(occ, top, bottom, side, conn8, steps, distance, resolution, write_distance):  # pragma: no cover
    """Chessboard (``conn8``) or taxicab steps; also ``distance = steps * resolution`` if asked.

    ``top``, ``bottom``, ``side``: whether the rows above / below the array and the columns beside it
    are a wall (obstacles) or open."""
    rows, cols = occ.shape
    inf = np.int64(rows + cols + 4)
    top_edge = np.int64(0) if top else inf
    bottom_edge = np.int64(0) if bottom else inf
    edge = np.int64(0) if side else inf
    p = np.empty(cols + 2, np.int32)  # the neighbouring row, padded (padding never wins)
    p[0] = inf
    p[cols + 1] = inf
    t = np.empty(cols, np.int32)
    for r in range(rows):  # forward: up-left, up, up-right, left
        orow = occ[r]
        srow = steps[r]
        if r == 0:
            for c in range(cols):
                p[c + 1] = top_edge
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
        _scan_right(t, srow, cols, edge)
    for r in range(rows - 1, -1, -1):  # backward: down-right, down, down-left, right
        srow = steps[r]
        if r == rows - 1:
            for c in range(cols):
                p[c + 1] = bottom_edge
        else:
            nxt = steps[r + 1]
            for c in range(cols):
                p[c + 1] = nxt[c]
        if conn8:
            for c in range(cols):
                a = min(min(np.int64(p[c]), np.int64(p[c + 1])), np.int64(p[c + 2])) + 1
                t[c] = a
        else:
            for c in range(cols):
                t[c] = np.int64(p[c + 1]) + 1
        for c in range(cols):  # a separate loop: fewer arrays, so the compiler vectorizes both
            t[c] = min(np.int64(t[c]), np.int64(srow[c]))
        _scan_left(t, srow, cols, edge)
        if write_distance:
            drow = distance[r]
            for c in range(cols):
                drow[c] = srow[c] * resolution


@njit(**_OPTS)
def chamfer_nearest(occ, top, bottom, side, row0, conn8, steps, nidx, distance, resolution,
                    write_distance):  # pragma: no cover - compiled
    """:func:`chamfer_steps` carrying the nearest obstacle cell along, packed as
    ``nidx = (row + 1) * (cols + 2) + (col + 1)`` with ``row`` counted from ``row0`` (the first row of
    ``occ`` in the whole grid; see :func:`decode_row`). Selects are branch-free: ``x += (y - x) * m``
    with ``m`` in {0, 1}."""
    rows, cols = occ.shape
    w = np.int64(cols + 2)
    inf = np.int64(rows + cols + 4)
    top_edge = np.int64(0) if top else inf
    bottom_edge = np.int64(0) if bottom else inf
    edge = np.int64(0) if side else inf
    p = np.empty(cols + 2, np.int32)  # the neighbouring row, padded (padding never wins)
    pi = np.zeros(cols + 2, nidx.dtype)
    p[0] = inf
    p[cols + 1] = inf
    t = np.empty(cols, np.int32)
    ti = np.empty(cols, nidx.dtype)
    for r in range(rows):  # forward: up-left, up, up-right, then left
        orow = occ[r]
        srow = steps[r]
        irow = nidx[r]
        if r == 0:
            for c in range(cols):
                p[c + 1] = top_edge
                pi[c + 1] = row0 * w + c + 1  # wall cell (row0 - 1, c)
        else:
            prev = steps[r - 1]
            previ = nidx[r - 1]
            for c in range(cols):
                p[c + 1] = prev[c]
                pi[c + 1] = previ[c]
        own = (row0 + r + 1) * w + 1
        for c in range(cols):
            a = np.int64(p[c + 1])
            ai = np.int64(pi[c + 1])
            if conn8:
                b = np.int64(p[c])
                m = np.int64(b < a)
                a += (b - a) * m
                ai += (np.int64(pi[c]) - ai) * m
                b = np.int64(p[c + 2])
                m = np.int64(b < a)
                a += (b - a) * m
                ai += (np.int64(pi[c + 2]) - ai) * m
            a += 1
            o = np.int64(orow[c])
            t[c] = a - a * o
            ti[c] = ai + (own + c - ai) * o
        _scan_right_idx(t, ti, srow, irow, cols, edge, own - 1)  # wall cell (r, -1)
    for r in range(rows - 1, -1, -1):  # backward: down-right, down, down-left, then right
        srow = steps[r]
        irow = nidx[r]
        if r == rows - 1:
            for c in range(cols):
                p[c + 1] = bottom_edge
                pi[c + 1] = (row0 + rows + 1) * w + c + 1  # wall cell (row0 + rows, c)
        else:
            nxt = steps[r + 1]
            nxti = nidx[r + 1]
            for c in range(cols):
                p[c + 1] = nxt[c]
                pi[c + 1] = nxti[c]
        for c in range(cols):
            a = np.int64(p[c + 1])
            ai = np.int64(pi[c + 1])
            if conn8:
                b = np.int64(p[c])
                m = np.int64(b < a)
                a += (b - a) * m
                ai += (np.int64(pi[c]) - ai) * m
                b = np.int64(p[c + 2])
                m = np.int64(b < a)
                a += (b - a) * m
                ai += (np.int64(pi[c + 2]) - ai) * m
            t[c] = a + 1
            ti[c] = ai
        for c in range(cols):  # a separate loop: fewer arrays, so the compiler vectorizes both
            a = np.int64(t[c])
            cur = np.int64(srow[c])
            m = np.int64(a < cur)
            t[c] = cur + (a - cur) * m
            ti[c] = irow[c] + (ti[c] - irow[c]) * m
        _scan_left_idx(t, ti, srow, irow, cols, edge, (row0 + r + 1) * w + cols + 1)  # wall cell (r, cols)
        if write_distance:
            drow = distance[r]
            for c in range(cols):
                drow[c] = srow[c] * resolution


@njit(cache=True, nogil=True, inline="always")
def decode_row(irow, cols, nr, nc):  # pragma: no cover - compiled
    """Unpack one row of :func:`chamfer_nearest`'s packed cells into ``nr``, ``nc`` (int64 buffers, or
    the output rows: each value is read before it is written)."""
    w = np.int64(cols + 2)
    inv = 1.0 / (cols + 2)
    for c in range(cols):
        i = np.int64(irow[c])
        q = np.int64(i * inv)  # i // w in floating point, then corrected
        q += np.int64(i - q * w >= w) - np.int64(i - q * w < 0)
        nr[c] = q - 1
        nc[c] = i - q * w - 1


@njit(**_OPTS)
def finish_window(a, b, lo, margin, checked, ws, wi, want_idx, steps, nearest_row, nearest_col, distance,
                  resolution, write_distance):  # pragma: no cover - compiled
    """Copy rows ``a:b`` of a window transform (``ws``/``wi``: rows ``lo:lo + len(ws)`` of the grid) into
    the outputs, unpacking the nearest cells. Returns False if ``checked`` and some copied cell lies
    farther than ``margin`` from its nearest obstacle in the window: an obstacle outside the window
    might then be nearer (one within ``margin`` rows of the cell always lies inside it)."""
    cols = ws.shape[1]
    worst = np.int64(0)
    br = np.empty(cols, np.int64)
    bc = np.empty(cols, np.int64)
    for r in range(a, b):
        src = ws[r - lo]
        srow = steps[r]
        for c in range(cols):
            v = np.int64(src[c])
            worst = max(worst, v)
            srow[c] = v
        if write_distance:
            drow = distance[r]
            for c in range(cols):
                drow[c] = src[c] * resolution
        if want_idx:
            decode_row(wi[r - lo], cols, br, bc)
            rrow = nearest_row[r]
            crow = nearest_col[r]
            for c in range(cols):
                rrow[c] = br[c]
                crow[c] = bc[c]
    return not checked or worst <= margin


@njit(**_OPTS)
def decode_rows(r0, r1, nidx, nearest_row, nearest_col):  # pragma: no cover - compiled
    """Rows ``r0:r1``: unpack ``nidx`` into ``nearest_row``/``nearest_col`` (which may be ``nidx``)."""
    cols = nidx.shape[1]
    br = np.empty(cols, np.int64)
    bc = np.empty(cols, np.int64)
    for r in range(r0, r1):
        decode_row(nidx[r], cols, br, bc)
        rrow = nearest_row[r]
        crow = nearest_col[r]
        for c in range(cols):
            rrow[c] = br[c]
            crow[c] = bc[c]


@njit(**_OPTS)
def label_gvd_rows(r0, r1, nearest_row, nearest_col, flat, comp_map, use_map, label, want_gvd, key, occ,
                   gvd):  # pragma: no cover - compiled
    """Rows ``r0:r1``: ``label`` (see :func:`_gather_labels`) and, if ``want_gvd``, the GVD (see
    :func:`gvd_rows`) from the labels of each row and its two neighbours, kept in a 3-row ring (the
    neighbour rows outside ``r0:r1`` are gathered again, not read back)."""
    rows, cols = nearest_row.shape
    ring = np.zeros((3, cols), np.int32)
    mark = np.empty(cols, np.bool_)
    for rr in range(max(0, r0 - 1), min(rows, r0 + 1)):
        _gather_labels(nearest_row[rr], nearest_col[rr], rows, cols, flat, comp_map, use_map, ring[rr % 3])
    for r in range(r0, r1):
        if r + 1 < rows:
            _gather_labels(nearest_row[r + 1], nearest_col[r + 1], rows, cols, flat, comp_map, use_map,
                           ring[(r + 1) % 3])
        la = ring[r % 3]
        lrow = label[r]
        for c in range(cols):
            lrow[c] = la[c]
        if want_gvd:
            _gvd_row(r, rows, cols, la, ring, key, occ, mark, gvd[r])


@njit(cache=True, nogil=True, inline="always")
def _gather_labels(nr, nc, rows, cols, flat, comp_map, use_map, out):  # pragma: no cover - compiled
    """``out[c]`` = label of the cell ``(nr[c], nc[c])``: ``flat[nr * cols + nc]``, mapped through
    ``comp_map`` if ``use_map``. ``flat`` is the label grid raveled plus one last element for any cell
    outside the grid (the wall), so that the loop is a plain gather."""
    outside = np.int64(rows * cols)
    n = out.shape[0]
    if use_map:
        for c in range(n):
            a = np.int64(nr[c])
            b = np.int64(nc[c])
            inside = np.int64((a >= 0) & (a < rows) & (b >= 0) & (b < cols))
            out[c] = comp_map[flat[outside + (a * cols + b - outside) * inside]]
    else:
        for c in range(n):
            a = np.int64(nr[c])
            b = np.int64(nc[c])
            inside = np.int64((a >= 0) & (a < rows) & (b >= 0) & (b < cols))
            out[c] = flat[outside + (a * cols + b - outside) * inside]


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
def column_block(c0, c1, occ, wall, vr):  # pragma: no cover - compiled
    """Columns ``c0:c1``: ``vr[r, c]`` = row of the obstacle nearest to ``(r, c)`` in column ``c``
    (ties: the one above). Wall border: rows ``-1`` and ``rows`` count as obstacles. No obstacle in
    the column: ``+-BIG``. Two sweeps over the rows, each a branch-free loop over the columns."""
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


@njit(**_OPTS)
def edt_rows(r0, r1, vr, wall, resolution, distance, nearest_row, nearest_col, want_nearest,
             flat, comp_map, use_map, want_label, label):  # pragma: no cover - compiled
    """Rows ``r0:r1`` of the Euclidean transform's row pass: ``distance`` and optionally the nearest
    obstacle and its label.

    ``vr`` holds the column pass result; it may be the very array ``nearest_row`` (each row is copied
    to a buffer before it is overwritten). Labels: see :func:`_gather_labels`.
    """
    rows, cols = vr.shape
    n = cols
    inf = np.int64(rows + cols + 4)
    g = np.empty(n + 2, np.int64)
    rowv = np.empty(n + 2, np.int64)
    s = np.empty(n + 2, np.int64)
    t = np.empty(n + 2, np.int64)
    val = np.empty(n, np.int64)
    arg = np.empty(n, np.int64)
    bnr = np.empty(n, np.int64)
    bnc = np.empty(n, np.int64)
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
        for c in range(n):
            a = arg[c]
            bnr[c] = rowv[a]
            bnc[c] = a - 1
        if want_nearest:
            rrow = nearest_row[r]
            crow = nearest_col[r]
            for c in range(n):
                rrow[c] = bnr[c]
                crow[c] = bnc[c]
        if want_label:
            _gather_labels(bnr, bnc, rows, cols, flat, comp_map, use_map, label[r])


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


def strip_cap(rows, cols):
    """Most provisional labels a strip of ``rows`` x ``cols`` cells can create: they are only created
    at cells with no labelled neighbour before them, so no two are 8-adjacent."""
    return ((rows + 1) // 2) * ((cols + 1) // 2)


@njit(**_OPTS)
def label_strip(r0, r1, occ, comp, parent, base):  # pragma: no cover - compiled
    """First pass of the 8-connected labelling on rows ``r0:r1`` alone: provisional labels
    ``base + 1, base + 2, ...`` in raster order (0 on free cells), unions in ``parent`` (each set's
    root is its smallest label). Returns the last label used (``base`` if none)."""
    cols = occ.shape[1]
    nxt = base + 1
    for r in range(r0, r1):
        orow = occ[r]
        crow = comp[r]
        if r == r0:
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
            if ur:  # up-left and left are neighbours of each other: one union is enough
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
    return nxt - 1


@njit(**_OPTS)
def merge_strips(occ, comp, parent, firsts, bases, lasts, comp_map):  # pragma: no cover - compiled
    """Join the strips (first rows ``firsts``, label ranges ``bases[k] + 1 .. lasts[k]``) across their
    boundaries and number the components 1.. in raster order of their first cell (the numbering of
    ``scipy.ndimage.label``): ``comp_map[i]`` becomes the final label of provisional label ``i`` (only
    the labels in use are written; ``comp_map[0] = 0``). Returns the number of components."""
    cols = occ.shape[1]
    for k in range(1, len(firsts)):
        b = firsts[k]
        for c in range(cols):
            if not occ[b, c]:
                continue
            for cc in range(max(0, c - 1), min(cols, c + 2)):
                if occ[b - 1, cc]:
                    _union(parent, comp[b, c], comp[b - 1, cc])
    comp_map[0] = 0
    count = 0
    for k in range(len(firsts)):  # labels grow with the strips: every root comes before its members
        for i in range(bases[k] + 1, lasts[k] + 1):
            p = parent[i]
            if p == i:
                count += 1
                comp_map[i] = count
            else:
                comp_map[i] = comp_map[_find(parent, p)]
    return count


@njit(**_OPTS)
def relabel_rows(r0, r1, comp, comp_map):  # pragma: no cover - compiled
    """Rows ``r0:r1``, in place: ``comp = comp_map[comp]``."""
    cols = comp.shape[1]
    for r in range(r0, r1):
        crow = comp[r]
        for c in range(cols):
            crow[c] = comp_map[crow[c]]


def label_components(occ, comp, strips=1):
    """8-connected labels of the obstacle cells into ``comp`` (0 on free cells), numbered 1.. in raster
    order of each component's first cell; returns their number. Sequential reference use of the
    strip kernels (:mod:`gridfield.brushfire` runs the strips on several threads)."""
    rows, cols = occ.shape
    strips = max(1, min(strips, rows))  # no empty strip
    firsts = np.array([k * rows // strips for k in range(strips)], np.int64)
    ends = [(k + 1) * rows // strips for k in range(strips)]
    bases = np.zeros(strips, np.int64)
    for k in range(1, strips):
        bases[k] = bases[k - 1] + strip_cap(ends[k - 1] - firsts[k - 1], cols)
    parent = np.zeros(int(bases[-1]) + strip_cap(ends[-1] - firsts[-1], cols) + 1, np.int32)
    lasts = np.array([label_strip(firsts[k], ends[k], occ, comp, parent, bases[k]) for k in range(strips)], np.int64)
    comp_map = np.zeros(len(parent), np.int32)
    count = merge_strips(occ, comp, parent, firsts, bases, lasts, comp_map)
    relabel_rows(0, rows, comp, comp_map)
    return count


# ----------------------------------------------------------------------------------------------
# generalized Voronoi diagram, saturation
# ----------------------------------------------------------------------------------------------
@njit(cache=True, nogil=True, inline="always")
def _gvd_dir(la, da, lb, db, fb, mark, a0, a1, off):  # pragma: no cover - compiled
    # cells a in a0:a1 against b = a + off of a neighbouring (or the same) row: a is marked if b is a
    # free cell of another label and a is farther from its obstacle (on a tie: a has the smaller label)
    for c in range(a0, a1):
        b = c + off
        lab_a = la[c]
        lab_b = lb[b]
        mark[c] |= (lab_a != lab_b) & (fb[b] == 0) & ((da[c] > db[b]) | ((da[c] == db[b]) & (lab_a < lab_b)))


@njit(cache=True, nogil=True, inline="always")
def _gvd_row(r, rows, cols, la, labels, key, occ, mark, out):  # pragma: no cover - compiled
    # labels is the label grid or a ring of 3 rows: either way row r + dr is labels[(r + dr) % len]
    da = key[r]
    fa = occ[r]
    mark[:] = False
    for dr in range(-1, 2):
        rr = r + dr
        if rr < 0 or rr >= rows:
            continue
        lb = labels[rr % labels.shape[0]]
        db = key[rr]
        fb = occ[rr]
        if dr != 0:
            _gvd_dir(la, da, lb, db, fb, mark, 0, cols, 0)
        _gvd_dir(la, da, lb, db, fb, mark, 1, cols, -1)
        _gvd_dir(la, da, lb, db, fb, mark, 0, cols - 1, 1)
    for c in range(cols):
        out[c] = mark[c] & (fa[c] == 0)


@njit(**_OPTS)
def gvd_rows(r0, r1, label, distance, occ, gvd):  # pragma: no cover - compiled
    """Rows ``r0:r1`` of the GVD: of each pair of 8-neighbouring free cells with different labels,
    mark the one farther from its obstacle; on a tie, the one with the smaller label. Each cell looks
    at its 8 neighbours, so rows can be done in any order, by any thread. ``distance`` may be any
    array that orders the cells as the distance does (the int32 steps of a chamfer metric)."""
    rows, cols = label.shape
    mark = np.empty(cols, np.bool_)
    for r in range(r0, r1):
        _gvd_row(r, rows, cols, label[r], label, distance, occ, mark, gvd[r])


@njit(**_OPTS)
def saturate_rows(r0, r1, distance, radius, far):  # pragma: no cover - compiled
    """Rows ``r0:r1``, in place: ``distance[distance >= radius] = far``."""
    cols = distance.shape[1]
    for r in range(r0, r1):
        drow = distance[r]
        for c in range(cols):
            if drow[c] >= radius:
                drow[c] = far
