"""The explorer's view: the figure, its axes and the drawing of what the model holds.

:class:`ExplorerView` lays out the figure (the map axes, the 3-D axes, the colour bar, the status
line) and draws the state of :class:`gridfield.explore._model.ExplorerModel`: occupancy, C-space,
obstacle outlines, the robot and the endpoints, the potential's background and colour bar, the path
and its stall points, the 3-D surface. It computes nothing: every method draws what the model
already holds (the field and path of the latest plan). The widgets, the mouse and keys and the
public actions are :class:`gridfield.explore.Explorer`'s.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.errors import GridfieldError
from ..core.grid import GridMap
from ..geometry.world import World
from ._model import ExplorerModel

#: Colours: C-obstacles (seed 004 draws them yellow) and the robot.
CSPACE_COLOR = "#f2d64b"
ROBOT_COLOR = "#444444"


class ExplorerView(ExplorerModel):
    """The explorer's figure over its model (the base of :class:`gridfield.explore.Explorer`,
    which documents the parameters and attributes).

    Parameters
    ----------
    target
        The model's target (:class:`gridfield.explore._model.ExplorerModel`).
    on_message : callable, optional
        Called with every status message.
    figsize : (float, float)
    **model
        The model's other keyword arguments (``params``, ``planner``, ``resolution``, ``start``,
        ``goal``, ``robot``).
    """

    def __init__(
        self,
        target: World | GridMap,
        *,
        on_message: Callable[[str], Any] | None = None,
        figsize: tuple[float, float] = (12.0, 7.5),
        **model: Any,
    ) -> None:
        import matplotlib.pyplot as plt

        super().__init__(target, **model)
        self.on_message = on_message
        self.show_3d = False
        self.message = ""
        self.figure = plt.figure(figsize=figsize)
        self.ax = self.figure.add_axes((0.05, 0.09, 0.56, 0.84))
        self.ax3d = self.figure.add_axes((0.05, 0.09, 0.56, 0.84), projection="3d")
        self.ax3d.set_visible(False)
        self.cax = self.figure.add_axes((0.625, 0.09, 0.012, 0.84))
        self._build_map_layer()

    def _build_map_layer(self) -> None:
        from matplotlib.colors import ListedColormap

        from ..plot import OCCUPIED_COLOR, frame_axes

        ax = self.ax
        xmin, ymin, xmax, ymax = self._bounds()
        extent = (xmin, xmax, ymin, ymax)
        shape = self.gridmap.shape if self.gridmap is not None else (2, 2)
        empty = np.ma.masked_array(np.zeros(shape), mask=True)
        self.field_image = ax.imshow(empty, origin="lower", extent=extent, cmap="viridis",
                                     interpolation="nearest", zorder=0, vmin=0.0, vmax=1.0)
        self.cspace_image = ax.imshow(empty.copy(), origin="lower", extent=extent,
                                      cmap=ListedColormap([CSPACE_COLOR]), vmin=0.5, vmax=1.5,
                                      interpolation="nearest", zorder=0.9, alpha=0.85)
        self.occupancy_image = ax.imshow(empty.copy(), origin="lower", extent=extent,
                                         cmap=ListedColormap([OCCUPIED_COLOR]), vmin=0.5, vmax=1.5,
                                         interpolation="nearest", zorder=1)
        self.outlines: list[Any] = []
        self.cspace_outlines: list[Any] = []
        self._drawn_outlines: list[Any] = []  # polygons burnt into a grid without a world
        (self.path_line,) = ax.plot([], [], color="tab:red", linewidth=2.0, zorder=5, label="path")
        (self.draft_line,) = ax.plot([], [], color="tab:orange", marker="o", linestyle="--", zorder=6)
        from matplotlib.patches import Polygon as MplPolygon

        self.robot_patch = ax.add_patch(MplPolygon(np.zeros((3, 2)), closed=True, facecolor="white", alpha=0.8,
                                                   edgecolor=ROBOT_COLOR, linewidth=1.5, zorder=6.5, visible=False))
        none = np.empty((0, 2))
        self.reference_marker = ax.scatter(none[:, 0], none[:, 1], s=22, color="black", zorder=7.5, label="robot")
        self.start_marker = ax.scatter(none[:, 0], none[:, 1], marker="o", s=70, color="tab:green",
                                       edgecolor="black", zorder=7, label="start")
        self.goal_marker = ax.scatter(none[:, 0], none[:, 1], marker="*", s=180, color="gold", edgecolor="black",
                                      zorder=7, label="goal")
        self.stall_marker = ax.scatter(none[:, 0], none[:, 1], marker="X", s=90, color="red", edgecolor="white",
                                       zorder=8, label="stall")
        self._redraw_map()
        frame_axes(ax, self._bounds())
        self._place_colorbar()
        self.colorbar = self.figure.colorbar(self.field_image, cax=self.cax)
        self.colorbar.set_label("U − min U (log scale)", fontsize=8)
        self.cax.tick_params(labelsize=7)
        self.status_text = self.figure.text(0.05, 0.02, "", fontsize=9, family="monospace")
        self.ax.set_title("click: start, then goal", fontsize=10)

    def _place_colorbar(self) -> None:
        """The colour bar beside the map as drawn (equal aspect: a tall map is drawn narrower than its
        axes box), as tall as the map: it stays clear of the sliders' labels at the right."""
        self.ax.apply_aspect()
        pos = self.ax.get_position(original=False)
        self.cax.set_position((pos.x1 + 0.012, pos.y0, 0.012, pos.height))

    # -- drawing ---------------------------------------------------------------------------
    def _set_message(self, text: str) -> None:
        self.message = text
        self.status_text.set_text(text if len(text) <= 150 else text[:147] + "...")
        if self.on_message is not None:
            self.on_message(text)

    def _redraw_map(self) -> None:
        """Occupancy, C-space, obstacle outlines and the robot, from the current state."""
        from ..plot import draw_outlines

        if self.gridmap is not None:
            occ = self.gridmap.occupied
            self.occupancy_image.set_data(np.ma.masked_array(np.ones(occ.shape), mask=~occ))
            grown = self.cgridmap.occupied & ~occ if (self.cspace_on and self.cgridmap is not None) else None
            self.cspace_image.set_data(np.ma.masked_array(np.ones(occ.shape), mask=~grown if grown is not None
                                                          else np.ones(occ.shape, bool)))
        for a in (*self.outlines, *self.cspace_outlines):
            a.remove()
        self.outlines, self.cspace_outlines = [], []
        if self.world is not None:
            self.outlines = draw_outlines(self.ax, self.world)
        elif self.gridmap is not None and self.gridmap.meta.get("drawn"):
            from matplotlib.collections import PatchCollection
            from matplotlib.patches import Polygon as MplPolygon

            self.outlines = [self.ax.add_collection(PatchCollection(
                [MplPolygon(v, closed=True) for v in self.gridmap.meta["drawn"]], facecolor="none",
                edgecolor="tab:blue", linewidth=1.6, zorder=3))]
        if self.cspace_on and self.cworld is not None and self.cworld is not self.world:
            self.cspace_outlines = self._draw_cspace_outlines(self.cworld)
        self._update_endpoints()

    def _draw_cspace_outlines(self, world: World) -> list[Any]:
        import shapely
        from matplotlib.collections import LineCollection

        rings = []
        for ob in world.obstacles:
            for part in shapely.get_parts(ob.geometry):
                if hasattr(part, "exterior"):
                    rings.append(np.asarray(part.exterior.coords))
                    rings += [np.asarray(r.coords) for r in part.interiors]
                else:
                    rings.append(np.asarray(part.coords).reshape(-1, 2))
        if not rings:
            return []
        return [self.ax.add_collection(LineCollection(rings, colors="#b8860b", linewidths=1.2, linestyles="--",
                                                      zorder=2.5))]

    def _update_endpoints(self) -> None:
        empty = np.empty((0, 2))
        self.start_marker.set_offsets(np.atleast_2d(self.start) if self.start is not None else empty)
        self.goal_marker.set_offsets(np.atleast_2d(self.goal) if self.goal is not None else empty)
        if self.robot is not None and self.start is not None and not self.robot.is_point:
            shape = self.robot.outline(self.start)
            xy = np.asarray(shape.exterior.coords if hasattr(shape, "exterior") else shape.coords, dtype=float)
            self.robot_patch.set_xy(xy)  # type: ignore[attr-defined]  # matplotlib stubs: a Polygon patch at runtime
            self.robot_patch.set_visible(True)
            self.reference_marker.set_offsets(np.atleast_2d(self.start))
        else:
            self.robot_patch.set_visible(False)
            self.reference_marker.set_offsets(empty)

    def _update_field_image(self) -> None:
        """Background and colour bar: the log-scaled :attr:`field` (the potential planner's), else nothing."""
        from matplotlib.colors import LogNorm

        from ..plot import potential_scale

        if self.field is None:
            self._hide_field()
            return
        fmap = self.field.map  # the vortex model lives on its own lattice
        u = np.asarray(self.field.potential, dtype=float)
        finite = np.isfinite(u) & ~fmap.occupied
        if not finite.any():
            self._hide_field()
            return
        z, lo, hi, _ = potential_scale(u, finite, None, True)
        self.field_image.set_data(np.ma.masked_array(z, mask=~finite))
        self.field_image.set_extent(fmap.grid.extent)
        self.field_image.set_norm(LogNorm(vmin=lo, vmax=hi))
        self.field_image.set_visible(True)
        self.colorbar.update_normal(self.field_image)
        self.cax.set_visible(not self.show_3d)  # the 3-D view has its own height axis

    def _hide_field(self) -> None:
        self.field_image.set_visible(False)
        self.cax.set_visible(False)

    def _update_3d(self) -> None:
        if not self.show_3d:
            return
        from ..plot import plot_surface

        self.ax3d.cla()
        self.surface = None
        if self.field is None:
            self.ax3d.text2D(0.5, 0.5, "the 3-D view shows the potential planner's field", ha="center",  # type: ignore[attr-defined]  # a 3-D Axes
                             transform=self.ax3d.transAxes)
            return
        try:
            self.surface = plot_surface(self.field, self.ax3d, path=self.path, title="potential surface")
        except GridfieldError as e:
            self.ax3d.text2D(0.5, 0.5, str(e), ha="center", transform=self.ax3d.transAxes)  # type: ignore[attr-defined]  # a 3-D Axes

    def _draw_path(self) -> None:
        """The background of the latest plan and its path, with the stall points."""
        from ..plot import stall_points

        assert self.path is not None
        self._update_field_image()
        pts = self.path.points
        self.path_line.set_data(pts[:, 0], pts[:, 1])
        self.stall_marker.set_offsets(stall_points(self.path))

    def _draw_no_path(self, text: str) -> None:
        """The background field alone (no path), with ``text`` (why) on the status line."""
        self._update_field_image()
        self.path_line.set_data([], [])
        self.stall_marker.set_offsets(np.empty((0, 2)))
        self._set_message(text)
        self._update_3d()
        self.figure.canvas.draw_idle()
