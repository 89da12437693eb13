"""Star worlds: the Rimon-Koditschek navigation function through the star-to-sphere transformation.

A *star world* is a disc workspace holding disjoint obstacles that are each star-shaped about a
centre ``q_i`` (polygons whose kernel contains ``q_i``, and discs). The star-to-sphere transformation
``h_lambda`` maps it onto a *sphere world* (model discs ``(p_i, r_i)`` in the same workspace), where
the sphere-world navigation function ``phi`` of :func:`gridfield.navigation.sphere_nav_function` is
known; ``phi(h_lambda(q))`` is then a navigation function of the star world (Rimon & Koditschek,
"Exact robot navigation using artificial potential functions", IEEE Trans. Robotics and Automation
8(5), 1992; Choset et al., *Principles of Robot Motion*, sec. 4.6; seed 002, third question).

The construction (all of it vectorized over query points ``q``, shape ``(N, 2)``):

- workspace disc ``(c_0, r_0)``: the disc inscribed in the world's bounds,
  ``beta_0(q) = 1 - |q - c_0|**2 / r_0**2``; goal term ``gamma(q) = |q - q_goal|**2 / r_0**2``
  (both scaled by ``r_0**2`` so that ``lambda`` does not depend on the world's units);
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
  linear) still decides which points are free (:meth:`StarObstacle.gauge`);
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

The planner ``star-nav`` (:func:`plan_star_nav`) follows ``-grad phi(h_lambda(q))`` like ``sphere-nav``.
:func:`star_nav_field` gives the arrays of ``gridfield field --planner star-nav`` and the seed's
figures (:func:`gridfield.plot.plot_star_world`).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import GridfieldError, ParameterError
from .path import Path

__all__ = [
    "STAR_PARAMETERS",
    "StarNavWarning",
    "StarObstacle",
    "StarWorld",
    "find_star_center",
    "follow_star_nav",
    "nav_function",
    "plan_star_nav",
    "spurious_minima",
    "star_betas",
    "star_nav_field",
    "star_to_sphere",
    "star_world",
]

# ==============================================================================================
# THE PARAMETERS OF star-nav: name -> default, allowed range (inclusive), meaning.
# (One place, to be ported to the parameter registry; ``lambda`` is the key in params dicts, world
# files and ``--param lambda=...``; Python arguments call it ``lam``.)
# ==============================================================================================
STAR_PARAMETERS: dict[str, dict[str, Any]] = {
    "kappa": {"default": None, "range": (1.0, 1000.0),
              "meaning": "navigation function exponent; default: the smallest of KAPPA_LADDER with no "
                         "spurious minimum detected (seed 002: 3)"},
    "lambda": {"default": 10.0, "range": (1e-6, 1e12),
               "meaning": "star-to-sphere switch parameter: larger keeps h_lambda closer to the identity "
                          "away from the obstacles (too small folds h_lambda; seed 002: 1; the default "
                          "reached the goal most often over 24 random spiky worlds, benchmarks/star_nav.py)"},
}

#: a follower step whose segment would touch an obstacle is cut to this fraction of the exact clearance
CLEARANCE_STEP = 0.5

#: kappa values tried, in order, when ``kappa`` is not given (starting at seed 002's 3).
KAPPA_LADDER = (3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0)


class StarNavWarning(UserWarning):
    """``kappa`` too small (spurious local minima detected) or ``lambda`` too small (``h_lambda`` folds)."""


def _param(params: Mapping[str, Any], name: str) -> float | None:
    spec = STAR_PARAMETERS[name]
    value = params.get(name, spec["default"])
    if value is None:
        return None
    lo, hi = spec["range"]
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if isinstance(value, bool) or not (math.isfinite(v) and lo <= v <= hi):
        raise ParameterError(f"{name} must be a number in [{lo:g}, {hi:g}] ({spec['meaning']}), got {value!r}")
    return v


# ----------------------------------------------------------------------------------------------
# The star world
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
    >>> from gridfield.world import world_from_dict
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
            return np.abs(np.hypot(*(q - self.center).T) - self.radius)
        assert self.vertices is not None
        a = self.vertices
        e = np.roll(a, -1, axis=0) - a
        rel = q[:, None, :] - a[None, :, :]
        t = np.clip(np.einsum("nkj,kj->nk", rel, e) / np.einsum("kj,kj->k", e, e), 0.0, 1.0)
        diff = rel - t[..., None] * e[None]
        return np.sqrt(np.min(np.einsum("nkj,nkj->nk", diff, diff), axis=1))


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
    >>> from gridfield.world import world_from_dict
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
        d = self.workspace_radius - np.hypot(*(p - self.workspace_center).T)
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
        ok = np.hypot(*(p - self.workspace_center).T) < self.workspace_radius
        for ob in self.obstacles:
            ok &= ob.gauge(p)[0] > 1.0
        return ok


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


def _workspace_of(world: Any, center: ArrayLike | None, radius: float | None) -> tuple[NDArray[np.float64], float]:
    xmin, ymin, xmax, ymax = world.bounds
    c = np.asarray(((xmin + xmax) / 2, (ymin + ymax) / 2) if center is None else center, dtype=float).reshape(-1)
    r = float(min(xmax - xmin, ymax - ymin) / 2 if radius is None else radius)
    if c.shape != (2,) or not np.all(np.isfinite(c)) or not (math.isfinite(r) and r > 0):
        raise ParameterError(f"workspace disc needs a finite centre (x, y) and radius > 0, got {center!r}, {radius!r}")
    return c, r


def star_world(world: Any, goal: ArrayLike, *, workspace_center: ArrayLike | None = None,
               workspace_radius: float | None = None) -> StarWorld:
    """Validate a :class:`~gridfield.world.World` as a star world and build its model sphere world.

    The workspace is the disc inscribed in the world's bounds (or the one given). Each obstacle must
    be a circle or a polygon star-shaped about its centre (the world file's ``center``, or the deepest
    point of its kernel, :func:`find_star_center`), strictly inside the workspace, and no two may
    touch or overlap.

    Parameters
    ----------
    world : World
        A vector world (:func:`gridfield.world.world_from_dict`, :func:`gridfield.io.read_world`).
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
    >>> from gridfield.world import world_from_dict
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
    if a.kind == "circle" and b.kind == "circle":
        return math.dist(a.center, b.center) <= a.radius + b.radius
    if a.kind == "circle" or b.kind == "circle":
        circle, poly = (a, b) if a.kind == "circle" else (b, a)
        return float(shapely.distance(poly.geometry, shapely.points(circle.center))) <= circle.radius
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
    >>> from gridfield.world import world_from_dict
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
    >>> from gridfield.world import world_from_dict
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
    from .navigation import _rk_terms  # the sphere-world terms gridfield already has

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
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> phi, grad = nav_function(star_world(w, (8, 2)), [[8, 2], [8.5, 2], [4, 4]], kappa=3, lam=10)
    >>> phi.round(4).tolist()  # 0 at the goal, 1 inside the obstacle
    [0.0, 0.0563, 1.0]
    """
    from .navigation import _rk_phi_grad

    p = np.atleast_2d(np.asarray(q, dtype=float))
    h, jac, _, free = star_to_sphere(sw, p, lam)
    hq = np.where(free[:, None], h, sw.goal + 0.5 * sw.workspace_radius)  # any valid point; masked below
    phi, gx, gy = _rk_phi_grad(hq[:, 0], hq[:, 1], sw.goal, sw.model_discs, sw.workspace_center,
                               sw.workspace_radius, float(kappa))
    grad = np.einsum("nab,na->nb", np.where(free[:, None, None], jac, 0.0), np.column_stack([gx, gy]))
    phi = np.where(free, phi, 1.0)
    grad[~free] = 0.0
    return phi, grad


# ----------------------------------------------------------------------------------------------
# checks: spurious minima (kappa) and folds (lambda)
# ----------------------------------------------------------------------------------------------
def _sample_lattice(sw: StarWorld, n: int) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    c0, r0 = sw.workspace_center, sw.workspace_radius
    xs = np.linspace(c0[0] - r0, c0[0] + r0, n)
    ys = np.linspace(c0[1] - r0, c0[1] + r0, n)
    return xs, ys, float(xs[1] - xs[0])


def spurious_minima(sw: StarWorld, *, kappa: float, lam: float, n: int = 161) -> NDArray[np.float64]:
    """Local minima of ``phi(h_lambda(q))`` other than the goal, found on an ``n x n`` lattice over the
    workspace: lattice points lower than their 8 neighbours, all 9 at least 2 lattice steps from
    every boundary and the point more than 2 steps from the goal.

    Parameters
    ----------
    sw : StarWorld
    kappa, lam : float
        The navigation function's exponent and the switch parameter.
    n : int
        Lattice points per side.

    Returns
    -------
    ndarray (K, 2)
        The spurious minima found.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> spurious_minima(star_world(w, (8, 2)), kappa=3, lam=10).shape
    (0, 2)
    """
    xs, ys, dx = _sample_lattice(sw, int(n))
    x, y = np.meshgrid(xs, ys)
    q = np.column_stack([x.ravel(), y.ravel()])
    # phi saturates at 1 far from the goal for a large kappa; compare kappa log gamma - log beta at h(q),
    # an increasing function of phi (phi**kappa = 1 / (1 + beta / gamma**kappa)) that does not saturate
    phi = _log_objective(sw, q, kappa, lam).reshape(x.shape)
    ok = (sw.clearance(q) > 2 * dx).reshape(x.shape) & sw.free(q).reshape(x.shape)
    pad = np.pad(phi, 1, constant_values=np.inf)
    okp = np.pad(ok, 1, constant_values=False)
    rows, cols = phi.shape
    is_min = ok.copy()
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            if dr == 0 and dc == 0:
                continue
            nb = pad[1 + dr:1 + dr + rows, 1 + dc:1 + dc + cols]
            is_min &= okp[1 + dr:1 + dr + rows, 1 + dc:1 + dc + cols] & (phi < nb)
    is_min &= np.hypot(x - sw.goal[0], y - sw.goal[1]) > 2 * dx
    return np.column_stack([x[is_min], y[is_min]])


def _log_objective(sw: StarWorld, q: NDArray[np.float64], kappa: float, lam: float) -> NDArray[np.float64]:
    """``kappa log gamma(h) - log beta(h)`` (``inf`` outside the free space): increasing with ``phi``."""
    h, _, _, free = star_to_sphere(sw, q, lam)
    gamma, log_beta, _, _, valid = _model_terms(sw, np.where(free[:, None], h, sw.goal + 0.5 * sw.workspace_radius))
    with np.errstate(divide="ignore"):
        f = kappa * np.log(gamma) - log_beta
    return np.where(free & cast("NDArray[np.bool_]", valid), f, np.inf)


def folds(sw: StarWorld, *, lam: float, n: int = 121) -> NDArray[np.float64]:
    """Free lattice points (``n x n`` over the workspace) where ``det J`` of ``h_lambda`` is ``<= 0``:
    there ``h_lambda`` is not a diffeomorphism (``lambda`` too small)."""
    xs, ys, _ = _sample_lattice(sw, int(n))
    x, y = np.meshgrid(xs, ys)
    q = np.column_stack([x.ravel(), y.ravel()])
    _, jac, _, free = star_to_sphere(sw, q, lam)
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    return q[free & np.logical_not(det > 0)]


def _choose_kappa(sw: StarWorld, kappa: float | None, lam: float) -> tuple[float, list[tuple[float, int]]]:
    """The kappa to use and the (kappa, spurious minima found) tried; warns when a given kappa is too small."""
    if kappa is not None:
        found = spurious_minima(sw, kappa=kappa, lam=lam)
        if len(found):
            x, y = found[0]
            warnings.warn(
                f"kappa={kappa:g} is too small: phi(h_lambda) has {len(found)} local minim{'a' if len(found) > 1 else 'um'} "
                f"besides the goal (one near ({x:.3g}, {y:.3g})); raise kappa (or leave it out to let star-nav choose)",
                StarNavWarning, stacklevel=3)
        return kappa, [(kappa, len(found))]
    tried = []
    for k in KAPPA_LADDER:
        found = spurious_minima(sw, kappa=k, lam=lam)
        tried.append((k, len(found)))
        if not len(found):
            return k, tried
    return KAPPA_LADDER[-1], tried


def _warn_folds(sw: StarWorld, lam: float) -> int:
    bad = folds(sw, lam=lam)
    if len(bad):
        x, y = bad[0]
        warnings.warn(f"lambda={lam:g} is too small: h_lambda folds (Jacobian determinant <= 0) at {len(bad)} "
                      f"sampled free points (one near ({x:.3g}, {y:.3g})); raise lambda", StarNavWarning, stacklevel=3)
    return len(bad)


# ----------------------------------------------------------------------------------------------
# the follower and the planner
# ----------------------------------------------------------------------------------------------
def follow_star_nav(sw: StarWorld, starts: ArrayLike, *, kappa: float, lam: float, step: float,
                    tolerance: float, max_iterations: int, window: int = 200
                    ) -> list[tuple[NDArray[np.float64], str, int]]:
    """Follow ``-grad phi(h_lambda(q))`` from many starts at once (normalized steps).

    The direction is ``-J^T b(h)``, with ``b`` the bracket of the sphere-world gradient (the gradient of
    ``log phi`` up to a positive factor, which never underflows). Each step is ``step`` long (shorter
    where ``phi`` went up: chattering), and at most the distance to the goal. Within a step of a
    boundary, a direction into it is projected onto the boundary's tangent (still a descent direction):
    near an obstacle whose model disc is small, the barrier of ``phi(h_lambda)`` is very thin and
    walking into it in ever shorter steps stalls. A step whose segment would touch an obstacle
    (checked exactly) is cut to half the exact clearance, so the path stays free. A start ends ``reached`` within ``tolerance`` of the goal (the goal is then
    appended), ``local_minimum`` when ``phi`` has not decreased over ``window`` steps or the direction
    vanishes, ``collision`` if it ever left the free space, else ``max_iterations``.

    Parameters
    ----------
    sw : StarWorld
    starts : array_like (N, 2)
        Free start points.
    kappa, lam : float
        The navigation function's exponent and the switch parameter.
    step, tolerance : float
        The step length and the goal tolerance.
    max_iterations, window : int
        The step budget, and the steps without a new lowest ``phi`` that end a start as ``local_minimum``.

    Returns
    -------
    list of (points (K, 2), status, iterations), one per start.

    Examples
    --------
    >>> from gridfield.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> sw = star_world(w, (8, 8))
    >>> [(s, bool(np.array_equal(pts[-1], sw.goal))) for pts, s, _ in follow_star_nav(
    ...     sw, [[2, 3], [7, 2]], kappa=3, lam=10, step=0.05, tolerance=0.05, max_iterations=2000)]
    [('reached', True), ('reached', True)]
    """
    p = np.atleast_2d(np.asarray(starts, dtype=float)).copy()
    n = len(p)
    goal = sw.goal
    trail = [p.copy()]
    status = np.array(["max_iterations"] * n, dtype=object)
    ends = np.full(n, max_iterations, dtype=int)
    active = np.ones(n, bool)
    best = np.full(n, np.inf)
    prev = np.full(n, np.inf)
    hcur = np.full(n, float(step))  # per start: shrinks where phi did not decrease (chattering), regrows
    since = np.zeros(n, int)
    for it in range(1, max_iterations + 1):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        q = p[idx]
        dgoal = np.hypot(*(q - goal).T)
        done = dgoal <= tolerance
        if done.any():
            status[idx[done]] = "reached"
            ends[idx[done]] = it - 1
            p[idx[done]] = goal
            active[idx[done]] = False
            idx, q, dgoal = idx[~done], q[~done], dgoal[~done]
            if idx.size == 0:
                trail.append(p.copy())
                break
        h, jac, _, free = star_to_sphere(sw, q, lam)
        gamma, log_beta, sx, sy, _ = _model_terms(sw, np.where(free[:, None], h, goal + 0.5 * sw.workspace_radius))
        with np.errstate(divide="ignore", invalid="ignore"):
            b = np.column_stack([2 * (h[:, 0] - goal[0]) / gamma - sx / kappa,
                                 2 * (h[:, 1] - goal[1]) / gamma - sy / kappa])
            direction = np.einsum("nab,na->nb", jac, b)
            nrm = np.hypot(direction[:, 0], direction[:, 1])
            log_phi = kappa * np.log(gamma) - log_beta  # increasing with phi, never saturates
        stuck = np.logical_not(np.isfinite(nrm) & (nrm > 0)) | ~free
        if stuck.any():
            status[idx[stuck]] = np.where(free[stuck], "local_minimum", "collision")
            ends[idx[stuck]] = it - 1
            active[idx[stuck]] = False
        go = ~stuck
        down = log_phi < prev[idx]
        hcur[idx] = np.where(down, np.minimum(step, 1.5 * hcur[idx]), np.maximum(0.5 * hcur[idx], 1e-4 * step))
        prev[idx] = log_phi
        better = log_phi < best[idx] - 1e-12
        best[idx[go & better]] = log_phi[go & better]
        since[idx[go & better]] = 0
        since[idx[go & ~better]] += 1
        flat = go & (since[idx] >= window)
        if flat.any():
            status[idx[flat]] = "local_minimum"
            ends[idx[flat]] = it - 1
            active[idx[flat]] = False
            go &= ~flat
        gi = idx[go]
        if gi.size:
            qg = q[go]
            unit = direction[go] / nrm[go][:, None]
            hstep = np.minimum(hcur[gi], dgoal[go])
            move = -unit
            clear, away = sw._nearest_boundary(qg)
            # within a step of a boundary, a direction into it loses its component along the boundary's
            # normal (still a descent direction): the thin barrier of a small model disc is not run into
            # in ever shorter steps, the start slides along the boundary instead
            into = np.einsum("ij,ij->i", move, away)
            slide = (clear < hstep) & (into < 0)
            if slide.any():
                m = move[slide] - into[slide][:, None] * away[slide]
                mn = np.hypot(m[:, 0], m[:, 1])
                ok = mn > 1e-9
                idx_s = np.flatnonzero(slide)[ok]
                move[idx_s] = m[ok] / mn[ok][:, None]
            new = qg + hstep[:, None] * move
            new_free = sw.free(new)
            hit = sw.segment_hits(qg, new, new_free)
            if hit.any():  # near an obstacle: at most half the clearance, so the segment stays free
                short = np.minimum(hstep[hit], CLEARANCE_STEP * clear[hit])
                new[hit] = qg[hit] + short[:, None] * move[hit]
                new_free[hit] = sw.free(new[hit])
            p[gi] = new
            out = ~new_free
            if out.any():
                status[gi[out]] = "collision"
                ends[gi[out]] = it
                active[gi[out]] = False
        trail.append(p.copy())
    arr = np.array(trail)  # (T, N, 2)
    out_list = []
    for j in range(n):
        k = int(ends[j])
        pts = arr[:k + 1, j]
        if status[j] == "reached" and not np.array_equal(pts[-1], goal):
            pts = np.vstack([pts, goal])
        out_list.append((pts, str(status[j]), k))
    return out_list


def plan_star_nav(world: Any, start: NDArray[np.float64], goal: NDArray[np.float64],
                  params: Mapping[str, Any]) -> Path:
    """Planner ``star-nav``: follow the star-world navigation function ``phi(h_lambda(q))``.

    Parameters (``params``): ``kappa`` and ``lambda`` (:data:`STAR_PARAMETERS`); ``step`` (default 1/200
    of the workspace radius), ``tolerance`` (default ``step``), ``max_iterations``, ``progress_window``
    (200). Without ``kappa`` the values of :data:`KAPPA_LADDER` are tried and the first with no
    spurious minimum detected (:func:`spurious_minima`) is used, and raised to the next values (twice
    at most) when the path still ends in a ``local_minimum`` (one too close to an obstacle for the
    lattice check); with a ``kappa`` that leaves one, a :class:`StarNavWarning` says so (the path may
    then end in a ``local_minimum``). A ``lambda`` for which ``h_lambda`` folds (:func:`folds`) is also
    warned about.

    Parameters
    ----------
    world : World
        A vector world of star-shaped polygons and discs.
    start, goal : ndarray (2,)
        Free points of the workspace disc.
    params : mapping
        As above.

    Returns
    -------
    Path
        ``status`` ``reached``, ``local_minimum``, ``collision`` or ``max_iterations``.

    ``extra`` holds ``kappa``, ``lambda``, ``kappa_tried`` (kappa, minima found), ``followed`` (kappa,
    status of each descent), ``folds``, the workspace and the star centres.

    Examples
    --------
    >>> from gridfield.io import bundled_map, read_world
    >>> w = read_world(bundled_map("star_two.yaml"))
    >>> p = plan_star_nav(w, np.array(w.start), np.array(w.goal), dict(w.params))
    >>> p.status, p.extra["kappa"], p.extra["lambda"]
    ('reached', 3.0, 1.0)
    """
    t0 = time.perf_counter()
    kappa = _param(params, "kappa")
    lam = _param(params, "lambda")
    assert lam is not None
    sw = star_world(world, goal, workspace_center=params.get("workspace_center"),
                    workspace_radius=params.get("workspace_radius"))
    start = np.asarray(start, dtype=float).reshape(2)
    try:
        _check_free(sw, "start", start)
    except ParameterError as e:
        raise GridfieldError(str(e)) from None
    r0 = sw.workspace_radius
    step = float(params.get("step", r0 / 200))
    if not (math.isfinite(step) and step > 0):
        raise ParameterError(f"step must be a positive number, got {params.get('step')!r}")
    tol = float(params.get("tolerance", step))
    if not (math.isfinite(tol) and tol >= 0):
        raise ParameterError(f"tolerance must be a finite number >= 0, got {params.get('tolerance')!r}")
    max_it = int(params.get("max_iterations", 50 * int(2 * r0 / step) + 1000))
    window = int(params.get("progress_window", 200))
    if max_it < 1 or window < 1:
        raise ParameterError(f"max_iterations and progress_window must be >= 1, got {max_it}, {window}")
    n_folds = _warn_folds(sw, lam)
    given = kappa is not None
    kappa, tried = _choose_kappa(sw, kappa, lam)
    followed = []
    while True:
        (pts, status, its), = follow_star_nav(sw, start[None, :], kappa=kappa, lam=lam, step=step, tolerance=tol,
                                              max_iterations=max_it, window=window)
        followed.append((kappa, status))
        larger = [k for k in KAPPA_LADDER if k > kappa]
        # a minimum too close to an obstacle for the lattice check: a chosen kappa is raised (twice at most)
        if given or status != "local_minimum" or not larger or len(followed) > 2:
            break
        kappa = larger[0]
    used = dict(params)
    used["kappa"], used["lambda"] = kappa, lam
    clearance = float(world.distance(pts).min()) if len(sw.obstacles) else math.nan
    extra = {"kappa": kappa, "lambda": lam, "kappa_tried": tried, "followed": followed, "folds": n_folds,
             "workspace_center": sw.workspace_center.tolist(), "workspace_radius": r0,
             "star_centers": {ob.id: ob.center.tolist() for ob in sw.obstacles}}
    return Path(pts, status, "star-nav", its, used, time.perf_counter() - t0, clearance, extra)


# ----------------------------------------------------------------------------------------------
# fields and figure data
# ----------------------------------------------------------------------------------------------
def star_nav_field(gridmap: Any, goal: ArrayLike, params: Mapping[str, Any] | None = None) -> Any:
    """The star-world navigation function at the cell centres of a rasterized world (for
    ``gridfield field --planner star-nav``), as a :class:`~gridfield.navigation.NavigationField` of kind
    ``"star-nav"``: ``value = phi(h_lambda)`` (``inf`` outside the free space), the analytic gradient,
    and in ``aux`` the arrays of the seed's figures (:func:`star_figure_data`).

    Parameters
    ----------
    gridmap : GridMap
        A rasterized vector world (``gridmap.world``).
    goal : array_like (2,)
    params : mapping, optional
        ``kappa``, ``lambda``, ``workspace_center``, ``workspace_radius``.

    Returns
    -------
    NavigationField

    Examples
    --------
    >>> from gridfield.io import bundled_map, read_world
    >>> from gridfield.rasterize import as_gridmap
    >>> w = read_world(bundled_map("star_two.yaml"))
    >>> nav = star_nav_field(as_gridmap(w, 0.5), w.goal, w.params)
    >>> nav.kind, nav.params["kappa"], float(np.nanmin(nav.value))
    ('star-nav', 3.0, 0.0)
    """
    from .navigation import NavigationField

    world = getattr(gridmap, "world", None)
    if world is None or not hasattr(world, "obstacles"):
        raise ParameterError("the star-nav field needs a vector world of star-shaped obstacles; this map is a grid")
    p = dict(params or {})
    kappa = _param(p, "kappa")
    lam = _param(p, "lambda")
    assert lam is not None
    g = np.asarray(goal, dtype=float).reshape(-1)
    sw = star_world(world, g, workspace_center=p.get("workspace_center"), workspace_radius=p.get("workspace_radius"))
    kappa, _ = _choose_kappa(sw, kappa, lam)
    xs, ys = gridmap.grid.cell_centers()
    x, y = np.meshgrid(xs, ys)
    q = np.column_stack([x.ravel(), y.ravel()])
    phi, grad = nav_function(sw, q, kappa=kappa, lam=lam)
    free = sw.free(q)
    value = np.where(free, phi, np.inf).reshape(x.shape)
    gx = grad[:, 0].reshape(x.shape)
    gy = grad[:, 1].reshape(x.shape)
    cell = gridmap.grid.cell_of(g[0], g[1])
    aux = {"grad_x": gx, "grad_y": gy, "figure": star_figure_data(sw, kappa=kappa, lam=lam, x=x, y=y, phi=value)}
    return NavigationField(gridmap, value, g, (int(cell[0]), int(cell[1])), "star-nav",
                           {"kappa": kappa, "lambda": lam, "workspace_center": sw.workspace_center.tolist(),
                            "workspace_radius": sw.workspace_radius}, aux)


def star_figure_data(sw: StarWorld, *, kappa: float, lam: float, x: NDArray[np.float64], y: NDArray[np.float64],
                     phi: NDArray[np.float64] | None = None, lines: int = 21) -> dict[str, Any]:
    """The arrays of seed 002's star-world figures on the lattice ``x, y`` (meshgrid arrays):

    ``humps``: ``max_i(1 - g_i**2, 0)`` (``-beta_i`` before its scaling), each obstacle's hump (1 at its
    centre, 0 on its boundary);
    ``attractive``: ``gamma**kappa`` (``gamma = |q - q_goal|**2 / r_0**2``); ``phi``: ``phi(h_lambda)``
    (``inf`` outside the free space); ``mapped_lines``: polylines of ``lines`` lattice lines of the free
    space mapped by ``h_lambda`` (NaN breaks them where they cross obstacles); ``model_discs``, the
    workspace, the goal, the obstacles' vertices (polygons) or discs.
    """
    q = np.column_stack([x.ravel(), y.ravel()])
    humps = np.zeros(len(q))
    for ob in sw.obstacles:
        hump = np.maximum(-ob.beta(q)[0], 0.0)  # -beta_i (unscaled) inside, divided by its largest value
        top = float(hump.max())
        humps = np.maximum(humps, hump / top if top > 0 else hump)
    humps_grid = humps.reshape(x.shape)
    r0 = sw.workspace_radius
    gamma = ((x - sw.goal[0]) ** 2 + (y - sw.goal[1]) ** 2) / r0**2
    attractive = gamma**kappa
    if phi is None:
        phi_v, _ = nav_function(sw, q, kappa=kappa, lam=lam)
        phi = np.where(sw.free(q), phi_v, np.inf).reshape(x.shape)
    c0 = sw.workspace_center
    ticks = np.linspace(-r0, r0, int(lines) + 2)[1:-1]
    t = np.linspace(-r0, r0, 400)
    mapped = []
    for k in ticks:
        for pts in (np.column_stack([c0[0] + t, np.full_like(t, c0[1] + k)]),
                    np.column_stack([np.full_like(t, c0[0] + k), c0[1] + t])):
            h, _, _, free = star_to_sphere(sw, pts, lam)
            mapped.append(np.where(free[:, None], h, np.nan))
    shapes = [ob.vertices if ob.kind == "polygon" else np.array([*ob.center, ob.radius]) for ob in sw.obstacles]
    return {"x": x, "y": y, "humps": humps_grid, "attractive": attractive, "phi": phi, "mapped_lines": mapped,
            "model_discs": sw.model_discs, "workspace": (c0.tolist(), r0), "goal": sw.goal.copy(),
            "obstacles": shapes, "centers": np.array([ob.center for ob in sw.obstacles]).reshape(-1, 2),
            "kappa": kappa, "lambda": lam}
