"""
Seed 002: brushfire, the completeness cases and the navigation functions
========================================================================

Seed 002 drives the repulsive potential with the brushfire distance D(q) of a 100 x 100 grid and
descends the gradient with the seed's tuned values: eta = 4.5, zeta = 0.1, d* = 5, Q* = 4,
alpha = 2.1 and a goal tolerance of 0.1. It then tests completeness with four start/goal pairs:
cases 1 and 2 reach the goal, cases 3 and 4 end in a local minimum, so "the attractive/repulsive
potential technique is not complete". A navigation function has no such minimum and reaches the
goal in all four cases.

The seed's grid world is not published with its report; the world below is gridfield's, built for
the seed's start and goal points: convex obstacles near the first two cases' lines of sight and one
concave (L-shaped) obstacle opening towards each of the last two starts. The seed's "Nu" weight on
the repulsion has no separate parameter here: ``eta`` carries it.
"""

# %%
# The world and its brushfire
# ---------------------------
# The 8-connected brushfire on the 1-unit grid (euclidean distances between cell centres, the
# distance D(q) of the repulsive potential), with the generalized Voronoi diagram in red.

import matplotlib.pyplot as plt

from gridfield.distance.brushfire import brushfire
from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.geometry.world import world_from_dict
from gridfield.planners import plan
from gridfield.plot import plot_brushfire, plot_map, plot_potential, plot_surface

world = world_from_dict({
    "bounds": [0, 0, 100, 100], "border": "wall", "resolution": 1.0,
    "obstacles": [
        {"polygon": [[60, 62], [84, 62], [84, 65], [63, 65], [63, 86], [60, 86]]},  # opens towards case 3
        {"polygon": [[62, 42], [80, 42], [80, 22], [83, 22], [83, 45], [62, 45]]},  # opens towards case 4
        {"circle": {"center": [30, 45], "radius": 6}},
        {"rectangle": [35, 20, 45, 28]},
        {"circle": {"center": [40, 78], "radius": 5}},
    ],
}, source="seed 002 world")
grid = as_gridmap(world)
params = {"zeta": 0.1, "d_star": 5, "eta": 4.5, "q_star": 4, "step_rule": "scaled", "alpha": 2.1,
          "tolerance": 0.1, "metric": "euclidean"}
dmap = brushfire(grid, metric="euclidean")
plot_brushfire(dmap, title="brushfire distance D(q) and the GVD")

# %%
# The potential of case 1
# -----------------------
# Near the obstacles the repulsion is high and it fades out at Q* = 4; the attraction is quadratic
# within d* = 5 of the goal and conic beyond, with its minimum at the goal.

cases = {1: ((25, 18), (50, 51)), 2: ((22, 80), (50, 51)), 3: ((87, 89), (49, 44)), 4: ((62, 13), (86, 57))}
fields = {goal: build_field(grid, goal, params, dmap=dmap) for _, goal in cases.values()}
start, goal = cases[1]
first = plan("potential", grid, start, goal, params)
fig = plt.figure(figsize=(7, 5.6))
plot_surface(fields[goal], fig.add_subplot(projection="3d"), path=first, title="case 1: U(q) and the path")

# %%
# Tuning the parameters
# ---------------------
# The seed's four tuning runs on case 1: a lower Q* with a higher eta makes the repulsion
# stronger but shorter-ranged; a higher zeta strengthens the attraction; a larger alpha takes
# longer steps, so the robot needs fewer of them (until they overshoot near the goal).

tuning = {
    "eta 4.5, zeta 0.1, Q* 4, alpha 2.1": {},
    "eta 5.5, Q* 3": {"eta": 5.5, "q_star": 3},
    "eta 5.5, zeta 0.2": {"eta": 5.5, "zeta": 0.2},
    "alpha 2.6": {"alpha": 2.6},
}
fig, axes = plt.subplots(1, 4, figsize=(16, 4.4), layout="constrained")
for ax, (label, change) in zip(axes, tuning.items(), strict=True):
    tuned = {**params, **change}
    run = plan("potential", grid, start, goal, tuned)
    print(f"{label}: {run.status} in {run.iterations} steps")
    plot_potential(build_field(grid, goal, tuned, dmap=dmap), ax, path=run, colorbar=False, quiver=False,
                   title=f"{label}\n{run.status}, {run.iterations} steps")

# %%
# Testing completeness: the potential planner
# -------------------------------------------
# Cases 1 and 2 reach the goal; in cases 3 and 4 the attraction pulls the robot into the inner
# corner of an L-shaped obstacle, where it balances the repulsion: a local minimum (marked).

fig, axes = plt.subplots(2, 2, figsize=(11, 10), layout="constrained")
for ax, (case, (start, goal)) in zip(axes.flat, cases.items(), strict=True):
    path = plan("potential", grid, start, goal, params)
    print(f"case {case}: start {start}, goal {goal}: potential {path.status}")
    plot_potential(fields[goal], ax, path=path, colorbar=False, title=f"case {case}: {path.status}")

# %%
# The navigation functions
# ------------------------
# The wavefront from the goal (a navigation function on the grid: its only minimum is the goal)
# and the fast-marching distance (``fmm``) reach the goal from every start that can reach it.

fig, axes = plt.subplots(2, 2, figsize=(11, 10), layout="constrained")
for ax, (case, (start, goal)) in zip(axes.flat, cases.items(), strict=True):
    paths = [plan(name, grid, start, goal, params) for name in ("wavefront", "fmm")]
    print(f"case {case}: " + ", ".join(f"{p.planner} {p.status}" for p in paths))
    plot_map(grid, ax, paths=paths, start=start, goal=goal, title=f"case {case}")
