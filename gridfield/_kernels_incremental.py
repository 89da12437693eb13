"""Numba kernels behind :class:`gridfield.incremental.IncrementalBrushfire` (private; imported on first use).

Everything works on a rectangular *window* ``rows r0:r1, cols c0:c1`` of the full-grid arrays, with
global cell indices. The Euclidean transform of a window (:func:`window_edt`) is the transform of
:mod:`gridfield._kernels_brushfire` (same column rule, same :func:`~gridfield._kernels_brushfire.edt_1d`)
restricted to the sites inside the window, so it picks the nearest site by the same rule: the
smallest squared distance, then the smallest column, then the smallest row. The full transform picks
exactly that one too (checked against brute force in the tests), which is what lets a window result
be merged cell by cell into a full-grid one (:func:`lower_merge`, :func:`raise_apply`).

The kernels are plain typed loops over numpy arrays (no typed containers), released from the GIL.

Conventions: ``nr``/``nc`` are the nearest obstacle cells (int32, ``(-1, -1)`` = none); wall-border
cells are row ``-1``/``rows`` or column ``-1``/``cols``; squared distances are in cells (int64).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._kernels_brushfire import BIG

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}
#: Squared distance meaning "no site" (larger than any squared distance on a grid).
NONE_D2 = np.int64(1) << np.int64(62)


# The two scalar helpers of the fused Khatib kernel, kept here in numba while this module is not yet
# ported to Cython (gridfield._kernels_potential is compiled; its helpers are C-level only). Same
# expressions as gridfield/_potential_rows.h, so khatib_window stays bit-identical to a full build.
# edt_1d likewise: the numba original of gridfield._kernels_brushfire.edt_1d (numba cannot call the
# compiled one).
@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(inline="always", cache=True, nogil=True, error_model="numpy")
def _rep_distance(fr, fc, res, metric, sat, far):  # pragma: no cover - compiled
    """``(D, |offset| in cells)`` for a nearest obstacle cell ``(fr, fc)`` cells away, after saturation."""
    length = math.sqrt(fr * fr + fc * fc)
    if metric == 0:
        dist = length * res
    elif metric == 1:
        dist = max(abs(fr), abs(fc)) * res
    else:
        dist = (abs(fr) + abs(fc)) * res
    return (far if dist >= sat else dist), length


@njit(inline="always", cache=True, nogil=True, error_model="numpy")
def _attraction(d2, zeta, d_star, ds2, conic):  # pragma: no cover - compiled
    """``(U, k)`` of the attractive potential at squared distance ``d2`` from the goal, with
    ``grad U = k * (p - goal)``: quadratic within ``d_star`` (``ds2 = d_star**2``; ``inf``: everywhere,
    ``0``: the goal only), beyond it conic (``conic``: ``zeta*d``, the ``d_star = 0`` case) or the
    combined ``d_star*zeta*d - 0.5*zeta*d_star**2``. Selects, no jumps, so that callers' loops vectorize."""
    d = math.sqrt(d2)
    quad = d2 <= ds2
    u = 0.5 * zeta * d2 if quad else (zeta * d if conic else zeta * d_star * d - 0.5 * zeta * ds2)
    k = zeta if quad else (zeta / d if conic else zeta * d_star / d)
    return u, k


@njit(cache=True, nogil=True, inline="always")
def _old_d2(r, c, a, b):  # pragma: no cover - compiled
    if a == -1 and b == -1:
        return NONE_D2
    dr = np.int64(r - a)
    dc = np.int64(c - b)
    return dr * dr + dc * dc


@njit(cache=True, nogil=True, inline="always")
def _less(d2, col, row, e2, ecol, erow):  # pragma: no cover - compiled
    # (d2, col, row) < (e2, ecol, erow) lexicographically: the tie rule of the full transform
    if d2 != e2:
        return d2 < e2
    if col != ecol:
        return col < ecol
    return row < erow


@njit(**_OPTS)
def window_edt(sites, r0, r1, c0, c1, wt, wb, wl, wr, inf, vr, g, rowv, s, t, val, arg, wnr, wnc,
               wd2):  # pragma: no cover - compiled
    """Euclidean transform of the sites (``sites[r, c] != 0``) inside the window: for each window cell,
    ``wnr``/``wnc`` (global cell of the nearest site) and ``wd2`` (its squared distance;
    :data:`NONE_D2` and ``(-1, -1)`` when the window holds no site). ``wt``/``wb``/``wl``/``wr``:
    whether the wall rows ``-1``/``rows`` or columns ``-1``/``cols`` count as sites (only when the
    window reaches that edge). Window-shaped outputs and scratch ``vr``; 1-D scratch of at least
    ``c1 - c0 + 2`` elements. ``inf``: larger than any row distance on the grid."""
    rows = sites.shape[0]
    n = c1 - c0
    top = np.int64(-1) if wt else np.int64(-BIG)
    bottom = np.int64(rows) if wb else np.int64(BIG)
    h = r1 - r0
    # column pass: nearest site row in each column (ties: the smaller row), swept row by row (the
    # arrays are row-major): down, the nearest site at or above; up, the one below if strictly nearer
    for i in range(h):
        r = np.int64(r0 + i)
        srow = sites[r0 + i]
        vrow = vr[i]
        if i == 0:
            for j in range(n):
                vrow[j] = r if srow[c0 + j] else top
        else:
            prev = vr[i - 1]
            for j in range(n):
                vrow[j] = r if srow[c0 + j] else prev[j]
    below = g[:n]  # scratch: the nearest site at or below, per column (g is reused by the row pass)
    for j in range(n):
        below[j] = bottom
    for i in range(h - 1, -1, -1):
        r = np.int64(r0 + i)
        srow = sites[r0 + i]
        vrow = vr[i]
        for j in range(n):
            if srow[c0 + j]:
                below[j] = r
            b = below[j]
            if (b - r) < (r - vrow[j]):
                vrow[j] = b
    for i in range(h):  # row pass: lower envelope (the full transform's edt_1d)
        r = np.int64(r0 + i)
        g[0] = 0 if wl else inf
        g[n + 1] = 0 if wr else inf
        rowv[0] = r
        rowv[n + 1] = r
        for j in range(n):
            v = vr[i, j]
            rowv[j + 1] = v
            g[j + 1] = min(abs(r - v), inf)
        if edt_1d(g, n, inf, s, t, val, arg):
            for j in range(n):
                a = arg[j]
                wnr[i, j] = rowv[a]
                wnc[i, j] = c0 + a - 1
                wd2[i, j] = val[j]
        else:
            for j in range(n):
                wnr[i, j] = -1
                wnc[i, j] = -1
                wd2[i, j] = NONE_D2


@njit(**_OPTS)
def ring_reached(r0, r1, c0, c1, rows, cols, wd2, nr, nc, out):  # pragma: no cover - compiled
    """For each side of the window that is not a grid edge (``out[0..3]``: rows ``r0``, ``r1 - 1``,
    columns ``c0``, ``c1 - 1``), whether some cell of that side may be reached by the change: its
    window distance ``sqrt(wd2)`` is at most its current distance (from ``nr``/``nc``) plus
    ``sqrt(2)``. A cell whose nearest obstacle the change alters (one it adds, or one it removes)
    is joined to the changed cells by an 8-connected path of cells meeting that bound (the lattice
    cells nearest to the straight segment), so when no side is reached no such cell lies outside."""
    slack = math.sqrt(2.0) + 1e-9
    h = r1 - r0
    w = c1 - c0
    for k in range(4):
        out[k] = False
    for k in range(4):
        if (k == 0 and r0 == 0) or (k == 1 and r1 == rows) or (k == 2 and c0 == 0) or (k == 3 and c1 == cols):
            continue
        n = w if k < 2 else h
        for m in range(n):
            if k == 0:
                i, j = 0, m
            elif k == 1:
                i, j = h - 1, m
            elif k == 2:
                i, j = m, 0
            else:
                i, j = m, w - 1
            d2 = wd2[i, j]
            if d2 == NONE_D2:
                continue
            r = r0 + i
            c = c0 + j
            o2 = _old_d2(r, c, nr[r, c], nc[r, c])
            if o2 == NONE_D2 or math.sqrt(np.float64(d2)) <= math.sqrt(np.float64(o2)) + slack:
                out[k] = True
                break


@njit(**_OPTS)
def lower_merge(r0, r1, c0, c1, wnr, wnc, wd2, nr, nc, distance, res, box):  # pragma: no cover - compiled
    """Insertion: every window cell whose window nearest site beats its current nearest obstacle
    (by the full transform's rule) takes it. ``box`` (int64[4]) grows to the bounding box
    ``r0, r1, c0, c1`` of the cells changed; returns their number."""
    count = 0
    for i in range(r1 - r0):
        r = r0 + i
        for j in range(c1 - c0):
            c = c0 + j
            d2 = wd2[i, j]
            if d2 == NONE_D2:
                continue
            a = nr[r, c]
            b = nc[r, c]
            if not _less(d2, wnc[i, j], wnr[i, j], _old_d2(r, c, a, b), b, a):
                continue
            nr[r, c] = wnr[i, j]
            nc[r, c] = wnc[i, j]
            distance[r, c] = np.sqrt(np.float64(d2)) * res
            count += 1
            box[0] = min(box[0], r)
            box[1] = max(box[1], r + 1)
            box[2] = min(box[2], c)
            box[3] = max(box[3], c + 1)
    return count


@njit(**_OPTS)
def orphan_box(r0, r1, c0, c1, rows, cols, nr, nc, mark, box):  # pragma: no cover - compiled
    """Removal: bounding box (``box``, int64[4]) of the window cells whose nearest obstacle is a
    removed cell (``mark`` set there); returns their number and the largest squared distance to it."""
    count = 0
    far2 = np.int64(0)
    for r in range(r0, r1):
        for c in range(c0, c1):
            a = nr[r, c]
            b = nc[r, c]
            if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                continue
            count += 1
            far2 = max(far2, _old_d2(r, c, a, b))
            box[0] = min(box[0], r)
            box[1] = max(box[1], r + 1)
            box[2] = min(box[2], c)
            box[3] = max(box[3], c + 1)
    return count, far2


@njit(**_OPTS)
def raise_check(b0, b1, e0, e1, r0, r1, c0, c1, rows, cols, nr, nc, mark, wd2):  # pragma: no cover - compiled
    """Removal: whether the window ``r0:r1, c0:c1`` (``wd2`` its transform of all obstacles) gives
    every orphan in the box ``b0:b1, e0:e1`` its exact nearest obstacle, i.e. one strictly nearer than
    any cell outside the window. Returns -1 if so, else the largest window distance (in cells, rounded
    up) among the orphans that failed (``-2`` when an orphan found no obstacle in the window)."""
    worst = np.int64(-1)
    for r in range(b0, b1):
        for c in range(e0, e1):
            a = nr[r, c]
            b = nc[r, c]
            if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                continue
            out = np.int64(BIG)
            if r0 > 0:
                out = min(out, r - r0 + 1)
            if r1 < rows:
                out = min(out, r1 - r)
            if c0 > 0:
                out = min(out, c - c0 + 1)
            if c1 < cols:
                out = min(out, c1 - c)
            d2 = wd2[r - r0, c - c0]
            if d2 == NONE_D2:
                if out < BIG:  # no obstacle in the window, but maybe outside: widen the window
                    return np.int64(-2)
                continue
            if d2 >= out * out:
                worst = max(worst, np.int64(math.ceil(math.sqrt(np.float64(d2)))))
    return worst


@njit(**_OPTS)
def raise_apply(b0, b1, e0, e1, r0, c0, rows, cols, nr, nc, mark, wnr, wnc, wd2, distance, res):  # pragma: no cover
    """Removal: the orphans in the box ``b0:b1, e0:e1`` take their window nearest obstacle."""
    for r in range(b0, b1):
        for c in range(e0, e1):
            a = nr[r, c]
            b = nc[r, c]
            if a < 0 or a >= rows or b < 0 or b >= cols or not mark[a, b]:
                continue
            d2 = wd2[r - r0, c - c0]
            if d2 == NONE_D2:
                nr[r, c] = -1
                nc[r, c] = -1
                distance[r, c] = np.inf
            else:
                nr[r, c] = wnr[r - r0, c - c0]
                nc[r, c] = wnc[r - r0, c - c0]
                distance[r, c] = np.sqrt(np.float64(d2)) * res


@njit(**_OPTS)
def max_distance2(r0, r1, c0, c1, nr, nc):  # pragma: no cover - compiled
    """Largest current squared distance (cells) over the window; :data:`NONE_D2` if some cell has none."""
    m = np.int64(0)
    for r in range(r0, r1):
        for c in range(c0, c1):
            m = max(m, _old_d2(r, c, nr[r, c], nc[r, c]))
    return m


@njit(**_OPTS)
def set_cells(cr, cc, arr, value):  # pragma: no cover - compiled
    """``arr[cr[k], cc[k]] = value`` for every k."""
    for k in range(cr.shape[0]):
        arr[cr[k], cc[k]] = value


# ----------------------------------------------------------------------------------------------
# labels and GVD on a window
# ----------------------------------------------------------------------------------------------
@njit(**_OPTS)
def labels_window(r0, r1, c0, c1, nr, nc, ids, border_label, label):  # pragma: no cover - compiled
    """``label`` = ``ids`` at the nearest obstacle (``border_label`` for a wall cell, 0 for none)."""
    rows, cols = nr.shape
    for r in range(r0, r1):
        for c in range(c0, c1):
            a = nr[r, c]
            b = nc[r, c]
            if a == -1 and b == -1:
                label[r, c] = 0
            elif a < 0 or a >= rows or b < 0 or b >= cols:
                label[r, c] = border_label
            else:
                label[r, c] = ids[a, b]


@njit(**_OPTS)
def gvd_window(r0, r1, c0, c1, label, key, occ, gvd):  # pragma: no cover - compiled
    """The GVD rule of :func:`gridfield._kernels_brushfire.gvd_rows` on the window cells: a free cell
    is marked if some 8-neighbouring free cell has another label and it is farther from its obstacle
    (on a tie: it has the smaller label)."""
    rows, cols = label.shape
    for r in range(r0, r1):
        for c in range(c0, c1):
            mk = False
            if not occ[r, c]:
                la = label[r, c]
                da = key[r, c]
                for dr in range(-1, 2):
                    rr = r + dr
                    if rr < 0 or rr >= rows:
                        continue
                    for dc in range(-1, 2):
                        cc = c + dc
                        if cc < 0 or cc >= cols or (dr == 0 and dc == 0) or occ[rr, cc]:
                            continue
                        lb = label[rr, cc]
                        db = key[rr, cc]
                        if la != lb and (da > db or (da == db and la < lb)):
                            mk = True
            gvd[r, c] = mk


@njit(**_OPTS)
def gather_rows(r0, r1, nr, nc, comp, border_label, label):  # pragma: no cover - compiled
    """Rows ``r0:r1`` of ``label`` = ``comp`` at the nearest obstacle (all columns)."""
    labels_window(r0, r1, 0, nr.shape[1], nr, nc, comp, border_label, label)


# ----------------------------------------------------------------------------------------------
# potential window (the fused Khatib kernel of gridfield.potential, on a window, same arithmetic)
# ----------------------------------------------------------------------------------------------
@njit(**_OPTS)
def khatib_window(r0, r1, c0, c1, occ, nr, nc, x0, y0, res, goal_x, goal_y, zeta, d_star, conic,
                  metric, eta, q_star, ipow, sat, far, U, GX, GY):  # pragma: no cover - compiled
    """Cells ``r0:r1, c0:c1`` of :func:`gridfield.potential._khatib_kernel`, expression for expression
    (so the values are bit-identical to a full build)."""
    ds2 = d_star * d_star
    inv_q = 1.0 / q_star
    for r in range(r0, r1):
        dy = y0 + (r + 0.5) * res - goal_y
        for c in range(c0, c1):
            dx = x0 + (c + 0.5) * res - goal_x
            u, k = _attraction(dx * dx + dy * dy, zeta, d_star, ds2, conic)
            gx = k * dx
            gy = k * dy
            a = nr[r, c]
            b = nc[r, c]
            fr = float(r - a)
            fc = float(c - b)
            free = not occ[r, c]
            dist, length = _rep_distance(fr, fc, res, metric, sat, far)
            inside = free and (a != -1 or b != -1) and dist < q_star
            dist = dist if inside else 1.0
            length = length if inside else 1.0
            inv_d = 1.0 / dist
            s = inv_d - inv_q
            inv_d2 = inv_d * inv_d
            den = 1.0 if ipow == 0 else (inv_d if ipow == 1 else (inv_d2 if ipow == 2 else (
                inv_d2 * inv_d if ipow == 3 else inv_d2 * inv_d2)))
            m = eta * s * den / length
            U[r, c] = (u + 0.5 * eta * s * s if inside else u) if free else np.inf
            GX[r, c] = (gx - m * fc if inside else gx) if free else 0.0
            GY[r, c] = (gy - m * fr if inside else gy) if free else 0.0


# ----------------------------------------------------------------------------------------------
# component numbers kept in place (maps without world ids), when a change renumbers nothing
# ----------------------------------------------------------------------------------------------
@njit(**_OPTS)
def first_cells(comp, first):  # pragma: no cover - compiled
    """``first[k]``: raster index ``r * cols + c`` of the first cell of component ``k`` (``first`` holds
    -1 on entry for ``k >= 1``)."""
    rows, cols = comp.shape
    for r in range(rows):
        for c in range(cols):
            k = comp[r, c]
            if k > 0 and first[k] < 0:
                first[k] = r * cols + c


@njit(cache=True, nogil=True, inline="always")
def _ring_parts(occ, mark, r, c):  # pragma: no cover - compiled
    """Number of 8-connected groups formed by the obstacle cells (``occ`` or ``mark``) among the 8
    neighbours of ``(r, c)``, connected through those neighbours only."""
    rows, cols = occ.shape
    dr = (-1, -1, -1, 0, 1, 1, 1, 0)
    dc = (-1, 0, 1, 1, 1, 0, -1, -1)
    on = np.zeros(8, np.bool_)
    parent = np.arange(8)
    for i in range(8):
        rr = r + dr[i]
        cc = c + dc[i]
        if 0 <= rr < rows and 0 <= cc < cols and (occ[rr, cc] or mark[rr, cc]):
            on[i] = True
    for i in range(8):
        if not on[i]:
            continue
        for j in range(i + 1, 8):
            if on[j] and abs(dr[i] - dr[j]) <= 1 and abs(dc[i] - dc[j]) <= 1:
                a = i
                while parent[a] != a:
                    a = parent[a]
                b = j
                while parent[b] != b:
                    b = parent[b]
                if a != b:
                    parent[max(a, b)] = min(a, b)
    n = 0
    for i in range(8):
        if on[i] and parent[i] == i:
            n += 1
    return n


@njit(**_OPTS)
def remove_in_place(fr, fc, occ, mark, comp, first, max_passes):  # pragma: no cover - compiled
    """Take the cells ``fr, fc`` (marked in ``mark``, already free in ``occ``) out of their components
    one by one, each only while provably no component splits or vanishes (its obstacle neighbours are
    connected around it) and the components keep their order by first cell (so their numbers stay).
    Cells that cannot go yet are retried after the others, for up to ``max_passes`` passes (peeling a
    removed blob from its edge). Returns False when that cannot be shown for every cell (the caller
    then renumbers everything)."""
    rows, cols = occ.shape
    total = rows * cols
    left = fr.shape[0]
    for _ in range(max_passes):
        progress = False
        for k in range(fr.shape[0]):
            r = fr[k]
            c = fc[k]
            if not mark[r, c]:  # already taken out
                continue
            t = comp[r, c]
            if _ring_parts(occ, mark, r, c) != 1:  # would split the component (for now), or it vanishes
                continue
            idx = r * cols + c
            j = first[t]
            if j == idx:  # the next cell of the component in raster order becomes its first
                j = idx + 1
                while j < total:
                    rr = j // cols
                    cc = j - rr * cols
                    if comp[rr, cc] == t:
                        break
                    j += 1
                if j >= first[t + 1]:
                    return False
            mark[r, c] = 0
            comp[r, c] = 0
            first[t] = j
            left -= 1
            progress = True
        if left == 0:
            return True
        if not progress:
            return False
    return False


@njit(**_OPTS)
def remove_rest_in_place(fr, fc, mark, comp, first, r0, r1, c0, c1):  # pragma: no cover - compiled
    """After :func:`remove_in_place` got stuck: take out the cells still marked (``fr, fc``) all at
    once if, for every component they belong to, the component's cells next to them stay connected
    to each other without them, through that component's cells inside the window ``r0:r1, c0:c1``
    (a flood fill there). Then every remaining part of the component touches one of those cells, so
    none is cut off. Returns False when that is not shown (a split, a vanished component, or a
    connection only outside the window)."""
    rows, cols = comp.shape
    total = rows * cols
    h = r1 - r0
    w = c1 - c0
    seen = np.zeros((h, w), np.bool_)
    qr = np.empty(h * w, np.int64)
    qc = np.empty(h * w, np.int64)
    for k in range(fr.shape[0]):
        r = fr[k]
        c = fc[k]
        if not mark[r, c]:
            continue
        t = comp[r, c]
        # the cells of t next to the stuck cells, and one to start from
        sr = -1
        sc = -1
        want = 0
        for m in range(fr.shape[0]):
            a = fr[m]
            b = fc[m]
            if not mark[a, b] or comp[a, b] != t:
                continue
            for dr in range(-1, 2):
                for dc in range(-1, 2):
                    aa = a + dr
                    bb = b + dc
                    if 0 <= aa < rows and 0 <= bb < cols and comp[aa, bb] == t and not mark[aa, bb]:
                        if aa < r0 or aa >= r1 or bb < c0 or bb >= c1:
                            return False
                        if not seen[aa - r0, bb - c0]:
                            seen[aa - r0, bb - c0] = True  # counted once (reset below)
                            want += 1
                            sr = aa
                            sc = bb
        if want == 0:  # the component would vanish
            return False
        # flood the component's other cells in the window from one contact; count the contacts met
        visit = np.zeros((h, w), np.bool_)
        qr[0] = sr
        qc[0] = sc
        visit[sr - r0, sc - c0] = True
        head = 0
        tail = 1
        met = 0
        while head < tail:
            a = qr[head]
            b = qc[head]
            head += 1
            if seen[a - r0, b - c0]:
                met += 1
            for dr in range(-1, 2):
                for dc in range(-1, 2):
                    aa = a + dr
                    bb = b + dc
                    if (r0 <= aa < r1 and c0 <= bb < c1 and not visit[aa - r0, bb - c0] and comp[aa, bb] == t
                            and not mark[aa, bb]):
                        visit[aa - r0, bb - c0] = True
                        qr[tail] = aa
                        qc[tail] = bb
                        tail += 1
        if met != want:
            return False
        seen[:, :] = False
        # all fine for t: take its stuck cells out, and move its first cell on if it was one of them
        for m in range(fr.shape[0]):
            a = fr[m]
            b = fc[m]
            if mark[a, b] and comp[a, b] == t:
                mark[a, b] = 0
                comp[a, b] = 0
        j = first[t]
        if comp[j // cols, j - (j // cols) * cols] != t:
            while j < total:
                a = j // cols
                if comp[a, j - a * cols] == t:
                    break
                j += 1
            if j >= first[t + 1]:
                return False
            first[t] = j
    return True


@njit(**_OPTS)
def insert_in_place(nr_, nc_, mark, comp, first, qr, qc):  # pragma: no cover - compiled
    """Give the new obstacle cells ``nr_, nc_`` (``mark == 1``, ``comp == 0``) the number of the one
    component they join, spreading from the cells next to existing obstacles, while provably no two
    components merge, no new one appears and the order by first cell stays. Returns False as soon as
    that cannot be shown."""
    rows, cols = comp.shape
    n = nr_.shape[0]
    tail = 0
    for k in range(n):
        r = nr_[k]
        c = nc_[k]
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols and comp[rr, cc] > 0 and mark[r, c] == 1:
                    mark[r, c] = 2
                    qr[tail] = r
                    qc[tail] = c
                    tail += 1
    head = 0
    while head < tail:
        r = qr[head]
        c = qc[head]
        head += 1
        t = 0
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols:
                    v = comp[rr, cc]
                    if v > 0:
                        if t == 0:
                            t = v
                        elif v != t:  # two components merge
                            return False
        comp[r, c] = t
        idx = r * cols + c
        if idx < first[t]:
            if idx < first[t - 1]:
                return False
            first[t] = idx
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                rr = r + dr
                cc = c + dc
                if 0 <= rr < rows and 0 <= cc < cols and mark[rr, cc] == 1:
                    mark[rr, cc] = 2
                    qr[tail] = rr
                    qc[tail] = cc
                    tail += 1
    return tail == n  # cells left over form components of their own
