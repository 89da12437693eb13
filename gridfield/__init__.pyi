# The curated top-level API of gridfield, for editors and type checkers; at run time gridfield/__init__.py
# loads each name on first use from this file (lazy_loader.attach_stub; tests/test_api.py checks the two agree).

from . import chunked as chunked
from . import compare as compare
from . import core as core
from . import distance as distance
from . import exact as exact
from . import fields as fields
from . import following as following
from . import geometry as geometry
from . import io as io
from . import plot as plot
from . import sweep as sweep
from .core import errors as errors
from .core.errors import GridfieldError as GridfieldError
from .core.errors import MapFormatError as MapFormatError
from .core.errors import ParameterError as ParameterError
from .core.grid import Grid as Grid
from .core.grid import GridMap as GridMap
from .core.path import Path as Path
from .core.results import DistanceMap as DistanceMap
from .core.results import Field as Field
from .core.results import GradientField as GradientField
from .distance.brushfire import brushfire as brushfire
from .distance.incremental import IncrementalBrushfire as IncrementalBrushfire
from .exact.anyangle import plan_anyangle as plan_anyangle
from .exact.continuous import plan_exact_potential as plan_exact_potential
from .exact.visibility import plan_visibility as plan_visibility
from .fields.costmap import Costmap as Costmap
from .fields.costmap import inflate as inflate
from .fields.navigation import NavigationField as NavigationField
from .fields.navigation import wavefront as wavefront
from .fields.navtable import navigation_field as navigation_field
from .fields.potential import build_field as build_field
from .following.basins import Basins as Basins
from .following.basins import basins as basins
from .following.diagnose import diagnose as diagnose
from .following.follower import follow as follow
from .following.follower import follow_many as follow_many
from .geometry.cspace import apply_robot as apply_robot
from .geometry.rasterize import rasterize as rasterize
from .geometry.world import World as World
from .io import bundled_map as bundled_map
from .io import load_field as load_field
from .io import read as read
from .io import read_world as read_world
from .io import save_field as save_field
from .planners import PLANNERS as PLANNERS
from .planners import Plan as Plan
from .planners import plan as plan
from .planners import plan_with_field as plan_with_field

__version__: str

__all__ = [
    "PLANNERS",
    "Basins",
    "Costmap",
    "DistanceMap",
    "Field",
    "GradientField",
    "Grid",
    "GridMap",
    "GridfieldError",
    "IncrementalBrushfire",
    "MapFormatError",
    "NavigationField",
    "ParameterError",
    "Path",
    "Plan",
    "World",
    "__version__",
    "apply_robot",
    "basins",
    "brushfire",
    "build_field",
    "bundled_map",
    "chunked",
    "compare",
    "core",
    "diagnose",
    "distance",
    "errors",
    "exact",
    "fields",
    "follow",
    "follow_many",
    "following",
    "geometry",
    "inflate",
    "io",
    "load_field",
    "navigation_field",
    "plan",
    "plan_anyangle",
    "plan_exact_potential",
    "plan_visibility",
    "plan_with_field",
    "plot",
    "rasterize",
    "read",
    "read_world",
    "save_field",
    "sweep",
    "wavefront",
]
