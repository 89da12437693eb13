"""
A ROS map: the TurtleBot3 world
===============================

A ROS map_server map (0.05 m cells), cropped to its known area: the brushfire distance map with the
generalized Voronoi diagram, and the potential path (default parameters, scaled to the cells) next
to the octile wavefront path.
"""

import matplotlib.pyplot as plt

from gridfield.demo import crop_to_known
from gridfield.distance.brushfire import brushfire
from gridfield.io import bundled_map, read_ros_map
from gridfield.planners import plan
from gridfield.plot import plot_brushfire, plot_map

grid = crop_to_known(read_ros_map(bundled_map("turtlebot3_world/map.yaml")))
start, goal = (-2.0, -0.5), (2.0, 0.5)
paths = [plan(name, grid, start, goal) for name in ("potential", "wavefront-octile")]
for p in paths:
    print(p.planner, p.status, round(p.length, 2))

fig, axes = plt.subplots(1, 2, figsize=(12, 5), layout="constrained")
plot_brushfire(brushfire(grid, metric="euclidean"), axes[0], title="distance to the nearest obstacle, GVD")
plot_map(grid, axes[1], paths=paths, start=start, goal=goal, title="paths")
