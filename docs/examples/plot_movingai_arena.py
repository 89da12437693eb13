"""
A Moving AI map: arena, its scenarios and the navigation escape
===============================================================

The Moving AI ``arena`` map with its longest benchmark scenario (the ``.scen`` file's y axis is
flipped into gridfield's y-up frame). With the default parameters the potential field stalls next
to the goal, which lies one cell from a wall; ``escape="navigation"`` reaches it, and the octile
wavefront matches the benchmark's optimal length.
"""

import matplotlib.pyplot as plt
import numpy as np

from gridfield.io import bundled_map, read_movingai_map, read_scen
from gridfield.planners import plan
from gridfield.plot import plot_map

grid = read_movingai_map(bundled_map("arena/arena.map"))
scen = read_scen(bundled_map("arena/arena.map.scen"), map_height=grid.shape[0])
i = int(np.argmax(scen.optimal))
start, goal = scen.start_xy[i], scen.goal_xy[i]
paths = [
    plan("potential", grid, start, goal),
    plan("potential", grid, start, goal, {"escape": "navigation"}),
    plan("wavefront-octile", grid, start, goal),
]
print(f"scenario {i}: optimal {scen.optimal[i]:.4f}")
for p in paths:
    print(p.planner, p.status, round(p.length, 4))

fig, ax = plt.subplots(figsize=(6, 6), layout="constrained")
plot_map(grid, ax, paths=paths, start=start, goal=goal, title=f"arena, scenario {i}")
