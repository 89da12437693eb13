"""
Seed 004: the configuration space of a robot
============================================

A triangular robot translating among seed 000's polygons: its C-obstacles are the Minkowski sums
of the obstacles with the reflected robot (:func:`gridfield.geometry.cspace.apply_robot`), and the planners
move its reference point through the free part of that space.
"""

import matplotlib.pyplot as plt

from gridfield.geometry.cspace import apply_robot
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan
from gridfield.plot import plot_map

world = read_world(bundled_map("seed000.yaml"))
robot = [(0.0, 0.0), (0.8, 0.0), (0.0, 0.6)]
cspace = apply_robot(world, robot)
path = plan("visibility", cspace, world.start, world.goal)
print(path.status, round(path.length, 3))

fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
# plotting computes nothing: the cells shown are the grid maps rasterized here
plot_map(as_gridmap(world, 0.1), axes[0], start=world.start, goal=world.goal, title="workspace")
plot_map(as_gridmap(cspace, 0.1), axes[1], paths=[path], title="configuration space and shortest path")
