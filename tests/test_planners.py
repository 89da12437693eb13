"""The planner registry: ``get_planner`` turns only a missing optional third-party package into
"not available in this installation"; a broken import inside gridfield and a registry entry naming a
function that does not exist are bugs and surface as such, from ``get_planner`` and from ``plan``."""

from __future__ import annotations

import sys
import textwrap
import warnings

import pytest

from gridfield.core.errors import GridfieldError
from gridfield.geometry.world import world_from_dict
from gridfield.planners import PLANNERS, Planner, get_planner, plan

WORLD = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})


@pytest.fixture
def register(tmp_path, monkeypatch):
    """``register(name, source)``: a throwaway module ``fake_planner_<name>`` holding ``source`` on
    sys.path, and a PLANNERS entry ``name`` pointing at its ``plan_fake``."""

    def make(name: str, source: str, func: str = "plan_fake", kind: str = "world") -> str:
        module = f"fake_planner_{name}"
        (tmp_path / f"{module}.py").write_text(textwrap.dedent(source))
        monkeypatch.setitem(PLANNERS, name, Planner(module, func, kind))
        monkeypatch.delitem(sys.modules, module, raising=False)  # undone on teardown: no module left behind
        return name

    monkeypatch.syspath_prepend(str(tmp_path))
    _importing_fakes(monkeypatch, "fake_planner_")
    return make


def _importing_fakes(monkeypatch, prefix: str) -> None:
    """Let the planner table load this test's throwaway modules (``prefix...``): gridfield imports its own
    planner modules by explicit statements only (``planners._module``), so a test module is imported here."""
    import importlib

    from gridfield import planners

    real = planners._module
    monkeypatch.setattr(planners, "_module", lambda name: importlib.import_module(name) if name.startswith(prefix)
                        else real(name))


PLAN_FAKE = """
def plan_fake(world, start, goal, params, *, cache=None):
    raise AssertionError("never called")
"""


def test_a_missing_third_party_dependency_is_not_available(register):
    name = register("optional", "import no_such_optional_dependency.sub\n" + PLAN_FAKE)
    with pytest.raises(GridfieldError, match=r"planner 'optional' is not available in this installation "
                                             r"\(install the package providing 'no_such_optional_dependency'"):
        get_planner(name)
    with pytest.raises(GridfieldError, match="not available in this installation"):
        plan(name, WORLD, (1, 5), (9, 5))


@pytest.mark.parametrize("source", [
    "from gridfield.core.path import NoSuchName\n",           # a broken import of gridfield's own code
    "import gridfield.no_such_submodule\n",               # a gridfield module that does not exist
    "raise ImportError('broken', name='gridfield.following.follower')\n",
])
def test_a_broken_gridfield_import_propagates(register, source):
    name = register("broken", source + PLAN_FAKE)
    with pytest.raises(ImportError) as got:
        get_planner(name)
    assert got.type is not GridfieldError and "not available" not in str(got.value)
    assert got.value.name.startswith("gridfield.")
    with pytest.raises(ImportError) as got:
        plan(name, WORLD, (1, 5), (9, 5))
    assert "not available" not in str(got.value)


def test_a_registry_entry_naming_a_missing_gridfield_module_propagates(monkeypatch):
    monkeypatch.setitem(PLANNERS, "lost", Planner("gridfield.no_such_planner_module", "plan_lost", "grid"))
    with pytest.raises(ModuleNotFoundError, match=r"gridfield\.no_such_planner_module"):
        get_planner("lost")


def test_a_misspelt_function_name_is_a_registry_bug_not_unavailable(monkeypatch):
    monkeypatch.setitem(PLANNERS, "typo", Planner("gridfield.following.follower", "plan_potentail", "grid"))
    for call in (lambda: get_planner("typo"), lambda: plan("typo", WORLD, (1, 5), (9, 5), resolution=0.5)):
        with pytest.raises(AttributeError, match=r"PLANNERS\['typo'\] names gridfield.following.follower.plan_potentail") as got:
            call()
        assert not isinstance(got.value, GridfieldError) and "not available" not in str(got.value)


def test_an_attribute_error_while_importing_propagates(register):
    name = register("attr", "import gridfield\ngridfield.no_such_attribute\n" + PLAN_FAKE)
    with pytest.raises(AttributeError, match="no_such_attribute"):
        get_planner(name)


# ----------------------------------------------------------------------------------------------
# what each planner reads: one table (PLANNERS[...].reads), from which the parameters' "read by" is derived
# ----------------------------------------------------------------------------------------------
def test_every_parameter_is_read_and_every_read_is_a_parameter():
    from gridfield.core.params import REGISTRY

    for name, entry in PLANNERS.items():
        assert set(entry.reads) <= set(REGISTRY), (name, set(entry.reads) - set(REGISTRY))
    unread = [n for n, spec in REGISTRY.items() if not spec.planners]
    assert unread == []


def test_a_new_planner_is_one_entry_and_its_reads_show_in_help(monkeypatch):
    """Adding a planner is one PLANNERS entry: the "read by" of the parameters it reads (--help,
    the docs) follows without touching the parameter registry."""
    from gridfield.core.params import REGISTRY, help_text

    assert "rrt" not in help_text("step")
    monkeypatch.setitem(PLANNERS, "rrt", Planner("fake_rrt", "plan_rrt", "world", ("step", "seed")))
    assert REGISTRY["step"].planners[-1] == "rrt" and help_text("step").endswith(", rrt")
    assert "rrt" not in REGISTRY["zeta"].planners


# alternative valid values, to show that a planner ignores the parameters it does not declare
_OTHER = {
    "zeta": 2.5, "d_star": 3.0, "eta": 7.0, "q_star": 1.5, "repulsive_power": 3.0, "repulsion": "sum",
    "metric": "chessboard", "gradient": "finite_difference", "saturate": 1.5, "model": "vortex", "ka": 5.0,
    "kr": 5.0, "ko": 1.0, "spacing": 0.5, "sample_radius": 0.7, "step_rule": "scaled", "step": 0.35,
    "alpha": 0.3, "min_speed": 0.2, "tolerance": 0.4, "max_iterations": 7, "sampling": "nearest",
    "gradient_threshold": 0.3, "progress_window": 3, "confine_window": 3, "escape": "random_walk",
    "escape_tries": 2, "escape_radius": 1.0, "seed": 3, "connectivity": 4, "clearance_weight": 2.0,
    "kappa": 5.0, "lambda": 3.0, "workspace_center": (4.0, 4.0), "workspace_radius": 9.0,
    "allow_unknown": "false", "goal_tolerance": 0.2, "robot_radius": 0.5, "inflation_radius": 1.5,
    "cost_scaling_factor": 2.0, "lut_precision": 100,
    "attraction": "octile", "clearance_gain": 3.0, "clearance_band": 2.0, "band_gain": 2.0,
}


def _ignores_undeclared(planner, target, start, goal, base_params, names=None):
    """Changing each parameter outside ``planner``'s reads (or those of ``names``) leaves the path as
    it is; changing one it reads changes it (so the check can fail)."""
    import numpy as np

    base = plan(planner, target, start, goal, base_params)
    reads = set(PLANNERS[planner].reads)
    for name in names or _OTHER:
        if name in reads:
            continue
        other = plan(planner, target, start, goal, {**base_params, name: _OTHER[name]})
        assert (other.status, other.iterations) == (base.status, base.iterations), name
        np.testing.assert_array_equal(other.points, base.points, err_msg=name)
    if not reads:
        return
    changed = []
    for n in reads:
        try:
            if not np.array_equal(plan(planner, target, start, goal, {**base_params, n: _OTHER[n]}).points,
                                  base.points):
                changed.append(n)
        except GridfieldError:  # e.g. the vortex model needs a vector world
            continue
    assert changed, "none of the declared reads changes the path: this check could not fail"


@pytest.mark.parametrize("planner", ["exact-potential", "visibility", "sphere-nav"])
def test_a_world_planner_reads_no_parameter_it_does_not_declare(planner):
    circles = world_from_dict({"bounds": [0, 0, 20, 20], "obstacles": [
        {"circle": {"center": [10.0, 7.0], "radius": 2.0}}, {"circle": {"center": [6.0, 13.0], "radius": 1.5}}]})
    start, goal = (3.0, 3.0), (16.5, 15.0)
    _ignores_undeclared(planner, circles, start, goal, {"kappa": 6.0} if planner == "sphere-nav" else {})


@pytest.mark.slow
def test_star_nav_reads_no_parameter_it_does_not_declare():
    """star-nav (about 1 s a plan): the parameters other planners read, one per concern."""
    from gridfield.fields.navigation import StarNavWarning
    from gridfield.io import bundled_map, read_world

    w = read_world(bundled_map("star_two.yaml"))
    warnings.simplefilter("ignore", StarNavWarning)  # seed 002's kappa 3 leaves a spurious minimum: it warns
    _ignores_undeclared("star-nav", w, w.start, w.goal, dict(w.params or {}),
                        names=["zeta", "eta", "q_star", "step_rule", "escape", "sampling", "connectivity",
                               "clearance_weight", "seed", "model"])


@pytest.mark.parametrize("planner", ["potential", "wavefront", "wavefront-octile", "fmm", "harmonic", "navfn"])
def test_a_grid_planner_reads_no_parameter_it_does_not_declare(planner):
    """Changing any parameter outside a planner's ``reads`` leaves its path unchanged (so the
    declared reads, and the "read by" derived from them, are complete); changing some it reads does
    change it (so the check can fail)."""
    import numpy as np

    from gridfield.core.grid import Grid, GridMap
    from gridfield.core.params import REGISTRY

    assert set(_OTHER) == set(REGISTRY)
    occ = np.zeros((24, 24), bool)
    occ[8:16, 10:13] = True
    occ[3:6, 16:20] = True
    gm = GridMap(Grid(occ.shape, 0.5), occ)
    _ignores_undeclared(planner, gm, (1.25, 5.25), (10.75, 6.25), {})
    if planner == "potential":  # the classic field too, and each complete model
        for model in ("khatib", "nf2", "nf-blend"):
            _ignores_undeclared(planner, gm, (1.25, 5.25), (10.75, 6.25), {"model": model})


@pytest.mark.parametrize("name", list(PLANNERS))
def test_every_planner_function_validates_a_raw_mapping(name):
    """Called directly (not through plan), each planner checks its params against the registry: a
    bad value or an unknown name is a ParameterError naming it, never a ValueError from float()."""
    import numpy as np

    from gridfield.core.errors import ParameterError
    from gridfield.core.grid import Grid, GridMap

    fn, kind = get_planner(name)
    target = GridMap(Grid((10, 10), 1.0), np.zeros((10, 10), bool)) if kind == "grid" else WORLD
    start, goal = np.array([0.5, 0.5]), np.array([9.5, 9.5])
    with pytest.raises(ParameterError, match="step must be a finite number > 0, got 'abc'"):
        fn(target, start, goal, {"step": "abc"})
    with pytest.raises(ParameterError, match="unknown parameter 'stepp'; did you mean 'step'"):
        fn(target, start, goal, {"stepp": 0.5})
