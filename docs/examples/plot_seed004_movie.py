"""
Seed 004: the robot's movie through its configuration space
===========================================================

Seed 004's workflow: draw the obstacles and a convex robot, compute the configuration space by
the star algorithm (the Minkowski sums of the obstacles with the reflected robot), then move the
robot's reference point down a potential whose attraction is quadratic near the goal and conic
far from it, with a minimum speed, a saturated distance to the obstacles and a local minimum
declared when the gradient falls below a threshold; and record the episode as a movie.

Here the obstacles are seed 000's polygons and the robot is a triangle whose reference point is
its right-angle corner (as in :doc:`plot_cspace`). The seed's own values are in units of its
drawing step; these are gridfield's for this map (cells of 0.1).
"""

# %%
# The configuration space, its brushfire and the potential
# --------------------------------------------------------
# The C-obstacles are rasterized on a grid of 0.1 and their brushfire distance is saturated at 1
# (farther cells count as far away). With the repulsive gain eta = 0.1 the robot reaches the
# goal; with eta = 1 the large scaled steps push it onto the first C-obstacle, where no free
# descent step is left (the figure's hint says so): a failed episode, like the seed's fourth movie.

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.animation import FuncAnimation
from matplotlib.patches import Polygon as PolygonPatch

from gridfield.distance.brushfire import brushfire
from gridfield.fields.potential import build_field
from gridfield.geometry.cspace import apply_robot, as_robot
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan
from gridfield.plot import plot_brushfire, plot_map, plot_potential

world = read_world(bundled_map("seed000.yaml"))
robot = as_robot([(0.0, 0.0), (0.8, 0.0), (0.0, 0.6)])
cspace = apply_robot(world, robot)
grid = as_gridmap(cspace, 0.1)
params = {"zeta": 1.0, "d_star": 3.0, "eta": 0.1, "q_star": 2.0, "saturate": 1.0, "step_rule": "scaled",
          "alpha": 0.05, "min_speed": 0.05, "gradient_threshold": 1e-3, "tolerance": 0.1}
path = plan("potential", grid, world.start, world.goal, params)
failed = plan("potential", grid, world.start, world.goal, {**params, "eta": 1.0})
print("eta 0.1:", path.status, round(path.length, 2), f"({len(path.points)} steps)")
print("eta 1:", failed.status, "at", failed.points[-1].round(2))

dmap = brushfire(grid, metric="euclidean", saturate=params["saturate"], far=params["saturate"])
fig, axes = plt.subplots(1, 3, figsize=(16, 4.4), layout="constrained")
plot_brushfire(dmap, axes[0], title="C-space: saturated brushfire distance")
plot_potential(build_field(grid, world.goal, params), axes[1], path=path, colorbar=False,
               title=f"eta = 0.1: {path.status}")
plot_potential(build_field(grid, world.goal, {**params, "eta": 1.0}), axes[2], path=failed, colorbar=False,
               title=f"eta = 1: {failed.status}")

# %%
# The movie
# ---------
# Left, the workspace: the robot's body placed at each step (:meth:`gridfield.geometry.world.Robot.outline`)
# never touches an obstacle. Right, the configuration space: its reference point moves over the
# brushfire of the C-obstacles. Far from the goal it moves at the conic part's constant speed; within
# d* = 3 of the goal it slows down, until the minimum speed takes over.

frames = np.unique(np.linspace(0, len(path.points) - 1, 24).round().astype(int))
pts = path.points
fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6), dpi=64, layout="constrained")
plot_map(world, left, legend=False, title="workspace")
plot_brushfire(dmap, right, colorbar=False, gvd=False, title="configuration space")
outline = np.asarray(robot.outline(pts[0]).exterior.coords)
body = left.add_patch(PolygonPatch(outline, closed=True, facecolor="tab:red", alpha=0.6, edgecolor="black"))
(trail,) = right.plot([], [], color="tab:red", linewidth=2)
(track,) = left.plot([], [], color="tab:red", linewidth=1, linestyle=":")
(point,) = right.plot([], [], "o", color="tab:red", markeredgecolor="white", markersize=8)
for ax in (left, right):  # no tick labels: half of each frame's drawing time
    ax.tick_params(labelbottom=False, labelleft=False)
    ax.set(xlabel="", ylabel="")
fig.canvas.draw()
fig.set_layout_engine("none")  # the layout is fixed: frames are drawn without recomputing it
plt.rcParams["animation.writer"] = "pillow"  # the gallery's thumbnail GIF needs no ffmpeg


def draw(k: int) -> None:
    i = frames[k]
    body.set_xy(np.asarray(robot.outline(pts[i]).exterior.coords))
    trail.set_data(pts[: i + 1, 0], pts[: i + 1, 1])
    track.set_data(pts[: i + 1, 0], pts[: i + 1, 1])
    point.set_data(pts[i : i + 1, 0], pts[i : i + 1, 1])
    right.set_title(f"configuration space: step {i}/{len(pts) - 1}")


movie = FuncAnimation(fig, draw, frames=len(frames), interval=100, repeat=False)
