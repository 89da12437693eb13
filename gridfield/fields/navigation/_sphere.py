"""Sphere worlds: the Rimon-Koditschek navigation function of disc obstacles inside a disc workspace.

Unlike the grid constructions, this one is analytic: ``phi`` and its gradient are closed-form
expressions of the discs, evaluated on a grid only for display (:func:`sphere_nav_function`), and the
planner ``sphere-nav`` follows the exact gradient in the continuous world (:func:`plan_sphere_nav`).
``kappa`` must be large enough for the goal to be the only minimum; without one, the planner climbs
:data:`KAPPA_LADDER`. The star-world planner (``_star_world`` and ``_star_nav``; documented in :mod:`gridfield.fields.navigation`) maps star worlds
onto these sphere worlds and reuses the terms computed here.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError
from ...core.grid import Grid, GridMap
from ...core.params import Follower, Navigation, validate
from ...core.path import Path
from ._field import NavigationField


# ----------------------------------------------------------------------------------------------
# Sphere worlds (Rimon-Koditschek)
# ----------------------------------------------------------------------------------------------
def _discs_of(world_or_discs: Any) -> NDArray[np.float64]:
    """Disc obstacles as an array ``(M, 3)`` of ``(cx, cy, r)``."""
    obstacles = getattr(world_or_discs, "obstacles", None)
    if obstacles is not None:
        bad = [f"{ob.id} ({ob.kind})" for ob in obstacles if ob.kind != "circle"]
        if bad:
            raise ParameterError(
                "the sphere-world navigation function needs a world whose obstacles are all circles; "
                f"obstacle(s) {', '.join(bad)} are not"
            )
        discs = np.array([[ob.center[0], ob.center[1], ob.radius] for ob in obstacles], dtype=float)
        return discs.reshape(-1, 3)
    d = np.asarray(world_or_discs, dtype=float)
    if d.size == 0:
        return d.reshape(0, 3)
    if d.ndim != 2 or d.shape[1] != 3 or not np.all(np.isfinite(d)) or np.any(d[:, 2] <= 0):
        raise ParameterError(f"discs must be an array (M, 3) of finite (cx, cy, r > 0), got shape {d.shape}")
    return d


def _workspace(world_or_discs: Any, center: ArrayLike | None, radius: float | None) -> tuple[NDArray[np.float64], float]:
    bounds = getattr(world_or_discs, "bounds", None)
    if center is None or radius is None:
        if bounds is None:
            raise ParameterError("give workspace_center and workspace_radius (or a World, whose inscribed circle is used)")
        xmin, ymin, xmax, ymax = bounds
        center = ((xmin + xmax) / 2, (ymin + ymax) / 2) if center is None else center
        radius = min(xmax - xmin, ymax - ymin) / 2 if radius is None else radius
    c = np.asarray(center, dtype=float).reshape(-1)
    r = float(radius)
    if c.shape != (2,) or not np.all(np.isfinite(c)) or not (math.isfinite(r) and r > 0):
        raise ParameterError(f"workspace disc needs a finite centre (x, y) and radius > 0, got {center!r}, {radius!r}")
    return c, r


def _check_sphere_world(discs: NDArray[np.float64], c0: NDArray[np.float64], r0: float) -> None:
    for i, (cx, cy, r) in enumerate(discs):
        if math.hypot(cx - c0[0], cy - c0[1]) + r >= r0:
            raise ParameterError(
                f"disc obstacle {i + 1} (centre ({cx:g}, {cy:g}), radius {r:g}) is not strictly inside the "
                f"workspace disc (centre ({c0[0]:g}, {c0[1]:g}), radius {r0:g}); a sphere world needs that"
            )
    for i in range(len(discs)):
        for j in range(i + 1, len(discs)):
            if math.hypot(*(discs[i, :2] - discs[j, :2])) <= discs[i, 2] + discs[j, 2]:
                raise ParameterError(f"disc obstacles {i + 1} and {j + 1} overlap; a sphere world needs disjoint discs")


def _rk_terms(x: NDArray[np.float64], y: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
              c0: NDArray[np.float64], r0: float) -> tuple[NDArray[np.float64], ...]:
    """gamma, log beta, sum(grad beta_i / beta_i) (x and y) and the free mask at points (x, y)."""
    dx, dy = x - goal[0], y - goal[1]
    gamma = dx * dx + dy * dy
    qx, qy = x - c0[0], y - c0[1]
    b0 = r0 * r0 - (qx * qx + qy * qy)
    valid = b0 > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        log_beta = np.log(np.where(valid, b0, 1.0))
        sx = -2 * qx / b0
        sy = -2 * qy / b0
        for cx, cy, r in discs:
            px, py = x - cx, y - cy
            bi = px * px + py * py - r * r
            valid = valid & (bi > 0)
            log_beta = log_beta + np.log(np.where(bi > 0, bi, 1.0))
            sx = sx + 2 * px / bi
            sy = sy + 2 * py / bi
    return gamma, log_beta, sx, sy, valid


def sphere_nav_function(
    world_or_discs: Any,
    goal: ArrayLike,
    *,
    kappa: float,
    workspace_center: ArrayLike | None = None,
    workspace_radius: float | None = None,
    grid: Grid,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rimon-Koditschek navigation function of a sphere world, at the cell centres of ``grid``.

    ``phi = gamma / (gamma**kappa + beta)**(1/kappa)`` with ``gamma = |q - goal|**2``,
    ``beta = beta_0 * prod(beta_i)``, ``beta_0 = r_0**2 - |q - c_0|**2`` (the workspace disc) and
    ``beta_i = |q - c_i|**2 - r_i**2`` (the disc obstacles). ``phi`` is 0 at the goal and 1 on every
    boundary; for ``kappa`` large enough its only minimum is the goal (the other critical points
    are saddles). Evaluated in log scale, so neither ``gamma**kappa`` nor ``beta`` overflows.

    The analytic gradient used is
    ``grad phi = phi * (beta / (gamma**kappa + beta)) * (grad gamma / gamma - (1/kappa) sum(grad beta_i / beta_i))``.

    Parameters
    ----------
    world_or_discs : World or array (M, 3)
        A world whose obstacles are all circles, or discs ``(cx, cy, r)``.
    goal : (x, y)
    kappa : float
        The exponent (> 0; the theory needs it large enough, about the number of obstacles or more).
    workspace_center, workspace_radius :
        The workspace disc; default: the circle inscribed in the world's bounds.
    grid : Grid
        Where to evaluate.

    Returns
    -------
    phi : ndarray, shape ``grid.shape``
        In [0, 1]; 1 outside the free space (inside obstacles, outside the workspace).
    grad : ndarray, shape ``(2,) + grid.shape``
        ``(d phi / dx, d phi / dy)``; 0 outside the free space.

    Examples
    --------
    >>> from gridfield.core.grid import Grid
    >>> phi, grad = sphere_nav_function([[0.5, 0.0, 0.2]], (-0.5, 0.0), kappa=2, workspace_center=(0, 0),
    ...                                 workspace_radius=1, grid=Grid((1, 4), 0.5, (-1, -0.25)))
    >>> phi.round(4)  # at x = -0.75, -0.25, 0.25, 0.75 (goal at -0.5, disc [0.3, 0.7])
    array([[0.0764, 0.0889, 0.9682, 0.998 ]])
    >>> grad[0].round(4)  # d phi / dx
    array([[-0.6751,  0.8091,  0.8499, -0.0312]])
    """
    discs = _discs_of(world_or_discs)
    c0, r0 = _workspace(world_or_discs, workspace_center, workspace_radius)
    k = float(kappa)
    if not (math.isfinite(k) and k > 0):
        raise ParameterError(f"kappa must be a positive number, got {kappa!r}")
    g = np.asarray(goal, dtype=float).reshape(-1)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise ParameterError(f"goal must be two finite numbers (x, y), got {goal!r}")
    xs, ys = grid.cell_centers()
    x, y = np.meshgrid(xs, ys)
    phi, gx, gy = _rk_phi_grad(x, y, g, discs, c0, r0, k)
    return phi, np.stack([gx, gy])


def _rk_phi_grad(x: NDArray[np.float64], y: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
                 c0: NDArray[np.float64], r0: float, kappa: float) -> tuple[NDArray[np.float64], ...]:
    from scipy.special import expit

    gamma, log_beta, sx, sy, valid = _rk_terms(x, y, goal, discs, c0, r0)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_gamma = np.log(gamma)
        log_phi = log_gamma - np.logaddexp(kappa * log_gamma, log_beta) / kappa
        phi = np.exp(log_phi)
        ratio = expit(log_beta - kappa * log_gamma)  # beta / (gamma**kappa + beta)
        bx = 2 * (x - goal[0]) / gamma - sx / kappa
        by = 2 * (y - goal[1]) / gamma - sy / kappa
        gx = phi * ratio * bx
        gy = phi * ratio * by
    at_goal = gamma == 0
    phi = np.where(valid, np.where(at_goal, 0.0, phi), 1.0)
    gx = np.where(valid & ~at_goal, gx, 0.0)
    gy = np.where(valid & ~at_goal, gy, 0.0)
    return phi, gx, gy


def _follow_sphere_nav(start: NDArray[np.float64], goal: NDArray[np.float64], discs: NDArray[np.float64],
                       c0: NDArray[np.float64], r0: float, kappa: float, step: float, tolerance: float,
                       max_iterations: int, window: int) -> tuple[NDArray[np.float64], str, int]:
    """Normalized descent along -grad phi: the direction is that of the bracket in the gradient formula,
    which needs no exponentials and never underflows. Steps shrink near obstacles to half the clearance."""
    p = start.astype(float).copy()
    pts = [p.copy()]
    best = math.inf
    since = 0
    for it in range(1, max_iterations + 1):
        if math.hypot(*(p - goal)) <= tolerance:
            pts.append(goal.copy())
            return np.array(pts), "reached", it - 1
        gamma, log_beta, sx, sy, _ = _rk_terms(p[:1], p[1:], goal, discs, c0, r0)
        bx = 2 * (p[0] - goal[0]) / gamma[0] - sx[0] / kappa
        by = 2 * (p[1] - goal[1]) / gamma[0] - sy[0] / kappa
        nrm = math.hypot(bx, by)
        if not (nrm > 0 and math.isfinite(nrm)):
            return np.array(pts), "local_minimum", it - 1
        clearance = min([r0 - math.hypot(*(p - c0))] + [math.hypot(p[0] - cx, p[1] - cy) - r for cx, cy, r in discs])
        h = min(step, max(0.5 * clearance, 1e-3 * step), math.hypot(*(p - goal)))
        p = p - h * np.array([bx, by]) / nrm
        if not _rk_terms(p[:1], p[1:], goal, discs, c0, r0)[4][0]:
            pts.append(p.copy())
            return np.array(pts), "collision", it
        pts.append(p.copy())
        log_phi = math.log(gamma[0]) - np.logaddexp(kappa * math.log(gamma[0]), log_beta[0]) / kappa
        if log_phi < best - 1e-12:
            best = log_phi
            since = 0
        else:
            since += 1
            if since >= window:
                return np.array(pts), "local_minimum", it
    return np.array(pts), "max_iterations", max_iterations


#: kappa values tried, in order, when plan_sphere_nav is given none.
KAPPA_LADDER = (2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0)


#: The largest default step budget of ``sphere-nav`` and ``star-nav`` (50 crossings of the workspace's
#: diameter + 1000 steps; ten times that of their default step, 1/200 of the workspace radius). A smaller
#: ``step``, whose default budget would exceed it, is refused up front unless ``max_iterations`` is given:
#: a star-nav step costs about a millisecond, and ``step=1e-9`` made the budget ~1e12 steps.
MAX_DEFAULT_ITERATIONS = 210_000


def _step_budget(fol: Follower, r0: float, planner: str) -> tuple[float, float, int, int]:
    """``step``, ``tolerance``, ``max_iterations`` and ``progress_window`` of a follower on a workspace disc of
    radius ``r0``: the given values, else 1/200 of ``r0``, ``step``, and 50 crossings of the diameter + 1000.

    Examples
    --------
    >>> _step_budget(Follower(), 5.0, "sphere-nav")
    (0.025, 0.025, 21000, 200)
    >>> _step_budget(Follower(step=1e-9), 5.0, "star-nav")
    Traceback (most recent call last):
    ...
    gridfield.core.errors.ParameterError: star-nav: step=1e-09 is too small for the default step budget ...
    """
    step = r0 / 200 if fol.step is None else float(fol.step)
    tol = step if fol.tolerance is None else float(fol.tolerance)
    if fol.max_iterations is not None:
        max_it = int(fol.max_iterations)
    else:
        crossings = 2 * r0 / step  # a float: a subnormal step gives inf, refused below (no OverflowError)
        budget = 50.0 * crossings + 1000
        max_it = 50 * int(crossings) + 1000 if math.isfinite(crossings) else MAX_DEFAULT_ITERATIONS + 1
        if max_it > MAX_DEFAULT_ITERATIONS:
            raise ParameterError(
                f"{planner}: step={step:g} is too small for the default step budget (50 crossings of the workspace's "
                f"diameter {2 * r0:g} + 1000 = {budget:.3g} steps, more than {MAX_DEFAULT_ITERATIONS}); use "
                f"step >= {2 * r0 / ((MAX_DEFAULT_ITERATIONS - 1000) // 50):.3g} or give max_iterations")
    return step, tol, max_it, int(fol.progress_window)


def plan_sphere_nav(world: Any, start: NDArray[np.float64], goal: NDArray[np.float64], params: Mapping[str, Any], *,
                    cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``sphere-nav``: follow the Rimon-Koditschek navigation function of a sphere world.

    The workspace is the disc inscribed in the world's bounds (or ``params["workspace_center"]`` /
    ``params["workspace_radius"]``); every obstacle must be a circle strictly inside it, and the circles
    must be disjoint (else :class:`ParameterError`). The follower takes normalized steps along the
    analytic ``-grad phi`` (``step``, default 1/200 of the workspace radius, shortened to half the
    clearance near obstacles) until within ``tolerance`` (default ``step``) of the goal; no progress in
    ``phi`` over 200 steps is a ``local_minimum`` (``kappa`` too small). Without ``kappa`` the values
    of :data:`KAPPA_LADDER` are tried in turn and the first that reaches the goal is kept
    (``extra["kappa"]``).

    Parameters
    ----------
    world : World
        A world whose obstacles are all circles.
    start, goal : ndarray, shape (2,)
        World points in the free space of the sphere world.
    params : mapping
        ``kappa``, ``workspace_center``, ``workspace_radius``, ``step``, ``tolerance``,
        ``max_iterations``, ``progress_window``; all optional.

    Returns
    -------
    Path
        ``status`` ``"reached"``, ``"local_minimum"``, ``"collision"`` or ``"max_iterations"``;
        ``params`` with the ``kappa`` used; ``extra`` with ``kappa``, ``tried`` (each kappa and its
        status), ``workspace_center`` and ``workspace_radius``; ``min_clearance`` from the world's exact
        distance.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1.5}}]})
    >>> p = plan_sphere_nav(w, np.array([2.0, 5.5]), np.array([8.0, 5.0]), {"kappa": 4})
    >>> p.status, p.end.tolist()
    ('reached', [8.0, 5.0])

    Exactly behind a disc, on the line through its centre, the descent runs into the saddle point:

    >>> plan_sphere_nav(w, np.array([2.0, 5.0]), np.array([8.0, 5.0]), {"kappa": 4}).status
    'local_minimum'
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    t0 = time.perf_counter()
    discs = _discs_of(world)
    nav = params.group(Navigation)
    c0, r0 = _workspace(world, nav.workspace_center, nav.workspace_radius)
    _check_sphere_world(discs, c0, r0)
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    for name, p in (("start", start), ("goal", goal)):
        if not _rk_terms(p[:1], p[1:], goal, discs, c0, r0)[4][0]:
            raise GridfieldError(f"{name} ({p[0]:g}, {p[1]:g}) is not in the free space of the sphere world "
                                 f"(inside the workspace disc of radius {r0:g} and outside every disc)")
    step, tol, max_it, window = _step_budget(params.group(Follower), r0, "sphere-nav")
    kappas = [float(nav.kappa)] if nav.kappa is not None else list(KAPPA_LADDER)  # the registry: finite, > 0
    tried = []
    for kappa in kappas:
        pts, status, its = _follow_sphere_nav(start, goal, discs, c0, r0, kappa, step, tol, max_it, window)
        tried.append((kappa, status))
        if status == "reached":
            break
    used = dict(params)
    used["kappa"] = kappa
    clearance = float(world.distance(pts).min()) if hasattr(world, "distance") and discs.size else math.nan
    extra = {"kappa": kappa, "tried": tried, "workspace_center": c0.tolist(), "workspace_radius": r0}
    return Path(pts, status, "sphere-nav", its, used, time.perf_counter() - t0, clearance, extra)


def sphere_nav_field(gridmap: GridMap, goal: ArrayLike, nav: Any) -> NavigationField:
    """The ``sphere-nav`` field of a map rasterized from a world of circles (``gridfield field``).

    Parameters
    ----------
    gridmap : GridMap
        Rasterized from a world of circles (``gridmap.world``).
    goal : (x, y)
    nav : Navigation
        The navigation parameters (``kappa``, ``workspace_center``, ``workspace_radius``); without ``kappa``
        the number of obstacles + 1.

    Returns
    -------
    NavigationField
        Of kind ``"sphere-nav"``, with the analytic gradient.

    Examples
    --------
    >>> from gridfield.core.params import Navigation, validate
    >>> from gridfield.geometry.rasterize import rasterize
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1}}]})
    >>> nav = sphere_nav_field(rasterize(w, 0.5), (8.0, 8.0), validate({"kappa": 3}).group(Navigation))
    >>> nav.kind, nav.potential.shape
    ('sphere-nav', (20, 20))
    """
    world = gridmap.world
    if world is None:
        raise ParameterError("the sphere-nav field needs a vector world of circles; this map is a grid")
    discs = _discs_of(world)
    c0, r0 = _workspace(world, nav.workspace_center, nav.workspace_radius)
    _check_sphere_world(discs, c0, r0)
    g = np.asarray(goal, dtype=float).reshape(-1)
    world.check_point("goal", g)
    kappa = float(len(discs) + 1 if nav.kappa is None else nav.kappa)  # kappa=None: as when not given
    phi, grad = sphere_nav_function(discs, g, kappa=kappa, workspace_center=c0, workspace_radius=r0,
                                    grid=gridmap.grid)
    (gr, gc), = gridmap.grid.world_to_cell(g)[0]
    return NavigationField(gridmap, phi, g, (int(gr), int(gc)), "sphere-nav",
                           {"kappa": kappa, "workspace_center": c0.tolist(), "workspace_radius": r0},
                           {"grad_x": grad[0], "grad_y": grad[1]})
