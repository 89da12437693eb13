"""
Incremental brushfire: a map that changes
=========================================

An obstacle appears on seed 000's grid: :class:`gridfield.distance.incremental.IncrementalBrushfire` repairs
the distance map only in the window the change reaches, and the result equals a full brushfire of
the new map.
"""

import matplotlib.pyplot as plt
import numpy as np

from gridfield.distance.brushfire import brushfire
from gridfield.distance.incremental import IncrementalBrushfire
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world
from gridfield.plot import plot_brushfire

grid = as_gridmap(read_world(bundled_map("seed000.yaml")), 0.1)
ib = IncrementalBrushfire(grid)
before = ib.distance_map
rows, cols = np.mgrid[60:80, 150:170]
r0, r1, c0, c1 = ib.update(occupied=np.stack([rows.ravel(), cols.ravel()], axis=1))
print("window rows", (r0, r1), "columns", (c0, c1))
full = brushfire(ib.gridmap, metric="euclidean")
print("equal to a full brushfire:", bool((ib.distance_map.distance == full.distance).all()))

fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), layout="constrained")
plot_brushfire(before, axes[0], title="before")
plot_brushfire(ib.distance_map, axes[1], title="after the update")
x0, y0 = grid.grid.origin
h = grid.grid.resolution
axes[1].add_patch(plt.Rectangle((x0 + c0 * h, y0 + r0 * h), (c1 - c0) * h, (r1 - r0) * h,
                                fill=False, edgecolor="magenta", linestyle="--", label="updated window"))
axes[1].legend(loc="upper left", fontsize=8)
