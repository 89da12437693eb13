"""Every numeric parameter of the registry, at the extremes of its range, through every planner that
reads it: a result or a clear ``gridfield.core.errors`` error, never a warning, never another exception.

The probes are the range's own bounds (``minimum`` when allowed, ``least``, ``maximum``, ``inf`` where
allowed) and the values a range "> 0" or ">= 0" lets through: the smallest subnormal (5e-324), the
smallest normal (2.2e-308), 1e-300 and 1e300. Values outside the range must be refused by the
registry with its message (the planner never sees them). Small maps, so that the whole walk stays
within about half a minute; the star-nav planner (half a second a run) takes the bounds only.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.params import REGISTRY, Spec
from gridfield.fields.navigation import StarNavWarning
from gridfield.geometry.world import world_from_dict
from gridfield.planners import PLANNERS, plan

_occ = np.zeros((16, 16), bool)
_occ[6:10, 7:9] = True
GRID = GridMap(Grid((16, 16), 0.5), _occ)
GRID_ENDS = ((1.25, 1.25), (6.75, 6.75))
CIRCLE = world_from_dict({"bounds": [0, 0, 8, 8], "resolution": 0.5,
                          "obstacles": [{"circle": {"center": [4, 4], "radius": 1}}]})
TRIANGLE = world_from_dict({"bounds": [0, 0, 8, 8], "obstacles": [{"polygon": [[3, 3], [4, 3], [3.5, 4]]}]})
WORLD_ENDS = ((2.0, 4.0), (6.0, 4.6))

#: what makes a planner read the parameter at all (the vortex model's charges, the scaled rule's gain, ...)
CONTEXT: dict[str, dict[str, Any]] = {
    **{k: {"model": "vortex"} for k in ("ka", "kr", "ko", "spacing", "sample_radius")},
    **{k: {"step_rule": "scaled"} for k in ("alpha", "min_speed")},
    **{k: {"escape": "random_walk"} for k in ("escape_tries", "escape_radius", "seed")},
    "clearance_weight": {"q_star": 2.0},
    "kappa": {"max_iterations": 300},  # a tiny exponent creeps on for the whole default budget (9 s)
}

TINY = (5e-324, 2.2e-308, 1e-300)
HUGE = 1e300


def _in_range(spec: Spec, v: float) -> bool:
    try:
        spec.check(v)
    except ParameterError:
        return False
    return True


def probes(spec: Spec, *, bounds_only: bool = False) -> list[Any]:
    """The values to walk: the range's bounds, then the tiny and huge values it admits (or not)."""
    if spec.kind == "point":
        return [(HUGE, HUGE), (-HUGE, 0.0), (TINY[0], TINY[0]), (4.0, 4.0)]
    out: list[Any] = []
    if spec.minimum is not None and not spec.strict:
        out.append(int(spec.minimum) if spec.kind == "integer" else spec.minimum)
    if spec.least is not None:
        out.append(spec.least)
    if spec.maximum is not None:
        out.append(int(spec.maximum) if spec.kind == "integer" else spec.maximum)
    if spec.allow_inf:
        out.append(math.inf)
    if spec.kind == "integer":
        out += [1, 10**18] if not bounds_only else []
    elif not bounds_only:
        out += [*TINY, HUGE]
    else:
        out += [TINY[0], HUGE]
    return list(dict.fromkeys(out))


def _target(planner: str) -> tuple[Any, tuple[tuple[float, float], tuple[float, float]]]:
    if PLANNERS[planner].kind == "grid":
        return GRID, GRID_ENDS
    return (TRIANGLE if planner == "star-nav" else CIRCLE), WORLD_ENDS


NUMERIC = [name for name, spec in REGISTRY.items() if spec.kind in ("number", "integer", "alpha", "point")]


def test_every_numeric_parameter_is_walked() -> None:
    assert len(NUMERIC) >= 25 and all(REGISTRY[n].planners for n in NUMERIC)


@pytest.mark.parametrize("name", NUMERIC)
def test_a_parameter_at_its_extremes_gives_a_result_or_a_clear_error(name: str) -> None:
    spec = REGISTRY[name]
    for planner in spec.planners:
        target, (start, goal) = _target(planner)
        for value in probes(spec, bounds_only=planner == "star-nav"):
            params = {**CONTEXT.get(name, {}), name: value}
            if planner in ("sphere-nav", "star-nav") and name != "kappa":
                params.setdefault("kappa", 3.0)  # one exponent, not the ladder (speed)
            if not _in_range(spec, value):
                with pytest.raises(ParameterError, match=name):
                    plan(planner, target, start, goal, params)
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                try:
                    path = plan(planner, target, start, goal, params)
                except GridfieldError:
                    continue
                except StarNavWarning:  # star-nav's own word for a kappa or lambda that leaves minima or folds
                    continue
                except Exception as e:  # the point of the test: any other exception fails
                    pytest.fail(f"{planner} with {name}={value!r}: {type(e).__name__}: {e}")
            assert np.isfinite(path.points).all(), (planner, name, value)


@pytest.mark.parametrize(("name", "value", "message"), [
    ("repulsive_power", 1e300, "repulsive_power must be at most 16"),
    ("clearance_weight", 1e6, "clearance_weight must be at most 1000"),
    ("kappa", 5e-324, "kappa must be at least 0.001"),
    ("max_iterations", 10**13, r"max_iterations must be at most 1e\+12"),
])
def test_values_beyond_the_narrowed_ranges_are_refused_by_the_registry(name: str, value: float, message: str) -> None:
    with pytest.raises(ParameterError, match=message):
        REGISTRY[name].check(value)


def test_a_balanced_eta_that_leaves_the_floats_is_a_clear_error() -> None:
    for q in (5e-324, 1e300):
        with pytest.raises(ParameterError, match="give eta"):
            plan("potential", GRID, *GRID_ENDS, {"q_star": q})


def test_the_weighted_wavefront_refuses_a_weight_beyond_the_range_when_called_directly() -> None:
    """Its bucket queue grows with the weight: at 1e15 the kernel crashed the process (a segfault)."""
    from gridfield.fields.navigation import wavefront

    with pytest.raises(ParameterError, match="clearance_weight must be at most 1000"):
        wavefront(GRID, GRID_ENDS[1], clearance_weight=1e15)
    assert np.isfinite(wavefront(GRID, GRID_ENDS[1], clearance_weight=1000.0).value).any()
