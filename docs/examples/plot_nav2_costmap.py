"""
Your Nav2 map in gridfield
==========================

A ROS 2 Nav2 user's map (the TurtleBot3 world, 0.05 m cells): the inflated costmap of Nav2's
inflation layer (robot radius 0.1 m, inflation radius 0.55 m, cost scaling factor 10), written as a
map_server YAML + PGM and read back bit-exactly, NavFn's potential and path on it next to the octile
wavefront's, and distance and gradient queries on the costmap at many points at once.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from gridfield.demo import crop_to_known
from gridfield.fields.costmap import inflate
from gridfield.fields.navfn import navfn
from gridfield.io import bundled_map, read, read_ros_map, write_costmap
from gridfield.planners import plan
from gridfield.plot import plot_map

grid = crop_to_known(read_ros_map(bundled_map("turtlebot3_world/map.yaml")))
costmap = inflate(grid, robot_radius=0.1, inflation_radius=0.55, cost_scaling_factor=10.0)
with tempfile.TemporaryDirectory() as d:
    back = read(write_costmap(Path(d) / "costmap.yaml", costmap))  # what `gridfield costmap --out` writes
print("read back bit-exactly:", bool(np.array_equal(back.cost, costmap.cost)))

start, goal = (-2.0, -0.5), (2.0, 0.5)
paths = [plan(name, costmap, start, goal) for name in ("navfn", "wavefront-octile")]
for p in paths:
    print(p.planner, p.status, round(p.length, 2), "min clearance", round(p.min_clearance, 3))
nav = navfn(costmap, goal)

# queries: 100 000 points at once
rng = np.random.default_rng(0)
x0, x1, y0, y1 = costmap.grid.extent
pts = np.stack([rng.uniform(x0, x1, 100_000), rng.uniform(y0, y1, 100_000)], axis=1)
d, g = costmap.distance(pts), costmap.gradient(pts)
print("median distance to an obstacle", round(float(np.nanmedian(d)), 3), "m")

fig, axes = plt.subplots(1, 3, figsize=(16, 5), layout="constrained")
ext = costmap.grid.extent
im = axes[0].imshow(costmap.cost, origin="lower", extent=ext, cmap="magma_r", vmin=0, vmax=254)
fig.colorbar(im, ax=axes[0], label="Nav2 cost")
axes[0].set_title("inflated costmap")
pot = np.where(np.isfinite(nav.value), nav.value, np.nan)
im = axes[1].imshow(pot, origin="lower", extent=ext, cmap="viridis")
fig.colorbar(im, ax=axes[1], label="NavFn potential")
axes[1].set_title("NavFn's navigation function from the goal")
plot_map(costmap, axes[2], paths=paths, start=start, goal=goal, title="navfn and wavefront-octile paths")
sel = slice(0, None, 400)
axes[2].quiver(pts[sel, 0], pts[sel, 1], g[sel, 0], g[sel, 1], color="tab:gray", width=0.002)
