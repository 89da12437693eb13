"""A robot that turns (issue 45): the pose grid built and a plan on it, beside a shapely-per-pose reference.

Run ``python benchmarks/turning.py [--size 200] [--headings 72] [--repeat 3] [--sample 20000]``.

The map: ``size x size`` cells of 5 cm (a 10 m room at 200), a wall across its middle with a 1.0 m
door, and 24 random boxes; the robot a 1.6 m x 0.5 m cart. Timed side by side in one run:

- ``apply_robot(gm, cart, headings=N)``: the pose grid ``[heading, row, col]``;
- the reference: shapely placing the cart, swept through each pose's heading bin, at the poses of a
  random sample of ``--sample`` poses (``shapely.intersects`` vectorized over the sample against the
  union of the occupied cell squares), extrapolated to every pose; the sample's verdicts are compared
  with the pose grid's (they must agree: the same swept shapes);
- ``plan_poses`` with ``potential`` (default) and ``wavefront-octile`` from below the wall to above it
  (the cart must turn to pass the door).

Targets (issue 45): a 200 x 200 x 72 pose grid in <= 2 s and a plan in <= 1 s.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
import shapely

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from _common import machine_facts, markdown_table  # noqa: E402

from gridfield.core.grid import Grid, GridMap  # noqa: E402
from gridfield.core.limits import override  # noqa: E402
from gridfield.following.posefollow import plan_poses  # noqa: E402
from gridfield.geometry.cspace import apply_robot, heading_centres, swept_robot  # noqa: E402
from gridfield.geometry.world import Robot  # noqa: E402

END_A, END_B = (2.5, 2.0), (7.5, 8.0)  # the query's start and goal positions
CART = Robot(vertices=[[-0.8, -0.25], [0.8, -0.25], [0.8, 0.25], [-0.8, 0.25]])


def room(size: int, seed: int = 0) -> GridMap:
    h = 10.0 / size
    occ = np.zeros((size, size), bool)
    mid = size // 2
    occ[mid - 1:mid + 1, :] = True
    door = round(0.5 / h)
    occ[mid - 1:mid + 1, mid - door:mid + door] = False
    rng = np.random.default_rng(seed)
    box = max(2, round(0.4 / h))
    placed = 0
    while placed < 24:
        r, c = rng.integers(0, size - box, 2)
        centre = ((c + box / 2) * h, (r + box / 2) * h)
        near_ends = min(math.dist(centre, END_A), math.dist(centre, END_B)) < 1.6
        if abs(r + box / 2 - mid) > size // 6 and not near_ends:
            occ[r:r + box, c:c + box] = True
            placed += 1
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
    return GridMap(Grid((size, size), h), occ)


def reference(gm: GridMap, headings: int, sample: int, pm_occ: np.ndarray, seed: int = 1) -> tuple[float, int]:
    """Seconds per pose of shapely's verdict, and how many sampled poses disagree with the pose grid."""
    h = gm.grid.resolution
    cells = np.argwhere(gm.occupied)
    c = gm.grid.cell_to_world(cells)
    obstacles = shapely.union_all(shapely.box(c[:, 0] - h / 2, c[:, 1] - h / 2, c[:, 0] + h / 2, c[:, 1] + h / 2))
    shapely.prepare(obstacles)
    rng = np.random.default_rng(seed)
    n, rows, cols = pm_occ.shape
    pick = np.column_stack([rng.integers(0, n, sample), rng.integers(0, rows, sample), rng.integers(0, cols, sample)])
    half = math.pi / headings
    swept = [swept_robot(CART, t - half, t + half, h) for t in heading_centres(headings)]
    xy = gm.grid.cell_to_world(pick[:, 1:])
    t0 = time.perf_counter()
    shapes = [shapely.affinity.translate(swept[k], x, y) for k, (x, y) in zip(pick[:, 0], xy, strict=True)]
    hit = shapely.intersects(np.array(shapes, dtype=object), obstacles)
    per_pose = (time.perf_counter() - t0) / sample
    return per_pose, int(np.count_nonzero(hit != pm_occ[tuple(pick.T)]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=200)
    ap.add_argument("--headings", type=int, default=72)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--sample", type=int, default=20000)
    a = ap.parse_args()
    import shapely.affinity  # noqa: F401  # the reference's translate

    gm = room(a.size)
    apply_robot(room(20), CART, headings=8)  # warm the imports and the kernels
    build, plans = [], {"potential": [], "wavefront-octile": []}
    with override(10**9):
        for _ in range(a.repeat):
            t = time.perf_counter()
            pm = apply_robot(gm, CART, headings=a.headings)
            build.append(time.perf_counter() - t)
            for planner in plans:
                t = time.perf_counter()
                path, _ = plan_poses(pm, (*END_A, 0.0), END_B, planner=planner)
                plans[planner].append(time.perf_counter() - t)
                assert path.status == "reached", path.status
        per_pose, disagree = reference(gm, a.headings, a.sample, pm.occupied)
    poses = pm.occupied.size
    rows = [["pose grid build (apply_robot)", f"{min(build):.3f}", "<= 2 s"],
            ["shapely per pose, extrapolated", f"{per_pose * poses:.1f}",
             f"{per_pose * 1e6:.1f} us/pose; {disagree} of {a.sample} sampled poses disagree"],
            ["plan, potential (default)", f"{min(plans['potential']):.3f}", "<= 1 s"],
            ["plan, wavefront-octile", f"{min(plans['wavefront-octile']):.3f}", "<= 1 s"]]
    print(f"{a.size} x {a.size} x {a.headings} poses ({poses} in all), min of {a.repeat}; {machine_facts()}")
    print(markdown_table(["step", "seconds", "note"], rows))
    print(f"build / shapely: {per_pose * poses / min(build):.0f}x")


if __name__ == "__main__":
    main()
