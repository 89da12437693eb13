"""
Seed 000: the stall point and the escapes
=========================================

Seed 000's world with the extra segment (17.5, 10)-(17.5, 8): the potential-field follower stalls
in the local minimum the seed reports near (16.97, 9.028). ``escape="navigation"`` leaves it along
the octile wavefront from the goal and reaches the goal.
"""

import matplotlib.pyplot as plt

from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan
from gridfield.plot import plot_map, plot_potential

world = read_world(bundled_map("seed000_segment.yaml"))
grid = as_gridmap(world, 0.1)
stalled = plan("potential", grid, world.start, world.goal, world.params)
escaped = plan("potential", grid, world.start, world.goal, {**world.params, "escape": "navigation"})
print(stalled.status, stalled.points[-1].round(2))
print(escaped.status, round(escaped.length, 2))

fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
field = build_field(grid, world.goal, world.params)
plot_potential(field, axes[0], path=stalled, title=f"potential: {stalled.status}")
plot_map(grid, axes[1], paths=[stalled, escaped], start=world.start, goal=world.goal,
         title="with escape='navigation'")
