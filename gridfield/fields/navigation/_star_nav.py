"""Star worlds: the planner ``star-nav``, its follower, the choice of ``kappa`` and the check of ``lambda``.

The planner ``star-nav`` (:func:`plan_star_nav`) follows ``-grad phi(h_lambda(q))`` like ``sphere-nav``.
:func:`star_nav_field` gives the arrays of ``gridfield field --planner star-nav`` and the seed's
figures (:func:`gridfield.plot.plot_star_world`).

Without a ``kappa``, the smallest of :data:`KAPPA_LADDER` with no spurious minimum found on a lattice
(:func:`spurious_minima`) is used; a ``lambda`` for which ``h_lambda`` folds (:func:`folds`) is warned
about (:class:`StarNavWarning`). The star world and ``h_lambda`` are built in ``_star_world``.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError
from ...core.params import Follower, Navigation, Params, validate
from ...core.path import Path
from ._field import NavigationField
from ._sphere import _step_budget
from ._star_world import StarWorld, _check_free, _model_terms, nav_function, star_to_sphere, star_world

#: a follower step whose segment would touch an obstacle is cut to this fraction of the exact clearance
CLEARANCE_STEP = 0.5

#: kappa values tried, in order, when ``kappa`` is not given (starting at seed 002's 3).
KAPPA_LADDER = (3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0)


class StarNavWarning(UserWarning):
    """``kappa`` too small (spurious local minima detected) or ``lambda`` too small (``h_lambda`` folds)."""


def _star_params(params: Mapping[str, Any] | None) -> tuple[Params, float | None, float]:
    """The checked parameters (the registry's rules: ``kappa`` and ``lambda`` finite numbers > 0), ``kappa``
    (None: chosen from :data:`KAPPA_LADDER`) and ``lambda``."""
    p = validate(params)  # a raw mapping from a direct call is checked too
    nav = p.group(Navigation)
    return p, nav.kappa, float(nav.lam)


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
    >>> from gridfield.geometry.world import world_from_dict
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
    there ``h_lambda`` is not a diffeomorphism (``lambda`` too small).

    Parameters
    ----------
    sw : StarWorld
        The star world (:func:`star_world`).
    lam : float
        The transformation's ``lambda``.
    n : int, optional
        Lattice points per side of the workspace's bounding square.

    Returns
    -------
    ndarray of float, shape (m, 2)
        The free lattice points where the transformation folds (empty: none found).

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> sw = star_world(w, (8, 2))
    >>> len(folds(sw, lam=10.0, n=41)), len(folds(sw, lam=0.01, n=41)) > 0
    (0, True)
    """
    xs, ys, _ = _sample_lattice(sw, int(n))
    x, y = np.meshgrid(xs, ys)
    q = np.column_stack([x.ravel(), y.ravel()])
    _, jac, _, free = star_to_sphere(sw, q, lam)
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    return q[free & np.logical_not(det > 0)]


def choose_kappa(sw: StarWorld, kappa: float | None, lam: float) -> tuple[float, list[tuple[float, int]]]:
    """The kappa to use and the (kappa, spurious minima found) tried; warns when a given kappa is too small.

    Parameters
    ----------
    sw : StarWorld
        The star world.
    kappa : float or None
        A given kappa (checked, kept, with a :class:`StarNavWarning` when :func:`spurious_minima` finds
        minima besides the goal), or None: the first value of :data:`KAPPA_LADDER` without one (its last
        value when every one has some).
    lam : float
        The transformation's ``lambda``.

    Returns
    -------
    kappa : float
        The kappa to use.
    tried : list of (float, int)
        Each kappa tried and how many spurious minima it has.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> choose_kappa(star_world(w, (8, 2)), None, 10.0)
    (3.0, [(3.0, 0)])
    """
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
        The step budget, and the steps without a new lowest ``phi`` that end a start as ``local_minimum``
        (0: no such rule).

    Returns
    -------
    list of (points (K, 2), status, iterations), one per start.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
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
        flat = go & (since[idx] >= window) if window else np.zeros_like(go)  # window 0: no progress rule
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
                  params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``star-nav``: follow the star-world navigation function ``phi(h_lambda(q))``.

    Parameters (``params``, the registry's :class:`~gridfield.core.params.Navigation` and
    :class:`~gridfield.core.params.Follower`): ``kappa``, ``lambda``, ``workspace_center``, ``workspace_radius``;
    ``step`` (default 1/200 of the workspace radius), ``tolerance`` (default ``step``), ``max_iterations``
    (default: 50 crossings of the workspace's diameter + 1000 steps; a ``step`` whose default budget would
    exceed :data:`~gridfield.fields.navigation._sphere.MAX_DEFAULT_ITERATIONS` is refused unless
    ``max_iterations`` is given; 0: no step), ``progress_window`` (200; 0: off). Without ``kappa`` the
    values of :data:`KAPPA_LADDER` are tried and the first with no spurious minimum detected
    (:func:`spurious_minima`) is used, and raised to the next values (twice at most) when the path still ends in a ``local_minimum`` (one too close to an obstacle for the
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
    params, kappa, lam = _star_params(params)
    t0 = time.perf_counter()
    nav = params.group(Navigation)
    sw = star_world(world, goal, workspace_center=nav.workspace_center, workspace_radius=nav.workspace_radius)
    start = np.asarray(start, dtype=float).reshape(2)
    try:
        _check_free(sw, "start", start)
    except ParameterError as e:
        raise GridfieldError(str(e)) from None
    r0 = sw.workspace_radius
    step, tol, max_it, window = _step_budget(params.group(Follower), r0, "star-nav")
    n_folds = _warn_folds(sw, lam)
    given = kappa is not None
    kappa, tried = choose_kappa(sw, kappa, lam)
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
    ``gridfield field --planner star-nav``), as a :class:`~gridfield.fields.navigation.NavigationField` of kind
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
    >>> from gridfield.geometry.rasterize import as_gridmap
    >>> w = read_world(bundled_map("star_two.yaml"))
    >>> nav = star_nav_field(as_gridmap(w, 0.5), w.goal, w.params)
    >>> nav.kind, nav.params["kappa"], float(np.nanmin(nav.value))
    ('star-nav', 3.0, 0.0)
    """
    world = getattr(gridmap, "world", None)
    if world is None or not hasattr(world, "obstacles"):
        raise ParameterError("the star-nav field needs a vector world of star-shaped obstacles; this map is a grid")
    p, kappa, lam = _star_params(params)
    nav = p.group(Navigation)
    g = np.asarray(goal, dtype=float).reshape(-1)
    sw = star_world(world, g, workspace_center=nav.workspace_center, workspace_radius=nav.workspace_radius)
    kappa, _ = choose_kappa(sw, kappa, lam)
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

    Parameters
    ----------
    sw : StarWorld
        The star world.
    kappa, lam : float
        The navigation function's ``kappa`` and the transformation's ``lambda``.
    x, y : ndarray of float
        The lattice (:func:`numpy.meshgrid` arrays).
    phi : ndarray of float, optional
        ``phi(h_lambda)`` on the lattice when the caller has it (else computed).
    lines : int, optional
        How many lattice lines of each direction are mapped.

    Returns
    -------
    dict
        The arrays above, with ``kappa``, ``lambda``, ``x``, ``y``, ``centers`` and ``workspace``;
        :func:`gridfield.plot.plot_star_world` draws it.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[3, 3], [5, 3], [5, 5], [3, 5]]}]})
    >>> x, y = np.meshgrid(np.linspace(0, 10, 11), np.linspace(0, 10, 11))
    >>> d = star_figure_data(star_world(w, (8, 2)), kappa=3, lam=10, x=x, y=y)
    >>> d["phi"].shape, float(d["humps"].max()), float(d["phi"][2, 8])  # phi is 0 at the goal (8, 2)
    ((11, 11), 1.0, 0.0)
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
