"""The harmonic navigation function: Laplace's equation, solved in shells and returned in log scale.

A discrete harmonic function has no local minimum away from its boundary, which makes it a navigation
function in exact arithmetic; in floating point it underflows far from the goal, hence the shells of
:func:`harmonic`. The sparse solves (MIC(0)-preconditioned conjugate gradients) are compiled kernels
(``gridfield/fields/_laplace.pyx``); scipy.sparse builds the matrix the residual is checked against.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core.errors import GridfieldError, ParameterError
from ...core.grid import GridMap
from ...core.params import validate
from ...core.path import Path
from ._field import NavigationField, _goal_cell, _plan_grid

# ----------------------------------------------------------------------------------------------
# Harmonic potential
# ----------------------------------------------------------------------------------------------
SOLVERS = ("pcg", "scipy-cg", "spsolve")
#: Relaxation of the MIC(0) preconditioner (1 = full modification; 0 = plain IC(0)).
MIC_OMEGA = 0.99


def _kernel_laplace() -> Any:
    """The compiled kernel module (gridfield/fields/_laplace.pyx), imported on first use."""
    from .. import _laplace  # type: ignore[attr-defined]  # a compiled extension, no stubs

    return _laplace


def _solve_dirichlet(unknown: NDArray[np.bool_], one: NDArray[np.bool_], rtol: float,
                     solver: str = "pcg") -> tuple[NDArray[np.float64], int]:
    """Solve the 5-point Laplace equation on the ``unknown`` cells with value 1 on the ``one`` cells and 0
    on every other cell (and outside the grid). Returns the solution on the grid (0 elsewhere) and the
    number of conjugate-gradient iterations (0 for the direct solver).

    The system is ``A w = b`` over the unknowns in row-major order: ``A`` has 4 on the diagonal and -1
    between neighbouring unknowns (a scipy.sparse CSR matrix built from index arrays), ``b`` counts each
    unknown's neighbours in ``one``. ``solver``: ``"pcg"`` compiled conjugate gradients with a MIC(0)
    preconditioner (default); ``"scipy-cg"`` :func:`scipy.sparse.linalg.cg` with the same preconditioner;
    ``"spsolve"`` the direct :func:`scipy.sparse.linalg.spsolve` (small maps, reference).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    rows, cols = unknown.shape
    n = int(unknown.sum())
    out = np.zeros(unknown.shape)
    if n == 0:
        return out, 0
    idx = np.full((rows + 2, cols + 2), -1, np.int64)
    idx[1:-1, 1:-1][unknown] = np.arange(n)
    left = idx[1:-1, :-2][unknown]
    right = idx[1:-1, 2:][unknown]
    down = idx[:-2, 1:-1][unknown]
    up = idx[2:, 1:-1][unknown]
    onep = np.pad(one, 1)
    b = (onep[1:-1, :-2].astype(np.float64)[unknown] + onep[1:-1, 2:][unknown] + onep[:-2, 1:-1][unknown]
         + onep[2:, 1:-1][unknown])
    nbr = np.stack([left, right, down, up])
    has = nbr >= 0
    row_i = np.concatenate([np.arange(n), np.broadcast_to(np.arange(n), nbr.shape)[has]])
    col_i = np.concatenate([np.arange(n), nbr[has]])
    vals = np.concatenate([np.full(n, 4.0), np.full(int(has.sum()), -1.0)])
    a = sp.csr_matrix((vals, (row_i, col_i)), shape=(n, n))
    k = _kernel_laplace()
    maxiter = 20 * (rows + cols) + 1000
    if solver == "pcg":
        x, its, _ = k.pcg_laplace(left, down, right, up, b, MIC_OMEGA, rtol, maxiter)
    elif solver == "scipy-cg":
        piv = k.mic0_factor(left, down, right, up, MIC_OMEGA)
        m = sla.LinearOperator((n, n), matvec=lambda r: k.mic0_apply(left, down, right, up, piv, np.ravel(r)),
                               dtype=np.float64)
        count = [0]

        def _count(_: Any) -> None:
            count[0] += 1

        x0 = k.mic0_apply(left, down, right, up, piv, b)
        x, _info = sla.cg(a, b, x0=x0, rtol=rtol, atol=0.0, M=m, maxiter=maxiter, callback=_count)
        its = count[0]
    elif solver == "spsolve":
        x = sla.spsolve(a.tocsc(), b)
        its = 0
    else:
        raise ParameterError(f"solver must be one of {SOLVERS}, got {solver!r}")
    r = a @ x - b  # (no BLAS calls here: OpenBLAS threads stall on a busy machine)
    resid = math.sqrt(float(np.sum(r * r)) / float(np.sum(b * b)))
    if not resid <= max(10 * rtol, 1e-10):
        raise GridfieldError(f"the harmonic solve ({solver}) did not converge: relative residual {resid:.2g} after "
                             f"{its} iterations (rtol {rtol:g})")
    out[unknown] = x
    return out, int(its)


def harmonic(
    gridmap: GridMap,
    goal: ArrayLike,
    *,
    tau: float = 1e-6,
    band: int | None = 64,
    rtol: float = 1e-12,
    solver: Literal["pcg", "scipy-cg", "spsolve"] = "pcg",
) -> NavigationField:
    """Harmonic navigation function: Laplace's equation with the goal at 0, obstacles and border at 1.

    Solves the 5-point discrete Laplace equation for ``w = 1 - u`` (1 at the goal cell, 0 on obstacle
    cells and outside the grid) on the free cells connected to the goal (4-connected: the cells a
    no-corner-cutting 8-connected path can reach). The sparse system (5-point Laplacian built from
    index arrays, a scipy.sparse matrix) is solved by conjugate gradients preconditioned by a modified
    incomplete Cholesky factorization, MIC(0) (compiled; ``solver="scipy-cg"`` runs
    :func:`scipy.sparse.linalg.cg` with the same preconditioner, ``"spsolve"`` the direct solver). Each
    solve is checked against the sparse matrix: relative residual at most ``max(10 * rtol, 1e-10)``.

    A discrete harmonic function has no local extrema away from its boundary values, so steepest
    descent over the neighbours reaches the goal -- in exact arithmetic. In floating point it does not:
    ``w`` decays exponentially along corridors and among clutter (by a factor of about
    ``exp(-pi * length / width)`` along a corridor), so far from the goal it drops below the solver's
    accuracy, underflows, and the field becomes numerically flat. This function therefore builds the
    field in *shells* and returns it in log scale:

    1. Shell 0 is the global solution ``w0``; its cells with ``w0 >= tau`` form the region ``S1``.
    2. Shell ``k`` solves Laplace's equation again, on the remaining reachable cells within taxicab
       distance ``band`` of the cells shell ``k - 1`` added (every remaining cell next to ``S_k`` is
       among them), with value 1 on ``S_k`` and 0 elsewhere; its cells with ``w_k >= tau`` join
       ``S_{k+1}``. Repeat until every reachable cell is in a shell.
    3. ``value = k * log(1/tau) - log(w_k)`` on shell ``k`` (0 at the goal, ``inf`` on obstacles and
       unreachable cells).

    Each shell is an exactly harmonic function of its own domain, resolved to relative accuracy, and
    every cell of shell ``k`` has a 4-neighbour of lower value (a larger ``w_k`` in the same shell, or a
    cell of an earlier shell), so the field has no local minimum other than the goal. Where ``w0`` is
    representable everywhere (small or open maps) there is one shell and ``value = -log(1 - u)``, a
    monotone function of the classic harmonic potential ``u``, which is kept in ``aux["harmonic"]``
    (``u`` of shell 0, 1 on obstacles).

    Parameters
    ----------
    gridmap : GridMap
    goal : (x, y)
    tau : float
        Smallest ``w`` trusted in a shell (default 1e-6, far above the solver's absolute error).
    band : int or None
        Width in cells of the region each continuation shell solves on (``None``: all remaining cells).
    rtol : float
        Relative residual tolerance of the conjugate-gradient solves.
    solver : {"pcg", "scipy-cg", "spsolve"}
        How each shell's linear system is solved (see above).

    Returns
    -------
    NavigationField
        ``kind="harmonic"``; ``aux`` holds ``harmonic`` (``u`` of shell 0), ``shell`` (shell index, -1
        off the field), ``shells``, ``iterations`` (CG iterations per shell) and ``seconds``.

    Examples
    --------
    >>> import numpy as np
    >>> from gridfield.core.grid import Grid, GridMap
    >>> nav = harmonic(GridMap(Grid((1, 3), 1.0), np.zeros((1, 3), bool)), (0.5, 0.5))
    >>> nav.aux["harmonic"].round(4)  # 1 - w: w = 1 at the goal, 0 beyond the border
    array([[0.    , 0.7333, 0.9333]])
    >>> bool(np.all(np.diff(nav.value[0]) > 0))
    True
    """
    from scipy import ndimage

    t0 = time.perf_counter()
    if not (isinstance(tau, int | float) and 0 < tau < 0.25):
        raise ParameterError(f"tau must be a number in (0, 0.25), got {tau!r}")
    if band is not None and (int(band) != band or band < 1):
        raise ParameterError(f"band must be a positive number of cells or None, got {band!r}")
    if not (0 < rtol < 1e-3):
        raise ParameterError(f"rtol must be in (0, 1e-3), got {rtol!r}")
    if solver not in SOLVERS:
        raise ParameterError(f"solver must be one of {SOLVERS}, got {solver!r}")
    g, (gr, gc) = _goal_cell(gridmap, goal)
    free = ~gridmap.occupied
    lab, _ = ndimage.label(free)  # 4-connected components
    reach = lab == lab[gr, gc]
    value = np.full(gridmap.shape, np.inf)
    value[gr, gc] = 0.0
    shell_of = np.full(gridmap.shape, -1, np.int32)
    shell_of[gr, gc] = 0
    inside = np.zeros(gridmap.shape, bool)
    inside[gr, gc] = True
    big_l = -math.log(tau)
    iterations: list[int] = []
    u0 = np.ones(gridmap.shape)
    u0[gr, gc] = 0.0
    shell = 0
    left = int(reach.sum()) - 1  # reachable cells not yet in a shell
    newest = (np.array([gr]), np.array([gc]))  # the cells the last shell added
    rows, cols = gridmap.shape
    while left > 0:
        if shell == 0 or band is None:
            box = (slice(None), slice(None))
            domain = reach & ~inside
        else:
            # Remaining cells next to S_k all lie next to the newest shell (the others were absorbed:
            # a cell next to the Dirichlet-1 set gets w >= 1/4), so the band around it suffices.
            rr, cc = newest
            box = (slice(max(0, int(rr.min()) - band), min(rows, int(rr.max()) + band + 1)),
                   slice(max(0, int(cc.min()) - band), min(cols, int(cc.max()) + band + 1)))
            seed = np.ones((box[0].stop - box[0].start, box[1].stop - box[1].start), bool)
            seed[rr - box[0].start, cc - box[1].start] = False
            near = ndimage.distance_transform_cdt(seed, metric="taxicab") <= band
            domain = reach[box] & ~inside[box] & near
        w, its = _solve_dirichlet(domain, inside[box], rtol, solver)
        iterations.append(its)
        if shell == 0:
            u0[domain] = 1.0 - w[domain]
        new = domain & (w >= tau)
        if not new.any():  # cannot happen: cells next to the shell have w >= 1/4
            raise GridfieldError("the harmonic shells stopped growing (the linear solve failed)")
        with np.errstate(divide="ignore"):
            value[box][new] = shell * big_l - np.log(w[new])
        shell_of[box][new] = shell
        inside[box] |= new
        nr, nc = np.nonzero(new)
        newest = (nr + (box[0].start or 0), nc + (box[1].start or 0))
        left -= len(nr)
        shell += 1
    params = {"tau": tau, "band": band, "rtol": rtol, "solver": solver}
    aux = {"harmonic": u0, "shell": shell_of, "shells": shell, "iterations": iterations,
           "seconds": time.perf_counter() - t0}
    return NavigationField(gridmap, value, g, (gr, gc), "harmonic", params, aux)


def plan_harmonic(gridmap: GridMap, start: NDArray[np.float64], goal: NDArray[np.float64],
                  params: Mapping[str, Any], *, cache: dict[Any, Any] | None = None) -> Path:
    """Planner ``harmonic``: harmonic navigation function (:func:`harmonic`) and steepest descent over
    the 8 neighbour cells.

    Parameters
    ----------
    gridmap : GridMap
    start, goal : ndarray, shape (2,)
        World points in free cells (checked by :func:`gridfield.planners.plan`).
    params : mapping
        Validated planner parameters (:mod:`gridfield.core.params`); none is read here (the field
        uses :func:`harmonic`'s defaults, the descent has no parameter).

    Returns
    -------
    Path
        From :func:`extract_path`: ``points`` from ``start`` to ``goal``, ``status``, ``params`` (the
        given ones and the field's), ``extra`` with ``value``, ``grid_length`` and ``field_seconds``.

    Examples
    --------
    >>> from gridfield.core.grid import Grid, GridMap
    >>> occ = np.zeros((5, 5), bool); occ[2, :4] = True
    >>> p = plan_harmonic(GridMap(Grid((5, 5), 1.0), occ), np.array([0.5, 0.5]), np.array([0.5, 4.5]), {})
    >>> p.status, bool(p.points[:, 0].max() > 4)
    ('reached', True)
    """
    params = validate(params)  # a raw mapping from a direct call is checked too
    t0 = time.perf_counter()
    nav = harmonic(gridmap, goal)
    return _plan_grid(nav, start, params, "harmonic", time.perf_counter() - t0, method="descent")
