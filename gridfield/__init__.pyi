# The curated top-level API of gridfield, for editors and type checkers; at run time
# gridfield/__init__.py loads each name on first use (tests/test_api.py checks that the two agree).
# brushfire, follow and rasterize are modules callable as their main function; typed here as the functions.

from . import errors as errors
from ._results import DistanceMap as DistanceMap
from ._results import Field as Field
from ._results import GradientField as GradientField
from ._version import __version__ as __version__
from .brushfire import brushfire as brushfire
from .cspace import apply_robot as apply_robot
from .errors import GridfieldError as GridfieldError
from .errors import MapFormatError as MapFormatError
from .errors import ParameterError as ParameterError
from .follow import follow as follow
from .follow import follow_many as follow_many
from .grid import Grid as Grid
from .grid import GridMap as GridMap
from .io import bundled_map as bundled_map
from .io import load_field as load_field
from .io import read as read
from .io import read_world as read_world
from .io import save_field as save_field
from .navigation import NavigationField as NavigationField
from .navigation import navigation_field as navigation_field
from .navigation import wavefront as wavefront
from .path import Path as Path
from .planners import PLANNERS as PLANNERS
from .planners import Plan as Plan
from .planners import plan as plan
from .planners import plan_with_field as plan_with_field
from .potential import build_field as build_field
from .rasterize import rasterize as rasterize
from .world import World as World

__all__ = [
    "PLANNERS",
    "DistanceMap",
    "Field",
    "GradientField",
    "Grid",
    "GridMap",
    "GridfieldError",
    "MapFormatError",
    "NavigationField",
    "ParameterError",
    "Path",
    "Plan",
    "World",
    "__version__",
    "apply_robot",
    "brushfire",
    "build_field",
    "bundled_map",
    "follow",
    "follow_many",
    "load_field",
    "navigation_field",
    "plan",
    "plan_with_field",
    "rasterize",
    "read",
    "read_world",
    "save_field",
    "wavefront",
]
