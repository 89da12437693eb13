"""One argument checker and one point parser (issue 18).

The functions that take planner parameters as arguments (descend, the potential arrays, the vortex
model, the samplers) must judge a value exactly as the registry does (gridfield.core.params.validate,
the check behind plan()): the same values refused, with the registry's message naming the
argument. Points given to plan(), descend, the potentials and the attraction are parsed by one
helper: strings, wrong shapes, NaN and inf are a ParameterError naming the argument.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from gridfield.core.errors import GridfieldError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.params import validate
from gridfield.fields.potential import attractive, build_field, repulsive, vortex_field, vortex_lattice
from gridfield.fields.sampling import attraction_force, grid_potential_sampler, grid_sampler, sample_force
from gridfield.following.descent import descend
from gridfield.io import bundled_map, read_world
from gridfield.planners import plan

GRID = Grid((3, 4), 1.0)
OCC = np.zeros((3, 4), bool)
OCC[0, 0] = True
GM = GridMap(GRID, OCC)
FIELD = build_field(GM, (3.5, 2.5), {"q_star": 1.5})


def _bowl(p):
    return (1.0 - p[0], 0.5 - p[1])


def _descend(**kw):
    return descend(_bowl, (0.0, 0.5), (1.0, 0.5), **kw)


def _repulsive(**kw):
    from gridfield.distance.brushfire import brushfire

    return repulsive(brushfire(GM, metric="euclidean", compute_labels=True), **kw)


def _vortex(**kw):
    return vortex_field(Grid((5, 5), 1.0, (-2.5, -2.5)), [[0.0, 0.0, 0.5]], (0.0, 2.0), (0.0, -2.0), **kw)


#: (call with one keyword argument, the argument, its registry entry)
ARGUMENTS = [
    *[(_descend, a, a) for a in ("step_rule", "step", "alpha", "min_speed", "tolerance", "max_iterations",
                                 "gradient_threshold", "progress_window", "confine_window", "escape",
                                 "escape_tries", "escape_radius")],
    (lambda **kw: attractive(GRID, (1.0, 1.0), **kw), "zeta", "zeta"),
    (lambda **kw: attractive(GRID, (1.0, 1.0), **kw), "d_star", "d_star"),
    (_repulsive, "eta", "eta"),
    (_repulsive, "q_star", "q_star"),
    (_repulsive, "power", "repulsive_power"),
    (_repulsive, "mode", "repulsion"),
    (_repulsive, "gradient", "gradient"),
    (_repulsive, "saturate", "saturate"),
    (_vortex, "ka", "ka"),
    (_vortex, "kr", "kr"),
    (_vortex, "ko", "ko"),
    (_vortex, "sample_radius", "sample_radius"),
    (lambda **kw: vortex_lattice((0, 0, 1, 1), **kw), "spacing", "spacing"),
    (lambda **kw: grid_sampler(FIELD, **kw), "sampling", "sampling"),
    (lambda **kw: grid_potential_sampler(FIELD, **kw), "sampling", "sampling"),
    (lambda **kw: sample_force(FIELD, [[1.5, 1.5]], **kw), "sampling", "sampling"),
]

VALUES = st.one_of(
    st.floats(-1e6, 1e6),  # no overflow of the arrays themselves: that is not the argument check
    st.integers(-3, 40),
    st.sampled_from([math.nan, math.inf, -math.inf, "1", "abc", "sum", "nearest", "finite_difference", "bilinear", "nearest", "normalized",
                     "scaled", "none", "random_walk", True, False, [0.1, 0.2], (0.5,), (0.1, -1.0), 1 + 2j]),
)


def _registry_message(name: str, value: object) -> str | None:
    try:
        validate({name: value})
    except ParameterError as e:
        return str(e)
    return None


@pytest.mark.parametrize(("call", "argument", "entry"), ARGUMENTS, ids=lambda x: getattr(x, "__name__", str(x)))
@settings(max_examples=40, deadline=None)
@given(value=VALUES)
@example(value=2.2250738585072014e-308)  # found by a fresh run: the vortex charges' sum overflowed
@example(value=5e-324)
@example(value=1e300)
def test_arguments_are_judged_as_the_registry_judges_them(call, argument, entry, value):
    expected = _registry_message(entry, value)
    try:
        call(**{argument: value})
    except GridfieldError as e:  # ParameterError included; a valid value may still fail later (a huge lattice)
        if expected is None:
            assert not str(e).startswith(f"{argument} must be"), (argument, value, str(e))
            return
        assert str(e) == argument + expected[len(entry):], (argument, value)
    else:
        assert expected is None, (argument, value, expected)


@pytest.mark.parametrize("call", [_descend, _repulsive, _vortex])
def test_none_is_no_value_for_a_function_argument(call):
    argument = {_descend: "step", _repulsive: "q_star", _vortex: "ka"}[call]
    with pytest.raises(ParameterError, match=rf"^{argument} must be .*, got None$"):
        call(**{argument: None})


BAD_POINTS = ["ab", ("1", "2"), [1.0, 2.0, 3.0], [[1.0, 2.0], [3.0, 4.0]], [1.0], (1.0, math.nan),
              (math.inf, 0.0), None, [True, False], [1.0, None]]


def _point_calls():
    world = read_world(bundled_map("seed000.yaml"))
    return [
        ("start", lambda p: plan("potential", world, p, (20.0, 10.0), resolution=0.5)),
        ("goal", lambda p: plan("potential", world, (1.0, 10.0), p, resolution=0.5)),
        ("start", lambda p: descend(_bowl, p, (1.0, 0.5))),
        ("goal", lambda p: descend(_bowl, (0.0, 0.5), p)),
        ("goal", lambda p: attractive(GRID, p)),
        ("goal", lambda p: attraction_force(p, {})),
        ("start", lambda p: vortex_field(GRID, [[0.0, 0.0, 0.5]], p, (1.0, 1.0))),
        ("goal", lambda p: vortex_field(GRID, [[0.0, 0.0, 0.5]], (1.0, 1.0), p)),
    ]


@pytest.mark.parametrize("bad", BAD_POINTS, ids=repr)
def test_bad_points_are_named_by_every_entry_point(bad):
    for name, call in _point_calls():
        with pytest.raises(ParameterError, match=rf"^{name} must be two finite numbers \(x, y\), got "):
            call(bad)


def test_good_points_in_every_accepted_form():
    for p in [(1.5, 1.5), [1.5, 1.5], np.array([1.5, 1.5]), np.array([[1.5, 1.5]]), (np.float32(1.5), 3 // 2 + 0.5)]:
        U, _, _ = attractive(GRID, p)
        assert float(U[1, 1]) == 0.0


def test_zero_charges_are_no_charges():
    # kr = 0 (ko = 0) with a lattice node on the start (on a charge sample): no 0 / 0 there
    f = _vortex(kr=0.0, ko=0.0)
    free = ~f.map.occupied
    X, Y = np.meshgrid(*f.grid.cell_centers())
    np.testing.assert_array_equal(f.potential[free], (0.5 * 25.0 * (X**2 + (Y + 2.0) ** 2))[free])
