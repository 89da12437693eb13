"""Star worlds: the validated world, its scaled obstacle functions and the star-to-sphere transformation.

What a star world is and why ``phi(h_lambda(q))`` navigates it: :mod:`gridfield.fields.navigation` (Rimon &
Koditschek 1992; Choset et al., sec. 4.6; seed 002, third question).

The construction (all of it vectorized over query points ``q``, shape ``(N, 2)``; the obstacle
functions ``beta_i`` of discs and star polygons are those of ``_star_obstacle``):

- workspace disc ``(c_0, r_0)``: the disc inscribed in the world's bounds,
  ``beta_0(q) = 1 - |q - c_0|**2 / r_0**2``; goal term ``gamma(q) = |q - q_goal|**2 / r_0**2``
  (both scaled by ``r_0**2`` so that ``lambda`` does not depend on the world's units);
- in the switches each ``beta_i`` is divided by ``scale_i``, a bound of ``g_i**2 - 1`` over the
  workspace (:attr:`StarObstacle.scale`), so that it lies in about ``[0, 1]`` on the free space and the
  products ``bar_beta_i`` stay O(1) however many obstacles there are (a positive multiple: same zero
  set and signs); ``T_i`` uses the unscaled ``beta_i``, so that ``T_i`` is the radial map
  ``q_i + r_i G_i u`` (a smoothed gauge map) and the identity for a disc;
- model disc of obstacle ``i``: centre ``p_i = q_i`` and radius ``r_i`` = the distance from ``q_i`` to
  the obstacle's boundary (so model discs lie inside their obstacles: disjoint, inside the
  workspace, away from the goal; for a disc ``r_i`` is its radius and ``T_i`` is the identity);
- ``T_i(q) = nu_i(q) (q - q_i) + p_i`` with ``nu_i(q) = (1 + beta_i(q))**0.5 r_i / |q - q_i|``
  (``= r_i G_i(q) / |q - q_i|`` on the free space), ``T_goal(q) = q``, and the workspace's ``T_0`` the identity (the
  workspace already is a disc);
- switches ``s_i(q, lambda) = gamma bar_beta_i / (gamma bar_beta_i + lambda beta_i)`` with
  ``bar_beta_i = prod_{j != i} beta_j`` (``j = 0`` included), ``s_goal = 1 - sum s_i``, and
  ``h_lambda(q) = s_goal q + sum s_i T_i(q)``. On the boundary of obstacle ``i``, ``s_i = 1`` and the
  other switches vanish, so ``h_lambda`` maps it onto the model circle; on the workspace circle and at
  the goal ``h_lambda`` is the identity. For ``lambda`` large enough ``h_lambda`` is a diffeomorphism
  of the free space (Rimon & Koditschek);
- ``phi(h_lambda(q))``, gradient ``J^T grad phi(h)`` with the analytic Jacobian ``J`` of ``h_lambda``
  (checked against finite differences in the tests).

The seed writes the switch with ``gamma_kappa``; gridfield uses ``gamma = |q - q_goal|**2`` as in
Rimon & Koditschek, so that ``kappa`` is only the navigation function's exponent.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import ParameterError
from ._sphere import _rk_phi_grad, _rk_terms  # the sphere-world terms
from ._star_obstacle import StarObstacle, _star_polygon


# ----------------------------------------------------------------------------------------------
# The star world
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class StarWorld:
    """A validated star world: disc workspace ``(workspace_center, workspace_radius)``, star-shaped
    obstacles, goal. Build one with :func:`star_world`.

    Attributes
    ----------
    obstacles : tuple of StarObstacle
        The star-shaped obstacles, each with its model disc.
    workspace_center : ndarray (2,)
    workspace_radius : float
        The disc workspace (by default the disc inscribed in the world's bounds).
    goal : ndarray (2,)

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [4, 4], "radius": 1}}]})
    >>> sw = star_world(w, (8, 2))
    >>> sw.workspace_center.tolist(), sw.workspace_radius, sw.free([[4, 4], [6, 6]]).tolist()
    ([5.0, 5.0], 5.0, [False, True])
    """

    obstacles: tuple[StarObstacle, ...]
    workspace_center: NDArray[np.float64]
    workspace_radius: float
    goal: NDArray[np.float64]

    @property
    def model_discs(self) -> NDArray[np.float64]:
        """The model sphere world's discs ``(M, 3)``: ``(p_x, p_y, r_i)``."""
        return np.array([[*ob.center, ob.model_radius] for ob in self.obstacles], dtype=float).reshape(-1, 3)

    def clearance(self, q: ArrayLike) -> NDArray[np.float64]:
        """Exact distance from points ``(N, 2)`` to the nearest obstacle boundary or the workspace circle
        (meaningful for free points)."""
        p = np.atleast_2d(np.asarray(q, dtype=float))
        d: NDArray[np.float64] = self.workspace_radius - np.hypot(*(p - self.workspace_center).T)
        for ob in self.obstacles:
            d = np.minimum(d, ob.boundary_distance(p))
        return d

    def _nearest_boundary(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Exact clearance of free points ``(N, 2)`` and the unit vector from the nearest boundary point
        (of an obstacle or the workspace circle) to each point (into the free space)."""
        d = q - self.workspace_center
        dist = np.hypot(d[:, 0], d[:, 1])
        best = self.workspace_radius - dist
        with np.errstate(invalid="ignore", divide="ignore"):
            away = np.where(dist[:, None] > 0, -d / dist[:, None], 0.0)
        for ob in self.obstacles:
            if ob.kind == "circle":
                e = q - ob.center
                de = np.hypot(e[:, 0], e[:, 1])
                cand, vec = de - ob.radius, e
            else:
                assert ob.vertices is not None
                a = ob.vertices
                ed = np.roll(a, -1, axis=0) - a
                rel = q[:, None, :] - a[None, :, :]
                t = np.clip(np.einsum("nkj,kj->nk", rel, ed) / np.einsum("kj,kj->k", ed, ed), 0.0, 1.0)
                diff = rel - t[..., None] * ed[None]
                dd = np.einsum("nkj,nkj->nk", diff, diff)
                k = np.argmin(dd, axis=1)
                vec = diff[np.arange(len(q)), k]
                cand = np.sqrt(dd[np.arange(len(q)), k])
            closer = cand < best
            if closer.any():
                nv = np.hypot(vec[closer, 0], vec[closer, 1])
                with np.errstate(invalid="ignore", divide="ignore"):
                    away[closer] = np.where(nv[:, None] > 0, vec[closer] / nv[:, None], 0.0)
                best = np.where(closer, cand, best)
        return best, away

    def segment_hits(self, a: NDArray[np.float64], b: NDArray[np.float64],
                     b_free: NDArray[np.bool_] | None = None) -> NDArray[np.bool_]:
        """Whether the segments ``a[n] -> b[n]`` (``a`` free) touch an obstacle or leave the workspace (exact);
        ``b_free``: :meth:`free` of ``b`` when known."""
        hit = ~(self.free(b) if b_free is None else b_free)
        for ob in self.obstacles:
            if ob.kind == "circle":
                v = b - a
                vv = np.einsum("ij,ij->i", v, v)
                with np.errstate(invalid="ignore", divide="ignore"):
                    t = np.clip(np.where(vv > 0, np.einsum("ij,ij->i", ob.center - a, v) / vv, 0.0), 0.0, 1.0)
                hit |= np.hypot(*(a + t[:, None] * v - ob.center).T) <= ob.radius
                continue
            assert ob.vertices is not None
            p0, p1 = ob.vertices, np.roll(ob.vertices, -1, axis=0)

            def orient(o: Any, x: Any, y: Any) -> Any:
                return (x[..., 0] - o[..., 0]) * (y[..., 1] - o[..., 1]) - (x[..., 1] - o[..., 1]) * (y[..., 0] - o[..., 0])

            A, B = a[:, None, :], b[:, None, :]
            d1, d2 = orient(A, B, p0[None]), orient(A, B, p1[None])
            d3, d4 = orient(p0[None], p1[None], A), orient(p0[None], p1[None], B)
            hit |= np.any((d1 * d2 <= 0) & (d3 * d4 <= 0), axis=1)
        return hit

    def free(self, q: ArrayLike) -> NDArray[np.bool_]:
        """Whether points ``(N, 2)`` lie strictly inside the workspace disc and outside every obstacle."""
        p = np.atleast_2d(np.asarray(q, dtype=float))
        ok: NDArray[np.bool_] = np.hypot(*(p - self.workspace_center).T) < self.workspace_radius
        for ob in self.obstacles:
            ok &= ob.gauge(p)[0] > 1.0
        return ok


def _workspace_of(world: Any, center: ArrayLike | None, radius: float | None) -> tuple[NDArray[np.float64], float]:
    xmin, ymin, xmax, ymax = world.bounds
    c = np.asarray(((xmin + xmax) / 2, (ymin + ymax) / 2) if center is None else center, dtype=float).reshape(-1)
    r = float(min(xmax - xmin, ymax - ymin) / 2 if radius is None else radius)
    if c.shape != (2,) or not np.all(np.isfinite(c)) or not (math.isfinite(r) and r > 0):
        raise ParameterError(f"workspace disc needs a finite centre (x, y) and radius > 0, got {center!r}, {radius!r}")
    return c, r


def star_world(world: Any, goal: ArrayLike, *, workspace_center: ArrayLike | None = None,
               workspace_radius: float | None = None) -> StarWorld:
    """Validate a :class:`~gridfield.geometry.world.World` as a star world and build its model sphere world.

    The workspace is the disc inscribed in the world's bounds (or the one given). Each obstacle must
    be a circle or a polygon star-shaped about its centre (the world file's ``center``, or the deepest
    point of its kernel, :func:`find_star_center`), strictly inside the workspace, and no two may
    touch or overlap.

    Parameters
    ----------
    world : World
        A vector world (:func:`gridfield.geometry.world.world_from_dict`, :func:`gridfield.io.read_world`).
    goal : array_like (2,)
        The goal, a free point of the workspace.
    workspace_center, workspace_radius : optional
        The workspace disc (default: the disc inscribed in the world's bounds).

    Returns
    -------
    StarWorld
        The obstacles with their model discs (centre ``q_i``, radius the distance from ``q_i`` to the
        boundary) and the scales of their ``beta_i``.

    Raises
    ------
    ParameterError
        An obstacle of another kind, not star-shaped about its centre, outside the workspace, or
        overlapping another; or the goal outside the workspace or inside an obstacle.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [
    ...     {"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}, {"circle": {"center": [7, 6], "radius": 1}}]})
    >>> sw = star_world(w, (8, 2))
    >>> sw.model_discs.tolist()
    [[4.0, 4.0, 1.0], [7.0, 6.0, 1.0]]
    """
    import shapely

    c0, r0 = _workspace_of(world, workspace_center, workspace_radius)
    obstacles = []
    for ob in world.obstacles:
        if ob.kind == "circle":
            so = StarObstacle(ob.id, "circle", np.asarray(ob.center, dtype=float), float(ob.radius),
                              radius=float(ob.radius))
            far = math.hypot(*(so.center - c0)) + so.radius
        elif ob.kind == "polygon":
            if len(ob.geometry.interiors):
                raise ParameterError(f"obstacle {ob.id} (polygon) has holes; a star-shaped obstacle has none")
            so = _star_polygon(ob.id, ob.vertices, getattr(ob, "star_center", None))
            far = float(np.hypot(*(so.vertices - c0).T).max())  # type: ignore[operator]
        else:
            raise ParameterError(
                f"obstacle {ob.id} is a {ob.kind}; star-nav needs polygons star-shaped about a centre and circles"
            )
        if far >= r0:
            raise ParameterError(
                f"obstacle {ob.id} ({ob.kind}) is not strictly inside the workspace disc (centre ({c0[0]:g}, "
                f"{c0[1]:g}), radius {r0:g}, the disc inscribed in the bounds); star-nav needs that"
            )
        obstacles.append((ob, so))
    for i, (a, _) in enumerate(obstacles):
        for b, _ in obstacles[i + 1:]:
            if _touch(a, b, shapely):
                raise ParameterError(f"obstacles {a.id} and {b.id} overlap or touch; a star world needs disjoint obstacles")
    sw = StarWorld(tuple(so for _, so in obstacles), c0, r0, np.zeros(2))
    g = np.asarray(goal, dtype=float).reshape(-1)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise ParameterError(f"goal must be two finite numbers (x, y), got {goal!r}")
    _check_free(sw, "goal", g)
    scaled = []
    # beta_i / scale_i lies in about [0, 1] on the free space (scale_i: the largest beta_i sampled on the
    # workspace circle and a lattice inside): the products in the switches stay O(1) for many obstacles
    ang = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    ticks = np.linspace(-r0, r0, 41)
    lx, ly = np.meshgrid(ticks, ticks)
    lat = np.column_stack([lx.ravel(), ly.ravel()])
    samples = c0 + np.vstack([r0 * np.column_stack([np.cos(ang), np.sin(ang)]), lat[np.hypot(*lat.T) < r0]])
    for so in sw.obstacles:
        scaled.append(dataclasses.replace(so, scale=max(1.0, float(so.beta(samples)[0].max()))))
    return StarWorld(tuple(scaled), c0, r0, g)


def _touch(a: Any, b: Any, shapely: Any) -> bool:
    touch: bool
    if a.kind == "circle" and b.kind == "circle":
        touch = math.dist(a.center, b.center) <= a.radius + b.radius
        return touch
    if a.kind == "circle" or b.kind == "circle":
        circle, poly = (a, b) if a.kind == "circle" else (b, a)
        touch = float(shapely.distance(poly.geometry, shapely.points(circle.center))) <= circle.radius
        return touch
    return bool(shapely.intersects(a.geometry, b.geometry))


def _check_free(sw: StarWorld, name: str, p: NDArray[np.float64]) -> None:
    c0, r0 = sw.workspace_center, sw.workspace_radius
    if math.hypot(*(p - c0)) >= r0:
        raise ParameterError(f"{name} ({p[0]:g}, {p[1]:g}) lies outside the workspace disc (centre ({c0[0]:g}, "
                             f"{c0[1]:g}), radius {r0:g}, the disc inscribed in the world's bounds)")
    for ob in sw.obstacles:
        if ob.gauge(p[None, :])[0][0] <= 1.0:
            raise ParameterError(f"{name} ({p[0]:g}, {p[1]:g}) lies inside or on obstacle {ob.id} ({ob.kind})")


# ----------------------------------------------------------------------------------------------
# beta, the switches, h_lambda
# ----------------------------------------------------------------------------------------------
def star_betas(sw: StarWorld, q: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``beta_j(q)`` for the workspace (``j = 0``) and each obstacle (scaled, as the switches use them),
    shape ``(M + 1, N)``, and their gradients, shape ``(M + 1, N, 2)``.

    Parameters
    ----------
    sw : StarWorld
    q : array_like (N, 2)
        Query points.

    Returns
    -------
    betas : ndarray (M + 1, N)
        ``beta_0 = 1 - |q - c_0|**2 / r_0**2`` and ``beta_i / scale_i`` (:meth:`StarObstacle.beta`).
    grads : ndarray (M + 1, N, 2)

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> b, _ = star_betas(star_world(w, (8, 2)), [[4, 4], [5, 4], [6, 4]])
    >>> b.round(3).tolist()  # workspace; the square: beta / scale, 0 on its edge
    [[0.92, 0.96, 0.92], [-0.026, 0.0, 0.081]]
    """
    p = np.atleast_2d(np.asarray(q, dtype=float))
    return _betas_from(sw, p, [ob.beta(p) for ob in sw.obstacles])


def _betas_from(sw: StarWorld, p: NDArray[np.float64], raw: list[tuple[NDArray[np.float64], NDArray[np.float64]]]
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    c0, r0 = sw.workspace_center, sw.workspace_radius
    d0 = p - c0
    betas = [1.0 - np.einsum("ij,ij->i", d0, d0) / r0**2]
    grads = [-2.0 * d0 / r0**2]
    for ob, (b, db) in zip(sw.obstacles, raw, strict=True):
        betas.append(b / ob.scale)
        grads.append(db / ob.scale)
    return np.array(betas), np.array(grads)


_EYE = np.eye(2)


def star_to_sphere(sw: StarWorld, q: ArrayLike, lam: float
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """``h_lambda(q)`` ``(N, 2)``, its Jacobian ``(N, 2, 2)`` (``J[n, a, b] = d h_a / d q_b``), the
    switches ``s_i`` ``(M, N)`` and the free mask ``(N,)``; NaN outside the free space.

    Parameters
    ----------
    sw : StarWorld
    q : array_like (N, 2)
        Query points.
    lam : float
        The switch parameter ``lambda``.

    Returns
    -------
    h : ndarray (N, 2)
    jac : ndarray (N, 2, 2)
    switches : ndarray (M, N)
    free : ndarray (N,) of bool

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> h, jac, s, free = star_to_sphere(star_world(w, (8, 2)), [[5, 5.5], [8, 2]], 10.0)
    >>> h.round(4).tolist()  # a point next to the square's corner, and the goal (fixed)
    [[4.8822, 5.3232], [8.0, 2.0]]
    """
    p = np.atleast_2d(np.asarray(q, dtype=float))
    n = len(p)
    raw = [ob.beta(p) for ob in sw.obstacles]
    betas, gbetas = _betas_from(sw, p, raw)
    free = np.all(betas > 0, axis=0) & sw.free(p)  # the exact gauge too: beta rounds at the vertices
    r0 = sw.workspace_radius
    dg = p - sw.goal
    gamma = np.einsum("ij,ij->i", dg, dg) / r0**2
    ggamma = 2.0 * dg / r0**2
    h = p.copy()
    jac = np.broadcast_to(_EYE, (n, 2, 2)).copy()
    m = len(sw.obstacles)
    s_all = np.zeros((m, n))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        big_b = np.prod(betas, axis=0)
        dlog_b = np.sum(gbetas / betas[..., None], axis=0)  # grad B / B
        for i, ob in enumerate(sw.obstacles):
            bi, gbi = betas[i + 1], gbetas[i + 1]
            ratio = big_b / (bi * bi)  # bar_beta_i / beta_i
            x = gamma * ratio
            gx = ratio[:, None] * ggamma + (gamma * ratio)[:, None] * (dlog_b - 2.0 * gbi / bi[:, None])
            s = x / (x + lam)
            gs = (lam / (x + lam) ** 2)[:, None] * gx
            d = p - ob.center
            dist = np.hypot(d[:, 0], d[:, 1])
            u = d / dist[:, None]
            # T_i = p_i + r_i sqrt(1 + beta_i) u with the unscaled beta_i (sqrt(1 + beta_i) = |q - q_i| / r for a disc)
            nu = np.sqrt(1.0 + raw[i][0])
            gnu = raw[i][1] / (2.0 * nu)[:, None]
            t = ob.center + (ob.model_radius * nu)[:, None] * u
            # J_T = r (u grad_nu^T + nu (I - u u^T) / dist)
            uu = u[:, :, None] * u[:, None, :]
            jt = ob.model_radius * (u[:, :, None] * gnu[:, None, :]
                                    + (nu / dist)[:, None, None] * (_EYE[None] - uu))
            h = h + s[:, None] * (t - p)
            jac = jac + (t - p)[:, :, None] * gs[:, None, :] + s[:, None, None] * (jt - _EYE[None])
            s_all[i] = s
    h[~free] = np.nan
    jac[~free] = np.nan
    s_all[:, ~free] = np.nan
    return h, jac, s_all, free


def _model_terms(sw: StarWorld, hq: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    return _rk_terms(hq[:, 0], hq[:, 1], sw.goal, sw.model_discs, sw.workspace_center, sw.workspace_radius)


def nav_function(sw: StarWorld, q: ArrayLike, *, kappa: float, lam: float) -> tuple[NDArray[np.float64], ...]:
    """``phi(h_lambda(q))`` ``(N,)`` and its gradient ``(N, 2)`` (``J^T grad phi``), with ``phi`` the
    sphere-world navigation function of the model world; ``phi = 1`` and gradient 0 outside the free
    space.

    Parameters
    ----------
    sw : StarWorld
    q : array_like (N, 2)
        Query points.
    kappa, lam : float
        The navigation function's exponent and the switch parameter.

    Returns
    -------
    phi : ndarray (N,)
    grad : ndarray (N, 2)

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> phi, grad = nav_function(star_world(w, (8, 2)), [[8, 2], [8.5, 2], [4, 4]], kappa=3, lam=10)
    >>> phi.round(4).tolist()  # 0 at the goal, 1 inside the obstacle
    [0.0, 0.0563, 1.0]
    """
    p = np.atleast_2d(np.asarray(q, dtype=float))
    h, jac, _, free = star_to_sphere(sw, p, lam)
    hq = np.where(free[:, None], h, sw.goal + 0.5 * sw.workspace_radius)  # any valid point; masked below
    phi, gx, gy = _rk_phi_grad(hq[:, 0], hq[:, 1], sw.goal, sw.model_discs, sw.workspace_center,
                               sw.workspace_radius, float(kappa))
    grad = np.einsum("nab,na->nb", np.where(free[:, None, None], jac, 0.0), np.column_stack([gx, gy]))
    phi = np.where(free, phi, 1.0)
    grad[~free] = 0.0
    return phi, grad
