# The public names of gridfield.fields, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import costmap as costmap
from . import incremental as incremental
from . import navfield as navfield
from . import navfn as navfn
from . import navigation as navigation
from . import navtable as navtable
from . import potential as potential
from . import potential_args as potential_args
from . import sampler_args as sampler_args
from . import sampling as sampling
from . import vortex as vortex
from .costmap import FREE_SPACE as FREE_SPACE
from .costmap import INSCRIBED_INFLATED_OBSTACLE as INSCRIBED_INFLATED_OBSTACLE
from .costmap import LETHAL_OBSTACLE as LETHAL_OBSTACLE
from .costmap import MAX_NON_OBSTACLE as MAX_NON_OBSTACLE
from .costmap import NO_INFORMATION as NO_INFORMATION
from .costmap import Costmap as Costmap
from .costmap import compute_cost as compute_cost
from .costmap import inflate as inflate
from .incremental import update_field as update_field
from .incremental import update_navigation as update_navigation
from .navfield import NF_MODELS as NF_MODELS
from .navfield import band_cost as band_cost
from .navfield import blend_cost as blend_cost
from .navfield import eikonal as eikonal
from .navfield import nav_field as nav_field
from .navfield import nf2_cost as nf2_cost
from .navfield import nf_potential as nf_potential
from .navfield import nf_skeleton as nf_skeleton
from .navfield import skeleton as skeleton
from .navfield import work_maps as work_maps
from .navfn import COST_FACTOR as COST_FACTOR
from .navfn import COST_NEUTRAL as COST_NEUTRAL
from .navfn import POT_HIGH as POT_HIGH
from .navfn import navfn_costs as navfn_costs
from .navfn import plan_navfn as plan_navfn
from .navigation import KINDS as KINDS
from .navigation import NavigationField as NavigationField
from .navigation import StarNavWarning as StarNavWarning
from .navigation import StarObstacle as StarObstacle
from .navigation import StarWorld as StarWorld
from .navigation import choose_kappa as choose_kappa
from .navigation import clearance_cost as clearance_cost
from .navigation import extract_path as extract_path
from .navigation import find_star_center as find_star_center
from .navigation import fmm as fmm
from .navigation import folds as folds
from .navigation import follow_star_nav as follow_star_nav
from .navigation import grid_options as grid_options
from .navigation import harmonic as harmonic
from .navigation import nav_function as nav_function
from .navigation import plan_fmm as plan_fmm
from .navigation import plan_harmonic as plan_harmonic
from .navigation import plan_sphere_nav as plan_sphere_nav
from .navigation import plan_star_nav as plan_star_nav
from .navigation import plan_wavefront as plan_wavefront
from .navigation import plan_wavefront_octile as plan_wavefront_octile
from .navigation import sphere_nav_field as sphere_nav_field
from .navigation import sphere_nav_function as sphere_nav_function
from .navigation import spurious_minima as spurious_minima
from .navigation import star_betas as star_betas
from .navigation import star_figure_data as star_figure_data
from .navigation import star_nav_field as star_nav_field
from .navigation import star_to_sphere as star_to_sphere
from .navigation import star_world as star_world
from .navigation import wavefront as wavefront
from .navtable import navigation_field as navigation_field
from .potential import GRADIENTS as GRADIENTS
from .potential import MODELS as MODELS
from .potential import REPULSIONS as REPULSIONS
from .potential import Field as Field
from .potential import attractive as attractive
from .potential import build_field as build_field
from .potential import finite_difference_gradient as finite_difference_gradient
from .potential import repulsive as repulsive
from .potential import resolve_params as resolve_params
from .potential import vortex_field as vortex_field
from .potential import vortex_lattice as vortex_lattice
from .potential_args import METRIC_CODE as METRIC_CODE
from .potential_args import integer_power as integer_power
from .potential_args import saturation as saturation
from .sampler_args import gradient_arrays as gradient_arrays
from .sampler_args import grid_args as grid_args
from .sampling import SAMPLINGS as SAMPLINGS
from .sampling import GradientField as GradientField
from .sampling import attraction_force as attraction_force
from .sampling import clearance_at as clearance_at
from .sampling import distance_at as distance_at
from .sampling import grid_blocked as grid_blocked
from .sampling import grid_potential_sampler as grid_potential_sampler
from .sampling import grid_sampler as grid_sampler
from .sampling import sample_force as sample_force
from .vortex import vortex_follower_params as vortex_follower_params
from .vortex import vortex_model_field as vortex_model_field

__all__ = [
    "COST_FACTOR",
    "COST_NEUTRAL",
    "FREE_SPACE",
    "GRADIENTS",
    "INSCRIBED_INFLATED_OBSTACLE",
    "KINDS",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "METRIC_CODE",
    "MODELS",
    "NF_MODELS",
    "NO_INFORMATION",
    "POT_HIGH",
    "REPULSIONS",
    "SAMPLINGS",
    "Costmap",
    "Field",
    "GradientField",
    "NavigationField",
    "StarNavWarning",
    "StarObstacle",
    "StarWorld",
    "attraction_force",
    "attractive",
    "band_cost",
    "blend_cost",
    "build_field",
    "choose_kappa",
    "clearance_at",
    "clearance_cost",
    "compute_cost",
    "costmap",
    "distance_at",
    "eikonal",
    "extract_path",
    "find_star_center",
    "finite_difference_gradient",
    "fmm",
    "folds",
    "follow_star_nav",
    "gradient_arrays",
    "grid_args",
    "grid_blocked",
    "grid_options",
    "grid_potential_sampler",
    "grid_sampler",
    "harmonic",
    "incremental",
    "inflate",
    "integer_power",
    "nav_field",
    "nav_function",
    "navfield",
    "navfn",
    "navfn_costs",
    "navigation",
    "navigation_field",
    "navtable",
    "nf2_cost",
    "nf_potential",
    "nf_skeleton",
    "plan_fmm",
    "plan_harmonic",
    "plan_navfn",
    "plan_sphere_nav",
    "plan_star_nav",
    "plan_wavefront",
    "plan_wavefront_octile",
    "potential",
    "potential_args",
    "repulsive",
    "resolve_params",
    "sample_force",
    "sampler_args",
    "sampling",
    "saturation",
    "skeleton",
    "sphere_nav_field",
    "sphere_nav_function",
    "spurious_minima",
    "star_betas",
    "star_figure_data",
    "star_nav_field",
    "star_to_sphere",
    "star_world",
    "update_field",
    "update_navigation",
    "vortex",
    "vortex_field",
    "vortex_follower_params",
    "vortex_lattice",
    "vortex_model_field",
    "wavefront",
    "work_maps",
]
