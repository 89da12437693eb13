# The public names of gridfield.geometry, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import cspace as cspace
from . import gridpoly as gridpoly
from . import rasterize as rasterize
from . import world as world
from .cspace import apply_robot as apply_robot
from .cspace import as_robot as as_robot
from .cspace import centre_footprint as centre_footprint
from .cspace import check_robot_point as check_robot_point
from .cspace import check_robot_polygon as check_robot_polygon
from .cspace import conservative_footprint as conservative_footprint
from .cspace import cspace_grid as cspace_grid
from .cspace import cspace_world as cspace_world
from .cspace import inflate_grid as inflate_grid
from .cspace import inflate_world as inflate_world
from .cspace import minkowski_obstacle as minkowski_obstacle
from .cspace import robot_clearance as robot_clearance
from .cspace import star_algorithm as star_algorithm
from .cspace import workspace_clearance as workspace_clearance
from .gridpoly import block_downsample as block_downsample
from .gridpoly import blocked_runs as blocked_runs
from .gridpoly import grid_world as grid_world
from .gridpoly import source_grid as source_grid
from .gridpoly import subdivide as subdivide
from .rasterize import as_gridmap as as_gridmap
from .rasterize import rasterize_geometry as rasterize_geometry
from .rasterize import rasterize_obstacle as rasterize_obstacle
from .world import CIRCLE_SEGMENTS as CIRCLE_SEGMENTS
from .world import VERTEX_ORDERS as VERTEX_ORDERS
from .world import Obstacle as Obstacle
from .world import Robot as Robot
from .world import World as World
from .world import robot_from_value as robot_from_value
from .world import sort_vertices as sort_vertices
from .world import world_from_dict as world_from_dict

__all__ = [
    "CIRCLE_SEGMENTS",
    "VERTEX_ORDERS",
    "Obstacle",
    "Robot",
    "World",
    "apply_robot",
    "as_gridmap",
    "as_robot",
    "block_downsample",
    "blocked_runs",
    "centre_footprint",
    "check_robot_point",
    "check_robot_polygon",
    "conservative_footprint",
    "cspace",
    "cspace_grid",
    "cspace_world",
    "grid_world",
    "gridpoly",
    "inflate_grid",
    "inflate_world",
    "minkowski_obstacle",
    "rasterize",
    "rasterize_geometry",
    "rasterize_obstacle",
    "robot_clearance",
    "robot_from_value",
    "sort_vertices",
    "source_grid",
    "star_algorithm",
    "subdivide",
    "workspace_clearance",
    "world",
    "world_from_dict",
]
