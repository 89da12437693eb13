"""Star-shaped obstacles: the smooth (R-function) obstacle function of a star polygon or a disc.

One obstacle of a star world (:mod:`gridfield.fields.navigation`; the world, its scaled obstacle functions and the
star-to-sphere transformation are in ``_star_world``, the planner in ``_star_nav``): the obstacle
function ``beta_i`` (all of it vectorized over query points ``q``, shape ``(N, 2)``), the exact gauge,
and the polygon's centre (:func:`find_star_center`):

- obstacle ``i``, a disc: ``beta_i(q) = |q - q_i|**2 / r**2 - 1``;
- obstacle ``i``, a polygon: ``beta_i`` is a C^2 function of the plane, exactly 0 on the boundary,
  negative inside, positive outside, built from R-functions (V. L. Rvachev's; V. Shapiro, "Semi-analytic
  geometry with R-functions", Acta Numerica 16, 2007). With outward unit normals ``n_k`` and
  ``c_k = n_k . (v_k - q_i) > 0``, the edge functions ``x_k(q) = n_k . (q - q_i) / c_k - 1`` are linear,
  0 on edge ``k``'s line and equal to the exact gauge minus 1 inside the cone from ``q_i`` over edge ``k``.
  At vertex ``k`` (edges ``k - 1`` and ``k``) the local function is the R-disjunction of ``x_{k-1}``
  and ``x_k`` if the vertex is convex (outside = outside either half-plane) and the R-conjunction if it
  is reflex (outside = outside both); on the two cones next to the vertex it has the sign of the exact
  gauge minus 1 (the line through ``q_i`` and ``v_k`` separates the two cones and is where ``x_{k-1} =
  x_k``), so it is a valid local description there. The R-functions are Rvachev's ``R_alpha`` system
  (``alpha`` = :data:`R_ALPHA`, close to max / min far from the vertex) times
  ``r**2 / (r**2 + eps**2)`` (``r**2 = x**2 + y**2``), the ``R_m`` construction with ``m = 2``: C^2 at
  the vertex as well (``m = 2`` because the Rimon-Koditschek function must be C^2 to be Morse), and
  degree 1 (distance-like) away from it, which a nested or higher ``m`` formula is not. Inside each
  cone the two vertex functions are glued with a C^2 smoothstep of the angle, which is 0 / 1 with
  vanishing first and second derivatives on the vertex rays, so the result ``B`` is C^2 across them;
  ``G = 1 + B`` is a smoothed gauge and ``beta_i = G**2 - 1`` (as for a disc; ``-1 + G**2 / (1 + G**4)``
  where ``G < 0``, deep inside, to keep the sign), blended to the disc function
  ``|q - q_i|**2 / r_i**2 - 1`` within ``r_i / 2`` of the centre (where the angle is undefined).
  A global R-function formula over a decomposition was not used: the union of the fan's triangles (or
  of any pieces sharing an edge) is 0 on the shared edges inside the polygon, and nesting ``R_m``
  raises its degree at every level until it underflows. Any C^1 function whose zero set has a corner
  has a vanishing gradient there, so ``grad beta_i = 0`` at the vertices (on the boundary, never in the
  free space). The analytic gradient is checked against finite differences in the tests, and sign and
  zero set against shapely. The exact gauge ``g_i`` (Minkowski functional about ``q_i``, piecewise
  linear) still decides which points are free (:meth:`StarObstacle.gauge`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import ParameterError


# ----------------------------------------------------------------------------------------------
# One star obstacle
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class StarObstacle:
    """One star-shaped obstacle and its model disc.

    Attributes
    ----------
    id : int
        The world obstacle's id.
    kind : {"polygon", "circle"}
    center : ndarray (2,)
        ``q_i``, the point the obstacle is star-shaped about.
    model_radius : float
        ``r_i``; the model disc's centre ``p_i`` is ``center``.
    vertices : ndarray (n, 2) or None
        Counter-clockwise polygon vertices.
    normals, offsets : ndarray (n, 2), (n,)
        Outward unit normal ``n_k`` of edge ``k`` (``v_k -> v_{k+1}``) and ``c_k = n_k . (v_k - q_i) > 0``.
    angles : ndarray (n + 1,)
        Increasing angles of the vertices about the centre, the last one the first plus ``2 pi``.
    radius : float
        The disc's radius (NaN for polygons).
    scale : float
        The switches use ``beta_i / scale``, ``scale`` an upper bound of ``beta_i`` over the workspace
        (sampled, :func:`star_world`), so that ``beta_i / scale`` lies in about ``[0, 1]`` on the free space.
    convex : ndarray (n,) of bool or None
        Whether vertex ``k`` (between edges ``k - 1`` and ``k``) is convex (else reflex).

    Examples
    --------
    >>> from gridfield.fields.navigation import star_world
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> ob = star_world(w, (8, 2)).obstacles[0]
    >>> ob.kind, ob.center.tolist(), ob.model_radius, ob.convex.tolist()
    ('polygon', [4.0, 4.0], 1.0, [True, True, True, True])
    >>> b, _ = ob.beta(np.array([[4.0, 4.0], [5.0, 4.0], [6.0, 4.0]]))  # centre, edge midpoint, outside
    >>> b.round(3).tolist()  # the exact gauge's g**2 - 1 would be [-1, 0, 3]
    [-1.0, 0.0, 3.084]
    """

    id: int
    kind: str
    center: NDArray[np.float64]
    model_radius: float
    vertices: NDArray[np.float64] | None = None
    normals: NDArray[np.float64] | None = None
    offsets: NDArray[np.float64] | None = None
    angles: NDArray[np.float64] | None = None
    radius: float = math.nan
    scale: float = 1.0
    convex: NDArray[np.bool_] | None = None

    def beta(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The obstacle function ``beta_i`` (unscaled; 0 on the boundary, negative inside, positive
        outside, C^2) and its analytic gradient ``(N, 2)`` at points ``(N, 2)``.

        A disc: ``|q - q_i|**2 / r**2 - 1``. A polygon: the construction of the module docstring
        (vertex R-functions glued by an angular partition of unity, a disc function at the centre).

        Parameters
        ----------
        q : ndarray (N, 2)
            Query points.

        Returns
        -------
        beta : ndarray (N,)
        grad : ndarray (N, 2)

        Examples
        --------
        >>> ob = StarObstacle(1, "circle", np.array([0.0, 0.0]), 2.0, radius=2.0)
        >>> b, g = ob.beta(np.array([[2.0, 0.0], [4.0, 0.0]]))
        >>> b.tolist(), g.tolist()
        ([0.0, 3.0], [[1.0, 0.0], [2.0, 0.0]])
        """
        d = q - self.center
        if self.kind == "circle":
            r2 = self.radius**2
            return np.einsum("ij,ij->i", d, d) / r2 - 1.0, 2.0 * d / r2
        return _polygon_beta(self, d)

    def gauge(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The exact gauge ``g(q)`` (``< 1`` inside, 1 on the boundary; piecewise linear for polygons, its
        gradient one-sided on the vertex rays) and its gradient ``(N, 2)`` at points ``(N, 2)``; it decides
        :meth:`StarWorld.free`.

        Parameters
        ----------
        q : ndarray (N, 2)
            Query points.

        Returns
        -------
        g : ndarray (N,)
        grad : ndarray (N, 2)

        Examples
        --------
        >>> ob = StarObstacle(1, "circle", np.array([0.0, 0.0]), 2.0, radius=2.0)
        >>> ob.gauge(np.array([[1.0, 0.0]]))[0].tolist()
        [0.5]
        """
        d = q - self.center
        if self.kind == "circle":
            r = self.radius
            dist = np.hypot(d[:, 0], d[:, 1])
            with np.errstate(invalid="ignore", divide="ignore"):
                grad = np.where(dist[:, None] > 0, d / (r * dist[:, None]), 0.0)
            return dist / r, grad
        assert self.normals is not None and self.offsets is not None and self.angles is not None
        a0 = self.angles[0]
        t = a0 + np.mod(np.arctan2(d[:, 1], d[:, 0]) - a0, 2 * math.pi)
        k = np.clip(np.searchsorted(self.angles, t, side="right") - 1, 0, len(self.offsets) - 1)
        grad = self.normals[k] / self.offsets[k][:, None]
        return np.einsum("ij,ij->i", d, grad), grad

    def boundary_distance(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Exact Euclidean distance from points ``(N, 2)`` to the obstacle's boundary.

        Parameters
        ----------
        q : ndarray (N, 2)
            Query points.

        Returns
        -------
        ndarray (N,)

        Examples
        --------
        >>> ob = StarObstacle(1, "circle", np.array([0.0, 0.0]), 2.0, radius=2.0)
        >>> ob.boundary_distance(np.array([[5.0, 0.0], [0.5, 0.0]])).tolist()
        [3.0, 1.5]
        """
        if self.kind == "circle":
            centre_distance: NDArray[np.float64] = np.hypot(*(q - self.center).T)
            return np.abs(centre_distance - self.radius)
        assert self.vertices is not None
        a = self.vertices
        e = np.roll(a, -1, axis=0) - a
        rel = q[:, None, :] - a[None, :, :]
        t = np.clip(np.einsum("nkj,kj->nk", rel, e) / np.einsum("kj,kj->k", e, e), 0.0, 1.0)
        diff = rel - t[..., None] * e[None]
        nearest_squared: NDArray[np.float64] = np.min(np.einsum("nkj,nkj->nk", diff, diff), axis=1)
        return np.sqrt(nearest_squared)


#: the R-functions' regularization: ``x ^ y = R_0(x, y) (x**2 + y**2) / (x**2 + y**2 + eps**2)`` with
#: ``eps = R_EPS * sin(turn)`` at a vertex turning by ``turn`` (the arguments are gauges minus 1, so the
#: rounded zone is about ``R_EPS`` times the centre-to-edge distance along each edge)
R_EPS = 0.1
#: the R_alpha system's alpha (0: Rvachev's R_0; towards 1: closer to max / min; 0.9 folds h_lambda least
#: of 0, 0.5, 0.9, 0.97 on the worlds of benchmarks/star_nav.py)
R_ALPHA = 0.9


def _r_function(x: NDArray[np.float64], y: NDArray[np.float64], disjunction: NDArray[np.bool_],
                eps: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """C^2 R-disjunction (``disjunction``) or R-conjunction of ``x, y`` and its partial derivatives.

    Rvachev's ``R_alpha`` system, ``(x + y +- sqrt(x**2 + y**2 - 2 alpha x y)) / (1 + alpha)`` (positive iff
    ``x > 0`` or / and ``y > 0``; ``alpha -> 1`` tends to max / min), analytic off the origin, times
    ``w = r**2 / (r**2 + eps**2)``: ``R_alpha r**2`` is homogeneous of degree 3 and smooth off the origin,
    hence C^2 (the ``R_m`` construction, ``m = 2``); dividing it by ``r**2 + eps**2`` keeps the sign rule
    and the order and leaves ``R_alpha`` (degree 1: distance-like) away from the origin. ``eps`` (per
    point) is the rounding radius in the ``(x, y)`` plane.
    """
    a = R_ALPHA
    r2 = x * x + y * y
    q2 = np.maximum(r2 - 2.0 * a * x * y, 0.0)
    q = np.sqrt(q2)
    sgn = np.where(disjunction, 1.0, -1.0)
    e2 = eps * eps
    w = r2 / (r2 + e2)
    r0 = (x + y + sgn * q) / (1.0 + a)
    dw = 2.0 * e2 / (r2 + e2) ** 2  # dw/dx = dw * x
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(q > 0, (x - a * y) / q, 0.0)
        uy = np.where(q > 0, (y - a * x) / q, 0.0)
    fx = (1.0 + sgn * ux) / (1.0 + a) * w + r0 * dw * x
    fy = (1.0 + sgn * uy) / (1.0 + a) * w + r0 * dw * y
    return r0 * w, fx, fy


def _smoothstep(s: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``S(s) = 6 s**5 - 15 s**4 + 10 s**3`` on [0, 1] (clipped) and ``S'``: 0 and 1 at the ends with
    vanishing first and second derivatives there (so gluing with it is C^2)."""
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10.0 + s * (6.0 * s - 15.0)), 30.0 * s * s * (s - 1.0) ** 2


def _polygon_beta(ob: StarObstacle, d: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``beta`` and its gradient for a star polygon at ``d = q - q_i`` (see the module docstring)."""
    assert ob.normals is not None and ob.offsets is not None and ob.angles is not None and ob.convex is not None
    nv = len(ob.offsets)
    t2 = np.einsum("ij,ij->i", d, d)
    t = np.sqrt(t2)
    a0 = ob.angles[0]
    th = a0 + np.mod(np.arctan2(d[:, 1], d[:, 0]) - a0, 2 * math.pi)
    k = np.clip(np.searchsorted(ob.angles, th, side="right") - 1, 0, nv - 1)  # cone of edge k: vertices k, k+1
    km, kp = (k - 1) % nv, (k + 1) % nv
    gn = ob.normals / ob.offsets[:, None]  # grad g_j = n_j / c_j

    def edge(j: NDArray[np.intp]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return np.einsum("ij,ij->i", d, gn[j]) - 1.0, gn[j]

    xm, gm = edge(km)
    x0, g0 = edge(k)
    xp, gp = edge(kp)
    # vertex k joins edges k-1 and k; vertex k+1 joins edges k and k+1 (disjunction where convex)
    turn = np.abs(ob.normals[:, 0] * np.roll(ob.normals, 1, axis=0)[:, 1]
                  - ob.normals[:, 1] * np.roll(ob.normals, 1, axis=0)[:, 0])  # sin of the turn at vertex k
    eps = R_EPS * np.maximum(turn, 1e-3)
    fa, fax, fay = _r_function(xm, x0, ob.convex[k], eps[k])
    fb, fbx, fby = _r_function(x0, xp, ob.convex[kp], eps[kp])
    grad_a = fax[:, None] * gm + fay[:, None] * g0
    grad_b = fbx[:, None] * g0 + fby[:, None] * gp
    width = ob.angles[k + 1] - ob.angles[k]
    sg, dsg = _smoothstep((th - ob.angles[k]) / width)
    with np.errstate(invalid="ignore", divide="ignore"):
        dth = np.where(t2[:, None] > 0, np.column_stack([-d[:, 1], d[:, 0]]) / t2[:, None], 0.0)
        dt = np.where(t[:, None] > 0, d / t[:, None], 0.0)
    big = (1.0 - sg) * fa + sg * fb
    grad_big = ((1.0 - sg)[:, None] * grad_a + sg[:, None] * grad_b
                + ((fb - fa) * dsg / width)[:, None] * dth)
    # near the centre (where the angle is undefined) blend to the disc function t**2 / r**2 - 1
    r = ob.model_radius
    chi, dchi = _smoothstep((t - 0.25 * r) / (0.25 * r))
    # the smoothed gauge G = 1 + B (B: the glued R-functions, about g - 1 near the boundary), squared as
    # a disc's beta is: beta = G**2 - 1 for G >= 0, and -1 + G**2 / (1 + G**4) below (still negative; C^2 at 0)
    gg = 1.0 + big
    pos = gg >= 0
    g4 = 1.0 + gg**4
    outer = np.where(pos, gg * gg - 1.0, gg * gg / g4 - 1.0)
    douter = np.where(pos, 2.0 * gg, 2.0 * gg * (1.0 - gg**4) / (g4 * g4))
    core = t2 / r**2 - 1.0
    chi, dchi = _smoothstep((t - 0.25 * r) / (0.25 * r))
    beta = chi * outer + (1.0 - chi) * core
    grad = (chi[:, None] * douter[:, None] * grad_big + (1.0 - chi)[:, None] * (2.0 * d / r**2)
            + ((outer - core) * dchi / (0.25 * r))[:, None] * dt)
    return beta, grad


# ----------------------------------------------------------------------------------------------
# the polygon's centre and edges
# ----------------------------------------------------------------------------------------------
def find_star_center(vertices: ArrayLike) -> tuple[NDArray[np.float64], float]:
    """The point deepest inside the kernel of a polygon, and its distance to the nearest edge line.

    The kernel (the points the polygon is star-shaped about) is the intersection of the inner
    half-planes of all edges; its Chebyshev centre maximizes the smallest distance to the edges'
    lines (a linear programme, solved with :func:`scipy.optimize.linprog`). A depth ``<= 0`` means the
    kernel has no interior: the polygon is not star-shaped about any point strictly.

    Parameters
    ----------
    vertices : array_like (n, 2)
        The polygon's vertices in order (either orientation).

    Returns
    -------
    center : ndarray (2,)
        The kernel's Chebyshev centre (the vertices' mean when the programme fails).
    depth : float
        Its distance to the nearest edge line (``-inf`` when the programme fails).

    Examples
    --------
    >>> c, depth = find_star_center([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]])  # an L
    >>> bool(0 < c[0] < 1 and 0 < c[1] < 1), round(depth, 6)
    (True, 0.5)
    """
    from scipy.optimize import linprog

    v = _ccw(np.asarray(vertices, dtype=float))
    n, off = _edge_lines(v)
    # maximize t subject to n_k . x + t <= n_k . v_k
    a = np.column_stack([n, np.ones(len(n))])
    span = float(np.ptp(v, axis=0).max())
    res = linprog([0.0, 0.0, -1.0], A_ub=a, b_ub=off, bounds=[(None, None), (None, None), (None, span)],
                  method="highs")
    if res.status != 0:
        return v.mean(axis=0), -math.inf
    return np.asarray(res.x[:2], dtype=float), float(res.x[2])


def _ccw(v: NDArray[np.float64]) -> NDArray[np.float64]:
    x, y = v[:, 0], v[:, 1]
    area2 = float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return v if area2 > 0 else v[::-1].copy()


def _edge_lines(v: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Outward unit normals and offsets ``n_k . v_k`` of the edges of a counter-clockwise polygon."""
    e = np.roll(v, -1, axis=0) - v
    n = np.column_stack([e[:, 1], -e[:, 0]]) / np.hypot(e[:, 0], e[:, 1])[:, None]
    return n, np.einsum("ij,ij->i", n, v)


def _star_polygon(oid: int, vertices: NDArray[np.float64], center: tuple[float, float] | None) -> StarObstacle:
    v = _ccw(vertices)
    # drop repeated consecutive vertices (zero-length edges)
    keep = np.any(v != np.roll(v, -1, axis=0), axis=1)
    v = v[keep]
    scale = float(np.ptp(v, axis=0).max())
    # drop vertices where the boundary runs straight on (the two edges on one line: no corner)
    ein, eout = v - np.roll(v, 1, axis=0), np.roll(v, -1, axis=0) - v
    cross = ein[:, 0] * eout[:, 1] - ein[:, 1] * eout[:, 0]
    straight = (np.abs(cross) <= 1e-12 * scale * scale) & (np.einsum("ij,ij->i", ein, eout) > 0)
    if straight.any() and (~straight).sum() >= 3:
        v = v[~straight]
    n, off = _edge_lines(v)
    if center is None:
        c, depth = find_star_center(v)
        if not depth > 1e-9 * scale:
            raise ParameterError(
                f"obstacle {oid} (polygon) is not star-shaped: no point sees its whole boundary (the "
                "intersection of its edges' inner half-planes has no interior); split it into star-shaped parts"
            )
    else:
        c = np.asarray(center, dtype=float)
    ck = off - n @ c
    bad = np.flatnonzero(~(ck > 1e-9 * scale))
    if bad.size:
        k = int(bad[0])
        a, b = v[k], v[(k + 1) % len(v)]
        raise ParameterError(
            f"obstacle {oid} (polygon) is not star-shaped about its centre ({c[0]:g}, {c[1]:g}): the centre "
            f"lies {'on the line of' if abs(ck[k]) <= 1e-9 * scale else 'outside the inner side of'} its edge "
            f"({a[0]:g}, {a[1]:g})-({b[0]:g}, {b[1]:g}); give a centre in the polygon's kernel or none "
            "(gridfield then finds one)"
        )
    d = v - c
    ang = np.arctan2(d[:, 1], d[:, 0])
    steps = np.mod(np.diff(np.concatenate([ang, ang[:1]])), 2 * math.pi)
    angles = np.concatenate([[ang[0]], ang[0] + np.cumsum(steps)])
    e = np.roll(v, -1, axis=0) - v  # edge k: v_k -> v_{k+1}
    ein = np.roll(e, 1, axis=0)  # edge k - 1, into vertex k
    convex = ein[:, 0] * e[:, 1] - ein[:, 1] * e[:, 0] > 0  # a left turn of a counter-clockwise polygon
    ob = StarObstacle(oid, "polygon", c, 0.0, v, n, ck, angles)
    r = float(ob.boundary_distance(c[None, :])[0])
    return StarObstacle(oid, "polygon", c, r, v, n, ck, angles, convex=convex)
