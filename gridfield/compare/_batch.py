"""The batch comparison: many random start/goal pairs on one world, planners against the exact
optimum (:func:`batch_compare`). Part of :mod:`gridfield.compare` (import the name from there)."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..core.errors import GridfieldError, ParameterError, check_positive
from ..geometry.world import World
from ._common import _as_world, _grid_factor, optimum_solver
from ._metrics import length_ratio


def _progress(iterable: Any, *, total: int, enabled: bool, desc: str) -> Any:
    if not enabled or not sys.stderr.isatty():
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, file=sys.stderr, leave=False)


def _random_pairs(world: World, gm: Any, n: int, rng: np.random.Generator, margin: float,
                  optimum: Callable[[NDArray[np.float64], NDArray[np.float64]], float]
                  ) -> list[tuple[NDArray[np.float64], NDArray[np.float64], float]]:
    xmin, ymin, xmax, ymax = world.bounds
    pairs: list[tuple[NDArray[np.float64], NDArray[np.float64], float]] = []
    tries = 0
    while len(pairs) < n:
        tries += 1
        if tries > 200 * n + 1000:
            raise GridfieldError(f"found only {len(pairs)} of {n} connected free start/goal pairs in "
                                 f"{world.source or 'the world'}; is there enough free space?")
        pts = rng.uniform([xmin, ymin], [xmax, ymax], size=(2, 2))
        if not (world.distance(pts) > margin).all() or not gm.is_free(pts).all():
            continue
        if np.hypot(*(pts[1] - pts[0])) < 2 * margin:
            continue
        opt = optimum(pts[0], pts[1])
        if not math.isfinite(opt):
            continue
        pairs.append((pts[0], pts[1], opt))
    return pairs


def batch_compare(
    world: World,
    n_pairs: int,
    *,
    resolution: float,
    params: Mapping[str, Any] | None = None,
    seed: int = 0,
    progress: bool = True,
    planners: Sequence[str] = ("potential", "exact-potential", "wavefront-octile"),
) -> dict[str, Any]:
    """Plan many random start/goal pairs on one world and compare planners with the optimum.

    Pairs are drawn uniformly in the bounds, both points at least one cell from every obstacle
    (and free on the grid), connected in the world; the visibility graph gives the optimum. On a
    grid map the exact planners use its exact polygons (:func:`gridfield.geometry.gridpoly.grid_world`), the
    optimum is the any-angle one (:mod:`gridfield.exact.anyangle`) and the grid planners run on the map
    downsampled to ``resolution`` (a multiple of the map's).

    Parameters
    ----------
    world : World or GridMap
    n_pairs : int
    resolution : float
        Cell size of the grid planners.
    params : mapping, optional
    seed : int
        Seed of the random pairs.
    progress : bool
        Show a tqdm progress bar (only when stderr is a terminal).
    planners : sequence of str
        Planners to run (grid planners on the rasterized world); unavailable ones are reported
        in ``"skipped"``.

    Returns
    -------
    dict
        ``{"world", "resolution", "pairs", "seed", "planners": {name: {"success_rate",
        "statuses": {status: count}, "length_ratio": {"mean", "median", "max"} (reached pairs, to
        the optimum), "agreement_with_exact"?}}, "skipped": {name: reason}, "rows": [per pair]}``.

    Examples
    --------
    >>> from gridfield.geometry.world import world_from_dict
    >>> w = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})
    >>> r = batch_compare(w, 3, resolution=0.5, planners=("visibility",), progress=False)
    >>> r["planners"]["visibility"]["success_rate"], r["planners"]["visibility"]["length_ratio"]["max"]
    (1.0, 1.0)
    """
    from ..geometry.rasterize import rasterize
    from ..planners import get_planner, plan

    world, base = _as_world(world, "batch_compare")
    if isinstance(n_pairs, bool) or not isinstance(n_pairs, int | np.integer) or n_pairs < 1:
        raise ParameterError(f"n_pairs must be a positive integer, got {n_pairs!r}")
    h = check_positive("resolution", resolution)
    kinds: dict[str, str] = {}
    skipped: dict[str, str] = {}
    for name in planners:
        try:
            kinds[name] = get_planner(name)[1]
        except GridfieldError as e:
            skipped[name] = str(e)
    if base is None:
        gm = rasterize(world, h)
    else:
        from ..geometry.gridpoly import block_downsample

        gm = block_downsample(base, _grid_factor(base, h))
    optimum = optimum_solver(world)

    rng = np.random.default_rng(seed)
    pairs = _random_pairs(world, gm, int(n_pairs), rng, h, optimum)
    rows: list[dict[str, Any]] = []
    for s, g, opt in _progress(pairs, total=len(pairs), enabled=progress, desc="pairs"):
        row: dict[str, Any] = {"start": s.tolist(), "goal": g.tolist(), "optimal_length": opt}
        for name, kind in kinds.items():
            try:
                p = plan(name, gm if kind == "grid" else world, s, g, params)
            except GridfieldError as e:
                row[name] = {"status": "error", "error": str(e)}
                continue
            row[name] = {"status": p.status, "length": p.length,
                         "length_ratio": length_ratio(p, opt) if p.reached else math.nan,
                         "end": p.end.tolist(), "seconds": p.seconds}
        rows.append(row)

    summary: dict[str, Any] = {}
    for name in kinds:
        st = [r[name]["status"] for r in rows]
        ratios = np.asarray([r[name].get("length_ratio", math.nan) for r in rows], dtype=float)
        ratios = ratios[np.isfinite(ratios)]
        entry: dict[str, Any] = {
            "success_rate": float(np.mean([x == "reached" for x in st])),
            "statuses": {k: st.count(k) for k in sorted(set(st))},
            "length_ratio": {"mean": float(ratios.mean()) if ratios.size else math.nan,
                             "median": float(np.median(ratios)) if ratios.size else math.nan,
                             "max": float(ratios.max()) if ratios.size else math.nan},
        }
        summary[name] = entry
    if "potential" in kinds and "exact-potential" in kinds:
        agree = [r["potential"]["status"] == r["exact-potential"]["status"] for r in rows]
        summary["potential"]["agreement_with_exact"] = float(np.mean(agree))
    return {"world": world.source, "resolution": h, "pairs": len(rows), "seed": seed, "planners": summary,
            "skipped": skipped, "rows": rows}
