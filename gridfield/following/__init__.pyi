# The public names of gridfield.following, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import basins as basins
from . import descent as descent
from . import diagnose as diagnose
from . import escapes as escapes
from . import follower as follower
from . import taut as taut
from .basins import Basins as Basins
from .basins import descent_successor as descent_successor
from .descent import DESCEND_UNIT as DESCEND_UNIT
from .descent import ESCAPES as ESCAPES
from .descent import FOLLOWER_GROUPS as FOLLOWER_GROUPS
from .descent import SLIDES as SLIDES
from .descent import STEP_RULES as STEP_RULES
from .descent import Rules as Rules
from .descent import descend as descend
from .descent import goal_hop as goal_hop
from .descent import resolve_rules as resolve_rules
from .descent import rules as rules
from .descent import without_loops as without_loops
from .diagnose import corner_passage as corner_passage
from .diagnose import robot_no_path as robot_no_path
from .diagnose import unreachable_hint as unreachable_hint
from .escapes import NavigationEscape as NavigationEscape
from .escapes import cut_loops as cut_loops
from .escapes import navigation_cut as navigation_cut
from .escapes import navigation_finish as navigation_finish
from .escapes import navigation_map as navigation_map
from .escapes import navigation_moves as navigation_moves
from .escapes import potential_increase as potential_increase
from .escapes import random_jump as random_jump
from .follower import SAMPLINGS as SAMPLINGS
from .follower import attraction_force as attraction_force
from .follower import descend_cells as descend_cells
from .follower import follow as follow
from .follower import follow_many as follow_many
from .follower import grid_blocked as grid_blocked
from .follower import grid_potential_sampler as grid_potential_sampler
from .follower import grid_sampler as grid_sampler
from .follower import plan_potential as plan_potential
from .follower import plan_potential_with_field as plan_potential_with_field
from .follower import resolve_follow_params as resolve_follow_params
from .follower import sample_force as sample_force
from .taut import crossed_clearance as crossed_clearance
from .taut import taut_path as taut_path

__all__ = [
    "DESCEND_UNIT",
    "ESCAPES",
    "FOLLOWER_GROUPS",
    "SAMPLINGS",
    "SLIDES",
    "STEP_RULES",
    "Basins",
    "NavigationEscape",
    "Rules",
    "attraction_force",
    "basins",
    "corner_passage",
    "crossed_clearance",
    "cut_loops",
    "descend",
    "descend_cells",
    "descent",
    "descent_successor",
    "diagnose",
    "escapes",
    "follow",
    "follow_many",
    "follower",
    "goal_hop",
    "grid_blocked",
    "grid_potential_sampler",
    "grid_sampler",
    "navigation_cut",
    "navigation_finish",
    "navigation_map",
    "navigation_moves",
    "plan_potential",
    "plan_potential_with_field",
    "potential_increase",
    "random_jump",
    "resolve_follow_params",
    "resolve_rules",
    "robot_no_path",
    "rules",
    "sample_force",
    "taut",
    "taut_path",
    "unreachable_hint",
    "without_loops",
]
