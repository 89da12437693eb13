"""
Seed 001: vertices in any order and the quadratic/conic potential
=================================================================

Seed 001 reads its obstacles' vertices from a text file in any order and puts them in cyclic order
by their angle around the centroid (its VerticesSorter). ``maps/seed001.yaml`` does the same with
``vertex_order: sort`` (:func:`gridfield.geometry.world.sort_vertices`). The potential planner then runs with
the seed's parameters: chi = 0.8 (gridfield's ``zeta``), d* = 2, eta = 0.8 and Q* = 2, with the
gradient step x += alpha * v.
"""

# %%
# The vertices as the file lists them and as sorted
# -------------------------------------------------
# Joined in the listed order, the first obstacle's outline crosses itself. Sorted by their angle
# around the centroid (the seed's transformed vertices), they give the polygon the world uses.
# Each vertex keeps its number in the file, so the right panel reads the cyclic order.

import matplotlib.pyplot as plt
import numpy as np

from gridfield.fields.potential import build_field
from gridfield.geometry.rasterize import as_gridmap
from gridfield.geometry.world import sort_vertices
from gridfield.io import bundled_map, read_world, read_yaml
from gridfield.planners import plan
from gridfield.plot import plot_map, plot_potential

listed = np.array(read_yaml(bundled_map("seed001.yaml"))["obstacles"][0]["polygon"], dtype=float)
ordered = sort_vertices(listed)
centroid = listed.mean(axis=0)
number = {tuple(v): k + 1 for k, v in enumerate(listed.tolist())}
print("listed:", listed.tolist())
print("cyclic order:", ", ".join(f"V{number[tuple(v)]}" for v in ordered.tolist()))

fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), layout="constrained")
for ax, pts, title in ((axes[0], listed, "as listed in the file"), (axes[1], ordered, "sorted by angle")):
    ring = np.vstack([pts, pts[:1]])
    ax.fill(ring[:, 0], ring[:, 1], alpha=0.25, color="tab:blue")
    ax.plot(ring[:, 0], ring[:, 1], "-o", color="tab:blue")
    for x, y in pts:
        ax.annotate(f"V{number[(x, y)]}", (x, y), textcoords="offset points", xytext=(6, 6))
    ax.plot(*centroid, "k+", markersize=12)
    ax.set_title(title)
    ax.set_aspect("equal")
for x, y in ordered:  # the transformed vertices and their angles
    axes[1].plot([centroid[0], x], [centroid[1], y], ":", color="grey")
    angle = np.degrees(np.arctan2(y - centroid[1], x - centroid[0]))
    axes[1].annotate(f"{angle:.0f}°", ((x + centroid[0]) / 2, (y + centroid[1]) / 2), color="grey", fontsize=8)

# %%
# The potential field and the path
# --------------------------------
# The world's ``params`` carry the seed's values; the follower takes gradient steps scaled by
# ``alpha``. The exact shortest path among the same polygons (``visibility``) is drawn for scale.

world = read_world(bundled_map("seed001.yaml"))
grid = as_gridmap(world)
path = plan("potential", grid, world.start, world.goal)
shortest = plan("visibility", world, world.start, world.goal)
print({k: world.params[k] for k in ("zeta", "d_star", "eta", "q_star")})
print(path.status, round(path.length, 2), "vs shortest", round(shortest.length, 2))

fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
field = build_field(grid, world.goal, world.params)
plot_potential(field, axes[0], path=path, title=f"U = U_att + U_rep: {path.status}")
plot_map(world, axes[1], paths=[path, shortest], title="potential path and exact shortest path")
