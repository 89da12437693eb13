"""
Seed 002: a star world and its navigation function
==================================================

A five-pointed star and an L-shaped block (``maps/star_two.yaml``, kappa = 3, lambda = 1): the
obstacle functions, the attractive part, the free space mapped onto a sphere world by the
star-to-sphere transformation, and the navigation function with the ``star-nav`` path.
"""

import numpy as np

from gridfield.fields.navigation import star_figure_data, star_world
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan
from gridfield.plot import plot_star_world

world = read_world(bundled_map("star_two.yaml"))
path = plan("star-nav", world, world.start, world.goal)
print(path.status, round(path.length, 2))

xmin, ymin, xmax, ymax = world.bounds
x, y = np.meshgrid(np.linspace(xmin, xmax, 61), np.linspace(ymin, ymax, 61))
data = star_figure_data(star_world(world, world.goal), kappa=path.extra["kappa"], lam=path.extra["lambda"],
                        x=x, y=y, lines=15)
plot_star_world(data, path=path, max_cells=30)
