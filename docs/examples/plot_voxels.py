"""
Voxel grids: two floors and a stair shaft
=========================================

A 48 x 48 x 48 voxel world (12 m on a side, cells of 0.25 m): a ground floor with a wall and a door,
an upper floor on a slab, a stair shaft between them, two pillars upstairs. Its brushfire distance
map and the path of the ``potential`` planner from the ground floor to the upper floor are drawn by
:mod:`gridfield.plot.voxels`: orthogonal slices through the start, a grid of x-y slices at several
heights, and 3-D scenes of the obstacles' isosurface and of the surface 0.5 m away from them (marching
cubes, a drawing step). Arrays are indexed ``[z, y, x]`` (layer, row, column); points are ``(x, y, z)``.
"""

import matplotlib.pyplot as plt
import numpy as np

from gridfield.core.grid import Grid, GridMap
from gridfield.distance.brushfire import brushfire
from gridfield.planners import plan
from gridfield.plot import plot_voxel_scene, plot_voxel_slices

n, h = 48, 0.25
z, y, x = np.indices((n, n, n))  # layer, row, column of every voxel
shaft = (y >= 4) & (y < 18) & (x >= 34) & (x < 46)  # x in [8.5, 11.5), y in [1, 4.5)
occ = (z >= 22) & (z < 25) & ~shaft  # the upper floor's slab, z in [5.5, 6.25), open over the shaft
occ |= shaft & (z < 3 + 3 * ((y - 4) // 2))  # the stairs: 0.75 m up every 0.5 m along y
door = (x >= 8) & (x < 14) & (z < 8)
occ |= (z < 22) & (y >= 28) & (y < 30) & ~door  # a ground-floor wall at y = 7 with a door
occ |= (z >= 25) & (((y >= 30) & (y < 34) & (x >= 10) & (x < 14)) | ((y >= 10) & (y < 14) & (x >= 16) & (x < 20)))
world = GridMap(Grid((n, n, n), h), occ, source="two floors")

start, goal = (1.1, 1.1, 0.6), (1.1, 10.6, 7.1)  # ground floor, corner; upper floor, beyond the wall
dmap = brushfire(world, metric="euclidean")
path = plan("potential", world, start, goal)
print(path)

# %%
# Orthogonal slices through the start: the distance to the nearest obstacle, the obstacles in grey,
# the path projected onto each plane (it climbs the shaft, x in [8.5, 11.5)).
plot_voxel_slices(dmap, paths=path)

# %%
# A grid of x-y slices: the ground floor with its wall and door, the stairs, the upper floor's pillars.
plot_voxel_slices(dmap, zs=[0.6, 3.1, 5.9, 7.1], paths=path, ncols=4)

# %%
# The scene: the obstacles' isosurface, and the surface at 0.5 m from them (a robot of radius 0.5
# keeps its centre outside it), with the path as a 3-D line.
fig = plt.figure(figsize=(12, 5.5), layout="constrained")
plot_voxel_scene(dmap, fig.add_subplot(1, 2, 1, projection="3d"), paths=path)
plot_voxel_scene(dmap, fig.add_subplot(1, 2, 2, projection="3d"), level=0.5, paths=path, legend=False)
