"""
Seed 003: the vortex field, Ko = 5 and Ko = 10
==============================================

Seed 003's two circles with the rotational (vortex) field sampled at spacing 0.4: with Ka = 25,
Kr = 30 the follower reaches the goal for Ko = 5 but not for Ko = 10, as the seed reports.
"""

import matplotlib.pyplot as plt

from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan
from gridfield.plot import plot_potential

world = read_world(bundled_map("seed003_circles.yaml"))
grid = as_gridmap(world)
fig, axes = plt.subplots(1, 2, figsize=(12, 5), layout="constrained")
for ax, ko in zip(axes, (5.0, 10.0), strict=True):
    params = {**world.params, "ko": ko}
    path = plan("potential", grid, world.start, world.goal, params)
    print(f"Ko = {ko:g}: {path.status}")
    plot_potential(build_field(grid, world.goal, params), ax, path=path, quiver_step=1,
                   title=f"Ko = {ko:g}: {path.status}")
