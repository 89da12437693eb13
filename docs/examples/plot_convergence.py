"""
Grid against exact geometry: a convergence study
================================================

The grid potential field against the exact (continuous) one on seed 000's world at cell sizes 0.4,
0.2 and 0.1: the Hausdorff and Fréchet distances between the paths and the length error shrink at
about first order in the cell size.
"""

import matplotlib.pyplot as plt

from gridfield.compare import convergence_study, study_errors, study_orders
from gridfield.io import bundled_map, read_world
from gridfield.plot import plot_convergence

world = read_world(bundled_map("seed000.yaml"))
rows = convergence_study(world, world.start, world.goal, [0.4, 0.2, 0.1])
print("observed orders:", {k: round(v, 2) for k, v in study_orders(rows).items() if v == v})  # v == v: not NaN

fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
plot_convergence([r["resolution"] for r in rows], study_errors(rows), ax, title="seed 000: grid vs exact")
