# The public names of gridfield.exact, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import anyangle as anyangle
from . import continuous as continuous
from . import visibility as visibility
from .anyangle import SLOT_DTYPE as SLOT_DTYPE
from .anyangle import AnyAngleGraph as AnyAngleGraph
from .anyangle import NavMesh as NavMesh
from .anyangle import convex_corners as convex_corners
from .anyangle import grid_graph as grid_graph
from .anyangle import navigation_mesh as navigation_mesh
from .anyangle import plan_anyangle as plan_anyangle
from .continuous import ExactField as ExactField
from .continuous import default_step as default_step
from .continuous import plan_exact_potential as plan_exact_potential
from .visibility import PINCH_RULES as PINCH_RULES
from .visibility import VisibilityGraph as VisibilityGraph
from .visibility import cached_visibility_graph as cached_visibility_graph
from .visibility import plan_visibility as plan_visibility
from .visibility import visibility_graph as visibility_graph
from .visibility import world_from_polygon_environment as world_from_polygon_environment

__all__ = [
    "PINCH_RULES",
    "SLOT_DTYPE",
    "AnyAngleGraph",
    "ExactField",
    "NavMesh",
    "VisibilityGraph",
    "anyangle",
    "cached_visibility_graph",
    "continuous",
    "convex_corners",
    "default_step",
    "grid_graph",
    "navigation_mesh",
    "plan_anyangle",
    "plan_exact_potential",
    "plan_visibility",
    "visibility",
    "visibility_graph",
    "world_from_polygon_environment",
]
