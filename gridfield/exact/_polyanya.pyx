# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Compiled Polyanya search behind :mod:`gridfield.exact.anyangle` (``search="polyanya"``; private).

Polyanya (Cui, Harabor & Grastien, "Compromise-free Pathfinding on a Navigation Mesh", IJCAI 2017)
finds the Euclidean shortest path over a mesh of convex polygons without a visibility graph. Written
here from the paper's description, in *lattice units* (cell ``(r, c)`` is ``[c, c + 1] x [r, r + 1]``).

The mesh (built by :func:`gridfield.exact.anyangle.navigation_mesh`) is a CSR of polygons: polygon ``p``
owns the slots ``pstart[p] .. pstart[p + 1] - 1``, its vertices in counter-clockwise order (collinear
ones kept: every point where the neighbour across the boundary changes is a vertex); slot ``k`` (one
32-byte record, so that a polygon is one run of memory) holds the vertex ``(x, y)``, its ``root``
number (-1 unless it is a *turning point*, a lattice point with exactly one of the four cells round
it blocked: the only points a taut path bends at), and the edge from it to the next slot's vertex,
whose neighbour across is ``nb`` (-1: an obstacle or the map's outside) where that edge is the
neighbour's slot ``nbslot`` (local index).

A search node is a root (the start or a turning vertex, reached with cost ``g``) and an *interval*
``[A, B]`` on an edge of the polygon it enters, every point of which the root sees; ``A`` lies on the
side of the edge's first vertex in that polygon, ``B`` on the side of its second. Expanding it
projects the interval through the polygon (rays root -> A and root -> B): the edges (or parts of
them) between the two rays are *observable* successors (same root), those outside the rays on the
side of an endpoint that is a polygon vertex and a turning point are *non-observable* successors
(rooted at that endpoint). A root on the interval's line (within ``EPS_D``) either lies on the
interval (then it sees the whole polygon) or beyond it (then only the nearer endpoint can be turned
round). ``f = g + h`` with ``h`` the exact distance from the root through the interval to the goal
(the goal mirrored across the interval's line when it lies on the root's side). Root-level pruning: a
node is dropped when its root vertex was reached with a smaller ``g`` (by more than ``EPS_G``; equal
``g`` must be kept: the same root reached through two polygons turns into different regions). No node
enters a dead end (a polygon with one neighbour) unless the goal is in it, and a node whose expansion
makes a single node with the same root is followed at once, past the heap (the paper's intermediate
pruning). The goal's polygons end the search: expanding one pushes a final node (root and goal in
sight, or turning at an interval endpoint), and the first final node popped is the optimum.

Everything runs without the GIL, on C buffers grown by doubling (nodes, the binary heap of their
``f``); the best ``g`` per root number lives in the caller's arrays, valid where ``stamp`` equals the
query's ``sid`` (no clearing per query; the caller serialises queries on one pair of arrays).
"""

from libc.math cimport INFINITY, sqrt, fabs
from libc.stdint cimport int32_t, int64_t, uint8_t
from libc.stdlib cimport free, malloc, realloc

from gridfield.exact._astar cimport Heap, _heap_pop, _heap_push

import numpy as np

__all__ = ["polyanya"]

cdef double EPS = 1e-8       # cross products (lattice units squared) treated as zero
cdef double EPS_D = 2e-8     # a root this close to an interval's line (lattice units) lies on it (>= EPS / 1)
cdef double EPS_G = 1e-9     # root-level pruning: a root's g may exceed its best by this much
cdef double EPS_LEN2 = 1e-18 # squared interval length below which an interval is dropped


cdef struct Node:
    double rx, ry, ax, ay, bx, by, g, f
    int32_t root, poly, edge, parent


cdef struct Slot:
    double x, y
    int32_t root, nb, nbslot, pad


cdef struct Mesh:
    const int64_t* pstart
    const Slot* sl
    const int32_t* degree
    double* best
    int32_t* stamp
    int32_t sid
    double tx, ty
    int32_t gp[4]
    int ngp


cdef struct Search:
    Node* nodes
    int64_t n, cap
    Heap heap  # the open list (the binary heap of _astar): f -> node index
    bint oom


cdef struct Chain:  # scratch of one expansion: the polygon's vertices from V[e + 1] round to V[e]
    double* x
    double* y
    double* sa
    double* sb
    int64_t* slot


cdef inline double _cross(double ax, double ay, double bx, double by) noexcept nogil:
    return ax * by - ay * bx


cdef inline double _dist(double ax, double ay, double bx, double by) noexcept nogil:
    return sqrt((ax - bx) * (ax - bx) + (ay - by) * (ay - by))


cdef inline int _on_line(double rx, double ry, double ax, double ay, double bx, double by, double cr) noexcept nogil:
    """Where a root whose cross product with the interval [A, B] is ``cr`` lies: 2 off the interval's
    line (farther than ``EPS_D``), 0 on the interval, -1 on the line beyond A, 1 beyond B."""
    cdef double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy, dot, tol
    if cr * cr > EPS_D * EPS_D * l2:
        return 2
    dot = (rx - ax) * dx + (ry - ay) * dy
    tol = EPS_D * sqrt(l2)
    if dot < -tol:
        return -1
    if dot > l2 + tol:
        return 1
    return 0


cdef double _h(double rx, double ry, double ax, double ay, double bx, double by, double tx, double ty) noexcept nogil:
    """Shortest distance from the root through the interval [A, B] to the goal (a lower bound)."""
    cdef double dx = bx - ax, dy = by - ay
    cdef double cr = _cross(dx, dy, rx - ax, ry - ay)
    cdef double ct = _cross(dx, dy, tx - ax, ty - ay)
    cdef double l2 = dx * dx + dy * dy, k, oa, ob
    cdef int where = _on_line(rx, ry, ax, ay, bx, by, cr)
    if where == 0:  # the root on the interval
        return _dist(rx, ry, tx, ty)
    if where == -1:  # on its line, beyond an end: through that end
        return _dist(rx, ry, ax, ay) + _dist(ax, ay, tx, ty)
    if where == 1:
        return _dist(rx, ry, bx, by) + _dist(bx, by, tx, ty)
    if (cr > 0) == (ct > 0) and ct != 0.0:  # the goal on the root's side: mirror it
        k = 2.0 * ct / l2
        tx = tx + k * dy
        ty = ty - k * dx
    oa = _cross(tx - rx, ty - ry, ax - rx, ay - ry)
    ob = _cross(tx - rx, ty - ry, bx - rx, by - ry)
    if (oa <= 0.0 and ob >= 0.0) or (oa >= 0.0 and ob <= 0.0):
        return _dist(rx, ry, tx, ty)
    # the segment root -> goal crosses the interval's line beyond one end: |r p| + |p t| is convex
    # along the line, least at the crossing, so over the interval at the end nearer the crossing
    if fabs(oa) < fabs(ob):
        return _dist(rx, ry, ax, ay) + _dist(ax, ay, tx, ty)
    return _dist(rx, ry, bx, by) + _dist(bx, by, tx, ty)


cdef inline bint _is_goal_poly(Mesh* M, int32_t p) noexcept nogil:
    cdef int i
    for i in range(M.ngp):
        if M.gp[i] == p:
            return True
    return False


cdef void _push(Search* S, Mesh* M, int32_t parent, double rx, double ry, int32_t root, double g,
                double ax, double ay, double bx, double by, int32_t poly, int32_t edge) noexcept nogil:
    """Add a node to the pool (``poly < 0``: a final node, the goal in sight of its root), with its f;
    the caller puts it on the heap. Root-level pruning, and no node into a dead end (a polygon whose
    one neighbour is the one the node comes from) but the goal's."""
    cdef Node* nd
    cdef Node* nn
    if S.oom:
        return
    if poly >= 0:
        if (ax - bx) * (ax - bx) + (ay - by) * (ay - by) < EPS_LEN2:
            return
        if M.degree[poly] <= 1 and not _is_goal_poly(M, poly):
            return
        if root >= 0:
            if M.stamp[root] == M.sid:
                if g > M.best[root] + EPS_G:
                    return
                if g < M.best[root]:
                    M.best[root] = g
            else:
                M.stamp[root] = M.sid
                M.best[root] = g
    if S.n == S.cap:
        nn = <Node*> realloc(S.nodes, 2 * S.cap * sizeof(Node))
        if nn == NULL:
            S.oom = True
            return
        S.nodes = nn
        S.cap *= 2
    nd = &S.nodes[S.n]
    nd.rx = rx
    nd.ry = ry
    nd.ax = ax
    nd.ay = ay
    nd.bx = bx
    nd.by = by
    nd.g = g
    nd.root = root
    nd.poly = poly
    nd.edge = edge
    nd.parent = parent
    if poly < 0:
        nd.f = g + _dist(rx, ry, M.tx, M.ty)
    else:
        nd.f = g + _h(rx, ry, ax, ay, bx, by, M.tx, M.ty)
    S.n += 1


cdef inline void _push_edge(Search* S, Mesh* M, int32_t parent, double rx, double ry, int32_t root, double g,
                            int64_t slot, double xx, double xy, double yx, double yy) noexcept nogil:
    """Successor across the edge of (global) ``slot`` from X (its first vertex's side) to Y."""
    cdef int32_t q = M.sl[slot].nb
    if q < 0:
        return
    # in the neighbour the edge runs the other way: A (its first vertex's side) is Y
    _push(S, M, parent, rx, ry, root, g, yx, yy, xx, xy, q, M.sl[slot].nbslot)


cdef void _expand(Search* S, Mesh* M, int32_t cur, Chain* C) noexcept nogil:
    cdef Node nd = S.nodes[cur]
    cdef int32_t P = nd.poly, root = nd.root, nroot
    cdef int64_t base = M.pstart[P], n = M.pstart[P + 1] - M.pstart[P], m, s, kA, kB, eA, eB
    cdef double rx = nd.rx, ry = nd.ry, ax = nd.ax, ay = nd.ay, bx = nd.bx, by = nd.by, g = nd.g
    cdef double cr, px, py, qx, qy, xbx, xby, xax, xay, t, g2, nx, ny, sta, stb
    cdef double* cx = C.x
    cdef double* cy = C.y
    cdef double* sa = C.sa
    cdef double* sb = C.sb
    cdef int64_t* cs = C.slot
    cdef bint goal = _is_goal_poly(M, P), bvert, avert
    # the chain c_0 = V[e + 1], ..., c_{n-1} = V[e]; chain edge m runs from c_m to c_{m+1}
    s = nd.edge + 1
    for m in range(n):
        if s == n:
            s = 0
        cs[m] = base + s
        cx[m] = M.sl[base + s].x
        cy[m] = M.sl[base + s].y
        s += 1
    cr = _cross(bx - ax, by - ay, rx - ax, ry - ay)
    where = _on_line(rx, ry, ax, ay, bx, by, cr)
    if where != 2:
        if where == 0:
            # the root on the interval, so on this convex polygon's boundary: it sees all of it
            for m in range(n - 1):
                _push_edge(S, M, cur, rx, ry, root, g, cs[m], cx[m], cy[m], cx[m + 1], cy[m + 1])
            if goal:
                _push(S, M, cur, rx, ry, root, g, 0, 0, 0, 0, -1, -1)
            return
        # the root beyond the interval on its line: only its nearer endpoint can be turned round
        if where < 0:
            nx, ny, m = ax, ay, n - 1
        else:
            nx, ny, m = bx, by, 0
        if nx != cx[m] or ny != cy[m] or not M.sl[cs[m]].root >= 0:
            return
        nroot = M.sl[cs[m]].root
        g2 = g + _dist(rx, ry, nx, ny)
        for m in range(n - 1):
            _push_edge(S, M, cur, nx, ny, nroot, g2, cs[m], cx[m], cy[m], cx[m + 1], cy[m + 1])
        if goal:
            _push(S, M, cur, nx, ny, nroot, g2, 0, 0, 0, 0, -1, -1)
        return
    if cr > 0:
        return  # the root on the polygon's side of the entry edge: cannot happen (defensive)
    # sides of the rays root -> B (sb >= 0: left of it) and root -> A (sa <= 0: right of it)
    kB = -1
    kA = -1
    for m in range(n):
        px = cx[m] - rx
        py = cy[m] - ry
        sb[m] = _cross(bx - rx, by - ry, px, py)
        sa[m] = _cross(ax - rx, ay - ry, px, py)
        if sb[m] < -EPS:
            kB = m
        if kA < 0 and sa[m] > EPS:
            kA = m
    # where the ray through B leaves the polygon: on chain edge eB at XB
    if kB < 0:
        eB = 0
        xbx = cx[0]
        xby = cy[0]
    elif kB >= n - 1:
        eB = n  # (defensive) nothing observable
        xbx = xby = 0.0
    else:
        eB = kB
        if fabs(sb[kB + 1]) <= EPS:
            xbx = cx[kB + 1]
            xby = cy[kB + 1]
        else:
            t = sb[kB] / (sb[kB] - sb[kB + 1])
            xbx = cx[kB] + (cx[kB + 1] - cx[kB]) * t
            xby = cy[kB] + (cy[kB + 1] - cy[kB]) * t
    # where the ray through A leaves it: on chain edge eA at XA
    if kA < 0:
        eA = n - 2
        xax = cx[n - 1]
        xay = cy[n - 1]
    elif kA == 0:
        eA = -1  # (defensive) nothing observable
        xax = xay = 0.0
    else:
        eA = kA - 1
        if fabs(sa[kA - 1]) <= EPS:
            xax = cx[kA - 1]
            xay = cy[kA - 1]
        else:
            t = sa[kA - 1] / (sa[kA - 1] - sa[kA])
            xax = cx[kA - 1] + (cx[kA] - cx[kA - 1]) * t
            xay = cy[kA - 1] + (cy[kA] - cy[kA - 1]) * t
    # observable successors: chain edges eB .. eA, from XB to XA, same root
    if eB < eA or (eB == eA and eB < n - 1 and
                   (xax - xbx) * (cx[eB + 1] - cx[eB]) + (xay - xby) * (cy[eB + 1] - cy[eB]) > 0):
        for m in range(eB, eA + 1):
            if m == eB:
                px, py = xbx, xby
            else:
                px, py = cx[m], cy[m]
            if m == eA:
                qx, qy = xax, xay
            else:
                qx, qy = cx[m + 1], cy[m + 1]
            _push_edge(S, M, cur, rx, ry, root, g, cs[m], px, py, qx, qy)
    # non-observable successors round B (= c_0, a turning point): chain edges 0 .. eB, up to XB
    bvert = eB < n and bx == cx[0] and by == cy[0] and M.sl[cs[0]].root >= 0
    if bvert:
        nroot = M.sl[cs[0]].root
        g2 = g + _dist(rx, ry, bx, by)
        for m in range(0, eB + 1):
            if m == eB:
                qx, qy = xbx, xby
            else:
                qx, qy = cx[m + 1], cy[m + 1]
            _push_edge(S, M, cur, bx, by, nroot, g2, cs[m], cx[m], cy[m], qx, qy)
    # and round A (= c_{n-1}): chain edges eA .. n - 2, from XA
    avert = eA >= 0 and ax == cx[n - 1] and ay == cy[n - 1] and M.sl[cs[n - 1]].root >= 0
    if avert:
        nroot = M.sl[cs[n - 1]].root
        g2 = g + _dist(rx, ry, ax, ay)
        for m in range(eA, n - 1):
            if m == eA:
                px, py = xax, xay
            else:
                px, py = cx[m], cy[m]
            _push_edge(S, M, cur, ax, ay, nroot, g2, cs[m], px, py, cx[m + 1], cy[m + 1])
    if goal:
        stb = _cross(bx - rx, by - ry, M.tx - rx, M.ty - ry)
        sta = _cross(ax - rx, ay - ry, M.tx - rx, M.ty - ry)
        if stb >= -EPS and sta <= EPS:
            _push(S, M, cur, rx, ry, root, g, 0, 0, 0, 0, -1, -1)
        else:
            if stb < -EPS and bvert:
                _push(S, M, cur, bx, by, M.sl[cs[0]].root, g + _dist(rx, ry, bx, by), 0, 0, 0, 0, -1, -1)
            if sta > EPS and avert:
                _push(S, M, cur, ax, ay, M.sl[cs[n - 1]].root, g + _dist(rx, ry, ax, ay), 0, 0, 0, 0, -1, -1)


def polyanya(const int64_t[::1] pstart, const uint8_t[::1] slots, const int32_t[::1] degree,
             double[::1] best, int32_t[::1] stamp, int32_t sid, int64_t maxn, double sx, double sy,
             const int64_t[::1] spolys, double tx, double ty, const int64_t[::1] tpolys):
    """Polyanya from ``(sx, sy)`` (in the polygons ``spolys``) to ``(tx, ty)`` (in ``tpolys``), lattice units.

    ``slots`` holds the raw bytes of the mesh's slot records (``x, y`` float64, ``root, nb, nbslot`` and
    a pad int32: 32 bytes each, :data:`gridfield.exact.anyangle.SLOT_DTYPE`); ``degree[p]`` is the number of
    edges of polygon ``p`` with a polygon across (1: a dead end). Returns ``(length, xs, ys,
    expanded, generated)``: the optimum (``inf`` when the goal cannot be reached), the lattice
    coordinates of the path's turning points (start and goal excluded), the nodes expanded and
    generated. ``best`` and ``stamp`` (one entry per root number) are the
    caller's workspace; ``sid`` must differ from every value already in ``stamp``.
    """
    cdef Mesh M
    cdef Search S
    cdef Chain C
    cdef int64_t i, k, base, n, cur, before, expanded = 0
    cdef int32_t p
    cdef double length = INFINITY, px, py, qx, qy
    cdef Node* nd
    cdef bint found = False
    M.pstart = &pstart[0]
    if slots.shape[0] % sizeof(Slot) != 0 or sizeof(Slot) != 32:
        raise ValueError(f"polyanya: slots must be whole 32-byte records, got {slots.shape[0]} bytes")
    M.sl = <const Slot*> &slots[0]
    M.degree = &degree[0]
    M.best = &best[0]
    M.stamp = &stamp[0]
    M.sid = sid
    M.tx = tx
    M.ty = ty
    M.ngp = <int> min(tpolys.shape[0], 4)
    for i in range(M.ngp):
        M.gp[i] = <int32_t> tpolys[i]
    S.cap = 1024
    S.heap.cap = 1024
    S.heap.size = 0
    S.n = 0
    S.oom = False
    S.nodes = <Node*> malloc(S.cap * sizeof(Node))
    S.heap.k = <double*> malloc(S.heap.cap * sizeof(double))
    S.heap.v = <int64_t*> malloc(S.heap.cap * sizeof(int64_t))
    C.x = <double*> malloc(4 * (maxn + 1) * sizeof(double))
    C.slot = <int64_t*> malloc((maxn + 1) * sizeof(int64_t))
    if S.nodes == NULL or S.heap.k == NULL or S.heap.v == NULL or C.x == NULL or C.slot == NULL:
        free(S.nodes); free(S.heap.k); free(S.heap.v); free(C.x); free(C.slot)
        raise MemoryError("polyanya: out of memory")
    C.y = C.x + (maxn + 1)
    C.sa = C.y + (maxn + 1)
    C.sb = C.sa + (maxn + 1)
    with nogil:
        # seeds: every edge of every polygon holding the start, but those the start lies on
        for i in range(spolys.shape[0]):
            p = <int32_t> spolys[i]
            base = pstart[p]
            n = pstart[p + 1] - base
            for k in range(n):
                px = M.sl[base + k].x
                py = M.sl[base + k].y
                qx = M.sl[base + (k + 1) % n].x
                qy = M.sl[base + (k + 1) % n].y
                if (_cross(qx - px, qy - py, sx - px, sy - py) == 0.0
                        and (sx - px) * (sx - qx) + (sy - py) * (sy - qy) <= 0.0):
                    continue
                _push_edge(&S, &M, -1, sx, sy, -1, 0.0, base + k, px, py, qx, qy)
            if _is_goal_poly(&M, p):
                _push(&S, &M, -1, sx, sy, -1, 0.0, 0, 0, 0, 0, -1, -1)
        for i in range(S.n):
            if not _heap_push(&S.heap, S.nodes[i].f, i):
                S.oom = True
        while S.heap.size > 0 and not S.oom:
            cur = S.heap.v[0]
            _heap_pop(&S.heap)
            nd = &S.nodes[cur]
            if nd.poly < 0:
                found = True
                length = nd.f
                break
            if nd.root >= 0 and nd.g > M.best[nd.root] + EPS_G:
                continue  # its root was reached more cheaply since
            while True:
                expanded += 1
                before = S.n
                _expand(&S, &M, <int32_t> cur, &C)
                # intermediate pruning: a lone successor with the same root is expanded at once
                if (S.n == before + 1 and S.nodes[before].poly >= 0 and S.nodes[before].root == S.nodes[cur].root
                        and not S.oom):
                    cur = before
                    continue
                for i in range(before, S.n):
                    if not _heap_push(&S.heap, S.nodes[i].f, i):
                        S.oom = True
                break
    xs = []
    ys = []
    try:
        if S.oom:
            raise MemoryError("polyanya: out of memory")
        if found:
            i = cur
            last = -1
            while i >= 0:
                if S.nodes[i].root >= 0 and S.nodes[i].root != last:
                    last = S.nodes[i].root
                    xs.append(S.nodes[i].rx)
                    ys.append(S.nodes[i].ry)
                i = S.nodes[i].parent
            xs.reverse()
            ys.reverse()
        generated = S.n
    finally:
        free(S.nodes); free(S.heap.k); free(S.heap.v); free(C.x); free(C.slot)
    return length, np.array(xs, dtype=np.float64), np.array(ys, dtype=np.float64), expanded, generated
