# The public names of gridfield.core, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import chunkcache as chunkcache
from . import coords as coords
from . import errors as errors
from . import grid as grid
from . import limits as limits
from . import params as params
from . import path as path
from . import planner_table as planner_table
from . import results as results
from .chunkcache import DEFAULT_BUDGET as DEFAULT_BUDGET
from .chunkcache import NONZERO as NONZERO
from .chunkcache import ChunkCache as ChunkCache
from .chunkcache import LazyArray as LazyArray
from .chunkcache import LazyGridMap as LazyGridMap
from .chunkcache import OccupancyRule as OccupancyRule
from .chunkcache import Raster as Raster
from .chunkcache import is_lazy as is_lazy
from .chunkcache import lazy_grid as lazy_grid
from .coords import INDEX_LIMIT as INDEX_LIMIT
from .coords import as_points as as_points
from .coords import as_xy as as_xy
from .coords import cell_index as cell_index
from .coords import scalar_index as scalar_index
from .errors import MESSAGE_LIMIT as MESSAGE_LIMIT
from .errors import ArgumentTypeError as ArgumentTypeError
from .errors import GridfieldError as GridfieldError
from .errors import MapFormatError as MapFormatError
from .errors import ParameterError as ParameterError
from .errors import SizeLimitError as SizeLimitError
from .errors import cap_message as cap_message
from .errors import check_finite as check_finite
from .errors import check_positive as check_positive
from .errors import shorten as shorten
from .grid import BORDERS as BORDERS
from .grid import RESOLUTION_RANGE as RESOLUTION_RANGE
from .grid import Grid as Grid
from .grid import GridMap as GridMap
from .grid import check_resolution as check_resolution
from .limits import BYTES_PER_CELL as BYTES_PER_CELL
from .limits import DEFAULT_MAX_SECONDS as DEFAULT_MAX_SECONDS
from .limits import ENV_VAR as ENV_VAR
from .limits import JOB_BYTES_PER_CELL as JOB_BYTES_PER_CELL
from .limits import MEMORY_FRACTION as MEMORY_FRACTION
from .limits import PROGRESS_ENV_VAR as PROGRESS_ENV_VAR
from .limits import PROGRESS_INTERVAL as PROGRESS_INTERVAL
from .limits import PROGRESS_SECONDS as PROGRESS_SECONDS
from .limits import SECONDS_ENV_VAR as SECONDS_ENV_VAR
from .limits import SECONDS_PER as SECONDS_PER
from .limits import SECONDS_POWER as SECONDS_POWER
from .limits import available_memory as available_memory
from .limits import check_cells as check_cells
from .limits import check_grid as check_grid
from .limits import check_seconds as check_seconds
from .limits import check_stages as check_stages
from .limits import default_max_cells as default_max_cells
from .limits import estimate_seconds as estimate_seconds
from .limits import grid_map_work as grid_map_work
from .limits import job as job
from .limits import job_bytes_per_cell as job_bytes_per_cell
from .limits import job_planners as job_planners
from .limits import max_cells as max_cells
from .limits import max_seconds as max_seconds
from .limits import memory_budget as memory_budget
from .limits import out_of_memory as out_of_memory
from .limits import override as override
from .limits import parse_max_cells as parse_max_cells
from .limits import progress as progress
from .limits import user_limit as user_limit
from .params import FIELD_GROUPS as FIELD_GROUPS
from .params import GROUPS as GROUPS
from .params import REGISTRY as REGISTRY
from .params import Attraction as Attraction
from .params import Escape as Escape
from .params import Follower as Follower
from .params import Model as Model
from .params import NavFn as NavFn
from .params import NavFunction as NavFunction
from .params import Navigation as Navigation
from .params import Params as Params
from .params import Repulsion as Repulsion
from .params import Spec as Spec
from .params import Vortex as Vortex
from .params import check as check
from .params import group as group
from .params import help_text as help_text
from .params import known as known
from .params import names as names
from .params import parse as parse
from .params import resolve as resolve
from .params import resolve_field as resolve_field
from .params import validate as validate
from .path import STATUSES as STATUSES
from .path import NavigationAux as NavigationAux
from .path import Path as Path
from .path import PathExtra as PathExtra
from .path import path_length as path_length
from .planner_table import PLANNERS as PLANNERS
from .planner_table import Planner as Planner
from .results import DistanceMap as DistanceMap
from .results import Field as Field
from .results import GradientField as GradientField

__all__ = [
    "BORDERS",
    "BYTES_PER_CELL",
    "DEFAULT_BUDGET",
    "DEFAULT_MAX_SECONDS",
    "ENV_VAR",
    "FIELD_GROUPS",
    "GROUPS",
    "INDEX_LIMIT",
    "JOB_BYTES_PER_CELL",
    "MEMORY_FRACTION",
    "MESSAGE_LIMIT",
    "NONZERO",
    "PLANNERS",
    "PROGRESS_ENV_VAR",
    "PROGRESS_INTERVAL",
    "PROGRESS_SECONDS",
    "REGISTRY",
    "RESOLUTION_RANGE",
    "SECONDS_ENV_VAR",
    "SECONDS_PER",
    "SECONDS_POWER",
    "STATUSES",
    "ArgumentTypeError",
    "Attraction",
    "ChunkCache",
    "DistanceMap",
    "Escape",
    "Field",
    "Follower",
    "GradientField",
    "Grid",
    "GridMap",
    "GridfieldError",
    "LazyArray",
    "LazyGridMap",
    "MapFormatError",
    "Model",
    "NavFn",
    "NavFunction",
    "Navigation",
    "NavigationAux",
    "OccupancyRule",
    "ParameterError",
    "Params",
    "Path",
    "PathExtra",
    "Planner",
    "Raster",
    "Repulsion",
    "SizeLimitError",
    "Spec",
    "Vortex",
    "as_points",
    "as_xy",
    "available_memory",
    "cap_message",
    "cell_index",
    "check",
    "check_cells",
    "check_finite",
    "check_grid",
    "check_positive",
    "check_resolution",
    "check_seconds",
    "check_stages",
    "chunkcache",
    "coords",
    "default_max_cells",
    "errors",
    "estimate_seconds",
    "grid",
    "grid_map_work",
    "group",
    "help_text",
    "is_lazy",
    "job",
    "job_bytes_per_cell",
    "job_planners",
    "known",
    "lazy_grid",
    "limits",
    "max_cells",
    "max_seconds",
    "memory_budget",
    "names",
    "out_of_memory",
    "override",
    "params",
    "parse",
    "parse_max_cells",
    "path",
    "path_length",
    "planner_table",
    "progress",
    "resolve",
    "resolve_field",
    "results",
    "scalar_index",
    "shorten",
    "user_limit",
    "validate",
]
