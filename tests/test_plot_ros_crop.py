"""Every figure of a ROS map shows its known part (issue 30: "ROS figures ... cropped to the known area"):
the brushfire and potential figures, as the map figure already did (a basins result holds no map: its figure
crops only when it carries its field). The known extent is taken
here from the map's free cells directly (numpy on the read occupancy), not from the plotting code."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from gridfield.distance.brushfire import brushfire
from gridfield.fields.potential import build_field
from gridfield.io import read
from gridfield.plot import plot_brushfire, plot_potential


def test_brushfire_and_potential_figures_crop_a_ros_map_to_its_known_part(test_maps):
    gm = read(test_maps / "ros_maps" / "turtlebot3_world" / "map.yaml")
    free = ~np.asarray(gm.occupied, bool)
    rows, cols = np.nonzero(free.any(axis=1))[0], np.nonzero(free.any(axis=0))[0]
    (x0, y0), h = gm.grid.origin, gm.grid.resolution
    known = (x0 + cols[0] * h, x0 + (cols[-1] + 1) * h, y0 + rows[0] * h, y0 + (rows[-1] + 1) * h)
    gx0, _, gx1, _ = gm.grid.bounds
    assert (known[1] - known[0]) < 0.5 * (gx1 - gx0)  # the premise: most of the map is unknown
    field = build_field(gm, (1.8, 0.5))
    for art in (plot_brushfire(brushfire(gm)), plot_potential(field)):
        try:
            (a, b), (c, d) = art.ax.get_xlim(), art.ax.get_ylim()
            # the whole known part is shown, with at most a 10-cell margin, not the whole grid
            assert a <= known[0] and b >= known[1] and c <= known[2] and d >= known[3]
            assert a >= known[0] - 10 * h and b <= known[1] + 10 * h and c >= known[2] - 10 * h and d <= known[3] + 10 * h
        finally:
            plt.close(art.figure)
